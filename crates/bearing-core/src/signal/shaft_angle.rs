//! The shaft's angle at every sample of a signal: what order tracking resamples by.
//!
//! A simulated run knows it from the inner ring's rotation; a measured one gets it from a
//! tachometer channel or a speed profile. Holding it as its own checked type means the
//! analysis never has to ask whether an angle track is finite, ordered or as long as the
//! signal it belongs to.

/// Shaft angle, rad, one value per sample of the signal it belongs to, starting anywhere and
/// never decreasing (a shaft that turns backwards is outside what order tracking handles).
#[derive(Debug, Clone, PartialEq)]
pub struct ShaftAngle {
    radians: Vec<f64>,
}

/// Why an angle track was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShaftAngleError {
    #[error("the shaft angle has {got} samples, the signal {expected}")]
    Length { got: usize, expected: usize },
    #[error("the shaft angle at sample {index} is not a finite number")]
    NonFinite { index: usize },
    #[error("the shaft angle decreases at sample {index} (the shaft must not turn backwards)")]
    Decreasing { index: usize },
    #[error("the shaft turns less than one revolution over the signal")]
    UnderOneRevolution,
}

impl ShaftAngle {
    /// Check an angle track, rad per sample, for a signal of `signal_len` samples.
    pub fn new(radians: Vec<f64>, signal_len: usize) -> Result<Self, ShaftAngleError> {
        if radians.len() != signal_len {
            return Err(ShaftAngleError::Length {
                got: radians.len(),
                expected: signal_len,
            });
        }
        if let Some(index) = radians.iter().position(|a| !a.is_finite()) {
            return Err(ShaftAngleError::NonFinite { index });
        }
        if let Some(index) = radians.windows(2).position(|w| w[1] < w[0]) {
            return Err(ShaftAngleError::Decreasing { index: index + 1 });
        }
        let span = radians.last().unwrap_or(&0.0) - radians.first().unwrap_or(&0.0);
        if span < std::f64::consts::TAU {
            return Err(ShaftAngleError::UnderOneRevolution);
        }
        Ok(ShaftAngle { radians })
    }

    /// The angle, rad, one value per sample.
    pub fn radians(&self) -> &[f64] {
        &self.radians
    }

    /// Revolutions turned over the whole track.
    pub fn revolutions(&self) -> f64 {
        (self.radians[self.radians.len() - 1] - self.radians[0]) / std::f64::consts::TAU
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_what_order_tracking_cannot_use() {
        let turning: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
        assert!(ShaftAngle::new(turning.clone(), 100).is_ok());
        assert_eq!(
            ShaftAngle::new(turning.clone(), 99),
            Err(ShaftAngleError::Length {
                got: 100,
                expected: 99
            })
        );
        let mut back = turning.clone();
        back[50] = 0.0;
        assert_eq!(
            ShaftAngle::new(back, 100),
            Err(ShaftAngleError::Decreasing { index: 50 })
        );
        let mut nan = turning;
        nan[3] = f64::NAN;
        assert_eq!(
            ShaftAngle::new(nan, 100),
            Err(ShaftAngleError::NonFinite { index: 3 })
        );
        assert_eq!(
            ShaftAngle::new(vec![0.0; 10], 10),
            Err(ShaftAngleError::UnderOneRevolution)
        );
    }
}
