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
//! The modules [`ball`], [`inner`], [`outer`] and [`cage`] name each slot's offset.
//!
//! Reduced fidelity levels (`solver.fidelity`) keep the layout and hold some slots fixed
//! between accepted steps (their derivative is zero; `BearingSystem::project` rewrites
//! them): with quasi-static balls, a ball's x and r are its equilibrium position and the
//! slots of their rates hold the lagged axial and radial force of its balance (N); with a
//! concentric cage, the cage's y, z and their rates copy the guiding ring's, and its tilts
//! and transverse angular velocities stay zero.

/// One body's slots: a module with a `usize` offset constant per slot (in order from 0),
/// and `KINDS`, `NAMES` and `LEN` generated from the same list, so the error scaling and
/// the offsets cannot drift apart.
macro_rules! slots {
    ($(#[$doc:meta])* $body:ident { $($(#[$sdoc:meta])* $slot:ident: $kind:ident,)* }) => {
        $(#[$doc])*
        pub mod $body {
            // the full path: `super` would read, to a file-level import scan, as model/
            use crate::model::layout::Kind;
            slots!(@offsets 0usize; $($(#[$sdoc])* $slot,)*);
            /// Kind of each slot, in order.
            pub const KINDS: &[Kind] = &[$(Kind::$kind),*];
            /// Name of each slot, in order.
            pub const NAMES: &[&str] = &[$(stringify!($slot)),*];
            /// Number of slots.
            pub const LEN: usize = KINDS.len();
        }
    };
    (@offsets $i:expr; ) => {};
    (@offsets $i:expr; $(#[$sdoc:meta])* $slot:ident, $($rest:tt)*) => {
        $(#[$sdoc])*
        pub const $slot: usize = $i;
        slots!(@offsets $i + 1; $($rest)*);
    };
}

slots! {
    /// A ball's slots, offsets from `Layout::ball(j)` (inertial cylindrical coordinates).
    ball {
        /// Axial position, m.
        X: Length,
        /// Radial position, m.
        R: Length,
        /// Orbit angle (azimuth), rad.
        THETA: Phase,
        /// Axial velocity, m/s (quasi-static balls: the lagged axial force, N).
        X_DOT: Velocity,
        /// Radial velocity, m/s (quasi-static balls: the lagged radial force, N).
        R_DOT: Velocity,
        /// Orbital speed, rad/s.
        THETA_DOT: AngularVelocity,
        /// Angular velocity about the axis, in the ball's azimuth frame, rad/s.
        W_X: AngularVelocity,
        /// Angular velocity along the radius, rad/s.
        W_R: AngularVelocity,
        /// Angular velocity along the orbit tangent, rad/s.
        W_T: AngularVelocity,
    }
}

slots! {
    /// The inner ring's slots, offsets from `Layout::inner`.
    inner {
        /// Axial position, m.
        X: Length,
        /// Y position, m.
        Y: Length,
        /// Z position, m.
        Z: Length,
        /// Tilt about Y, rad.
        TILT_Y: Angle,
        /// Tilt about Z, rad.
        TILT_Z: Angle,
        /// Axial velocity, m/s.
        X_DOT: Velocity,
        /// Y velocity, m/s.
        Y_DOT: Velocity,
        /// Z velocity, m/s.
        Z_DOT: Velocity,
        /// Tilt rate about Y, rad/s.
        TILT_Y_DOT: AngularVelocity,
        /// Tilt rate about Z, rad/s.
        TILT_Z_DOT: AngularVelocity,
    }
}

slots! {
    /// The outer ring's slots on its pedestal (eq. 29), offsets from `Layout::outer`.
    outer {
        /// Y position, m.
        Y: Length,
        /// Z position, m.
        Z: Length,
        /// Y velocity, m/s.
        Y_DOT: Velocity,
        /// Z velocity, m/s.
        Z_DOT: Velocity,
    }
}

slots! {
    /// The cage's slots, offsets from `Layout::cage`.
    cage {
        /// Axial position, m.
        X: Length,
        /// Y position, m.
        Y: Length,
        /// Z position, m.
        Z: Length,
        /// Spin angle, rad.
        SPIN: Phase,
        /// Tilt about Y, rad.
        TILT_Y: Angle,
        /// Tilt about Z, rad.
        TILT_Z: Angle,
        /// Axial velocity, m/s.
        X_DOT: Velocity,
        /// Y velocity, m/s.
        Y_DOT: Velocity,
        /// Z velocity, m/s.
        Z_DOT: Velocity,
        /// Spin speed, rad/s.
        W_X: AngularVelocity,
        /// Angular velocity about Y, rad/s.
        W_Y: AngularVelocity,
        /// Angular velocity about Z, rad/s.
        W_Z: AngularVelocity,
    }
}

pub const BALL: usize = ball::LEN;
pub const INNER: usize = inner::LEN;
pub const OUTER: usize = outer::LEN;
pub const CAGE: usize = cage::LEN;

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

/// Kind of every component, from the bodies' slot tables.
pub fn kinds(l: &Layout) -> Vec<Kind> {
    let mut k = Vec::with_capacity(l.len);
    for _ in 0..l.balls {
        k.extend_from_slice(ball::KINDS);
    }
    k.extend_from_slice(inner::KINDS);
    k.extend_from_slice(outer::KINDS);
    k.extend_from_slice(cage::KINDS);
    k
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The generated offsets run 0..LEN in the order listed (the state vectors, the
    /// quasi-static initial state and the docs all assume this order).
    #[test]
    fn slot_offsets_follow_the_list() {
        assert_eq!((ball::X, ball::THETA_DOT, ball::W_T, BALL), (0, 5, 8, 9));
        assert_eq!((inner::X_DOT, inner::TILT_Z_DOT, INNER), (5, 9, 10));
        assert_eq!((outer::Y, outer::Z_DOT, OUTER), (0, 3, 4));
        assert_eq!((cage::SPIN, cage::W_X, cage::W_Z, CAGE), (3, 9, 11, 12));
        assert_eq!(ball::NAMES[ball::R_DOT], "R_DOT");
        let l = Layout::new(15);
        let k = kinds(&l);
        assert_eq!(k.len(), l.len);
        assert_eq!(k[l.ball(3) + ball::THETA], Kind::Phase);
        assert_eq!(k[l.cage + cage::SPIN], Kind::Phase);
        assert_eq!(k[l.inner + inner::TILT_Y], Kind::Angle);
    }
}
