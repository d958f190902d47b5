//! Time-weighted averages over the steady window: speeds, ring reaction and contact
//! statistics per ball and per azimuth.

use super::output::{BallSummary, SolverStats, Summary};
use super::rhs::Diagnostics;
use crate::model::Model;
use crate::physics::kinematics::rolling_kinematics;
use std::f64::consts::TAU;

/// Time-weighted sums over the steady window.
pub struct Averages {
    time: f64,
    shaft: f64,
    cage: f64,
    reaction: [f64; 3],
    /// Per ball (each ball orbits through the whole bearing).
    balls: ContactSums,
    /// Per azimuth bin (centred on the ball positions at t = 0).
    zone: ContactSums,
}

impl Averages {
    pub fn new(z: usize) -> Self {
        Averages {
            time: 0.0,
            shaft: 0.0,
            cage: 0.0,
            reaction: [0.0; 3],
            balls: ContactSums::new(z),
            zone: ContactSums::new(z),
        }
    }
    pub fn add(&mut self, m: &Model, t: f64, w: f64, y: &[f64], d: &Diagnostics) {
        self.time += w;
        self.shaft += w * m.shaft_speed(t);
        self.cage += w * y[m.layout.cage + 9];
        for k in 0..3 {
            self.reaction[k] += w * d.inner_reaction[k];
        }
        for j in 0..m.z {
            let th = y[m.layout.ball(j) + 2];
            let k = ((th.rem_euclid(TAU) * m.z as f64 / TAU).round() as usize) % m.z;
            let c = (
                d.inner_load[j],
                d.outer_load[j],
                d.inner_alpha[j],
                d.outer_alpha[j],
            );
            self.zone.add(k, w, c);
            self.balls.add(j, w, c);
        }
    }
    pub fn finish(self, m: &Model, window: [f64; 2], stats: SolverStats) -> Summary {
        let tt = self.time.max(f64::MIN_POSITIVE);
        let shaft = self.shaft / tt;
        let cage = self.cage / tt;
        let balls = self.balls.finish();
        // Pure-rolling (epicyclic) cage speed at the load-weighted mean contact angles,
        // with outer-race control: the kinematics the quasi-static solution uses.
        let (mut wsum, mut ai, mut ao) = (0.0, 0.0, 0.0);
        for b in &balls {
            if b.outer_contact_angle.is_finite() && b.inner_contact_angle.is_finite() {
                wsum += b.outer_load;
                ai += b.outer_load * b.inner_contact_angle;
                ao += b.outer_load * b.outer_contact_angle;
            }
        }
        let (ai, ao) = if wsum > 0.0 {
            (ai / wsum, ao / wsum)
        } else {
            (m.free_contact_angle, m.free_contact_angle)
        };
        let epi =
            rolling_kinematics(0.5 * m.pitch_diameter, ai, ao, 0.5 * m.ball_diameter, shaft)[0];
        Summary {
            stats,
            steady_window: window,
            mean_shaft_speed: shaft,
            mean_cage_speed: cage,
            epicyclic_cage_speed: epi,
            cage_slip: if epi != 0.0 { 1.0 - cage / epi } else { 0.0 },
            mean_inner_ring_reaction: [
                self.reaction[0] / tt,
                self.reaction[1] / tt,
                self.reaction[2] / tt,
            ],
            balls,
            load_zone: self.zone.finish(),
        }
    }
}

/// Time-weighted contact statistics in bins: one bin per ball, or per azimuth (bin k
/// collects whichever ball is within half a ball spacing of `2 pi k / Z`, so it compares
/// with quasi-static ball k). Angles are averaged over the time the contact is loaded.
struct ContactSums {
    time: Vec<f64>,
    load_i: Vec<f64>,
    load_o: Vec<f64>,
    ang_i: Vec<f64>,
    ang_o: Vec<f64>,
    t_i: Vec<f64>,
    t_o: Vec<f64>,
}

impl ContactSums {
    fn new(z: usize) -> Self {
        ContactSums {
            time: vec![0.0; z],
            load_i: vec![0.0; z],
            load_o: vec![0.0; z],
            ang_i: vec![0.0; z],
            ang_o: vec![0.0; z],
            t_i: vec![0.0; z],
            t_o: vec![0.0; z],
        }
    }
    /// Add loads (N) and angles (rad) `(inner, outer, inner angle, outer angle)` with weight `w` (s).
    fn add(&mut self, k: usize, w: f64, (li, lo, ai, ao): (f64, f64, f64, f64)) {
        self.time[k] += w;
        self.load_i[k] += w * li;
        self.load_o[k] += w * lo;
        if li > 0.0 {
            self.ang_i[k] += w * ai;
            self.t_i[k] += w;
        }
        if lo > 0.0 {
            self.ang_o[k] += w * ao;
            self.t_o[k] += w;
        }
    }
    fn finish(self) -> Vec<BallSummary> {
        (0..self.time.len())
            .map(|k| {
                let t = self.time[k].max(f64::MIN_POSITIVE);
                BallSummary {
                    inner_load: self.load_i[k] / t,
                    outer_load: self.load_o[k] / t,
                    inner_contact_angle: if self.t_i[k] > 0.0 {
                        self.ang_i[k] / self.t_i[k]
                    } else {
                        f64::NAN
                    },
                    outer_contact_angle: if self.t_o[k] > 0.0 {
                        self.ang_o[k] / self.t_o[k]
                    } else {
                        f64::NAN
                    },
                }
            })
            .collect()
    }
}
