//! The stepping loop: initial state, adaptive or fixed RK4, defect-aware step bound,
//! uniform output sampling by Hermite interpolation, steady-window averages, progress
//! and cancellation.

use super::integrator::{hermite, AdaptiveRk4, FixedRk4, OdeSystem, StepStats};
use super::model::Model;
use super::rhs::{rhs, Diagnostics};
use super::state::{kinds, Kind};
use crate::physics::defect::wrap_angle;
use crate::quasi_static::QsState;
use crate::scene::{Integrator, Scene};
use crate::simulation::{
    BallSummary, Channel, Channels, RunControl, SimError, SimResult, SolverStats, Summary,
};
use std::f64::consts::TAU;
use std::sync::atomic::Ordering;
use std::time::Instant;

/// The model as an ODE system.
pub struct BearingSystem<'m> {
    pub model: &'m Model,
}

impl OdeSystem for BearingSystem<'_> {
    fn dim(&self) -> usize {
        self.model.layout.len
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        rhs(self.model, t, y, dy, None);
    }
}

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

/// Natural size of each state component, for error control.
fn scales(m: &Model) -> (Vec<f64>, Vec<bool>) {
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

/// Largest step that cannot carry any ball across more than a tenth of a defect.
fn defect_step_bound(m: &Model, t: f64, y: &[f64]) -> f64 {
    let mut bound = f64::INFINITY;
    let shaft = m.shaft_angle(t);
    let ws = m.shaft_speed(t);
    for (race, ring_angle, ring_speed) in [(&m.inner_race, shaft, ws), (&m.outer_race, 0.0, 0.0)] {
        for d in &race.defects {
            for j in 0..m.z {
                let b = m.layout.ball(j);
                let rel = y[b + 5] - ring_speed;
                if rel.abs() < 1e-9 {
                    continue;
                }
                let delta = wrap_angle(y[b + 2] - ring_angle - d.angle);
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

/// Which channels to record and how.
struct Recorder {
    fs: f64,
    next: usize,
    n: usize,
    accel: [Vec<f64>; 2],
    cage: Option<Vec<f64>>,
    cage_ecc: Option<Vec<f64>>,
    inner: Option<[Vec<f64>; 3]>,
    loads: Option<(usize, Vec<f64>, Vec<f64>)>,
    scratch_y: Vec<f64>,
    scratch_f: Vec<f64>,
    diag: Diagnostics,
}

/// Run the integration. `qs` is the quasi-static start at the initial speed.
pub fn integrate(
    m: &Model,
    scene: &Scene,
    qs: &QsState,
    ctl: RunControl<'_>,
) -> Result<SimResult, SimError> {
    let RunControl {
        cancel,
        mut progress,
    } = ctl;
    let sv = &scene.solver;
    let tend = sv.duration;
    let n = m.layout.len;
    let mut sys = BearingSystem { model: m };
    let mut y = initial_state(m, qs);
    let mut f = vec![0.0; n];
    let mut y_next = vec![0.0; n];
    let mut f_next = vec![0.0; n];
    let mut diag = Diagnostics::new(m.z);
    let mut stats = StepStats::default();
    rhs(m, 0.0, &y, &mut f, Some(&mut diag));
    stats.rhs_evals += 1;

    let n_samples = (tend * sv.sample_rate).floor() as usize + 1;
    let mut rec = Recorder {
        fs: sv.sample_rate,
        next: 0,
        n: n_samples,
        accel: [Vec::with_capacity(n_samples), Vec::with_capacity(n_samples)],
        cage: scene
            .outputs
            .cage_speed
            .then(|| Vec::with_capacity(n_samples)),
        cage_ecc: scene
            .outputs
            .cage_speed
            .then(|| Vec::with_capacity(n_samples)),
        inner: scene
            .outputs
            .inner_ring_displacement
            .then(|| std::array::from_fn(|_| Vec::with_capacity(n_samples))),
        loads: scene.outputs.contact_loads_ball.map(|k| {
            (
                k,
                Vec::with_capacity(n_samples),
                Vec::with_capacity(n_samples),
            )
        }),
        scratch_y: vec![0.0; n],
        scratch_f: vec![0.0; n],
        diag: Diagnostics::new(m.z),
    };

    // Steady window: after the ramp plus a settling time (the start-up transient of the
    // cage and the pedestal dies out within ~40 ms for the H7005C at 10000 rpm).
    let ramp = m.speed.2;
    let settle = (0.25 * (tend - ramp)).min(0.1);
    // A run that ends before the speed settles averages over its second half instead of
    // reporting an empty window.
    let w0 = if ramp + settle < tend {
        ramp + settle
    } else {
        0.5 * tend
    };
    let mut acc = Averages::new(m.z);

    let (scale, phase) = scales(m);
    let mut adaptive = AdaptiveRk4::new(n, sv.rtol, sv.atol, scale, phase);
    let mut fixed = FixedRk4::new(n);
    let is_fixed = sv.integrator == Integrator::Rk4Fixed;
    let mut h = sv.initial_step.min(tend);
    let h_min = 1e-14_f64.max(tend * 1e-13);
    let start = Instant::now();
    let mut last_report = Instant::now();
    let mut t = 0.0;
    rec.sample(m, t, 0.0, &y, &f, &y, &f);
    while t < tend {
        if let Some(c) = cancel {
            if c.load(Ordering::Relaxed) {
                return Err(SimError::Cancelled { at: t });
            }
        }
        let remaining = tend - t;
        let mut h_try = if is_fixed {
            sv.initial_step
        } else {
            h.min(sv.max_step).min(defect_step_bound(m, t, &y))
        };
        // land exactly on the end without a sliver step
        if h_try >= remaining * (1.0 - 1e-12) {
            h_try = remaining;
        } else if h_try > 0.5 * remaining {
            h_try = 0.5 * remaining;
        }
        let y_new: &[f64] = if is_fixed {
            fixed.step(&mut sys, t, &y, &f, h_try, &mut stats);
            &fixed.y_new
        } else {
            let err = adaptive.attempt(&mut sys, t, &y, &f, h_try, &mut stats);
            if !(err <= 1.0) {
                stats.rejected += 1;
                h = h_try * adaptive.reject_factor(err);
                if h < h_min {
                    return Err(SimError::Numerical {
                        time: t,
                        message: format!("step size underflow: h = {h:.3e} s below {h_min:.1e} s (error norm {err:.3e})"),
                    });
                }
                continue;
            }
            h = h_try * adaptive.accept_factor(err);
            &adaptive.y_new
        };
        y_next.copy_from_slice(y_new);
        let t_new = if h_try == remaining { tend } else { t + h_try };
        rhs(m, t_new, &y_next, &mut f_next, Some(&mut diag));
        stats.rhs_evals += 1;
        if let Some(i) = y_next
            .iter()
            .chain(f_next.iter())
            .position(|v| !v.is_finite())
        {
            return Err(SimError::Numerical {
                time: t_new,
                message: format!("non-finite state or derivative (component {} of {}) after a step of {h_try:.3e} s", i % n, n),
            });
        }
        stats.record(h_try);
        rec.sample(m, t, h_try, &y, &f, &y_next, &f_next);
        if t_new > w0 {
            let wgt = t_new - t.max(w0);
            acc.add(m, t_new, wgt, &y_next, &diag);
        }
        std::mem::swap(&mut y, &mut y_next);
        std::mem::swap(&mut f, &mut f_next);
        t = t_new;
        if let Some(p) = progress.as_deref_mut() {
            if last_report.elapsed().as_millis() >= 10 {
                last_report = Instant::now();
                p(t / tend);
            }
        }
    }
    if let Some(p) = progress.as_deref_mut() {
        p(1.0);
    }
    let wall = start.elapsed().as_secs_f64();
    let summary = acc.finish(
        m,
        [w0, tend],
        SolverStats {
            accepted_steps: stats.accepted,
            rejected_steps: stats.rejected,
            rhs_evaluations: stats.rhs_evals,
            min_step: stats.min_step,
            max_step: stats.max_step,
            wall_time: wall,
        },
    );
    Ok(SimResult {
        summary,
        channels: rec.finish(),
    })
}

impl Recorder {
    /// Record every output sample in `(t, t + h]` (or at t when h = 0).
    fn sample(
        &mut self,
        m: &Model,
        t: f64,
        h: f64,
        y0: &[f64],
        f0: &[f64],
        y1: &[f64],
        f1: &[f64],
    ) {
        let o = m.layout.outer;
        let c = m.layout.cage;
        let i = m.layout.inner;
        while self.next < self.n {
            let ts = self.next as f64 / self.fs;
            if ts > t + h + 1e-15 || (h == 0.0 && ts > t) {
                break;
            }
            let s = if h > 0.0 {
                ((ts - t) / h).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let interp = |k: usize| {
                if h > 0.0 {
                    hermite(y0[k], f0[k], y1[k], f1[k], h, s)
                } else {
                    y0[k]
                }
            };
            // The state is interpolated (cubic Hermite, 4th order) and the right-hand side
            // evaluated there: acceleration and contact loads are functions of the state,
            // so they come out as accurate as the state, whatever the step placement.
            // (Differentiating the interpolated velocity is only 2nd order and made the
            // band RMS depend on where the steps fell.)
            for k in 0..y0.len() {
                self.scratch_y[k] = interp(k);
            }
            rhs(
                m,
                ts,
                &self.scratch_y,
                &mut self.scratch_f,
                Some(&mut self.diag),
            );
            self.accel[0].push(self.scratch_f[o + 2]);
            self.accel[1].push(self.scratch_f[o + 3]);
            if let Some(v) = self.cage.as_mut() {
                v.push(interp(c + 9));
            }
            if let Some(v) = self.cage_ecc.as_mut() {
                // cage centre relative to its guiding ring (outer ring unless inner-land guided)
                let (gy, gz) = if m.land.is_some() && !m.land_on_outer {
                    (interp(i + 1), interp(i + 2))
                } else {
                    (interp(o), interp(o + 1))
                };
                let e = (interp(c + 1) - gy).hypot(interp(c + 2) - gz);
                v.push(m.land.as_ref().map_or(e, |l| e / l.clearance));
            }
            if let Some(v) = self.inner.as_mut() {
                for k in 0..3 {
                    v[k].push(interp(i + k));
                }
            }
            if let Some((ball, li, lo)) = self.loads.as_mut() {
                li.push(self.diag.inner_load[*ball]);
                lo.push(self.diag.outer_load[*ball]);
            }
            self.next += 1;
        }
    }

    fn finish(self) -> Channels {
        let mut ch = Vec::new();
        let [ay, az] = self.accel;
        ch.push(Channel {
            name: "outer_ring_accel_y".into(),
            unit: "m/s^2".into(),
            data: ay,
        });
        ch.push(Channel {
            name: "outer_ring_accel_z".into(),
            unit: "m/s^2".into(),
            data: az,
        });
        if let Some(v) = self.cage {
            ch.push(Channel {
                name: "cage_speed".into(),
                unit: "rad/s".into(),
                data: v,
            });
        }
        if let Some(v) = self.cage_ecc {
            ch.push(Channel {
                name: "cage_eccentricity".into(),
                unit: "-".into(),
                data: v,
            });
        }
        if let Some([x, y, z]) = self.inner {
            ch.push(Channel {
                name: "inner_ring_disp_x".into(),
                unit: "m".into(),
                data: x,
            });
            ch.push(Channel {
                name: "inner_ring_disp_y".into(),
                unit: "m".into(),
                data: y,
            });
            ch.push(Channel {
                name: "inner_ring_disp_z".into(),
                unit: "m".into(),
                data: z,
            });
        }
        if let Some((k, li, lo)) = self.loads {
            ch.push(Channel {
                name: format!("ball{k}_inner_load"),
                unit: "N".into(),
                data: li,
            });
            ch.push(Channel {
                name: format!("ball{k}_outer_load"),
                unit: "N".into(),
                data: lo,
            });
        }
        Channels {
            sample_rate: self.fs,
            start_time: 0.0,
            channels: ch,
        }
    }
}

/// Time-weighted sums over the steady window.
struct Averages {
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
    fn new(z: usize) -> Self {
        Averages {
            time: 0.0,
            shaft: 0.0,
            cage: 0.0,
            reaction: [0.0; 3],
            balls: ContactSums::new(z),
            zone: ContactSums::new(z),
        }
    }
    fn add(&mut self, m: &Model, t: f64, w: f64, y: &[f64], d: &Diagnostics) {
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
    fn finish(self, m: &Model, window: [f64; 2], stats: SolverStats) -> Summary {
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
        let epi = crate::quasi_static::rolling_kinematics(
            0.5 * m.pitch_diameter,
            ai,
            ao,
            0.5 * m.ball_diameter,
            shaft,
        )[0];
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
