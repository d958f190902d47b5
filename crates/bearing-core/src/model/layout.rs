//! Layout of the flat state vector.
//!
//! Ball j (9 values at `9 j`): axial position x, radial position r, azimuth theta (all
//! inertial cylindrical, m, m, rad), their rates (m/s, m/s, rad/s) and the absolute
//! angular velocity in the ball's azimuth frame `[w_x, w_r, w_t]` (rad/s). Ball
//! orientation is not integrated: a sphere's forces do not depend on it.
//! Inner ring (10): x, y, z (m), tilt about Y and Z (rad), and their rates.
//! Outer ring (4): y, z (m) and rates (pedestal, eq. 29).
//! Cage (12): x, y, z (m), spin angle, tilt about Y, tilt about Z (rad), velocities
//! (m/s) and angular velocity (rad/s).
//!
//! Reduced fidelity levels (`solver.fidelity`) keep the layout and hold some slots fixed
//! between accepted steps (their derivative is zero; `BearingSystem::project` rewrites
//! them): with quasi-static balls, a ball's x and r are its equilibrium position and the
//! slots of their rates hold the lagged axial and radial force of its balance (N); with a
//! concentric cage, the cage's y, z and their rates copy the guiding ring's, and its tilts
//! and transverse angular velocities stay zero.

pub const BALL: usize = 9;
pub const INNER: usize = 10;
pub const OUTER: usize = 4;
pub const CAGE: usize = 12;

/// Offsets of each body in the state vector.
#[derive(Debug, Clone, Copy)]
pub struct Layout {
    pub balls: usize,
    pub inner: usize,
    pub outer: usize,
    pub cage: usize,
    pub len: usize,
}

impl Layout {
    pub fn new(ball_count: usize) -> Self {
        let inner = BALL * ball_count;
        let outer = inner + INNER;
        let cage = outer + OUTER;
        Layout {
            balls: ball_count,
            inner,
            outer,
            cage,
            len: cage + CAGE,
        }
    }
    #[inline]
    pub fn ball(&self, j: usize) -> usize {
        BALL * j
    }
}

/// What kind of quantity a state component is, for error scaling.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Length,
    Angle,
    /// An angle that grows without bound (orbit, spin); its error is judged absolutely.
    Phase,
    Velocity,
    AngularVelocity,
}

/// Kind of every component.
pub fn kinds(l: &Layout) -> Vec<Kind> {
    use Kind::*;
    let mut k = Vec::with_capacity(l.len);
    for _ in 0..l.balls {
        k.extend_from_slice(&[
            Length,
            Length,
            Phase,
            Velocity,
            Velocity,
            AngularVelocity,
            AngularVelocity,
            AngularVelocity,
            AngularVelocity,
        ]);
    }
    k.extend_from_slice(&[
        Length,
        Length,
        Length,
        Angle,
        Angle,
        Velocity,
        Velocity,
        Velocity,
        AngularVelocity,
        AngularVelocity,
    ]);
    k.extend_from_slice(&[Length, Length, Velocity, Velocity]);
    k.extend_from_slice(&[
        Length,
        Length,
        Length,
        Phase,
        Angle,
        Angle,
        Velocity,
        Velocity,
        Velocity,
        AngularVelocity,
        AngularVelocity,
        AngularVelocity,
    ]);
    k
}
