//! Time averages over the steady window: speeds, ring reaction and contact statistics
//! per ball and per azimuth. The cage speed is integrated over each step as the cubic
//! through its value and rate at both ends (the solver's own dense output); the rest are
//! trapezoid sums over the accepted steps. (A sum of each step's end value times its
//! length, the rule before, is first order: on the Table-1 case it read the references'
//! cage speed 2.9e-6 of it low, because their step lengths follow the phase of the
//! speed's changes; docs/lab/benchmarks.md.) The cage's spin angle is not used instead:
//! the error norm holds a phase only to an absolute tolerance per step, and on a 0.1 s
//! run the Rosenbrock-W method's angle drifted 6e-5 of the speed from its own speed's
//! integral.

use super::output::{BallSummary, CageMotion, CageState, SolverStats, Summary};
use super::rhs::Diagnostics;
use crate::model::layout::cage;
use crate::model::Model;
use crate::ode::hermite::hermite_integral;
use crate::ode::method::LastStep;
use crate::physics::defect::rem_turn;
use crate::physics::frames::angles;
use crate::physics::kinematics::rolling_kinematics;
use std::f64::consts::TAU;

/// Sums over the steady window.
pub struct Averages {
    /// Start of the window, s.
    start: f64,
    time: f64,
    shaft: f64,
    reaction: [f64; 3],
    /// Integral of the cage's spin speed over the window so far, rad.
    cage_turn: f64,
    /// Per ball (each ball orbits through the whole bearing).
    balls: ContactSums,
    /// Per azimuth bin (centred on the ball positions at t = 0).
    zone: ContactSums,
    orbit: CageOrbit,
    /// The latest step's end, once a step reached the window, and the weight (s) it has
    /// so far: its step's half, added with the next step's half when that comes (so each
    /// sample is summed once).
    latest: Sample,
    pending: Option<f64>,
}

/// What the averages read of one state: its values at one instant.
struct Sample {
    /// Shaft speed, rad/s.
    shaft: f64,
    /// Force of the balls on the inner ring, N.
    reaction: [f64; 3],
    /// Per ball: its azimuth bin, and inner and outer load (N) and contact angle (rad).
    bin: Vec<usize>,
    contact: Vec<(f64, f64, f64, f64)>,
    /// Cage-centre eccentricity ratio, -.
    eccentricity: f64,
    /// Contact angles, inner then outer, rad (kept to allocate once).
    angles: Vec<f64>,
}

impl Sample {
    fn new(z: usize) -> Self {
        Sample {
            shaft: 0.0,
            reaction: [0.0; 3],
            bin: vec![0; z],
            contact: vec![(0.0, 0.0, 0.0, 0.0); z],
            eccentricity: 0.0,
            angles: vec![0.0; 2 * z],
        }
    }
    fn read(&mut self, m: &Model, t: f64, y: &[f64], d: &Diagnostics) -> f64 {
        self.shaft = m.shaft_speed(t);
        self.reaction = d.inner_reaction;
        let (inner, outer) = self.angles.split_at_mut(m.z);
        angles(&d.inner_alpha, inner);
        angles(&d.outer_alpha, outer);
        for j in 0..m.z {
            let th = y[m.layout.ball(j) + 2];
            // `th.rem_euclid(TAU)`, to the bit
            let r = rem_turn(th);
            let th = if r < 0.0 { r + TAU } else { r };
            self.bin[j] = ((th * m.z as f64 / TAU).round() as usize) % m.z;
            self.contact[j] = (d.inner_load[j], d.outer_load[j], inner[j], outer[j]);
        }
        let (phi, e) = CageOrbit::place(m, y);
        self.eccentricity = e;
        phi
    }
}

impl Averages {
    /// Sums for a bearing of `z` balls over a window from `start` (s).
    pub fn new(z: usize, start: f64) -> Self {
        Averages {
            start,
            time: 0.0,
            shaft: 0.0,
            reaction: [0.0; 3],
            cage_turn: 0.0,
            balls: ContactSums::new(z),
            zone: ContactSums::new(z),
            orbit: CageOrbit::default(),
            latest: Sample::new(z),
            pending: None,
        }
    }

    /// Add an accepted step; steps ending before the window are skipped (one ending on
    /// its start gives the first sample, with no weight).
    ///
    /// `s` is the solver's last step and `t1` its end (the solver's time, which a step cut
    /// to a point reaches exactly where `s.t + s.h` may not), `d` the diagnostics at its
    /// end.
    pub fn add(&mut self, m: &Model, s: &LastStep, t1: f64, d: &Diagnostics) {
        let t0 = s.t;
        if t1 < self.start {
            return;
        }
        let (w, h) = (m.layout.cage + cage::W_X, t1 - t0);
        if h > 0.0 {
            let from = ((self.start - t0) / h).clamp(0.0, 1.0);
            self.cage_turn += hermite_integral(s.y0[w], s.f0[w], s.y1[w], s.f1[w], h, from);
        }
        self.pending = Some(match self.pending {
            // the step's start is the latest sample: half the step to each end
            Some(left) => {
                self.weigh(left + 0.5 * h);
                0.5 * h
            }
            // no sample at the window's start: its part of the step takes the end's
            // value, a first-order error over one step of the whole window
            None => t1 - self.start,
        });
        let phi = self.latest.read(m, t1, s.y1, d);
        self.orbit.turn_to(phi, self.latest.eccentricity);
    }

    /// Add the latest sample with weight `w`, s.
    fn weigh(&mut self, w: f64) {
        let s = &self.latest;
        self.time += w;
        self.shaft += w * s.shaft;
        for k in 0..3 {
            self.reaction[k] += w * s.reaction[k];
        }
        self.orbit.weigh(w, s.eccentricity);
        for (j, (&k, &c)) in s.bin.iter().zip(&s.contact).enumerate() {
            self.zone.add(k, w, c);
            self.balls.add(j, w, c);
        }
    }

    pub fn finish(mut self, m: &Model, window: [f64; 2], stats: SolverStats) -> Summary {
        if let Some(w) = self.pending.take() {
            self.weigh(w);
        }
        let tt = self.time.max(f64::MIN_POSITIVE);
        let shaft = self.shaft / tt;
        let cage = self.cage_turn / tt;
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
    /// The centre's azimuth, rad, and eccentricity ratio, -.
    fn place(m: &Model, y: &[f64]) -> (f64, f64) {
        let ([dy, dz], e) = m.cage_offset(y);
        // azimuth measured like the balls' (from +Z towards -Y), so positive with the shaft
        ((-dy).atan2(dz), e)
    }
    /// Follow the centre to azimuth `phi` (rad) at eccentricity `e`.
    fn turn_to(&mut self, phi: f64, e: f64) {
        self.max_ecc = self.max_ecc.max(e);
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
    fn weigh(&mut self, w: f64, e: f64) {
        self.time += w;
        self.ecc += w * e;
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

    /// A cage speed rising as a quadratic and a ring reaction rising linearly in time, over
    /// steps of 0.3 and 1.7 ms in turn: the window's means are their exact ones. A rule
    /// that weights each step's end value by its length would read them high by the rate
    /// times half the sum of the squared steps over the window (0.075 N for the reaction),
    /// the trapezoid the cage speed high by `c` times a sixth of the sum of the cubed steps
    /// over the window (4.1e-5 rad/s); what is left is rounding (speeds of ~500 rad/s, sums of 100 steps):
    /// 1e-9 rad/s and 1e-9 N are far above it and far below either rule's error.
    #[test]
    fn means_over_uneven_steps_are_second_order() {
        use crate::scene::{fault_case_scene, FaultCase};
        let s = fault_case_scene("h7005c", FaultCase::None).unwrap();
        let m = Model::new(&s.validated().unwrap());
        let (a, b, c) = (440.0, 50.0, 100.0); // rad/s, rad/s^2, rad/s^3
        let (p, q) = (30.0, 100.0); // N, N/s
        let w = m.layout.cage + cage::W_X;
        let n = m.layout.len;
        let state = |t: f64| {
            let (mut y, mut f) = (vec![0.0; n], vec![0.0; n]);
            y[w] = a + b * t + c * t * t;
            f[w] = b + 2.0 * c * t;
            (y, f)
        };
        let (start, end): (f64, f64) = (0.3, 0.4);
        // one step across the window's start, 1 ns inside it, then 0.3 and 1.7 ms in turn
        let mut times = vec![0.29, start + 1e-9];
        while *times.last().unwrap() < end - 1e-12 {
            let h: f64 = if times.len() % 2 == 0 { 0.3e-3 } else { 1.7e-3 };
            times.push((times.last().unwrap() + h).min(end));
        }
        let mut acc = Averages::new(m.z, start);
        let mut diag = Diagnostics::new(m.z);
        for ts in times.windows(2) {
            let ((y0, f0), (y1, f1)) = (state(ts[0]), state(ts[1]));
            diag.inner_reaction = [p + q * ts[1], 0.0, 0.0];
            let step = LastStep {
                t: ts[0],
                h: ts[1] - ts[0],
                y0: &y0,
                f0: &f0,
                y1: &y1,
                f1: &f1,
            };
            acc.add(&m, &step, ts[1], &diag);
        }
        let sum = acc.finish(&m, [start, end], SolverStats::default());
        let mid = 0.5 * (start + end);
        let cage = a + b * mid + c * (end.powi(3) - start.powi(3)) / (3.0 * (end - start));
        assert!(
            (sum.mean_cage_speed - cage).abs() < 1e-9,
            "{}",
            sum.mean_cage_speed
        );
        let r = sum.mean_inner_ring_reaction[0];
        assert!((r - (p + q * mid)).abs() < 1e-9, "{r}");
    }

    /// A step ending on the window's start gives its first sample; over the next step,
    /// ball 0 moves from azimuth bin 0 to bin 1 while its inner load rises from 10 to 30 N
    /// (the other balls unloaded, each in its own bin). Each end weighs half the step in
    /// its own bin: bin 0 reads 10 N (ball 0's start alone), bin 1 (ball 1 throughout,
    /// ball 0's end) 30 N over three half-steps, 10 N, and ball 0 20 N. The end-value rule
    /// read 0, 15 and 30 N. Exact in binary but for the divisions: 1e-12 N.
    #[test]
    fn each_end_of_a_step_weighs_in_its_own_bin() {
        use crate::scene::{fault_case_scene, FaultCase};
        let s = fault_case_scene("h7005c", FaultCase::None).unwrap();
        let m = Model::new(&s.validated().unwrap());
        let (start, h) = (0.3, 1e-5);
        let bin = TAU / m.z as f64;
        let n = m.layout.len;
        let mut acc = Averages::new(m.z, start);
        let mut diag = Diagnostics::new(m.z);
        let zero = vec![0.0; n];
        let mut ends = [vec![0.0; n], vec![0.0; n]];
        for (k, y) in ends.iter_mut().enumerate() {
            for j in 0..m.z {
                y[m.layout.ball(j) + 2] = j as f64 * bin;
            }
            y[m.layout.ball(0) + 2] = k as f64 * bin;
        }
        for (k, t1) in [start, start + h].into_iter().enumerate() {
            diag.inner_load[0] = [10.0, 30.0][k];
            let y0 = if k == 0 { &zero } else { &ends[0] };
            let step = LastStep {
                t: t1 - h,
                h,
                y0,
                f0: &zero,
                y1: &ends[k],
                f1: &zero,
            };
            acc.add(&m, &step, t1, &diag);
        }
        let sum = acc.finish(&m, [start, start + h], SolverStats::default());
        let loads = [
            sum.load_zone[0].inner_load,
            sum.load_zone[1].inner_load,
            sum.balls[0].inner_load,
        ];
        for (got, want) in loads.into_iter().zip([10.0, 10.0, 20.0]) {
            assert!((got - want).abs() < 1e-12, "{loads:?}");
        }
    }

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
