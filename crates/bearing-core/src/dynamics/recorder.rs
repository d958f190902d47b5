//! Uniform output sampling: the state is interpolated at every output instant inside a
//! step (cubic Hermite, with what the method interpolates better itself overwritten:
//! `Method::refine_dense`) and the forces the channels read (the pedestal rows of the right-hand side and,
//! when asked for, one ball's contact loads) evaluated there.

use super::ball_equilibrium::BalanceTrack;
use super::output::{Channel, Channels};
use super::rhs::{output_forces, pocket_offset};
use crate::model::layout::{ball, cage};
use crate::model::Model;
use crate::ode::hermite::hermite;
use crate::physics::defect::wrap_angle;
use crate::scene::Outputs;

/// Which channels to record and how.
pub struct Recorder {
    fs: f64,
    next: usize,
    n: usize,
    accel: [Vec<f64>; 2],
    cage: Option<Vec<f64>>,
    cage_ecc: Option<Vec<f64>>,
    inner: Option<[Vec<f64>; 3]>,
    loads: Option<(usize, Vec<f64>, Vec<f64>)>,
    /// Ball index, then its azimuth (rad), its orbital speed less the cage's (rad/s) and
    /// its offset in its pocket (m).
    pocket: Option<(usize, [Vec<f64>; 3])>,
    scratch_y: Vec<f64>,
}

impl Recorder {
    /// Channels for `outputs`, sampled at `fs` (Hz) from 0 to `tend` (s).
    pub fn new(m: &Model, outputs: &Outputs, fs: f64, tend: f64) -> Recorder {
        let n_samples = (tend * fs).floor() as usize + 1;
        let n = m.layout.len;
        Recorder {
            fs,
            next: 0,
            n: n_samples,
            accel: [Vec::with_capacity(n_samples), Vec::with_capacity(n_samples)],
            cage: outputs.cage_speed.then(|| Vec::with_capacity(n_samples)),
            cage_ecc: outputs.cage_speed.then(|| Vec::with_capacity(n_samples)),
            inner: outputs
                .inner_ring_displacement
                .then(|| std::array::from_fn(|_| Vec::with_capacity(n_samples))),
            loads: outputs.contact_loads_ball.map(|k| {
                (
                    k,
                    Vec::with_capacity(n_samples),
                    Vec::with_capacity(n_samples),
                )
            }),
            pocket: outputs
                .ball_pocket
                .map(|k| (k, std::array::from_fn(|_| Vec::with_capacity(n_samples)))),
            scratch_y: vec![0.0; n],
        }
    }

    /// Record every output sample in `(t, t + h]` (or at t when h = 0). `refine`, given
    /// the fraction of the step and the state interpolated there, may overwrite the
    /// components the method that took the step interpolates better itself.
    #[allow(clippy::too_many_arguments)]
    pub fn sample(
        &mut self,
        m: &Model,
        t: f64,
        h: f64,
        y0: &[f64],
        f0: &[f64],
        y1: &[f64],
        f1: &[f64],
        track: Option<&BalanceTrack>,
        refine: &dyn Fn(f64, &mut [f64]) -> bool,
    ) {
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
            if h > 0.0 {
                refine(s, &mut self.scratch_y);
            }
            if track.is_some() && m.quasi_static_balls {
                // `track` describes the balance at the step's end: start from it there
                for j in 0..m.z {
                    let b = m.layout.ball(j);
                    self.scratch_y[b + ball::X] = y1[b + ball::X];
                    self.scratch_y[b + ball::R] = y1[b + ball::R];
                }
            }
            // Only the forces the channels read: the outer ring's, and the one ball's
            // contact loads when asked for (the same values as the whole right-hand side's,
            // for about half the work).
            let out = output_forces(
                m,
                ts,
                &self.scratch_y,
                track,
                self.loads.as_ref().map(|l| l.0),
            );
            let [ay, az] = out.accel;
            self.accel[0].push(ay);
            self.accel[1].push(az);
            if let Some(v) = self.cage.as_mut() {
                v.push(interp(c + cage::W_X));
            }
            if let Some(v) = self.cage_ecc.as_mut() {
                v.push(m.cage_offset(&self.scratch_y).1);
            }
            if let Some(v) = self.inner.as_mut() {
                for (k, vk) in v.iter_mut().enumerate() {
                    vk.push(interp(i + k));
                }
            }
            if let Some((_, li, lo)) = self.loads.as_mut() {
                li.push(out.ball_loads[0]);
                lo.push(out.ball_loads[1]);
            }
            if let Some((k, [azimuth, lead, offset])) = self.pocket.as_mut() {
                let b = m.layout.ball(*k);
                azimuth.push(wrap_angle(self.scratch_y[b + ball::THETA]));
                lead.push(self.scratch_y[b + ball::THETA_DOT] - self.scratch_y[c + cage::W_X]);
                offset.push(pocket_offset(m, ts, &self.scratch_y, *k));
            }
            self.next += 1;
        }
    }

    pub fn finish(self) -> Channels {
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
        if let Some((k, [azimuth, lead, offset])) = self.pocket {
            for (name, unit, data) in [
                ("azimuth", "rad", azimuth),
                ("cage_lead", "rad/s", lead),
                ("pocket_offset", "m", offset),
            ] {
                ch.push(Channel {
                    name: format!("ball{k}_{name}"),
                    unit: unit.into(),
                    data,
                });
            }
        }
        Channels {
            sample_rate: self.fs,
            start_time: 0.0,
            channels: ch,
        }
    }
}
