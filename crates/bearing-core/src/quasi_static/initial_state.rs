//! The dynamic model's state at t = 0, built from a quasi-static equilibrium.

use super::solver::QsState;
use crate::model::Model;

/// State vector at t = 0 from a quasi-static solution at the initial speed.
pub fn initial_state(m: &Model, qs: &QsState) -> Vec<f64> {
    let l = &m.layout;
    let mut y = vec![0.0; l.len];
    // the pedestal carries the applied radial load
    let oy = m.applied_force[1] / m.pedestal_k[0];
    let oz = m.applied_force[2] / m.pedestal_k[1];
    let mut cage_speed = 0.0;
    for j in 0..m.z {
        let b = l.ball(j);
        let [x, r] = qs.balls[j];
        let [thd, wx, wr] = qs.kinematics[j];
        y[b] = x;
        y[b + 2] = m.pocket_angles[j];
        // ball radius measured from the displaced outer ring centre; the shift is small
        // against the ball spacing, so the azimuth is kept
        let (s, c) = y[b + 2].sin_cos();
        let py = -r * s + oy;
        let pz = r * c + oz;
        y[b + 1] = (py * py + pz * pz).sqrt();
        y[b + 2] = (-py).atan2(pz);
        y[b + 5] = thd;
        y[b + 6] = wx;
        y[b + 7] = wr;
        cage_speed += thd / m.z as f64;
    }
    let i = l.inner;
    y[i] = qs.ring[0];
    y[i + 1] = qs.ring[1] + oy;
    y[i + 2] = qs.ring[2] + oz;
    y[i + 3] = qs.ring[3];
    y[i + 4] = qs.ring[4];
    let o = l.outer;
    y[o] = oy;
    y[o + 1] = oz;
    let c = l.cage;
    if m.land.is_some() && !m.land_on_outer {
        y[c + 1] = y[i + 1];
        y[c + 2] = y[i + 2];
    } else {
        y[c + 1] = oy;
        y[c + 2] = oz;
    }
    y[c + 9] = cage_speed;
    y
}
