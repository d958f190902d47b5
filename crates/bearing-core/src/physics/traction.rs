//! EHL traction coefficient (eqs. 14-15) and its slip-direction decomposition (eq. 16).

/// Traction curve `mu(s) = (a + b s) exp(-c s) + d`, s the slip speed in m/s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TractionCurve {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
}

/// Below this slip speed (m/s) the coefficient is scaled linearly to zero, so a curve
/// with mu(0) != 0 has no discontinuity at zero slip (fully flooded EHL: q_bd = 0).
pub const SLIP_REGULARIZATION: f64 = 1e-3;

impl TractionCurve {
    /// Coefficient at slip speed `s` >= 0, -.
    #[inline]
    pub fn mu(&self, s: f64) -> f64 {
        let mu = (self.a + self.b * s) * (-self.c * s).exp() + self.d;
        if s < SLIP_REGULARIZATION {
            mu * s / SLIP_REGULARIZATION
        } else {
            mu
        }
    }

    /// `mu(s) / s`, finite at s = 0: multiplies the slip vector to give the traction direction
    /// and magnitude without dividing by a vanishing speed, 1/(m/s).
    #[inline]
    pub fn mu_over_s(&self, s: f64) -> f64 {
        if s < SLIP_REGULARIZATION {
            ((self.a + self.b * s) * (-self.c * s).exp() + self.d) / SLIP_REGULARIZATION
        } else {
            self.mu(s) / s
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curve_is_continuous_and_peaks_where_designed() {
        // ADORE sample deck: peak 0.05 at 1 m/s, tends to 0.036.
        let t = TractionCurve {
            a: -0.036,
            b: 0.1018,
            c: 1.547,
            d: 0.036,
        };
        assert!(t.mu(0.0).abs() < 1e-12);
        assert!((t.mu(1.0) - 0.05).abs() < 2e-4, "{}", t.mu(1.0));
        assert!((t.mu(50.0) - 0.036).abs() < 1e-6);
        // continuity across the regularization threshold
        let s = SLIP_REGULARIZATION;
        assert!((t.mu(s * (1.0 - 1e-9)) - t.mu(s * (1.0 + 1e-9))).abs() < 1e-9);
        assert!((t.mu_over_s(0.3) * 0.3 - t.mu(0.3)).abs() < 1e-15);
    }
}
