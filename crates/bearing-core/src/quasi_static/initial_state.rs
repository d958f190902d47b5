//! The dynamic model's state at t = 0, built from a quasi-static equilibrium.

use super::solver::QsState;
use crate::model::layout::{ball, cage, inner, outer};
use crate::model::Model;

/// State vector at t = 0 from a quasi-static solution at the initial speed.
pub fn initial_state(m: &Model, qs: &QsState) -> Vec<f64> {
    let l = &m.layout;
    let mut y = vec![0.0; l.len];
    // the pedestal carries the applied radial load
    let oy = m.applied_force[1] / m.pedestal_k[0];
    let oz = m.applied_force[2] / m.pedestal_k[1];
    // the traction balance's cage speed and spins; the pure-rolling kinematics otherwise
    let cage_speed = qs
        .balance
        .as_ref()
        .map_or(qs.epicyclic_cage_speed, |b| b.cage_speed);
    for j in 0..m.z {
        let b = l.ball(j);
        let [x, r] = qs.balls[j];
        let [thd, wx, wr] = qs.kinematics[j];
        y[b + ball::X] = x;
        y[b + ball::THETA] = m.pocket_angles[j];
        // ball radius measured from the displaced outer ring centre; the shift is small
        // against the ball spacing, so the azimuth is kept
        let (s, c) = y[b + ball::THETA].sin_cos();
        let py = -r * s + oy;
        let pz = r * c + oz;
        y[b + ball::R] = (py * py + pz * pz).sqrt();
        y[b + ball::THETA] = (-py).atan2(pz);
        match &qs.balance {
            Some(bal) => {
                y[b + ball::THETA_DOT] = bal.cage_speed;
                [y[b + ball::W_X], y[b + ball::W_R], y[b + ball::W_T]] = bal.spins[j];
            }
            None => {
                y[b + ball::THETA_DOT] = thd;
                y[b + ball::W_X] = wx;
                y[b + ball::W_R] = wr;
            }
        }
    }
    let i = l.inner;
    y[i + inner::X] = qs.ring[0];
    y[i + inner::Y] = qs.ring[1] + oy;
    y[i + inner::Z] = qs.ring[2] + oz;
    y[i + inner::TILT_Y] = qs.ring[3];
    y[i + inner::TILT_Z] = qs.ring[4];
    let o = l.outer;
    y[o + outer::Y] = oy;
    y[o + outer::Z] = oz;
    let c = l.cage;
    if m.cage_guided_by_inner() {
        y[c + cage::Y] = y[i + inner::Y];
        y[c + cage::Z] = y[i + inner::Z];
    } else {
        y[c + cage::Y] = oy;
        y[c + cage::Z] = oz;
    }
    y[c + cage::W_X] = cage_speed;
    y
}
