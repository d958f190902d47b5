//! Computed order tracking: the analysis of a signal whose shaft speed varies.
//!
//! A fault line is a fixed number of events per shaft revolution (its *order*: BPFO / f_r,
//! ...), so when the speed varies over the record the line smears across the spectrum in
//! Hz but stays sharp over shaft angle. The signal is therefore resampled at constant
//! angle increments (Fyfe and Munck, MSSP 11, 1997; Randall, *Vibration-based condition
//! monitoring*, 2011, sec. 3.6) and the whole pipeline (envelope spectra, DTCWT, kurtogram,
//! verdict) runs on the resampled signal as if it had been sampled in time at the mean
//! speed: a frequency of that report is an order times the mean shaft frequency, so its
//! lines read in Hz at the mean speed and the fault orders are reported beside them.
//!
//! Resampling: the fractional sample at each target angle comes from the angle track
//! (linear between samples: the speed changes little within one sample), the signal value
//! there from a cubic (Catmull-Rom) interpolation of the samples. The angle step is chosen
//! so that the slowest stretch of the window keeps its sample density (no stretch is
//! thinned, so none aliases), up to [`MAX_UPSAMPLING`] times the input's samples.

use std::f64::consts::TAU;
use std::sync::atomic::AtomicBool;

use super::analysis::{
    analyze_with, window_range, AnalysisError, AnalysisOptions, AnalysisOutput, LevelSpectra,
};
use super::frequencies::KinematicGeometry;
use super::order_tracking_report::{FaultOrders, OrderTracking};
use super::shaft_angle::ShaftAngle;

/// Most samples the resampled signal may hold, per input sample of the window: a run-up
/// from a tenth of the speed would otherwise ask for ten times the samples.
pub const MAX_UPSAMPLING: f64 = 8.0;

/// Shaft frequency over the window `[i0, i1)` of `angle`, Hz: slowest, fastest (over strides
/// of a hundredth of the window, so a tachometer's quantisation does not read as speed
/// changes) and mean.
fn speed_range(angle: &[f64], fs: f64) -> ([f64; 2], f64) {
    let n = angle.len();
    let stride = (n / 100).max(1);
    let (mut lo, mut hi) = (f64::INFINITY, 0.0_f64);
    let mut i = 0;
    while i + stride < n {
        let w = (angle[i + stride] - angle[i]) / (stride as f64 / fs) / TAU;
        lo = lo.min(w);
        hi = hi.max(w);
        i += stride;
    }
    let mean = (angle[n - 1] - angle[0]) / ((n - 1) as f64 / fs) / TAU;
    if !lo.is_finite() {
        lo = mean;
        hi = mean;
    }
    ([lo, hi], mean)
}

/// `x` resampled at `m` angles equally spaced from `angle[0]` to `angle[last]`.
fn resample(x: &[f64], angle: &[f64], m: usize) -> Vec<f64> {
    let n = x.len();
    let (a0, a1) = (angle[0], angle[n - 1]);
    let step = (a1 - a0) / (m - 1) as f64;
    // one sample beyond either end extrapolated linearly (a clamped end would make the
    // cubic first-order there)
    let at = |i: isize| {
        if i < 0 {
            2.0 * x[0] - x[1]
        } else if i as usize >= n {
            2.0 * x[n - 1] - x[n - 2]
        } else {
            x[i as usize]
        }
    };
    let mut j = 0usize;
    (0..m)
        .map(|k| {
            let target = a0 + k as f64 * step;
            while j + 2 < n && angle[j + 1] <= target {
                j += 1;
            }
            let span = angle[j + 1] - angle[j];
            let t = if span > 0.0 {
                ((target - angle[j]) / span).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let i = j as isize;
            let (p0, p1, p2, p3) = (at(i - 1), at(i), at(i + 1), at(i + 2));
            // Catmull-Rom
            p1 + 0.5
                * t
                * (p2 - p0
                    + t * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3 + t * (3.0 * (p1 - p2) + p3 - p0)))
        })
        .collect()
}

/// [`super::analysis::analyze_with`] on `signal` resampled to constant shaft angle
/// (`angle`, one value per sample): for records whose speed varies over the window
/// (`opts.window`, in s of the input). The report's `order_tracking` says so, its
/// frequencies are at the mean speed, and the verdict's summary ends with the orders.
pub fn analyze_tracked(
    signal: &[f64],
    fs: f64,
    geometry: &KinematicGeometry,
    angle: &ShaftAngle,
    opts: &AnalysisOptions,
    cancel: Option<&AtomicBool>,
    spectra: LevelSpectra,
) -> Result<AnalysisOutput, AnalysisError> {
    let invalid = |field: &str, message: String| AnalysisError::Invalid {
        field: field.into(),
        message,
    };
    if !(fs.is_finite() && fs > 0.0) {
        return Err(invalid("sample_rate", format!("must be > 0 Hz (got {fs})")));
    }
    let a = angle.radians();
    if a.len() != signal.len() {
        return Err(invalid(
            "shaft_angle",
            format!("has {} samples, the signal {}", a.len(), signal.len()),
        ));
    }
    if let Some(index) = signal.iter().position(|v| !v.is_finite()) {
        return Err(AnalysisError::NonFinite { index });
    }
    let (i0, i1) = window_range(opts, fs, signal.len())?;
    let (x, a) = (&signal[i0..i1], &a[i0..i1]);
    let revolutions = (a[a.len() - 1] - a[0]) / TAU;
    if revolutions < 1.0 {
        return Err(invalid(
            "shaft_angle",
            format!("the shaft turns {revolutions:.3} revolutions in the window, order tracking needs at least one"),
        ));
    }
    let ([lo, hi], mean) = speed_range(a, fs);
    // keep the slowest stretch's density, within MAX_UPSAMPLING
    let density = fs / lo.max(mean / MAX_UPSAMPLING);
    let m = ((revolutions * density).round() as usize).max(x.len());
    let resampled = resample(x, a, m);
    let samples_per_revolution = (m - 1) as f64 / revolutions;
    let fs_tracked = samples_per_revolution * mean;
    let tracked_opts = AnalysisOptions {
        window: None,
        ..opts.clone()
    };
    let mut out = analyze_with(
        &resampled,
        fs_tracked,
        geometry,
        mean,
        &tracked_opts,
        cancel,
        spectra,
    )?;
    let t = &out.report.theory;
    let tracking = OrderTracking {
        mean_shaft_hz: mean,
        shaft_hz_range: [lo, hi],
        revolutions,
        samples_per_revolution,
        orders: FaultOrders {
            bpfo: t.bpfo / mean,
            bpfi: t.bpfi / mean,
            bsf: t.bsf / mean,
            ftf: t.ftf / mean,
        },
    };
    out.report.window = [i0 as f64 / fs, i1 as f64 / fs];
    if let Some(v) = out.report.verdict.as_mut() {
        v.summary = format!("{}; {}", v.summary, tracking.clause());
    }
    out.report.order_tracking = Some(tracking);
    Ok(out)
}

/// Whether a speed range smears the verdict's highest line over more than one spectral
/// bin of a `duration` s window: its frequency moves by `f_line (hi - lo) / mean`, the bins
/// are `1 / duration` wide. Below that, the spectrum in Hz is as sharp as an order spectrum.
pub fn speed_varies(range_hz: [f64; 2], mean_hz: f64, highest_line_hz: f64, duration: f64) -> bool {
    mean_hz > 0.0 && highest_line_hz * (range_hz[1] - range_hz[0]) / mean_hz * duration > 1.0
}

/// [`speed_varies`] for an angle track over `[i0, i1)` at `fs`.
pub fn angle_speed_varies(angle: &[f64], fs: f64, highest_line_hz: f64) -> bool {
    if angle.len() < 2 {
        return false;
    }
    let (range, mean) = speed_range(angle, fs);
    speed_varies(range, mean, highest_line_hz, (angle.len() - 1) as f64 / fs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_a_chirp_at_constant_angle_gives_a_tone() {
        // x = sin(k theta(t)) with theta accelerating: at constant angle steps it is a pure
        // sinusoid of k cycles per radian
        let fs = 10_000.0;
        let n = 20_000;
        let theta: Vec<f64> = (0..n)
            .map(|i| {
                let t = i as f64 / fs;
                TAU * (10.0 * t + 0.5 * 20.0 * t * t)
            })
            .collect();
        let k = 2.0;
        let x: Vec<f64> = theta.iter().map(|a| (k * a).sin()).collect();
        let m = 40_000;
        let y = resample(&x, &theta, m);
        let step = (theta[n - 1] - theta[0]) / (m - 1) as f64;
        let worst = y
            .iter()
            .enumerate()
            .map(|(j, v)| (v - (k * (theta[0] + j as f64 * step)).sin()).abs())
            .fold(0.0, f64::max);
        // Catmull-Rom is third-order accurate: the error on a sinusoid scales as (omega h)^3,
        // 2.5e-4 at the chirp's top 2 x 50 Hz = 100 Hz sampled at 10 kHz (0.016 measured at
        // 350 Hz, (omega h)^3 = 0.011: a factor 1.5)
        assert!(worst < 1e-3, "{worst}");
    }

    #[test]
    fn speed_variation_is_judged_against_one_bin() {
        // 0.8 % speed change, 1000 Hz line, 0.1 s: moves 8 Hz, bins are 10 Hz -> no
        assert!(!speed_varies([99.6, 100.4], 100.0, 1000.0, 0.1));
        assert!(speed_varies([90.0, 110.0], 100.0, 1000.0, 0.1));
    }
}
