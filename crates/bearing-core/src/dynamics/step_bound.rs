//! Defects are never stepped over: the step is bounded by the time to the next defect
//! edge plus a tenth of the transit.

use crate::model::layout::ball;
use crate::model::Model;
use crate::physics::defect::wrap_angle;
use std::f64::consts::TAU;

/// Largest step that cannot carry any ball across more than a tenth of a defect.
pub fn defect_step_bound(m: &Model, t: f64, y: &[f64]) -> f64 {
    let mut bound = f64::INFINITY;
    let shaft = m.shaft_angle(t);
    let ws = m.shaft_speed(t);
    for (race, ring_angle, ring_speed) in [(&m.inner_race, shaft, ws), (&m.outer_race, 0.0, 0.0)] {
        for d in &race.defects {
            for j in 0..m.z {
                let b = m.layout.ball(j);
                let rel = y[b + ball::THETA_DOT] - ring_speed;
                if rel.abs() < 1e-9 {
                    continue;
                }
                let delta = wrap_angle(y[b + ball::THETA] - ring_angle - d.angle);
                let transit = 2.0 * d.half_angle / rel.abs();
                let to_entry = if delta.abs() < d.half_angle {
                    0.0
                } else if rel > 0.0 {
                    (-d.half_angle - delta).rem_euclid(TAU)
                } else {
                    (delta - d.half_angle).rem_euclid(TAU)
                };
                bound = bound.min(to_entry / rel.abs() + 0.1 * transit);
            }
        }
    }
    bound
}
