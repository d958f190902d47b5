//! Envelope spectrum.
//!
//! Scaling and window (what every [`Spectrum`] produced here means):
//!
//! 1. the envelope `e = |analytic(x)|` is computed over the whole analysis record
//!    (see [`super::hilbert`]), optionally from a band-passed signal;
//! 2. its mean is removed (the DC line would otherwise dwarf everything);
//! 3. it is multiplied by a periodic Hann window `w[i] = 0.5 (1 - cos(2 pi i / n))`;
//! 4. `amplitude[k] = c_k |E[k]| / sum(w)`, `E` the real FFT (no zero padding), with `c_k = 2`
//!    except `c_0 = 1` and, for even `n`, `c_{n/2} = 1`: single-sided amplitude corrected for
//!    the window's coherent gain, so a sinusoidal envelope component `A cos(2 pi f t)` with `f`
//!    on a bin reads `A` (in the unit of the signal); between bins the Hann scalloping loss is
//!    at most 1.42 dB.
//!
//! Bin `k` is at `k * df` with `df = fs / n`.

use std::sync::Arc;

use realfft::{RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex64;
use serde::{Deserialize, Serialize};

use super::hilbert::HilbertPlan;

/// A single-sided amplitude spectrum.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct Spectrum {
    /// Bin spacing, Hz: bin `k` is at `k * df`.
    pub df: f64,
    /// Amplitude per bin, in the unit of the analysed quantity (e.g. g or m/s^2): Hann window,
    /// coherent-gain corrected, single-sided (module documentation).
    pub amplitude: Vec<f64>,
}

impl Spectrum {
    /// Frequency of bin `k`, Hz.
    pub fn frequency(&self, k: usize) -> f64 {
        k as f64 * self.df
    }

    /// Number of bins.
    pub fn len(&self) -> usize {
        self.amplitude.len()
    }

    /// True if there are no bins.
    pub fn is_empty(&self) -> bool {
        self.amplitude.is_empty()
    }
}

/// Planned Hann amplitude spectrum for records of one length.
pub struct SpectrumPlan {
    n: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    window: Vec<f64>,
    window_sum: f64,
    input: Vec<f64>,
    output: Vec<Complex64>,
    scratch: Vec<Complex64>,
}

impl SpectrumPlan {
    /// Plan for records of `n >= 2` samples.
    pub fn new(n: usize) -> Self {
        assert!(n >= 2, "a spectrum needs at least two samples");
        Self::with_forward(RealFftPlanner::<f64>::new().plan_fft_forward(n))
    }

    /// Plan around an existing forward real FFT (shared with other users of the same length).
    pub fn with_forward(r2c: Arc<dyn RealToComplex<f64>>) -> Self {
        let n = r2c.len();
        assert!(n >= 2, "a spectrum needs at least two samples");
        let window = hann(n);
        let window_sum = window.iter().sum();
        SpectrumPlan {
            n,
            input: r2c.make_input_vec(),
            output: r2c.make_output_vec(),
            scratch: r2c.make_scratch_vec(),
            r2c,
            window,
            window_sum,
        }
    }

    /// Amplitude spectrum of `x` (mean removed, Hann window, module-level scaling), `fs` in Hz.
    pub fn amplitude(&mut self, x: &[f64], fs: f64) -> Spectrum {
        let n = self.n;
        assert_eq!(x.len(), n, "record length differs from the plan");
        let mean = x.iter().sum::<f64>() / n as f64;
        for ((d, v), w) in self.input.iter_mut().zip(x).zip(&self.window) {
            *d = (v - mean) * w;
        }
        self.r2c
            .process_with_scratch(&mut self.input, &mut self.output, &mut self.scratch)
            .expect("buffer sizes come from the plan");
        let amplitude = single_sided(&self.output, n, self.window_sum);
        Spectrum {
            df: fs / n as f64,
            amplitude,
        }
    }
}

/// Periodic Hann window of `n` samples, `0.5 (1 - cos(2 pi i / n))`.
fn hann(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 0.5 * (1.0 - (2.0 * std::f64::consts::PI * i as f64 / n as f64).cos()))
        .collect()
}

/// Single-sided amplitudes of the half spectrum `c` of `n` windowed samples (module docs).
fn single_sided(c: &[Complex64], n: usize, window_sum: f64) -> Vec<f64> {
    c.iter()
        .enumerate()
        .map(|(k, c)| {
            let single = if k == 0 || (n.is_multiple_of(2) && k == n / 2) {
                1.0
            } else {
                2.0
            };
            // sqrt(re^2 + im^2), not hypot: no overflow at these magnitudes, and faster
            single * (c.re * c.re + c.im * c.im).sqrt() / window_sum
        })
        .collect()
}

/// Envelope spectra of records of one length, transforms planned once and buffers reused:
/// the spectrum of the envelope runs through the Hilbert plan's own forward transform and
/// buffers (one set of `n`-sized buffers, not two).
pub struct EnvelopeSpectrumPlan {
    hilbert: HilbertPlan,
    window: Vec<f64>,
    window_sum: f64,
}

impl EnvelopeSpectrumPlan {
    /// Plan for records of `n >= 2` samples.
    pub fn new(n: usize) -> Self {
        assert!(n >= 2, "a spectrum needs at least two samples");
        let r2c = RealFftPlanner::<f64>::new().plan_fft_forward(n);
        let window = hann(n);
        EnvelopeSpectrumPlan {
            hilbert: HilbertPlan::with_forward(r2c),
            window_sum: window.iter().sum(),
            window,
        }
    }

    /// Envelope spectrum of `x` sampled at `fs` Hz, the envelope optionally taken from the
    /// band `[f0, f1]` Hz only.
    pub fn compute(&mut self, x: &[f64], fs: f64, band: Option<[f64; 2]>) -> Spectrum {
        let n = x.len();
        self.hilbert.compute_envelope(x, fs, band);
        let h = &mut self.hilbert;
        let mean = h.im.iter().sum::<f64>() / n as f64;
        // the forward transform's buffers are free again: window the envelope into them
        for ((d, v), w) in h.input.iter_mut().zip(&h.im).zip(&self.window) {
            *d = (v - mean) * w;
        }
        h.r2c
            .process_with_scratch(&mut h.input, &mut h.half, &mut h.scratch)
            .expect("buffer sizes come from the plan");
        Spectrum {
            df: fs / n as f64,
            amplitude: single_sided(&h.half, n, self.window_sum),
        }
    }
}

/// Envelope spectrum of `x` (plans a transform; use [`EnvelopeSpectrumPlan`] for many records).
pub fn envelope_spectrum(x: &[f64], fs: f64, band: Option<[f64; 2]>) -> Spectrum {
    EnvelopeSpectrumPlan::new(x.len()).compute(x, fs, band)
}

/// RMS of `x` counting only its content between DC (excluded) and `fmax` (an FFT brick-wall
/// low-pass, by Parseval over the kept bins), in the unit of `x`.
pub fn band_rms(x: &[f64], fs: f64, fmax: f64) -> f64 {
    let n = x.len();
    if n == 0 {
        return 0.0;
    }
    let fwd = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut input = x.to_vec();
    let mut spec = fwd.make_output_vec();
    fwd.process(&mut input, &mut spec)
        .expect("buffers sized by the plan");
    let mut e = 0.0;
    for (k, c) in spec.iter().enumerate().skip(1) {
        if k as f64 * fs / n as f64 > fmax {
            break;
        }
        // one-sided bins stand for two, except Nyquist
        e += if 2 * k == n { 1.0 } else { 2.0 } * c.norm_sqr();
    }
    (e / (n as f64 * n as f64)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn band_rms_keeps_only_the_band() {
        // offset 5 + 0.8 cos(100 Hz) + 0.6 cos(3 kHz) on bins: below 1 kHz only the 100 Hz
        // line counts (0.8 / sqrt 2); below 5 kHz both (sqrt(0.32 + 0.18) = sqrt 0.5).
        let (n, fs) = (10_000, 10_000.0);
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                5.0 + 0.8 * (2.0 * PI * 100.0 * t).cos() + 0.6 * (2.0 * PI * 3000.0 * t).cos()
            })
            .collect();
        assert!((band_rms(&x, fs, 1000.0) - 0.8 / 2f64.sqrt()).abs() < 1e-12);
        assert!((band_rms(&x, fs, 5000.0) - 0.5f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn on_bin_sinusoid_reads_its_amplitude() {
        let (n, fs) = (1000, 1000.0);
        let x: Vec<f64> = (0..n)
            .map(|i| 0.7 * (2.0 * PI * 50.0 * i as f64 / fs + 0.3).cos() + 2.0)
            .collect();
        let s = SpectrumPlan::new(n).amplitude(&x, fs);
        assert_eq!(s.df, 1.0);
        // exact on a bin up to rounding: 1e-12; mean removed so DC ~ 0
        assert!((s.amplitude[50] - 0.7).abs() < 1e-12, "{}", s.amplitude[50]);
        assert!(s.amplitude[0] < 1e-12);
    }

    #[test]
    fn envelope_spectrum_shows_the_modulation() {
        // carrier 2 kHz, 30% modulation at 37 Hz: envelope 1 + 0.3 cos -> line of 0.3 at 37 Hz
        let (n, fs) = (10_000, 10_000.0);
        let x: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                (1.0 + 0.3 * (2.0 * PI * 37.0 * t).cos()) * (2.0 * PI * 2000.0 * t).cos()
            })
            .collect();
        let s = envelope_spectrum(&x, fs, None);
        assert!((s.amplitude[37] - 0.3).abs() < 1e-9);
        let others = s
            .amplitude
            .iter()
            .enumerate()
            .filter(|(k, _)| (*k as i64 - 37).abs() > 1)
            .map(|(_, a)| *a);
        assert!(others.fold(0.0, f64::max) < 1e-9);
    }
}
