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

use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex64;

/// Planned transforms and buffers for signals of one length; reuse it across signals.
///
/// Both parts of the analytic signal are real, so each is one inverse *real* FFT of the
/// half spectrum: `Re z = IFFT(H X)` is `x` itself without a band (no transform at all), and
/// `Im z = IFFT(-j H X)` with the DC and Nyquist bins zeroed (they are real). A real inverse
/// FFT of `n` points runs a complex FFT of `n / 2`: against one complex inverse of `n`
/// points this halves the transform's work and its buffers (a 2^20-sample record needed
/// 25 MB of twiddles and 32 MB of complex buffers for it).
pub struct HilbertPlan {
    n: usize,
    pub(super) r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    /// Forward transform's input; free after [`Self::compute_envelope`].
    pub(super) input: Vec<f64>,
    /// Forward transform's output (then the inverse's input); free after
    /// [`Self::compute_envelope`].
    pub(super) half: Vec<Complex64>,
    work: Vec<Complex64>,
    re: Vec<f64>,
    /// Imaginary part of the analytic signal; the envelope after
    /// [`Self::compute_envelope`].
    pub(super) im: Vec<f64>,
    /// One scratch buffer for both transforms (they never run at once).
    pub(super) scratch: Vec<Complex64>,
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
        let c2r = RealFftPlanner::<f64>::new().plan_fft_inverse(n);
        HilbertPlan {
            n,
            input: r2c.make_input_vec(),
            half: r2c.make_output_vec(),
            work: Vec::new(),
            re: Vec::new(),
            im: c2r.make_output_vec(),
            scratch: vec![
                Complex64::new(0.0, 0.0);
                r2c.get_scratch_len().max(c2r.get_scratch_len())
            ],
            r2c,
            c2r,
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

    /// Real and imaginary parts of the analytic signal of `x` (length `len()`), optionally
    /// band-passed to `band = [f0, f1]` Hz at sample rate `fs` Hz. They live in the plan
    /// until the next call; without a band the real part is `x` itself.
    fn parts<'a>(
        &'a mut self,
        x: &'a [f64],
        fs: f64,
        band: Option<[f64; 2]>,
    ) -> (&'a [f64], &'a [f64]) {
        let n = self.n;
        assert_eq!(x.len(), n, "signal length differs from the plan");
        self.input.copy_from_slice(x);
        self.r2c
            .process_with_scratch(&mut self.input, &mut self.half, &mut self.scratch)
            .expect("buffer sizes come from the plan");
        let df = fs / n as f64;
        let keep =
            |k: usize| band.is_none_or(|[f0, f1]| (k as f64 * df) >= f0 && (k as f64 * df) <= f1);
        let scale = 1.0 / n as f64;
        let last = self.half.len() - 1;
        let nyquist = n.is_multiple_of(2);
        // real part: the band-passed signal (x itself without a band)
        if band.is_some() {
            // the half spectrum is needed twice: work on a copy (allocated on first use)
            self.work.resize(self.half.len(), Complex64::new(0.0, 0.0));
            for (k, (w, h)) in self.work.iter_mut().zip(&self.half).enumerate() {
                *w = if keep(k) {
                    h * scale
                } else {
                    Complex64::new(0.0, 0.0)
                };
            }
            // DC and Nyquist of a real signal are real
            self.work[0].im = 0.0;
            if nyquist {
                self.work[last].im = 0.0;
            }
            self.re.resize(n, 0.0);
            self.c2r
                .process_with_scratch(&mut self.work, &mut self.re, &mut self.scratch)
                .expect("buffer sizes come from the plan");
        }
        // imaginary part: -j X on the positive frequencies, DC and Nyquist zero; in place,
        // the half spectrum is not needed again
        for (k, h) in self.half.iter_mut().enumerate() {
            *h = if keep(k) {
                Complex64::new(h.im * scale, -h.re * scale)
            } else {
                Complex64::new(0.0, 0.0)
            };
        }
        self.half[0] = Complex64::new(0.0, 0.0);
        if nyquist {
            self.half[last] = Complex64::new(0.0, 0.0);
        }
        self.c2r
            .process_with_scratch(&mut self.half, &mut self.im, &mut self.scratch)
            .expect("buffer sizes come from the plan");
        let re: &[f64] = if band.is_some() { &self.re } else { x };
        (re, &self.im)
    }

    /// Analytic signal of `x` (see [`Self::envelope_into`] for `fs` and `band`).
    pub fn analytic(&mut self, x: &[f64], fs: f64, band: Option<[f64; 2]>) -> Vec<Complex64> {
        let (re, im) = self.parts(x, fs, band);
        re.iter()
            .zip(im)
            .map(|(&r, &i)| Complex64::new(r, i))
            .collect()
    }

    /// Envelope `|z|` of `x` written into `out` (resized to `len()`), `z` the analytic signal,
    /// optionally band-passed to `band = [f0, f1]` Hz at sample rate `fs` Hz.
    pub fn envelope_into(
        &mut self,
        x: &[f64],
        fs: f64,
        band: Option<[f64; 2]>,
        out: &mut Vec<f64>,
    ) {
        self.compute_envelope(x, fs, band);
        out.clear();
        out.extend_from_slice(&self.im);
    }

    /// The envelope as [`Self::envelope_into`] computes it, left in `self.im` (no copy;
    /// valid until the next call).
    pub(super) fn compute_envelope(&mut self, x: &[f64], fs: f64, band: Option<[f64; 2]>) {
        self.parts(x, fs, band);
        let re: &[f64] = if band.is_some() { &self.re } else { x };
        // sqrt(re^2 + im^2): no overflow is possible at signal amplitudes, so libm's
        // hypot (a tenth of the whole analysis's instructions) is not needed
        for (i, r) in self.im.iter_mut().zip(re) {
            *i = (r * r + *i * *i).sqrt();
        }
    }
}

/// Analytic signal of `x` (allocates a plan; use [`HilbertPlan`] for repeated calls).
pub fn analytic_signal(x: &[f64]) -> Vec<Complex64> {
    if x.is_empty() {
        return Vec::new();
    }
    HilbertPlan::new(x.len()).analytic(x, 1.0, None)
}

/// Envelope `|analytic(x)|`.
pub fn envelope(x: &[f64]) -> Vec<f64> {
    if x.is_empty() {
        return Vec::new();
    }
    let mut out = Vec::new();
    HilbertPlan::new(x.len()).envelope_into(x, 1.0, None, &mut out);
    out
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
