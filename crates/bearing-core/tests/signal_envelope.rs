//! Envelope of a known amplitude-modulated tone, and the envelope-spectrum scaling.

use bearing_core::signal::hilbert::{envelope, HilbertPlan};
use bearing_core::signal::spectrum::envelope_spectrum;
use std::f64::consts::PI;

#[test]
fn am_envelope_is_recovered() {
    // x = (1 + m cos(2 pi fm t + p)) cos(2 pi fc t), fc = 1234 Hz, fm = 17 Hz, m = 0.6,
    // 1 s at 8 kHz. The FFT Hilbert transform is exact for a record holding whole periods
    // whose modulation stays below the carrier; what remains is float64 rounding of 8000-point
    // FFTs (~1e-13). We check the 1e-6 away from the ends (first/last 5 %).
    let (fs, n) = (8000.0, 8000);
    let (fc, fm, m) = (1234.0, 17.0, 0.6);
    let want: Vec<f64> = (0..n)
        .map(|i| 1.0 + m * (2.0 * PI * fm * i as f64 / fs + 0.4).cos())
        .collect();
    let x: Vec<f64> = (0..n)
        .map(|i| want[i] * (2.0 * PI * fc * i as f64 / fs).cos())
        .collect();
    let e = envelope(&x);
    let err = (n / 20..n - n / 20)
        .map(|i| (e[i] - want[i]).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-6, "envelope error {err}");

    // same through a band-pass around the carrier (the whole AM signal lies in 1100-1400 Hz)
    let mut plan = HilbertPlan::new(n);
    let mut eb = Vec::new();
    plan.envelope_into(&x, fs, Some([1100.0, 1400.0]), &mut eb);
    let err = (n / 20..n - n / 20)
        .map(|i| (eb[i] - want[i]).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-6, "band-passed envelope error {err}");
}

#[test]
fn am_envelope_non_periodic_record_is_accurate_away_from_the_ends() {
    // Not whole periods (fc = 1234.37 Hz, fm = 17.3 Hz): the FFT sees a wrap-around jump, whose
    // error decays away from the ends; in the middle half of a 2^16-sample record it is below
    // 1e-3 of the carrier amplitude. This documents the edge behaviour; the window option lets a
    // user drop the ends.
    let (fs, n) = (8000.0, 1 << 16);
    let (fc, fm, m) = (1234.37, 17.3, 0.6);
    let want: Vec<f64> = (0..n)
        .map(|i| 1.0 + m * (2.0 * PI * fm * i as f64 / fs).cos())
        .collect();
    let x: Vec<f64> = (0..n)
        .map(|i| want[i] * (2.0 * PI * fc * i as f64 / fs).cos())
        .collect();
    let e = envelope(&x);
    let err = (n / 4..3 * n / 4)
        .map(|i| (e[i] - want[i]).abs())
        .fold(0.0, f64::max);
    assert!(err < 1e-3, "envelope error {err}");
}

#[test]
fn envelope_spectrum_reads_the_modulation_depth() {
    // The AM tone above has an envelope line of amplitude m at fm: the documented scaling
    // (Hann, coherent-gain corrected, single-sided) reads m on the bin; 1e-9 is rounding.
    let (fs, n) = (8000.0, 8000);
    let x: Vec<f64> = (0..n)
        .map(|i| {
            let t = i as f64 / fs;
            (1.0 + 0.6 * (2.0 * PI * 17.0 * t).cos()) * (2.0 * PI * 1234.0 * t).cos()
        })
        .collect();
    let s = envelope_spectrum(&x, fs, None);
    assert_eq!(s.df, 1.0);
    assert!((s.amplitude[17] - 0.6).abs() < 1e-9, "{}", s.amplitude[17]);
}
