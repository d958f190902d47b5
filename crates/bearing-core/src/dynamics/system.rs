//! The bearing model as a problem for the generic ODE solver ([`crate::ode`]).

use super::ball_equilibrium::BalanceTrack;
use super::rhs::{self, rhs_tracked, Diagnostics};
use super::step_bound::defect_step_bound;
use crate::model::layout::{ball, cage, inner, outer, BALL, CAGE, INNER, OUTER};
use crate::model::Model;
use crate::ode::block_jacobian::{difference_step, BlockJacobian};
use crate::ode::etd_rk4::{LinearPart, Oscillator, RelaxingGroup, RelaxingPairs};
use crate::ode::problem::{JacobianSystem, OdeSystem};
use crate::ode::rosenbrock_tableau::ROS34PRW_EXPLICIT_STABILITY;
use std::ops::Range;

/// Which part of the bearing's Jacobian a linearly implicit method gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JacobianScope {
    /// Full fidelity: every body's diagonal block ([`bearing_jacobian`]); reduced
    /// levels: the cage's land film alone.
    Blocks,
    /// Each ball's velocities on each other ([`ball_velocity_jacobian`]), and the cage's
    /// land film at the reduced levels and wherever it is too stiff for the method's
    /// explicit part at full fidelity (a whirling cage): implicit in the traction's slip
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
    /// Scratch state for the land film's Jacobian.
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

    /// The land film's rows of the cage, `d(y'', z'')/d(y, z, y', z')`, by differences of
    /// the land force alone: `rows[i][j]` for acceleration `i` (y'', z'') and column `j`
    /// (y, z, y', z'); zero without a land.
    fn land_film_rows(&mut self, t: f64, y: &[f64]) -> [[f64; 4]; 2] {
        let m = self.model;
        let c = m.layout.cage;
        let mut rows = [[0.0; 4]; 2];
        if m.land.is_none() {
            return rows;
        }
        let a0 = rhs::cage_land_acceleration(m, t, y);
        self.land_y.copy_from_slice(y);
        for (j, col) in [cage::Y, cage::Z, cage::Y_DOT, cage::Z_DOT]
            .into_iter()
            .enumerate()
        {
            let k = c + col;
            let d;
            (self.land_y[k], d) = difference_step(y[k], self.scale[k]);
            let a = rhs::cage_land_acceleration(m, t, &self.land_y);
            self.land_y[k] = y[k];
            rows[0][j] = (a[0] - a0[0]) / d;
            rows[1][j] = (a[1] - a0[1]) / d;
        }
        rows
    }

    /// The cage block of `jac`: the land film's rows with `d(y, z)/d(y', z')` = 1, or all
    /// zero (`include` false: the cage explicit).
    fn set_land_film(&self, rows: &[[f64; 4]; 2], include: bool, jac: &mut BlockJacobian) {
        let c = self.model.layout.cage;
        let on = if include { 1.0 } else { 0.0 };
        jac.set(c + cage::Y, c + cage::Y_DOT, on);
        jac.set(c + cage::Z, c + cage::Z_DOT, on);
        let cols = [cage::Y, cage::Z, cage::Y_DOT, cage::Z_DOT];
        for (i, row) in [cage::Y_DOT, cage::Z_DOT].into_iter().enumerate() {
            for (j, col) in cols.into_iter().enumerate() {
                // a select, not a product: an excluded block is zero even if a row is not finite
                jac.set(c + row, c + col, if include { rows[i][j] } else { 0.0 });
            }
        }
    }
}

/// Bound on the largest eigenvalue magnitude of the land film's linearisation
/// `[[0, I], [K, C]]` (`K` the acceleration's derivative by the cage's position, `C` by its
/// velocity), 1/s: `|lambda| <= |C| + sqrt(|K|)` in the infinity norm, from
/// `lambda^2 = C lambda + K` on an eigenvector.
fn land_film_rate(rows: &[[f64; 4]; 2]) -> f64 {
    let norm = |j0: usize| {
        rows.iter()
            .map(|r| r[j0].abs() + r[j0 + 1].abs())
            .fold(0.0, f64::max)
    };
    norm(2) + norm(0).sqrt()
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
    /// radial velocity run away (the step underflowed within 3-8 ms). `BallVelocities`
    /// at full fidelity: the balls' velocity blocks, and the land film where it is too
    /// stiff for the method's explicit part at a step of `h`.
    fn jacobian(&mut self, t: f64, y: &[f64], f0: &[f64], h: f64, jac: &mut BlockJacobian) -> u64 {
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
        // five land-force evaluations, a small fraction of one right-hand side
        if m.quasi_static_balls {
            let rows = self.land_film_rows(t, y);
            self.set_land_film(&rows, true, jac);
        } else if self.scope == JacobianScope::BallVelocities {
            // The land film goes implicit only where the explicit part could not be stable
            // on it at this step: a whirling cage's film (`h` times the bound 3.0-3.8 when
            // held explicit on the 10 ms ramp under the rheology law), not a quiet cage's
            // (median 0.8-0.9, at most 2.6, at 2000 and 10000 rpm), whose mean speed's
            // error an always-implicit film raised from 8e-6 to 6e-5 at 2000 rpm
            // (docs/lab/benchmarks.md). The choice holds as long as this Jacobian (up to
            // 20 steps); a step the excluded film cannot take is rejected, and a rejection
            // with an aged Jacobian refreshes it.
            let rows = self.land_film_rows(t, y);
            let stiff = h * land_film_rate(&rows) > ROS34PRW_EXPLICIT_STABILITY;
            self.set_land_film(&rows, stiff, jac);
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
    let blocks = body_blocks(m);
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
/// carry the vibration, stay explicit and undamped. The rings are zero blocks; the cage
/// block holds the land film where [`BearingSystem`]'s Jacobian puts it there (reduced
/// levels; a film too stiff for the explicit part).
pub fn ball_velocity_jacobian(m: &Model) -> BlockJacobian {
    let l = &m.layout;
    let mut blocks = Vec::with_capacity(2 * l.balls + 3);
    for j in 0..l.balls {
        let velocities = ball_velocity_block(m, j);
        blocks.push(l.ball(j)..velocities.start);
        blocks.push(velocities);
    }
    blocks.extend(rings_and_cage(m));
    let first = first_velocity_slot(m);
    let groups = (first..BALL)
        .map(|k| (0..l.balls).map(|j| l.ball(j) + k).collect())
        .collect();
    BlockJacobian::partial(blocks, groups)
}

/// What [`EtdRk4`] takes exactly on the bearing:
///
/// - each ball's contact oscillator (its axial and radial position and velocity on its two
///   Hertz contacts, whose modes ring at ~58 kHz and hold RK4's step to ~7.6 us;
///   docs/lab/benchmarks.md, "Where the stiffness is"), with each mode's own damping
///   where it passes 1e5 1/s: at low speed the traction's resistance to the ball's axial
///   sliding makes the soft mode overdamped, -1.2e6 1/s near 1500 rpm on the Table-1
///   case's loaded balls, which held `etd_rk4` to ~2 us there (docs/lab/benchmarks.md,
///   "The sliding ball's damping and the cage taken exactly");
/// - the relaxation of the rolling spin `w_t` (the traction's slip relaxation: 1.1e5 1/s
///   on a loaded ball at 10000 rpm, near 1e6 1/s at 1000-2000 rpm);
/// - each ball's orbital speed and spin about the axis `w_x` as one relaxing pair, whole:
///   `w_x` relaxes at 5.8e4 1/s at 10000 rpm, near 1e6 1/s at 1000-2000 rpm, and there the
///   orbital speed drives it at ~2e6 1/s while relaxing itself at ~3.6e5 1/s (a loaded
///   ball's block at 0.01 s of the Table-1 ramp: `[[-3.58e5, 2.0e4], [2.10e6, -8.23e5]]`,
///   eigenvalues -2.8e5 and -9.0e5). With `w_x` alone at its diagonal rate that coupling,
///   in the remainder, held the ramp's steps from 0.02 to 0.1 s below the alias bound
///   (4 800 steps whose largest error was `w_x`), and the orbital speed at its own rate
///   cost steps; whole, the pair took the Table-1 case from 66 355 to 64 701 accepted
///   steps (45-run means) and 2000 rpm from 30 759 to 24 193 right-hand sides, as cheap as
///   10000 rpm (docs/lab/benchmarks.md). Difference steps 1e-3 rad/s for the orbital speed
///   (1.8e-5 m/s at the pitch radius) and 1e-2 rad/s for the spin, inside the traction
///   curve's linear part as below;
/// - the cage's radial velocities, which its land film damps, and its spin, which the
///   pocket and land films damp (at 1 Pa s the spin held the step once the radial
///   velocities were taken: 10 868 of 55 345 attempts rejected on the `very_viscous`
///   stress scene; with it, 2 022 of 30 618).
///
/// Balls do not act on each other directly, so every ball's column goes in one
/// difference: ten right-hand sides per linearisation (two for the pairs).
///
/// - Position step 1e-9 m: a thousandth of the contact deformation at the preset's loads
///   (a few um), so the secant is the tangent stiffness within about 1e-3, far above
///   rounding (positions ~2e-2 m carry ulps of 3e-18 m). A mismatch costs no accuracy,
///   only step size: what `L` misses stays in the explicit remainder.
/// - Velocity step 3e-5 m/s, and spin step 1e-2 rad/s (a slip speed of about 3e-5 m/s at
///   the contact): inside the traction curve's linear part, which reaches a few mm/s at the
///   preset's loads. The Table-1 case took the same steps within 0.5 % at 1e-5 and 1e-4
///   m/s.
/// - Cage velocity step 1e-5 m/s, small beside its whirl (eccentricity ~1e-5 m at ~440
///   rad/s, ~4e-3 m/s); its spin step 1e-2 rad/s, as the balls'. Its radial velocities as
///   one 2x2 block (the film's cross-coupling) took the same steps as two rates: not kept.
/// - The spin along the radius `w_r` is left out: at 1000-5000 rpm it couples to `w_x`
///   too strongly for a diagonal rate (with the pair above, a 3x3 block would be needed);
///   it still holds some steps of the ramp's first 0.02 s.
/// - Modes slower than 1e3 rad/s (rates, 1/s) stay explicit: an RK4 step of at most
///   1e-4 s resolves them (`omega h` <= 0.1).
/// - Damping below 1e5 1/s stays explicit: at the alias bound's ~11.5 us step (1.35 pi at
///   3.7e5 rad/s) its `c h` is at most about 1.15, within the explicit stages' reach. That leaves the contact damping (ratio 0.05,
///   docs/reference/model.md's defaults; 2 zeta omega = 3.7e4 1/s at 58 kHz) in the
///   remainder: taken exactly as well it saved another 4 % of the steps but moved the
///   35-51 kHz band 1.9 % (s.e. 0.25 %) below the reference, against 0.9 % without it.
/// - 80 steps per linearisation: on the Table-1 case 20, 40 and 80 took the same steps
///   within 0.3 % (65 591, 65 666, 65 780 accepted) for 3.7 % and 2.0 % fewer evaluations
///   at the two doublings.
/// - `omega h` <= 1.35 pi on the fastest contact mode ([`LinearPart::alias_limit`]), below
///   the stages' 1.5 pi: measured on the Table-1 case (docs/lab/benchmarks.md, "Stages a
///   third of the step apart").
/// - Quasi-static balls (their centres algebraic, their velocity slots forces) have no
///   oscillator.
///
/// [`EtdRk4`]: crate::ode::etd_rk4::EtdRk4
pub fn linear_part(m: &Model) -> LinearPart {
    let l = &m.layout;
    let oscillators = (0..l.balls)
        .filter(|_| !m.quasi_static_balls)
        .map(|j| {
            let b = l.ball(j);
            Oscillator {
                pos: [b + ball::X, b + ball::R],
                vel: [b + ball::X_DOT, b + ball::R_DOT],
            }
        })
        .collect();
    let every_ball = |slot: usize| RelaxingGroup {
        components: (0..l.balls).map(|j| l.ball(j) + slot).collect(),
        step: 1e-2,
    };
    let cage_rate = |slot: usize, step: f64| RelaxingGroup {
        components: vec![l.cage + slot],
        step,
    };
    LinearPart {
        oscillators,
        position_step: 1e-9,
        velocity_step: Some(3e-5),
        slowest_damping: 1e5,
        relaxing_pairs: vec![RelaxingPairs {
            pairs: (0..l.balls)
                .map(|j| [l.ball(j) + ball::THETA_DOT, l.ball(j) + ball::W_X])
                .collect(),
            steps: [1e-3, 1e-2],
        }],
        relaxing: vec![
            every_ball(ball::W_T),
            cage_rate(cage::Y_DOT, 1e-5),
            cage_rate(cage::Z_DOT, 1e-5),
            cage_rate(cage::W_X, 1e-2),
        ],
        slowest: 1e3,
        max_age: 80,
        alias_limit: 1.35 * std::f64::consts::PI,
    }
}

/// Every body's slots, one range each: each ball's, the inner ring's, the outer ring's and
/// the cage's (the blocks of [`bearing_jacobian`]).
pub fn body_blocks(m: &Model) -> Vec<Range<usize>> {
    let l = &m.layout;
    (0..l.balls)
        .map(|j| l.ball(j)..l.ball(j) + BALL)
        .chain(rings_and_cage(m))
        .collect()
}

/// Ball `j`'s velocities, the block [`ball_velocity_jacobian`] takes implicitly: at full
/// fidelity the axial, radial and orbital speeds and the three spin components; with
/// quasi-static balls (their centres algebraic) the orbital speed and the spins.
pub fn ball_velocity_block(m: &Model, j: usize) -> Range<usize> {
    let b = m.layout.ball(j);
    b + first_velocity_slot(m)..b + BALL
}

fn first_velocity_slot(m: &Model) -> usize {
    if m.quasi_static_balls {
        ball::THETA_DOT
    } else {
        ball::X_DOT
    }
}

fn rings_and_cage(m: &Model) -> [Range<usize>; 3] {
    let l = &m.layout;
    [
        l.inner..l.inner + INNER,
        l.outer..l.outer + OUTER,
        l.cage..l.cage + CAGE,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix4;

    /// `land_film_rate` bounds the largest eigenvalue magnitude of `[[0, I], [K, C]]` (the
    /// bound follows from `lambda^2 x = K x + C lambda x`) and, on film-like matrices
    /// (stiffness and damping of the order of the land film's, coupled across y and z), is
    /// not loose by more than a factor of 3, so the threshold it is compared with keeps its
    /// meaning.
    #[test]
    fn land_film_rate_bounds_the_films_eigenvalues() {
        for (k, c, kc, cc) in [
            (-1e9, -2e4, 0.0, 0.0),
            (-1e9, -2e4, 3e8, 5e3),
            (-4e10, -1e3, -1e10, 2e2),
            (-1e6, -3e5, 1e5, -1e5),
            (2e8, -1e4, 0.0, 0.0),
        ] {
            let rows = [[k, kc, c, cc], [kc, k, cc, c]];
            let m = Matrix4::new(
                0.0, 0.0, 1.0, 0.0, //
                0.0, 0.0, 0.0, 1.0, //
                rows[0][0], rows[0][1], rows[0][2], rows[0][3], //
                rows[1][0], rows[1][1], rows[1][2], rows[1][3],
            );
            let largest = m
                .complex_eigenvalues()
                .iter()
                .map(|l| l.norm())
                .fold(0.0, f64::max);
            let rate = land_film_rate(&rows);
            assert!(
                rate >= largest * (1.0 - 1e-9),
                "{rows:?}: {rate} < {largest}"
            );
            assert!(rate <= 3.0 * largest, "{rows:?}: {rate} against {largest}");
        }
    }
}
