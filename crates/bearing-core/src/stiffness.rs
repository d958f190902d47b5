//! Where the bearing's stiffness is (issue 34): the eigenvalues of the right-hand side's
//! Jacobian at a state of a run, and of what is left of it when chosen diagonal blocks are
//! taken out, as an integrator exact on those blocks (implicit in them, or by their
//! exponential) would take them. The largest magnitude left bounds the step an explicit
//! method is stable at: RK4 about [`RK4_STABILITY`] / |lambda|.
//!
//! A lab tool, like the stress suite and behind the same feature: `bearing-sim bench
//! stiffness` prints it. Full fidelity (a reduced level's algebraic slots have no rows).

use crate::dynamics::error_scale::scales;
use crate::dynamics::rhs::rhs;
use crate::dynamics::system::BearingSystem;
use crate::model::layout::{ball, BALL, CAGE, INNER, OUTER};
use crate::model::Model;
use crate::ode::error::SolveError;
use crate::ode::error_norm::ErrorNorm;
use crate::ode::explicit_rk::ExplicitRk;
use crate::ode::solver::{Solver, StepLimits};
use crate::ode::tableau::RK4_FSAL;
use crate::quasi_static::{initial_state, solve_model};
use crate::scene::ValidScene;
use crate::simulation::SimError;
use nalgebra::{Complex, DMatrix};
use std::ops::Range;

/// RK4's stability boundary, one figure for the imaginary axis (`2 sqrt 2`) and the
/// negative real axis (2.785): `h |lambda|` up to about this is stable, -.
pub const RK4_STABILITY: f64 = 2.8;

/// Which diagonal blocks are taken out of the Jacobian.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Removed {
    /// Nothing: the whole Jacobian.
    Nothing,
    /// Each ball's velocities on each other (axial, radial and orbital speed, three spin
    /// components): what `slip_implicit` takes implicitly.
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

    /// The blocks of a model's state this takes out.
    fn blocks(self, m: &Model) -> Vec<Range<usize>> {
        let l = &m.layout;
        let balls = (0..l.balls).map(|j| l.ball(j));
        match self {
            Removed::Nothing => vec![],
            Removed::BallVelocities => balls.map(|b| b + ball::X_DOT..b + BALL).collect(),
            Removed::Balls => balls.map(|b| b..b + BALL).collect(),
            Removed::Bodies => balls
                .map(|b| b..b + BALL)
                .chain([
                    l.inner..l.inner + INNER,
                    l.outer..l.outer + OUTER,
                    l.cage..l.cage + CAGE,
                ])
                .collect(),
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
    pub parts: Vec<PartSpectrum>,
}

/// The state of `scene`'s run at `t` (s; 0 for its initial state), reached with `rk4_fsal`
/// at the scene's tolerances, and the `count` largest eigenvalues of each part of its
/// Jacobian.
pub fn stiffness_at(scene: &ValidScene, t: f64, count: usize) -> Result<StiffnessReport, SimError> {
    let m = Model::new(scene);
    let qs = solve_model(&m, m.shaft_speed(0.0))?;
    let y = state_at(&m, scene, initial_state(&m, &qs), t)?;
    let (scale, _) = scales(&m);
    let jacobian = central_jacobian(&m, t, &y, &scale);
    let parts = Removed::ALL
        .into_iter()
        .map(|removed| {
            let mut left = jacobian.clone();
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
    let limits = StepLimits {
        t_end: t,
        initial_step: sv.initial_step,
        max_step: sv.max_step,
        min_step: 1e-14_f64.max(t * 1e-13),
    };
    let mut solver = Solver::new(&mut sys, method, y0, limits);
    while !solver.finished() {
        solver.step(&mut sys)?;
    }
    Ok(solver.y().to_vec())
}

/// `d f / d y` at `(t, y)` by central differences, each component moved by 1e-7 of its
/// natural size (`scale`, the error norm's: 0.35 nm for a length, 2 um/s for a speed of the
/// H7005C at 10000 rpm), small beside a loaded contact's deflection (micrometres) and the
/// slip over which the traction law bends (millimetres per second), and large enough that
/// rounding stays near 1e-9 of a derivative: the spectrum's questions are factors of two.
fn central_jacobian(m: &Model, t: f64, y: &[f64], scale: &[f64]) -> DMatrix<f64> {
    let n = y.len();
    let mut jac = DMatrix::zeros(n, n);
    let (mut yp, mut fp, mut fm) = (y.to_vec(), vec![0.0; n], vec![0.0; n]);
    for k in 0..n {
        let d = 1e-7 * scale[k];
        yp[k] = y[k] + d;
        rhs(m, t, &yp, &mut fp, None);
        yp[k] = y[k] - d;
        rhs(m, t, &yp, &mut fm, None);
        yp[k] = y[k];
        for i in 0..n {
            jac[(i, k)] = (fp[i] - fm[i]) / (2.0 * d);
        }
    }
    jac
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::rhs::Diagnostics;
    use crate::scene::{fault_case_scene, FaultCase};

    fn preset() -> ValidScene {
        fault_case_scene("h7005c", FaultCase::None)
            .expect("preset")
            .validated()
            .expect("valid")
    }

    /// The most loaded ball's axial-radial block of the Jacobian rings at the ball between
    /// its two Hertz springs: `sqrt((k_i + k_o) / m)` with `k = dQ/d delta = 1.5 K^(2/3)
    /// Q^(1/3)` (`Q = K delta^1.5`), lowered by the contacts' damping to `sqrt(1 - zeta^2)` of
    /// it, `zeta` being each contact's ratio times `(sqrt k_i + sqrt k_o) / sqrt(k_i + k_o)`
    /// (each contact is damped at `2 zeta sqrt(k m)` of its own stiffness): 0.25 % at the
    /// preset's 0.05. Within 0.1 %: the contact lines' turning as the ball moves adds a
    /// stiffness of about `Q / ((f_i + f_o - 1) D)`, 0.1 % of the contacts' and across them
    /// (under 0.05 % of the frequency), and the traction's dependence on the ball's position
    /// less. Measured: 6e-8 apart (ball 0 at 82.9 N, 2026-11-29).
    #[test]
    fn a_loaded_balls_contact_mode_is_the_ball_between_its_two_hertz_springs() {
        let scene = preset();
        let m = Model::new(&scene);
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
        let (ki, ko) = (
            spring(diag.inner_load[j], m.inner_race.hertz.k),
            spring(diag.outer_load[j], m.outer_race.hertz.k),
        );
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
            (ringing / expected - 1.0).abs() < 1e-3,
            "ball {j} (Q {:.1} N): {ringing:.4e} rad/s against {expected:.4e} ({:.1e})",
            diag.inner_load[j],
            ringing / expected - 1.0
        );
    }

    /// The bearing's stiffness is local to its bodies (the premise of the block Jacobian,
    /// `ode::block_jacobian`): with every body's block out, the largest eigenvalue left is
    /// under a tenth of the whole Jacobian's (measured 2.4 % at the preset's start, 2026-11-29);
    /// and each part's eigenvalues come largest first.
    #[test]
    fn taking_every_bodys_block_out_leaves_a_tenth_of_the_stiffness() {
        let report = stiffness_at(&preset(), 0.0, 4).expect("runs");
        let top = |r: Removed| {
            let part = report.parts.iter().find(|p| p.removed == r).expect("part");
            assert!(part.largest.windows(2).all(|w| w[0].norm() >= w[1].norm()));
            part.largest[0].norm()
        };
        let (whole, left) = (top(Removed::Nothing), top(Removed::Bodies));
        assert!(left < 0.1 * whole, "{left:.3e} left of {whole:.3e}");
    }
}
