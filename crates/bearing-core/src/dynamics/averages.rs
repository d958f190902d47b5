//! Time-weighted averages over the steady window: speeds, ring reaction and contact
//! statistics per ball and per azimuth.

use super::output::{BallSummary, CageMotion, CageState, SolverStats, Summary};
use super::rhs::Diagnostics;
use crate::model::Model;
use crate::physics::defect::rem_turn;
use crate::physics::frames::angles;
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
    orbit: CageOrbit,
    /// A step's contact angles, inner then outer, rad (kept to allocate once).
    angles: Vec<f64>,
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
            orbit: CageOrbit::default(),
            angles: vec![0.0; 2 * z],
        }
    }
    pub fn add(&mut self, m: &Model, t: f64, w: f64, y: &[f64], d: &Diagnostics) {
        self.time += w;
        self.shaft += w * m.shaft_speed(t);
        self.cage += w * y[m.layout.cage + 9];
        self.orbit.add(m, w, y);
        for k in 0..3 {
            self.reaction[k] += w * d.inner_reaction[k];
        }
        let (inner, outer) = self.angles.split_at_mut(m.z);
        angles(&d.inner_alpha, inner);
        angles(&d.outer_alpha, outer);
        for j in 0..m.z {
            let th = y[m.layout.ball(j) + 2];
            // `th.rem_euclid(TAU)`, to the bit
            let r = rem_turn(th);
            let th = if r < 0.0 { r + TAU } else { r };
            let k = ((th * m.z as f64 / TAU).round() as usize) % m.z;
            let c = (d.inner_load[j], d.outer_load[j], inner[j], outer[j]);
            self.zone.add(k, w, c);
            self.balls.add(j, w, c);
        }
    }
    pub fn finish(self, m: &Model, window: [f64; 2], stats: SolverStats) -> Summary {
        let tt = self.time.max(f64::MIN_POSITIVE);
        let shaft = self.shaft / tt;
        let cage = self.cage / tt;
        let cage_motion = self.orbit.finish(cage);
        let balls = self.balls.finish();
        let load_zone = self.zone.finish();
        // Pure-rolling (epicyclic) cage speed of the loaded balls: the contact angles of the
        // load zone, each azimuth weighted by its contact load, with outer-race control (the
        // kinematics the quasi-static solution uses). Per-ball orbit averages would weigh
        // every ball alike and let the nearly unloaded balls' angles (inner 20-28 deg, outer
        // 4-10 deg at 10000 rpm) set the reference, which is not how the loaded balls roll.
        let [ai, ao] = loaded_contact_angles(&load_zone, m.free_contact_angle);
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
            load_zone,
            loaded_contact_angles: [ai, ao],
            cage_motion,
        }
    }
}

/// The cage centre relative to its guiding ring: time-weighted eccentricity and the
/// unwrapped azimuth of the centre (for the whirl speed).
#[derive(Default)]
struct CageOrbit {
    time: f64,
    ecc: f64,
    max_ecc: f64,
    /// Azimuth of the first and latest sample, rad, and the unwrapped turn since the first.
    first: Option<f64>,
    last: f64,
    swept: f64,
}

impl CageOrbit {
    fn add(&mut self, m: &Model, w: f64, y: &[f64]) {
        let ([dy, dz], e) = m.cage_offset(y);
        self.time += w;
        self.ecc += w * e;
        self.max_ecc = self.max_ecc.max(e);
        // azimuth measured like the balls' (from +Z towards -Y), so positive with the shaft
        let phi = (-dy).atan2(dz);
        match self.first {
            None => self.first = Some(phi),
            Some(_) => {
                let mut d = phi - self.last;
                d -= TAU * (d / TAU).round();
                self.swept += d;
            }
        }
        self.last = phi;
    }

    fn finish(self, cage_speed: f64) -> CageMotion {
        let t = self.time.max(f64::MIN_POSITIVE);
        let mean = self.ecc / t;
        let whirl = self.swept / t;
        let orbits = whirl.abs() > 0.1 * cage_speed.abs() && mean > 0.1;
        CageMotion {
            state: if orbits {
                CageState::Whirling
            } else {
                CageState::Quiet
            },
            mean_eccentricity: mean,
            max_eccentricity: self.max_ecc,
            whirl_speed: whirl,
        }
    }
}

/// Inner and outer contact angles of the load zone, each azimuth bin weighted by its mean
/// load on that race (rad); `fallback` where no bin was loaded.
fn loaded_contact_angles(zone: &[BallSummary], fallback: f64) -> [f64; 2] {
    let weighted = |load: fn(&BallSummary) -> f64, angle: fn(&BallSummary) -> f64| {
        let (mut w, mut sum) = (0.0, 0.0);
        for b in zone.iter().filter(|b| angle(b).is_finite()) {
            w += load(b);
            sum += load(b) * angle(b);
        }
        if w > 0.0 {
            sum / w
        } else {
            fallback
        }
    };
    [
        weighted(|b| b.inner_load, |b| b.inner_contact_angle),
        weighted(|b| b.outer_load, |b| b.outer_contact_angle),
    ]
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loaded_angles_follow_the_loaded_azimuths() {
        // a loaded bin at 15/13 deg and a nearly unloaded one at 25/5 deg
        let bin = |q: f64, ai: f64, ao: f64| BallSummary {
            inner_load: q,
            outer_load: q + 2.5,
            inner_contact_angle: ai.to_radians(),
            outer_contact_angle: ao.to_radians(),
        };
        let zone = [
            bin(90.0, 15.0, 13.0),
            bin(0.5, 25.0, 5.0),
            BallSummary {
                inner_contact_angle: f64::NAN,
                ..bin(0.0, 0.0, 0.0)
            },
        ];
        let [ai, ao] = loaded_contact_angles(&zone, 0.0);
        // (90 * 15 + 0.5 * 25) / 90.5 deg and (92.5 * 13 + 3 * 5 + 2.5 * 0) / 98 deg
        assert!((ai.to_degrees() - (90.0 * 15.0 + 0.5 * 25.0) / 90.5).abs() < 1e-12);
        assert!((ao.to_degrees() - (92.5 * 13.0 + 3.0 * 5.0) / 98.0).abs() < 1e-12);
        assert_eq!(loaded_contact_angles(&[], 0.26), [0.26, 0.26]);
    }
}
