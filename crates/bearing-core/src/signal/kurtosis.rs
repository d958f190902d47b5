//! Pearson kurtosis.

/// Pearson (non-excess) kurtosis `m4 / m2^2` with population central moments (mean removed,
/// divide by n); 3 for a Gaussian, 1.5 for a sine, large for sparse impulses. Returns 0 for
/// fewer than 2 samples or a constant signal (no spread to measure).
pub fn kurtosis(x: &[f64]) -> f64 {
    let n = x.len();
    if n < 2 {
        return 0.0;
    }
    let mean = x.iter().sum::<f64>() / n as f64;
    let (mut m2, mut m4) = (0.0, 0.0);
    for v in x {
        let d = v - mean;
        let d2 = d * d;
        m2 += d2;
        m4 += d2 * d2;
    }
    m2 /= n as f64;
    m4 /= n as f64;
    if m2 <= 0.0 {
        return 0.0;
    }
    m4 / (m2 * m2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn known_values() {
        // sine over whole periods: exactly 1.5 (up to rounding, 1e-12)
        let s: Vec<f64> = (0..1000)
            .map(|i| (2.0 * std::f64::consts::PI * i as f64 / 100.0).sin())
            .collect();
        assert!((kurtosis(&s) - 1.5).abs() < 1e-12);
        // two-level square wave: exactly 1
        let q: Vec<f64> = (0..100)
            .map(|i| if i % 2 == 0 { 3.0 } else { -1.0 })
            .collect();
        assert!((kurtosis(&q) - 1.0).abs() < 1e-12);
        // one impulse in n zeros: n - 2 + 1/(n-1)... check the closed form (n^2 - 3n + 3)/(n - 1)
        let mut p = vec![0.0; 50];
        p[7] = 1.0;
        let n = 50.0;
        assert!((kurtosis(&p) - (n * n - 3.0 * n + 3.0) / (n - 1.0)).abs() < 1e-9);
        assert_eq!(kurtosis(&[2.0; 10]), 0.0);
    }
}
