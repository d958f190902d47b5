//! The bearing model as a problem for the generic ODE solver ([`crate::ode`]).

use super::ball_equilibrium::BalanceTrack;
use super::rhs::{self, rhs_tracked, Diagnostics};
use super::step_bound::defect_step_bound;
use crate::model::layout::{ball, cage, inner, outer, BALL, CAGE, INNER, OUTER};
use crate::model::Model;
use crate::ode::block_jacobian::{difference_step, BlockJacobian};
use crate::ode::problem::{JacobianSystem, OdeSystem};

/// Which part of the bearing's Jacobian a linearly implicit method gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianScope {
    /// Full fidelity: every body's diagonal block ([`bearing_jacobian`]); reduced
    /// levels: the cage's land film alone.
    Blocks,
    /// Each ball's velocities on each other ([`ball_velocity_jacobian`]), and at the
    /// reduced levels the cage's land film too: implicit in the traction's slip
    /// relaxation, explicit in the contact's elastic modes.
    BallVelocities,
}

/// The model as an ODE system.
pub struct BearingSystem<'m> {
    pub model: &'m Model,
    /// Natural size of each state component (finite-difference increments).
    pub scale: &'m [f64],
    /// Diagnostics of the last step-end evaluation.
    pub diag: Diagnostics,
    /// Quasi-static balls: their balance at the last accepted step and how it follows
    /// the rings (Newton's start inside the next step).
    pub track: BalanceTrack,
    /// Scratch state for the land film's Jacobian (reduced levels).
    land_y: Vec<f64>,
    /// What [`JacobianSystem::jacobian`] fills.
    pub scope: JacobianScope,
}

impl<'m> BearingSystem<'m> {
    pub fn new(model: &'m Model, scale: &'m [f64]) -> Self {
        BearingSystem {
            model,
            scale,
            diag: Diagnostics::new(model.z),
            track: BalanceTrack::new(model.z),
            land_y: vec![0.0; model.layout.len],
            scope: JacobianScope::Blocks,
        }
    }

    /// The land film's rows of the cage, `d(y'', z'')/d(y, z, y', z')` with
    /// `d(y, z)/d(y', z')` = 1, by differences of the land force alone (the other entries
    /// of the cage block zero).
    fn land_film_jacobian(&mut self, t: f64, y: &[f64], jac: &mut BlockJacobian) {
        let m = self.model;
        let c = m.layout.cage;
        jac.set(c + cage::Y, c + cage::Y_DOT, 1.0);
        jac.set(c + cage::Z, c + cage::Z_DOT, 1.0);
        if m.land.is_none() {
            return;
        }
        let a0 = rhs::cage_land_acceleration(m, t, y);
        self.land_y.copy_from_slice(y);
        for col in [cage::Y, cage::Z, cage::Y_DOT, cage::Z_DOT] {
            let k = c + col;
            let d;
            (self.land_y[k], d) = difference_step(y[k], self.scale[k]);
            let a = rhs::cage_land_acceleration(m, t, &self.land_y);
            self.land_y[k] = y[k];
            jac.set(c + cage::Y_DOT, k, (a[0] - a0[0]) / d);
            jac.set(c + cage::Z_DOT, k, (a[1] - a0[1]) / d);
        }
    }
}

impl OdeSystem for BearingSystem<'_> {
    fn dim(&self) -> usize {
        self.model.layout.len
    }
    fn rhs(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        rhs_tracked(self.model, t, y, dy, None, Some(&self.track));
    }
    fn rhs_at_step_end(&mut self, t: f64, y: &[f64], dy: &mut [f64]) {
        rhs_tracked(
            self.model,
            t,
            y,
            dy,
            Some(&mut self.diag),
            Some(&self.track),
        );
    }
    /// Reduced fidelity levels: write the components an algebraic condition fixes.
    /// Quasi-static balls: each ball's equilibrium centre, and the in-plane force the next
    /// step's balances take as given, from the step-end evaluation at `y`. Concentric
    /// cage: the guiding ring's radial position and velocity (so the reported cage offset
    /// and land eccentricity describe the cage the right-hand side used).
    fn project(&mut self, _t: f64, y: &mut [f64]) {
        let m = self.model;
        let l = &m.layout;
        if m.quasi_static_balls {
            for j in 0..m.z {
                let b = l.ball(j);
                [y[b + ball::X], y[b + ball::R]] = self.diag.ball_centre[j];
                [y[b + ball::X_DOT], y[b + ball::R_DOT]] = self.diag.ball_other_force[j];
            }
            // copied in place: the stepping loop allocates nothing
            self.track.rings.copy_from_slice(&self.diag.track.rings);
            self.track.follows.copy_from_slice(&self.diag.track.follows);
        }
        if m.concentric_cage {
            let (i, o, c) = (l.inner, l.outer, l.cage);
            let [py, pz, vy, vz] = if m.cage_guided_by_inner() {
                [
                    y[i + inner::Y],
                    y[i + inner::Z],
                    y[i + inner::Y_DOT],
                    y[i + inner::Z_DOT],
                ]
            } else {
                [
                    y[o + outer::Y],
                    y[o + outer::Z],
                    y[o + outer::Y_DOT],
                    y[o + outer::Z_DOT],
                ]
            };
            [
                y[c + cage::Y],
                y[c + cage::Z],
                y[c + cage::Y_DOT],
                y[c + cage::Z_DOT],
            ] = [py, pz, vy, vz];
        }
    }
    /// No step carries a ball across a defect unseen (`defect_step_bound`).
    fn step_limit(&self, t: f64, y: &[f64]) -> Option<f64> {
        Some(defect_step_bound(self.model, t, y))
    }
}

impl JacobianSystem for BearingSystem<'_> {
    /// Full fidelity: the block-diagonal Jacobian by coloured differences (31 right-hand
    /// sides). Reduced levels: only the cage's land film, `d(y'', z'')/d(y, z, y', z')` of
    /// the cage (with `d(y, z)/d(y', z')` = 1), by differences of the land force alone,
    /// every other entry zero. What holds a reduced level's explicit step in the ramp is
    /// that film (docs/lab/benchmarks.md, "Fidelity levels"), and a whole block Jacobian
    /// there both costs 31 quasi-static right-hand sides and, aged, let the cage's
    /// radial velocity run away (the step underflowed within 3-8 ms).
    fn jacobian(&mut self, t: f64, y: &[f64], f0: &[f64], jac: &mut BlockJacobian) -> u64 {
        let m = self.model;
        // the grouped columns by differences: every block (`Blocks` at full fidelity) or the
        // ball velocities (`BallVelocities`, whose partial matrix groups only those); the
        // reduced levels' `Blocks` hold the land film alone
        let mut cost = 0;
        if m.quasi_static_balls && self.scope == JacobianScope::Blocks {
            jac.clear();
        } else {
            let track = &self.track;
            jac.evaluate(t, y, f0, self.scale, |t, y, dy| {
                rhs_tracked(m, t, y, dy, None, Some(track))
            });
            cost = jac.cost_in_rhs() as u64;
        }
        if m.quasi_static_balls {
            // five land-force evaluations, a small fraction of one right-hand side
            self.land_film_jacobian(t, y, jac);
        }
        cost
    }
    /// The land film's Jacobian is cheap and changes fast with the cage's eccentricity:
    /// fresh at every step.
    fn jacobian_max_age(&self) -> u32 {
        if self.model.quasi_static_balls {
            1
        } else {
            20
        }
    }
}

/// The block-diagonal Jacobian of the bearing: one block per ball (9), the inner ring
/// (10), the outer ring (4) and the cage (12). Colouring: a ball's derivative depends on
/// its own state, the rings and the cage, never on another ball's, so component k of
/// every ball is perturbed at once (9 evaluations); the two rings do not act on each
/// other directly, so inner component k goes with outer component k (10); the cage,
/// which touches every ball and its guiding ring, goes alone (12). 31 right-hand sides
/// per Jacobian.
pub fn bearing_jacobian(m: &Model) -> BlockJacobian {
    let l = &m.layout;
    let mut blocks: Vec<_> = (0..l.balls).map(|j| l.ball(j)..l.ball(j) + BALL).collect();
    blocks.push(l.inner..l.inner + INNER);
    blocks.push(l.outer..l.outer + OUTER);
    blocks.push(l.cage..l.cage + CAGE);
    let mut groups: Vec<Vec<usize>> = (0..BALL)
        .map(|k| (0..l.balls).map(|j| l.ball(j) + k).collect())
        .collect();
    for k in 0..INNER {
        let mut g = vec![l.inner + k];
        if k < OUTER {
            g.push(l.outer + k);
        }
        groups.push(g);
    }
    for k in 0..CAGE {
        groups.push(vec![l.cage + k]);
    }
    BlockJacobian::new(blocks, groups)
}

/// The ball-velocity Jacobian: per ball, the block of its velocities (at full fidelity
/// the axial, radial and orbital speeds and the three spin components; with quasi-static
/// balls the orbital speed and spin, their centres being algebraic) on each other, by
/// coloured differences (component k of every ball at once: 6 or 4 right-hand sides).
/// That block holds the traction's slip relaxation, the system's fastest dissipative mode
/// (a loaded ball's slip relaxes in microseconds, faster at low speed where the film is
/// thinner); the positions' columns are left out, so the contact's elastic modes, which
/// carry the vibration, stay explicit and undamped. The rings are zero blocks and the cage
/// block holds the land film at the reduced levels.
pub fn ball_velocity_jacobian(m: &Model) -> BlockJacobian {
    let l = &m.layout;
    let first = if m.quasi_static_balls {
        ball::THETA_DOT
    } else {
        ball::X_DOT
    };
    let mut blocks = Vec::with_capacity(2 * l.balls + 3);
    for j in 0..l.balls {
        let b = l.ball(j);
        blocks.push(b..b + first);
        blocks.push(b + first..b + BALL);
    }
    blocks.push(l.inner..l.inner + INNER);
    blocks.push(l.outer..l.outer + OUTER);
    blocks.push(l.cage..l.cage + CAGE);
    let groups = (first..BALL)
        .map(|k| (0..l.balls).map(|j| l.ball(j) + k).collect())
        .collect();
    BlockJacobian::partial(blocks, groups)
}
