//! Where the bearing's stiffness is (issue 34): the eigenvalues of the right-hand side's
//! Jacobian at a state of a run, and of what is left of it when chosen diagonal blocks are
//! taken out, as an integrator exact on those blocks (implicit in them, or by their
//! exponential) would take them. The largest magnitude left indicates the step an explicit
//! method would be stable at on the rest, RK4 about [`RK4_STABILITY`] / |lambda|: an
//! indication, not a bound, since how the explicit rest couples to the exact blocks is not
//! in it (and with every diagonal block out the trace is zero, so some eigenvalues left have
//! positive real parts).
//!
//! A lab tool, like the stress suite and behind the same feature: `bearing-sim bench
//! stiffness` prints it. Full fidelity only: a reduced level's algebraic slots have no rows.

use crate::dynamics::error_scale::scales;
use crate::dynamics::rhs::rhs;
use crate::dynamics::run::step_limits;
use crate::dynamics::system::{ball_velocity_block, body_blocks, BearingSystem};
use crate::model::Model;
use crate::ode::error::SolveError;
use crate::ode::error_norm::ErrorNorm;
use crate::ode::explicit_rk::ExplicitRk;
use crate::ode::solver::Solver;
use crate::ode::tableau::RK4_FSAL;
use crate::quasi_static::{initial_state, solve_model};
use crate::scene::{Fidelity, ValidScene};
use crate::simulation::SimError;
use nalgebra::{Complex, DMatrix};
use std::ops::Range;

/// RK4's stability boundary, one figure for the imaginary axis (`2 sqrt 2`) and the
/// negative real axis (2.785): `h |lambda|` up to about this is stable there, -. Between the
/// axes the boundary dips to about 2.6, so a step from it may be up to 7 % optimistic.
pub const RK4_STABILITY: f64 = 2.8;

/// Which diagonal blocks are taken out of the Jacobian.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Removed {
    /// Nothing: the whole Jacobian.
    Nothing,
    /// Each ball's velocities on each other (axial, radial and orbital speed, three spin
    /// components): the balls' part of what `slip_implicit` takes implicitly (it also takes
    /// the cage's land film where that is stiff). Its damping goes with it: what is left of
    /// a contact mode is undamped.
    BallVelocities,
    /// Each ball's whole block (positions, velocities and spins).
    Balls,
    /// Every body's block: each ball, the inner ring, the outer ring, the cage.
    Bodies,
}

impl Removed {
    pub const ALL: [Removed; 4] = [
        Removed::Nothing,
        Removed::BallVelocities,
        Removed::Balls,
        Removed::Bodies,
    ];

    /// The blocks of a model's state this takes out: the solver's own
    /// (`dynamics::system`), so the two cannot drift apart.
    fn blocks(self, m: &Model) -> Vec<Range<usize>> {
        let balls = 0..m.layout.balls;
        match self {
            Removed::Nothing => vec![],
            Removed::BallVelocities => balls.map(|j| ball_velocity_block(m, j)).collect(),
            Removed::Balls => body_blocks(m).into_iter().take(m.layout.balls).collect(),
            Removed::Bodies => body_blocks(m),
        }
    }
}

/// The eigenvalues of what is left of the Jacobian once `removed`'s blocks are out,
/// largest magnitude first, 1/s.
#[derive(Debug, Clone)]
pub struct PartSpectrum {
    pub removed: Removed,
    pub largest: Vec<Complex<f64>>,
}

/// The spectra at one state of a run.
#[derive(Debug, Clone)]
pub struct StiffnessReport {
    /// Time of the state, s.
    pub t: f64,
    /// Its Jacobian, `d f_i / d y_j`, by central differences.
    pub jacobian: DMatrix<f64>,
    /// The largest eigenvalues of the Jacobian, whole and with each [`Removed`] part taken
    /// out, in [`Removed::ALL`]'s order.
    pub parts: Vec<PartSpectrum>,
}

/// Why there is no spectrum.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StiffnessError {
    #[error("solver.fidelity: the spectrum needs the full model (a reduced level's algebraic slots have no rows), got {0:?}")]
    ReducedFidelity(Fidelity),
    #[error(transparent)]
    Run(#[from] SimError),
    #[error("the Jacobian at t = {0} s has a non-finite entry")]
    NonFinite(f64),
}

/// The state of `scene`'s run at `t` (s; 0 for its initial state), reached with `rk4_fsal`
/// at the scene's tolerances, and the `count` largest eigenvalues of each part of its
/// Jacobian.
pub fn stiffness_at(
    scene: &ValidScene,
    t: f64,
    count: usize,
) -> Result<StiffnessReport, StiffnessError> {
    if scene.solver.fidelity != Fidelity::Full {
        return Err(StiffnessError::ReducedFidelity(scene.solver.fidelity));
    }
    let m = Model::new(scene);
    let qs = solve_model(&m, m.shaft_speed(0.0)).map_err(SimError::from)?;
    let y = state_at(&m, scene, initial_state(&m, &qs), t).map_err(SimError::from)?;
    let (scale, _) = scales(&m);
    let jacobian = central_jacobian(&m, t, &y, &scale);
    // (nalgebra's Schur iteration has no iteration limit: a NaN would never converge)
    if jacobian.iter().any(|v| !v.is_finite()) {
        return Err(StiffnessError::NonFinite(t));
    }
    // the eigenvalues of D^-1 J D (D the natural sizes) are J's, and its entries are closer
    // in size (rates per natural size), which the Schur iteration, without balancing of its
    // own, needs for accuracy; taking a diagonal block out of it takes the same out of J
    let balanced = DMatrix::from_fn(jacobian.nrows(), jacobian.ncols(), |i, j| {
        jacobian[(i, j)] * scale[j] / scale[i]
    });
    let parts = Removed::ALL
        .into_iter()
        .map(|removed| {
            let mut left = balanced.clone();
            for b in removed.blocks(&m) {
                left.view_mut((b.start, b.start), (b.len(), b.len()))
                    .fill(0.0);
            }
            let mut largest: Vec<Complex<f64>> =
                left.complex_eigenvalues().iter().copied().collect();
            largest.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
            largest.truncate(count);
            PartSpectrum { removed, largest }
        })
        .collect();
    Ok(StiffnessReport { t, jacobian, parts })
}

fn state_at(m: &Model, scene: &ValidScene, y0: Vec<f64>, t: f64) -> Result<Vec<f64>, SolveError> {
    if t <= 0.0 {
        return Ok(y0);
    }
    let sv = &scene.solver;
    let (scale, phase) = scales(m);
    let mut sys = BearingSystem::new(m, &scale);
    let norm = ErrorNorm::new(sv.rtol, sv.atol, scale.clone(), phase);
    let method = ExplicitRk::adaptive(&RK4_FSAL, m.layout.len, norm);
    let mut solver = Solver::new(&mut sys, method, y0, step_limits(scene, t));
    while !solver.finished() {
        solver.step(&mut sys)?;
    }
    Ok(solver.y().to_vec())
}

/// `d f / d y` at `(t, y)` by central differences, each component moved by 1e-7 of its
/// natural size (`scale`, the error norm's; on the H7005C at 10000 rpm 0.28 nm for a
/// length, 1.9 um/s for a speed, 7e-4 rad/s for an angular velocity), small beside a loaded
/// contact's deflection (micrometres) and the slip over which the traction law bends
/// (millimetres per second). Divided by the increment actually represented, so a large
/// angle (the orbit's, after seconds) costs accuracy, not a wrong scale: the spectrum's
/// questions are factors of two.
fn central_jacobian(m: &Model, t: f64, y: &[f64], scale: &[f64]) -> DMatrix<f64> {
    let n = y.len();
    let mut jac = DMatrix::zeros(n, n);
    let (mut yp, mut fp, mut fm) = (y.to_vec(), vec![0.0; n], vec![0.0; n]);
    for k in 0..n {
        let d = 1e-7 * scale[k];
        let (up, down) = (y[k] + d, y[k] - d);
        yp[k] = up;
        rhs(m, t, &yp, &mut fp, None);
        yp[k] = down;
        rhs(m, t, &yp, &mut fm, None);
        yp[k] = y[k];
        for i in 0..n {
            jac[(i, k)] = (fp[i] - fm[i]) / (up - down);
        }
    }
    jac
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::rhs::Diagnostics;
    use crate::model::layout::{ball, CAGE};
    use crate::scene::{fault_case_scene, FaultCase};

    fn preset() -> ValidScene {
        fault_case_scene("h7005c", FaultCase::None)
            .expect("preset")
            .validated()
            .expect("valid")
    }

    /// The preset's initial state, its Jacobian, and its most loaded ball with the two
    /// contacts' stiffnesses `k = dQ/d delta = 1.5 K^(2/3) Q^(1/3)` (`Q = K delta^1.5`), N/m.
    fn start() -> (Model, Vec<f64>, DMatrix<f64>, usize, [f64; 2]) {
        let m = Model::new(&preset());
        let qs = solve_model(&m, m.shaft_speed(0.0)).expect("equilibrium");
        let y = initial_state(&m, &qs);
        let (scale, _) = scales(&m);
        let jac = central_jacobian(&m, 0.0, &y, &scale);
        let mut diag = Diagnostics::new(m.z);
        rhs(&m, 0.0, &y, &mut vec![0.0; y.len()], Some(&mut diag));
        let j = (0..m.z)
            .max_by(|a, b| diag.inner_load[*a].total_cmp(&diag.inner_load[*b]))
            .expect("balls");
        let spring = |q: f64, k: f64| 1.5 * k.powf(2.0 / 3.0) * q.cbrt();
        let k = [
            spring(diag.inner_load[j], m.inner_race.hertz.k),
            spring(diag.outer_load[j], m.outer_race.hertz.k),
        ];
        (m, y, jac, j, k)
    }

    /// The most loaded ball's axial-radial block of the Jacobian rings at the ball between
    /// its two Hertz springs, `sqrt((k_i + k_o) / m)`, lowered by the contacts' damping to
    /// `sqrt(1 - zeta^2)` of it, `zeta` being each contact's ratio times `(sqrt k_i + sqrt
    /// k_o) / sqrt(k_i + k_o)` (each contact is damped at `2 zeta sqrt(k m)` of its own
    /// stiffness): 0.25 % at the preset's 0.05. Within 1e-4: the contact lines' turning as
    /// the ball moves (`Q / ((f_i + f_o - 1) D)`, 0.25 % of the pair's stiffness) and the
    /// ball's lateral stiffness between the curvature centres (about 1 %) act across the
    /// contact line, so they move the frequency at second order; the traction's position
    /// terms are smaller. Measured: 6e-8 apart (ball 0 at 82.9 N, 2026-11-29).
    #[test]
    fn a_loaded_balls_contact_mode_is_the_ball_between_its_two_hertz_springs() {
        let (m, _, jac, j, [ki, ko]) = start();
        let zeta = m.contact.damping_ratio * (ki.sqrt() + ko.sqrt()) / (ki + ko).sqrt();
        let expected = ((ki + ko) / m.ball_mass).sqrt() * (1.0 - zeta * zeta).sqrt();
        let b = m.layout.ball(j);
        let slots = [b + ball::X, b + ball::R, b + ball::X_DOT, b + ball::R_DOT];
        let block = DMatrix::from_fn(4, 4, |r, c| jac[(slots[r], slots[c])]);
        let ringing = block
            .complex_eigenvalues()
            .iter()
            .map(|l| l.im.abs())
            .fold(0.0, f64::max);
        assert!(
            (ringing / expected - 1.0).abs() < 1e-4,
            "ball {j}: {ringing:.6e} rad/s against {expected:.6e}"
        );
    }

    /// What each part leaves at the preset's start (1000 rpm): the whole Jacobian's largest
    /// eigenvalue is real and negative (the balls' slip relaxation); with the balls'
    /// velocity blocks out, the largest left is the most loaded ball's contact mode,
    /// undamped (its damping went with the velocity block): `sqrt((k_i + k_o) / m)` within
    /// 1 %, for the rings' share in the motion (each several times a ball's mass) and the
    /// across-line terms of the test above (measured 0.04 %, 2026-11-29); with every body's
    /// block out, under a tenth of the whole's magnitude is left, the stiffness being local to
    /// the bodies (the block Jacobian's premise; measured 2.4 %). Largest first in each part.
    #[test]
    fn the_parts_leave_the_slip_then_the_contact_mode_then_the_couplings() {
        let (m, _, _, _, [ki, ko]) = start();
        let report = stiffness_at(&preset(), 0.0, 4).expect("runs");
        let top = |r: Removed| {
            let part = report.parts.iter().find(|p| p.removed == r).expect("part");
            assert!(part.largest.windows(2).all(|w| w[0].norm() >= w[1].norm()));
            part.largest[0]
        };
        let whole = top(Removed::Nothing);
        assert!(
            whole.re < 0.0 && whole.im.abs() <= 1e-6 * whole.re.abs(),
            "{whole}"
        );
        let contact = top(Removed::BallVelocities);
        let undamped = ((ki + ko) / m.ball_mass).sqrt();
        assert!(
            (contact.im.abs() / undamped - 1.0).abs() < 0.01 && contact.re.abs() < 1e-3 * undamped,
            "{contact} against {undamped:.4e} rad/s"
        );
        let left = top(Removed::Bodies).norm();
        assert!(left < 0.1 * whole.norm(), "{left:.3e} left of {whole}");
    }

    /// On the Table-1 ramp (0.05 s, 5500 rpm) the stiffest mode each ball's block leaves is
    /// the cage's (its land film; `slip_implicit` takes it implicitly where it is stiff):
    /// with the cage's block out as well, less than a third of it is left (measured 3.80e5
    /// 1/s, then 3.36e4, 2026-11-29). Reached by running there, the path the bench's
    /// default times take.
    #[test]
    fn on_the_ramp_the_cage_holds_what_the_balls_blocks_leave() {
        let scene = preset();
        let report = stiffness_at(&scene, 0.05, 1).expect("runs");
        let balls_out = report
            .parts
            .iter()
            .find(|p| p.removed == Removed::Balls)
            .expect("part")
            .largest[0]
            .norm();
        let m = Model::new(&scene);
        let c = m.layout.cage;
        let mut left = report.jacobian.clone();
        for b in Removed::Balls.blocks(&m).into_iter().chain([c..c + CAGE]) {
            left.view_mut((b.start, b.start), (b.len(), b.len()))
                .fill(0.0);
        }
        let cage_out = left
            .complex_eigenvalues()
            .iter()
            .map(|l| l.norm())
            .fold(0.0, f64::max);
        assert!(
            cage_out < balls_out / 3.0,
            "{cage_out:.3e} left of {balls_out:.3e}"
        );
    }
}
