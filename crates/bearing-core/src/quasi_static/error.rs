//! Why the quasi-static solver found no equilibrium.

/// A failed quasi-static solve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum QsError {
    /// The requested shaft speed is not a speed.
    #[error("shaft speed {rpm} rev/min must be finite and >= 0")]
    InvalidSpeed { rpm: f64 },
    /// Newton-Levenberg did not bring the ring force residual below tolerance.
    #[error("quasi-static equilibrium did not converge: largest ring force residual {residual:.3e} N after {iterations} iterations of the direct solve{}{}", moment_hint(*moment_reached, applied_moment), load_hint(*axial_load, *radial_load, *axial_load_needed))]
    NoEquilibrium {
        /// Largest ring force residual left, N.
        residual: f64,
        iterations: u32,
        /// With a free tilt under a moment: the largest fraction of the moment (0..1) for
        /// which continuation found an equilibrium.
        moment_reached: Option<f64>,
        /// Applied moment about Y and Z, N m.
        applied_moment: [f64; 2],
        /// Applied axial load, N.
        axial_load: f64,
        /// Applied radial load, N.
        radial_load: f64,
        /// With the ring's tilt locked and the axial load near or below it: the axial load the
        /// radial load needs, about `Fr tan(alpha0)` with the free contact angle, N.
        axial_load_needed: Option<f64>,
    },
    /// The pocket cycle's ball integration failed, or no balance was bracketed.
    #[error("the pocket-cycle cage balance failed: {reason}")]
    PocketCycle { reason: String },
}

/// A radial load is carried only through contact angles: a ring that may not tilt needs at
/// least about `Fr tan(alpha)` of axial load, since even one ball carrying everything pushes
/// back `tan(alpha)` times axially what it takes radially.
fn load_hint(axial: f64, radial: f64, needed: Option<f64>) -> String {
    match needed {
        Some(n) => format!(
            "; with the inner ring's tilt locked the radial load {radial} N needs an axial load of about Fr tan(alpha0) = {n:.1} N or more to keep the balls in angular contact, and {axial} N is applied: raise operating.axial_load (or lower operating.radial_load)"
        ),
        None => String::new(),
    }
}

fn moment_hint(reached: Option<f64>, moment: &[f64; 2]) -> String {
    match reached {
        // Measured on the H7005C: the moment a free ring takes grows with the axial load and
        // the tilt stiffness falls to zero at the limit.
        Some(f) => format!(
            "; with a free inner-ring tilt one angular contact bearing carries a moment only up to a limit set mostly by its axial load, and an equilibrium was found up to {:.0} % of the applied moment [{}, {}] N m: raise the axial load, lower the moment or lock the tilt",
            100.0 * f,
            moment[0],
            moment[1]
        ),
        None => String::new(),
    }
}
