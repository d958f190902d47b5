//! The cage speed at which one ball's run round its orbit, in a pocket turning with the
//! cage, leaves the cage no mean torque.
//!
//! The steady traction balance ([`super::cage_balance`]) holds every ball at the cage's
//! speed. In a running bearing a lightly loaded ball does not follow the cage: its orbital
//! speed relaxes towards its own rolling speed only over tens of milliseconds (the
//! traction's slope at a few newtons), so it drifts through its pocket's clearance and
//! presses on a face for part of the orbit only (docs/lab/paper-trends.md, "where the two
//! laws' cage slips differ"). Here one ball runs round its orbit at the quasi-static
//! positions of every azimuth, with its orbital speed and spin as states under the same
//! race, pocket and drag forces as the dynamic model (eqs. 19-22, 30, 32), in a concentric
//! pocket turning at a given cage speed; orbit after orbit until it repeats. The balls are
//! alike and evenly spaced, so the cage takes `Z` times one ball's mean pocket torque; the
//! cage speed is where that balances the land film's drag and the windage.

use super::cage_balance::drag_torque;
use crate::model::Model;
use crate::ode::block_jacobian::BlockJacobian;
use crate::ode::error_norm::ErrorNorm;
use crate::ode::problem::{JacobianSystem, OdeSystem};
use crate::ode::rosenbrock::Rosenbrock;
use crate::ode::solver::{Solver, StepLimits};
use crate::physics::cage_pocket::{pocket_contact, CageMotion};
use crate::physics::frames::Azimuth;
use crate::physics::race_contact::{race_contact, BallMotion, RingMotion};
use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// State slots of the one-ball problem.
const PHI: usize = 0;
const V: usize = 1;
const WX: usize = 2;
const WR: usize = 3;
const WT: usize = 4;
/// The time integral of the ball's pocket torque on the cage, N m s.
const TORQUE: usize = 5;
const N: usize = 6;

/// How the cycle is computed. The defaults are what `tests/engine_dynamics.rs`
/// (`pocket_cycle_is_converged_in_its_numerical_choices`) checks against tighter settings at
/// the paper's point under the preset's physics.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PocketCycleSettings {
    /// Error control of the one-ball integration, relative and absolute (the latter in units
    /// of each state's natural size), -. Default 1e-6: against 1e-7 it moved the curve's
    /// balanced cage speed at the paper's point by 5e-8 relative (2026-11-28, with the pocket
    /// at the mid-plane as first built) and, under the preset's physics (the rheology law
    /// with rolling resistance), by 2.7e-6 (2026-11-29).
    pub tolerance: f64,
    /// Orbits averaged per block where the ball's orbit does not repeat within 8, -. Default 8.
    pub block_orbits: u32,
    /// Cage speed the search starts from, rad/s; `None` for the steady balance's (or the
    /// epicyclic speed where that found none).
    pub start: Option<f64>,
    /// Accepted one-ball steps a whole search may take, -. Default 10 million: the preset's
    /// point at 10000 rpm needs about 0.14 million under the paper's curve and 1.1 million
    /// under the rheology law (2026-11-28), and the count grows with the orbit's period.
    /// Under the preset's physics (2026-11-29, release builds, a quiet machine) 2000 rpm took
    /// 9 s and fitted 3 million; 1000 rpm took 26-30 s and ran out of 3 million but not of 10
    /// (below 1000 rpm the preset has no quasi-static equilibrium at its loads). The budget
    /// bounds a search to about a minute; over HTTP the request's timeout stops it first.
    pub step_budget: u64,
}

impl PocketCycleSettings {
    /// Why these settings cannot run, naming the field: a zero or non-finite start would
    /// give an orbit of no or infinite period, on which the integration never ends.
    pub fn check(&self) -> Result<(), String> {
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(format!("tolerance {} must be positive", self.tolerance));
        }
        if self.block_orbits == 0 {
            return Err("block_orbits must be at least 1".into());
        }
        if let Some(c) = self.start {
            if !(c.is_finite() && c > 0.0) {
                return Err(format!("start {c} rad/s must be a positive cage speed"));
            }
        }
        if self.step_budget == 0 {
            return Err("step_budget must be at least 1".into());
        }
        Ok(())
    }
}

impl Default for PocketCycleSettings {
    fn default() -> Self {
        PocketCycleSettings {
            tolerance: 1e-6,
            block_orbits: 8,
            start: None,
            step_budget: 10_000_000,
        }
    }
}

/// The cage speed by the pocket cycle, and the torques the search met on the way.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct PocketCycle {
    /// Cage speed at which one ball's mean torque on its pocket over an orbit (an orbit
    /// that repeats, or the mean of blocks of 8 where none does), times the ball count,
    /// balances the land film's drag and the windage, rad/s.
    pub cage_speed: f64,
    /// Every cage speed tried (rad/s) with the net mean torque on the cage there (N m),
    /// in the order tried. Each trial starts from the ball's state at the end of the one
    /// before, so where the torque does not fall steadily with the speed the balance may
    /// not be unique, or the orbit may remember its history
    /// (docs/reference/model.md, "Cage speed by the pocket cycle").
    #[cfg_attr(feature = "openapi", schema(value_type = Vec<Vec<f64>>))]
    pub torque_curve: Vec<[f64; 2]>,
    /// Whether the torques of `torque_curve` fall as the cage speed rises (a rise within 1e-3
    /// of the land's and the windage's drag, what a trial's torque is known to, not counted).
    pub monotone: bool,
    /// Trial cage speeds whose orbits neither repeated within 8 orbits nor averaged out
    /// within 7 blocks (64 orbits at the default block), their torque the last block's mean, -.
    pub unsettled: u32,
    /// Orbits integrated in all, -.
    pub orbits: u32,
}

/// One ball round its orbit in a pocket turning at `cage` rad/s.
struct OneBall<'a> {
    m: &'a Model,
    inner: RingMotion,
    outer: RingMotion,
    /// Quasi-static ball centre (axial, radial; m) at azimuths `k TAU / grid.len()`.
    grid: &'a [[f64; 2]],
    cage: f64,
    /// Axial position of the cage's centre, m: the balls' mean (the pocket forces' axial
    /// parts centre a free cage on them).
    cage_axial: f64,
    scale: [f64; N],
}

impl OneBall<'_> {
    /// Centre (axial, radial; m) at azimuth `phi` and its derivative in `phi` (m/rad),
    /// interpolated linearly between grid points.
    fn place(&self, phi: f64) -> ([f64; 2], [f64; 2]) {
        let n = self.grid.len();
        let u = phi.rem_euclid(TAU) / TAU * n as f64;
        let k = (u.floor() as usize).min(n - 1);
        let f = u - k as f64;
        let (a, b) = (self.grid[k], self.grid[(k + 1) % n]);
        let d = n as f64 / TAU;
        (
            [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])],
            [(b[0] - a[0]) * d, (b[1] - a[1]) * d],
        )
    }

    fn eval(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let m = self.m;
        let (phi, v) = (y[PHI], y[V]);
        let az = Azimuth::new(phi);
        let ([x, r], [dx, dr]) = self.place(phi);
        let (er, et) = (az.e_r(), az.e_t());
        let ball = BallMotion {
            centre: Vector3::new(x, 0.0, 0.0) + r * er,
            velocity: Vector3::new(dx * v, 0.0, 0.0) + dr * v * er + r * v * et,
            omega: az.from_frame(&Vector3::new(y[WX], y[WR], y[WT])),
        };
        let ci = race_contact(&m.inner_race, &self.inner, &ball, &m.contact);
        let co = race_contact(&m.outer_race, &self.outer, &ball, &m.contact);
        let spin_angle = self.cage * t;
        let cage = CageMotion {
            centre: Vector3::new(self.cage_axial, 0.0, 0.0),
            velocity: Vector3::zeros(),
            rot: Matrix3::identity(),
            spin_angle,
            omega: Vector3::new(self.cage, 0.0, 0.0),
        };
        let pc = pocket_contact(
            &m.pocket,
            &cage,
            &Azimuth::new(spin_angle),
            &ball.centre,
            &ball.velocity,
            &ball.omega,
        );
        let mut f = ci.force_on_ball + co.force_on_ball + pc.force_on_ball;
        let mut mo = ci.moment_on_ball + co.moment_on_ball + pc.moment_on_ball;
        if let Some(drag) = &m.ball_drag {
            f += drag.force(&ball.velocity);
            mo += drag.moment(&ball.omega);
        }
        let fa = az.to_frame(&f);
        let ma = az.to_frame(&mo);
        let (mb, ib) = (m.ball_mass, m.ball_inertia);
        dy[PHI] = v;
        // eq. 30's orbital equation with its Coriolis term (the radius follows the azimuth)
        dy[V] = (fa.z - 2.0 * mb * dr * v * v) / (mb * r);
        // eq. 32 in the azimuth frame turning at v
        dy[WX] = ma.x / ib;
        dy[WR] = ma.y / ib + v * y[WT];
        dy[WT] = ma.z / ib - v * y[WR];
        dy[TORQUE] = pc.moment_on_cage.x;
    }
}

impl OdeSystem for OneBall<'_> {
    fn dim(&self) -> usize {
        N
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        self.eval(t, y, dy)
    }
}

impl JacobianSystem for OneBall<'_> {
    fn jacobian(&mut self, t: f64, y: &[f64], f0: &[f64], _h: f64, jac: &mut BlockJacobian) -> u64 {
        let scale = self.scale;
        jac.evaluate(t, y, f0, &scale, |t, y, dy| self.eval(t, y, dy));
        jac.cost_in_rhs() as u64
    }
}

/// How a search computes, what it may still spend, and whether its caller has stopped
/// waiting.
struct Search<'a> {
    settings: &'a PocketCycleSettings,
    steps_left: u64,
    stop: &'a dyn Fn() -> bool,
}

/// The mean torque (N m) one ball puts on the cage over one orbit, from `y` (advanced to
/// the orbit's end, its azimuth wrapped and its torque integral reset).
fn orbit_torque(ob: &mut OneBall, y: &mut [f64; N], search: &mut Search) -> Result<f64, String> {
    let period = TAU / ob.cage;
    // the azimuth and the torque integral are measured against their scales, not their size
    let unbounded = vec![true, false, false, false, false, true];
    let tol = search.settings.tolerance;
    let norm = ErrorNorm::new(tol, tol, ob.scale.to_vec(), unbounded);
    // the traction's and the pocket's stiffness act on the ball's speeds and azimuth; the
    // torque integral feeds nothing back
    let jac = BlockJacobian::partial(vec![0..5, 5..6], (0..5).map(|c| vec![c]).collect());
    let limits = StepLimits {
        t_end: period,
        initial_step: period * 1e-4,
        max_step: period / 400.0,
        min_step: period * 1e-12,
    };
    let mut solver = Solver::new(ob, Rosenbrock::new(N, norm, jac), y.to_vec(), limits);
    while !solver.finished() {
        solver.step(ob).map_err(|e| e.to_string())?;
        search.steps_left = search.steps_left.checked_sub(1).ok_or_else(|| {
            format!(
                "no settled cycle within {} integration steps of the ball",
                search.settings.step_budget
            )
        })?;
        if search.steps_left.is_multiple_of(1024) && (search.stop)() {
            return Err("stopped".into());
        }
    }
    y.copy_from_slice(solver.y());
    let mean = y[TORQUE] / period;
    y[PHI] = wrap(y[PHI] - TAU);
    y[TORQUE] = 0.0;
    Ok(mean)
}

fn wrap(a: f64) -> f64 {
    let x = a.rem_euclid(TAU);
    if x > 0.5 * TAU {
        x - TAU
    } else {
        x
    }
}

/// Net mean torque on the cage at `cage` rad/s once the ball's orbit repeats (N m), and the
/// orbits that took; `y` carries the ball's state from one call to the next.
fn net_torque(
    m: &Model,
    inner: &RingMotion,
    outer: &RingMotion,
    grid: &[[f64; 2]],
    cage: f64,
    y: &mut [f64; N],
    search: &mut Search,
) -> Result<(f64, u32, bool), String> {
    let w_scale = inner.spin.abs().max(1.0) * 3.0;
    let mut ob = OneBall {
        m,
        inner: *inner,
        outer: *outer,
        grid,
        cage,
        cage_axial: grid.iter().map(|p| p[0]).sum::<f64>() / grid.len() as f64,
        scale: [1e-3, cage.abs().max(1.0), w_scale, w_scale, w_scale, 1e-6],
    };
    let resist = drag_torque(m, inner, outer, cage);
    let z = m.z as f64;
    // a periodic orbit: successive orbits' means agree to 1e-4 of the drag per ball (or of
    // the first orbit's torque where the scene has no drag)
    let first = orbit_torque(&mut ob, y, search)?;
    let tol = 1e-4 * resist.abs().max(z * first.abs()).max(1e-12) / z;
    let mut last = first;
    for k in 2..=8 {
        let t = orbit_torque(&mut ob, y, search)?;
        if (t - last).abs() <= tol {
            return Ok((z * t + resist, k, true));
        }
        last = t;
    }
    // none within 8 orbits (the ball meets a face on some orbits and not on others): the
    // mean over blocks of orbits, until two blocks agree to 1e-3 of the drag
    let mut last_block = f64::NAN;
    let mut orbits = 8;
    let block = search.settings.block_orbits;
    for _ in 0..7 {
        let mut sum = 0.0;
        for _ in 0..block {
            sum += orbit_torque(&mut ob, y, search)?;
        }
        orbits += block;
        let mean = sum / f64::from(block);
        if (mean - last_block).abs() <= 10.0 * tol {
            return Ok((z * mean + resist, orbits, true));
        }
        last_block = mean;
    }
    Ok((z * last_block + resist, orbits, false))
}

/// The cage speed where [`net_torque`] vanishes, from the start `cage0` (rad/s; the steady
/// balance's, or the epicyclic speed where that found none, unless `settings` name one)
/// and ball spin `w0` (azimuth frame, rad/s) at azimuth 0: bracketed in steps of 0.2 % of
/// `cage0`, then by the Illinois method to 1e-6 of it; `stop` is asked before each trial
/// and every 1024 steps, and the search gives up after the settings' step budget.
#[allow(clippy::too_many_arguments)]
pub(super) fn pocket_cycle(
    m: &Model,
    inner: &RingMotion,
    outer: &RingMotion,
    grid: &[[f64; 2]],
    cage0: f64,
    w0: [f64; 3],
    settings: &PocketCycleSettings,
    stop: &dyn Fn() -> bool,
) -> Result<PocketCycle, String> {
    let cage0 = settings.start.unwrap_or(cage0);
    // centred in its pocket at azimuth 0, orbiting with the cage
    let mut y = [0.0, cage0, w0[0], w0[1], w0[2], 0.0];
    let mut curve: Vec<[f64; 2]> = Vec::new();
    let mut orbits = 0;
    let mut unsettled = 0;
    let mut search = Search {
        settings,
        steps_left: settings.step_budget,
        stop,
    };
    let mut eval = |c: f64, y: &mut [f64; N]| -> Result<f64, String> {
        if stop() {
            return Err("stopped".into());
        }
        let (t, k, settled) = net_torque(m, inner, outer, grid, c, y, &mut search)?;
        if !t.is_finite() {
            return Err(format!("the mean torque at {c} rad/s is not finite"));
        }
        orbits += k;
        unsettled += u32::from(!settled);
        curve.push([c, t]);
        Ok(t)
    };
    let step = 2e-3 * cage0;
    let (mut a, mut fa) = (cage0, eval(cage0, &mut y)?);
    // a positive torque speeds the cage up: look above, else below
    let dir = if fa > 0.0 { 1.0 } else { -1.0 };
    let (mut b, mut fb) = (a + dir * step, eval(a + dir * step, &mut y)?);
    let mut tries = 0;
    // (an exact zero ends the bracket too: signum(0.0) is 1)
    while fa.signum() == fb.signum() && fa != 0.0 && fb != 0.0 {
        tries += 1;
        if tries > 20 {
            return Err(format!(
                "no balance within {:.1} % of the start's {cage0:.3} rad/s",
                100.0 * 21.0 * step / cage0
            ));
        }
        (a, fa) = (b, fb);
        b += dir * step;
        fb = eval(b, &mut y)?;
    }
    // Illinois: the secant, halving the retained end's value when one end keeps its place
    let mut side = 0;
    let mut prev = f64::NAN;
    let mut c = 0.5 * (a + b);
    let mut converged = false;
    for _ in 0..40 {
        c = (a * fb - b * fa) / (fb - fa);
        // the secant has stopped moving, or the bracket has closed
        if (c - prev).abs() < 1e-6 * cage0 || (b - a).abs() < 1e-6 * cage0 {
            converged = true;
            break;
        }
        prev = c;
        let fc = eval(c, &mut y)?;
        if fc == 0.0 {
            converged = true;
            break;
        }
        if fc.signum() == fb.signum() {
            (b, fb) = (c, fc);
            if side == -1 {
                fa *= 0.5;
            }
            side = -1;
        } else {
            (a, fa) = (c, fc);
            if side == 1 {
                fb *= 0.5;
            }
            side = 1;
        }
    }
    if !converged {
        return Err(format!(
            "the root between {a:.4} and {b:.4} rad/s did not converge in 40 steps"
        ));
    }
    // a trial's torque is known to about 1e-3 of the drag (its orbits' agreement): smaller
    // rises are not counted
    let drag = drag_torque(m, inner, outer, c);
    let mut sorted = curve.clone();
    sorted.sort_by(|p, q| p[0].total_cmp(&q[0]));
    let monotone = sorted
        .windows(2)
        .all(|w| w[1][1] <= w[0][1] + 1e-3 * drag.abs());
    Ok(PocketCycle {
        cage_speed: c,
        torque_curve: curve,
        monotone,
        unsettled,
        orbits,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settings_that_cannot_run_are_refused_by_name() {
        let ok = PocketCycleSettings::default();
        assert_eq!(ok.check(), Ok(()));
        for (bad, field) in [
            (
                PocketCycleSettings {
                    start: Some(0.0),
                    ..ok
                },
                "start",
            ),
            (
                PocketCycleSettings {
                    start: Some(f64::NAN),
                    ..ok
                },
                "start",
            ),
            (
                PocketCycleSettings {
                    start: Some(-440.0),
                    ..ok
                },
                "start",
            ),
            (
                PocketCycleSettings {
                    tolerance: 0.0,
                    ..ok
                },
                "tolerance",
            ),
            (
                PocketCycleSettings {
                    tolerance: f64::INFINITY,
                    ..ok
                },
                "tolerance",
            ),
            (
                PocketCycleSettings {
                    block_orbits: 0,
                    ..ok
                },
                "block_orbits",
            ),
            (
                PocketCycleSettings {
                    step_budget: 0,
                    ..ok
                },
                "step_budget",
            ),
        ] {
            let e = bad.check().unwrap_err();
            assert!(e.contains(field), "{bad:?}: {e}");
        }
    }
}
