//! Natural size of each state component, for the step controller's error norm.

use crate::model::layout::{kinds, Kind};
use crate::model::Model;

/// Natural size of each state component, for error control.
pub fn scales(m: &Model) -> (Vec<f64>, Vec<bool>) {
    let rb = 0.5 * m.ball_diameter;
    let rp = 0.5 * m.pitch_diameter;
    let w = m.speed.0.max(m.speed.1).max(1.0);
    let v = w * rp;
    let ks = kinds(&m.layout);
    let sc = ks
        .iter()
        .map(|k| match k {
            Kind::Length => rb,
            Kind::Angle | Kind::Phase => rb / rp,
            Kind::Velocity => v,
            Kind::AngularVelocity => v / rb,
        })
        .collect();
    (sc, ks.iter().map(|k| *k == Kind::Phase).collect())
}
