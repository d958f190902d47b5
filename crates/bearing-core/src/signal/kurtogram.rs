//! Spectral kurtosis over a 1/3-binary tree of frequency bands: the kurtogram of Antoni
//! (2007, "Fast computation of the kurtogram for the detection of transient faults", MSSP
//! 21: 108-124), the second way to choose the band a fault's impulses live in (the first is
//! the DTCWT level of largest kurtosis, [`super::analysis`]).
//!
//! Level `k` splits `[0, fs/2]` into `2^k` bands, and the intermediate level `k + log2 3 -
//! 1` (written `k + 0.6`) into `3 * 2^(k-1)`, as Antoni's tree does. Each band's complex
//! envelope is taken with an ideal (rectangular) band-pass in the frequency domain: the
//! band's bins of one FFT of the signal (extended by its mirror image, so that the FFT's
//! periodic wrap has no step), shifted to baseband and transformed back at the band's own,
//! decimated, length. That costs one FFT of twice the signal plus, per level, inverse
//! FFTs whose lengths add up to twice the signal's, and it is the kurtogram of an exact filter
//! bank where Antoni's fast algorithm uses short quasi-analytic FIR filters (whose overlap
//! it corrects for); band edges and the kurtosis of each band are the same in intent.
//!
//! Spectral kurtosis of a band's complex envelope `c` (its mean removed): `K = <|c|^4> /
//! <|c|^2>^2 - 2`, zero
//! for stationary Gaussian noise (complex), large when the band carries sparse impulses.

use rustfft::num_complex::Complex64;
use rustfft::FftPlanner;

/// One band of the tree.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    /// Level in the 1/3-binary tree: 0, 1, 1.6, 2, 2.6, ... (the number of halvings of the
    /// full band, log2 of `fs / 2 / bandwidth`), -.
    pub level: f64,
    /// Lower and upper edge, Hz.
    pub low_hz: f64,
    pub high_hz: f64,
    /// Spectral kurtosis of the band's complex envelope, -.
    pub kurtosis: f64,
}

impl Band {
    pub fn center_hz(&self) -> f64 {
        0.5 * (self.low_hz + self.high_hz)
    }
    pub fn bandwidth_hz(&self) -> f64 {
        self.high_hz - self.low_hz
    }
}

/// The kurtogram: every band of every level, and the one of largest kurtosis.
#[derive(Debug, Clone, PartialEq)]
pub struct Kurtogram {
    /// Per level (in increasing order of level), its bands from low to high frequency.
    pub levels: Vec<Vec<Band>>,
    pub best: Band,
}

impl Kurtogram {
    /// The band of largest kurtosis among those at least `min_bandwidth_hz` wide (the
    /// whole band if none is): an envelope shows modulation only up to its band's width,
    /// so a band narrower than the fault frequencies sought cannot show them, however
    /// impulsive it is.
    pub fn best_at_least(&self, min_bandwidth_hz: f64) -> Band {
        self.levels
            .iter()
            .flatten()
            .filter(|b| b.bandwidth_hz() >= min_bandwidth_hz)
            .copied()
            .max_by(|a, b| a.kurtosis.total_cmp(&b.kurtosis))
            .unwrap_or(self.levels[0][0])
    }

    /// The band of largest kurtosis among those at least `min_bandwidth_hz` wide that do
    /// not overlap `first` (none if no such band exists): a second resonance the impulses
    /// excite, as a compound fault's two defects may excite two (the kurtogram's
    /// counterpart of the DTCWT's runner-up component).
    pub fn runner_up_at_least(&self, min_bandwidth_hz: f64, first: &Band) -> Option<Band> {
        self.levels
            .iter()
            .flatten()
            .filter(|b| b.bandwidth_hz() >= min_bandwidth_hz)
            .filter(|b| b.high_hz <= first.low_hz || b.low_hz >= first.high_hz)
            .copied()
            .max_by(|a, b| a.kurtosis.total_cmp(&b.kurtosis))
    }
}

/// Why no kurtogram can be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum KurtogramError {
    #[error("levels: must be in 1..=12 (got {0})")]
    Levels(usize),
    #[error("samples: {n} samples is too short for {levels} levels (need >= {need})")]
    TooShort {
        n: usize,
        levels: usize,
        need: usize,
    },
    #[error("sample_rate: must be > 0 Hz (got {0})")]
    SampleRate(f64),
}

/// Fewest samples for `levels` levels: the narrowest band must keep 16 samples of envelope.
pub fn min_length(levels: usize) -> usize {
    16 << (levels + 1)
}

/// The kurtogram of `x` sampled at `fs` Hz over levels 0 to `levels` (with the
/// intermediate levels between them).
pub fn kurtogram(x: &[f64], fs: f64, levels: usize) -> Result<Kurtogram, KurtogramError> {
    if !(1..=12).contains(&levels) {
        return Err(KurtogramError::Levels(levels));
    }
    if !(fs.is_finite() && fs > 0.0) {
        return Err(KurtogramError::SampleRate(fs));
    }
    let n = x.len();
    if n < min_length(levels) {
        return Err(KurtogramError::TooShort {
            n,
            levels,
            need: min_length(levels),
        });
    }
    let mut planner = FftPlanner::<f64>::new();
    let mean = x.iter().sum::<f64>() / n as f64;
    // The record and its mirror image, `2n` samples: an FFT treats its input as periodic,
    // and the plain record's wrap from the last sample to the first is a step, a broadband
    // impulse that gave near-empty bands next to Nyquist a spectral kurtosis in the
    // hundreds or thousands (measured against Antoni's reference, docs/lab/kurtogram-reference.md).
    // The mirrored record wraps without a step.
    let mut spectrum: Vec<Complex64> = x
        .iter()
        .chain(x.iter().rev())
        .map(|&v| Complex64::new(v - mean, 0.0))
        .collect();
    let m = spectrum.len();
    planner.plan_fft_forward(m).process(&mut spectrum);
    // bins 0..=m/2 hold [0, fs/2]
    let half = m / 2;

    let mut out: Vec<Vec<Band>> = Vec::new();
    let mut buf: Vec<Complex64> = Vec::new();
    let mut split = |parts: usize, level: f64| -> Vec<Band> {
        (0..parts)
            .map(|i| {
                let lo = i * half / parts;
                let hi = ((i + 1) * half / parts).max(lo + 1);
                buf.clear();
                buf.extend_from_slice(&spectrum[lo..hi]);
                planner.plan_fft_inverse(buf.len()).process(&mut buf);
                // the first half of the band signal is the record, the second its mirror
                let record = &buf[..buf.len().div_ceil(2)];
                Band {
                    level,
                    low_hz: lo as f64 * fs / m as f64,
                    high_hz: hi as f64 * fs / m as f64,
                    kurtosis: complex_kurtosis(record),
                }
            })
            .collect()
    };
    out.push(split(1, 0.0));
    for k in 1..=levels {
        out.push(split(1 << k, k as f64));
        if k < levels {
            // between 2^k and 2^(k+1) bands: 3 * 2^(k-1)
            out.push(split(3 << (k - 1), k as f64 + 3f64.log2() - 1.0));
        }
    }
    let best = out
        .iter()
        .flatten()
        .copied()
        .max_by(|a, b| a.kurtosis.total_cmp(&b.kurtosis))
        .expect("at least one band");
    Ok(Kurtogram { levels: out, best })
}

/// `<|c - <c>|^4> / <|c - <c>|^2>^2 - 2` (the band signal's mean removed, as Antoni
/// does); 0 for a band with no energy.
fn complex_kurtosis(c: &[Complex64]) -> f64 {
    let mean = c.iter().sum::<Complex64>() / c.len() as f64;
    let (mut m2, mut m4) = (0.0, 0.0);
    for v in c {
        let p = (v - mean).norm_sqr();
        m2 += p;
        m4 += p * p;
    }
    let n = c.len() as f64;
    m2 /= n;
    m4 /= n;
    if m2 <= 0.0 {
        return 0.0;
    }
    m4 / (m2 * m2) - 2.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Deterministic Gaussian noise (xorshift64* and Box-Muller).
    fn noise(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        let mut u = || {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            ((s.wrapping_mul(0x2545F4914F6CDD1D) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        (0..n)
            .map(|_| (-2.0 * u().ln()).sqrt() * (2.0 * PI * u()).cos())
            .collect()
    }

    #[test]
    fn gaussian_noise_has_no_spectral_kurtosis() {
        let x = noise(1 << 16, 7);
        let k = kurtogram(&x, 20_000.0, 5).unwrap();
        // the estimate's standard deviation is about 2 / sqrt(samples in the band): the
        // narrowest band here keeps 1024 samples, so |K| < 0.35 is over five of them
        for b in k.levels.iter().flatten() {
            assert!(b.kurtosis.abs() < 0.35, "{b:?}");
        }
    }

    #[test]
    fn impulses_ringing_at_a_resonance_are_found_in_its_band() {
        // 3.2 kHz resonance struck 100 times a second, buried in noise of the same RMS
        let fs = 20_000.0;
        let n = 1 << 16;
        let mut x = noise(n, 11);
        let (fr, zeta) = (3_200.0, 0.03);
        for k in 0..(n as f64 / fs * 100.0) as usize {
            let t0 = k as f64 / 100.0;
            let i0 = (t0 * fs).ceil() as usize;
            for (i, v) in x.iter_mut().enumerate().skip(i0).take(200) {
                let t = i as f64 / fs - t0;
                *v += 4.0 * (-2.0 * PI * zeta * fr * t).exp() * (2.0 * PI * fr * t).sin();
            }
        }
        let k = kurtogram(&x, fs, 6).unwrap();
        let b = k.best;
        assert!(b.low_hz <= fr && fr <= b.high_hz, "{b:?}");
        // narrower than the whole band, and impulsive: the estimate's standard deviation
        // for noise alone is about 2 / sqrt(samples in the band), 0.02 for the 8192 of a
        // level-3 band, so K > 1 is far outside what noise gives (measured: 1.92)
        assert!(b.level >= 1.0 && b.kurtosis > 1.0, "{b:?}");
        // and the whole band, where the noise outside the resonance dilutes the impulses,
        // has less
        assert!(k.levels[0][0].kurtosis < b.kurtosis, "{:?}", k.levels[0][0]);
    }

    /// Two resonances struck at two rates (a compound fault's two defects): the best band
    /// holds one, the runner-up the other, and the two do not overlap.
    #[test]
    fn the_runner_up_band_finds_a_second_resonance() {
        let fs = 20_000.0;
        let n = 1 << 16;
        let mut x = noise(n, 13);
        let mut strike = |fr: f64, rate: f64, amp: f64| {
            for k in 0..(n as f64 / fs * rate) as usize {
                let t0 = k as f64 / rate;
                let i0 = (t0 * fs).ceil() as usize;
                for (i, v) in x.iter_mut().enumerate().skip(i0).take(200) {
                    let t = i as f64 / fs - t0;
                    *v += amp * (-2.0 * PI * 0.03 * fr * t).exp() * (2.0 * PI * fr * t).sin();
                }
            }
        };
        strike(3_200.0, 100.0, 4.0);
        strike(7_700.0, 137.0, 3.0);
        let k = kurtogram(&x, fs, 6).unwrap();
        // bands at least 600 Hz wide (four harmonics of 137 Hz and more)
        let best = k.best_at_least(600.0);
        let second = k.runner_up_at_least(600.0, &best).unwrap();
        let holds = |b: &Band, f: f64| b.low_hz <= f && f <= b.high_hz;
        assert!(
            (holds(&best, 3_200.0) && holds(&second, 7_700.0))
                || (holds(&best, 7_700.0) && holds(&second, 3_200.0)),
            "{best:?} {second:?}"
        );
        assert!(second.high_hz <= best.low_hz || second.low_hz >= best.high_hz);
        assert!(
            second.bandwidth_hz() >= 600.0 && second.kurtosis > 1.0,
            "{second:?}"
        );
    }

    #[test]
    fn the_tree_has_antonis_band_counts() {
        let x = noise(1 << 12, 3);
        let k = kurtogram(&x, 1_000.0, 3).unwrap();
        let counts: Vec<usize> = k.levels.iter().map(Vec::len).collect();
        assert_eq!(counts, [1, 2, 3, 4, 6, 8]);
        let levels: Vec<f64> = k
            .levels
            .iter()
            .map(|l| (l[0].level * 10.0).round() / 10.0)
            .collect();
        assert_eq!(levels, [0.0, 1.0, 1.6, 2.0, 2.6, 3.0]);
        // each level tiles [0, fs/2] without gaps
        for l in &k.levels {
            assert_eq!(l[0].low_hz, 0.0);
            assert!((l.last().unwrap().high_hz - 500.0).abs() < 1e-9);
            for w in l.windows(2) {
                assert_eq!(w[0].high_hz, w[1].low_hz);
            }
        }
    }

    #[test]
    fn bad_arguments_are_named() {
        assert_eq!(
            kurtogram(&[0.0; 10], 1.0, 0),
            Err(KurtogramError::Levels(0))
        );
        assert!(matches!(
            kurtogram(&[0.0; 10], 1.0, 3),
            Err(KurtogramError::TooShort { .. })
        ));
        assert_eq!(
            kurtogram(&[0.0; 4096], -1.0, 3),
            Err(KurtogramError::SampleRate(-1.0))
        );
    }
}
