//! FFT-based analytic signal (discrete Hilbert transform) and envelope.
//!
//! `z = IFFT(H * FFT(x))` with `H[0] = 1`, `H[k] = 2` for `0 < k < n/2`, `H[n/2] = 1` (n even),
//! `H[k] = 0` for negative frequencies, so `Re z = x` and `|z|` is the envelope. The FFT treats
//! the record as periodic: a record that does not hold whole periods has edge errors that decay
//! away from both ends.
//!
//! An optional pass band `[f0, f1]` (Hz) zeroes every bin outside it before the inverse
//! transform (an ideal, zero-phase band-pass), so the envelope is that of the band-passed signal.

use std::sync::Arc;

use realfft::{RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex64;
use rustfft::{Fft, FftPlanner};

/// Planned transforms and buffers for signals of one length; reuse it across signals.
pub struct HilbertPlan {
    n: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    ifft: Arc<dyn Fft<f64>>,
    input: Vec<f64>,
    half: Vec<Complex64>,
    full: Vec<Complex64>,
    scratch_r2c: Vec<Complex64>,
    scratch_fft: Vec<Complex64>,
}

impl HilbertPlan {
    /// Plan for signals of `n` samples (n >= 1).
    pub fn new(n: usize) -> Self {
        assert!(n >= 1, "HilbertPlan needs at least one sample");
        Self::with_forward(RealFftPlanner::<f64>::new().plan_fft_forward(n))
    }

    /// Plan around an existing forward real FFT (shared with other users of the same length).
    pub fn with_forward(r2c: Arc<dyn RealToComplex<f64>>) -> Self {
        let n = r2c.len();
        let ifft = FftPlanner::<f64>::new().plan_fft_inverse(n);
        HilbertPlan {
            n,
            input: r2c.make_input_vec(),
            half: r2c.make_output_vec(),
            scratch_r2c: r2c.make_scratch_vec(),
            full: vec![Complex64::new(0.0, 0.0); n],
            scratch_fft: vec![Complex64::new(0.0, 0.0); ifft.get_inplace_scratch_len()],
            r2c,
            ifft,
        }
    }

    /// Signal length this plan is for.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether the plan is for empty signals (never: `new` requires n >= 1).
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Analytic signal of `x` (length `len()`), optionally band-passed to `band = [f0, f1]` Hz
    /// at sample rate `fs` Hz. The result lives in the plan until the next call.
    pub fn analytic(&mut self, x: &[f64], fs: f64, band: Option<[f64; 2]>) -> &[Complex64] {
        let n = self.n;
        assert_eq!(x.len(), n, "signal length differs from the plan");
        self.input.copy_from_slice(x);
        self.r2c
            .process_with_scratch(&mut self.input, &mut self.half, &mut self.scratch_r2c)
            .expect("buffer sizes come from the plan");
        let df = fs / n as f64;
        let keep = |k: usize| {
            band.map_or(true, |[f0, f1]| {
                (k as f64 * df) >= f0 && (k as f64 * df) <= f1
            })
        };
        let scale = 1.0 / n as f64;
        self.full
            .iter_mut()
            .for_each(|c| *c = Complex64::new(0.0, 0.0));
        for (k, h) in self.half.iter().enumerate() {
            if !keep(k) {
                continue;
            }
            // DC and (even n) Nyquist are their own mirror images: weight 1; others 2.
            let w = if k == 0 || (n % 2 == 0 && k == n / 2) {
                1.0
            } else {
                2.0
            };
            self.full[k] = h * (w * scale);
        }
        self.ifft
            .process_with_scratch(&mut self.full, &mut self.scratch_fft);
        &self.full
    }

    /// Envelope `|z|` of `x` (see [`Self::analytic`]) written into `out` (resized to `len()`).
    pub fn envelope_into(
        &mut self,
        x: &[f64],
        fs: f64,
        band: Option<[f64; 2]>,
        out: &mut Vec<f64>,
    ) {
        let z = self.analytic(x, fs, band);
        out.clear();
        out.extend(z.iter().map(|c| c.norm()));
    }
}

/// Analytic signal of `x` (allocates a plan; use [`HilbertPlan`] for repeated calls).
pub fn analytic_signal(x: &[f64]) -> Vec<Complex64> {
    if x.is_empty() {
        return Vec::new();
    }
    HilbertPlan::new(x.len()).analytic(x, 1.0, None).to_vec()
}

/// Envelope `|analytic(x)|`.
pub fn envelope(x: &[f64]) -> Vec<f64> {
    analytic_signal(x).iter().map(|c| c.norm()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn real_part_is_the_signal_and_cosine_maps_to_sine() {
        // whole periods: the discrete Hilbert transform is exact to rounding (1e-12)
        let n = 256;
        let x: Vec<f64> = (0..n)
            .map(|i| (2.0 * PI * 5.0 * i as f64 / n as f64).cos())
            .collect();
        let z = analytic_signal(&x);
        for (i, c) in z.iter().enumerate() {
            assert!((c.re - x[i]).abs() < 1e-12);
            assert!((c.im - (2.0 * PI * 5.0 * i as f64 / n as f64).sin()).abs() < 1e-12);
        }
        // odd length too
        let x: Vec<f64> = (0..255)
            .map(|i| (2.0 * PI * 7.0 * i as f64 / 255.0).cos())
            .collect();
        let e = envelope(&x);
        assert!(e.iter().all(|v| (v - 1.0).abs() < 1e-12));
    }

    #[test]
    fn band_keeps_only_the_band() {
        // two tones at 50 and 400 Hz; keeping 300-500 Hz leaves the 400 Hz one, envelope 0.5
        let (n, fs) = (1000, 1000.0);
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                (2.0 * PI * 50.0 * t).sin() + 0.5 * (2.0 * PI * 400.0 * t).sin()
            })
            .collect();
        let mut plan = HilbertPlan::new(n);
        let mut e = Vec::new();
        plan.envelope_into(&x, fs, Some([300.0, 500.0]), &mut e);
        assert!(e.iter().all(|v| (v - 0.5).abs() < 1e-12));
    }
}
