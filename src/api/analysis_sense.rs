//! Whether an analysis request can mean anything: a diagnosis needs fault lines the
//! spectrum can show, samples whose moments are finite, and a shaft speed some bearing
//! can turn at. Before these checks a 1 Hz sample rate answered "no fault" with no line
//! searched, and samples of 1e308 answered 4 141 nulls.

use super::problem::FieldProblem;
use crate::jobs::AnalysisInput;
use bearing_core::signal::frequencies::characteristic_frequencies;

/// Largest sample magnitude. The kurtosis sums fourth powers: over the largest accepted
/// signal (about 1e7 samples, `--max-job-bytes`) `1e60^4 x 1e7 = 1e247` stays finite with
/// room for the filters' gain, where 1e308 overflowed. No measurement unit comes near it.
pub const MAX_ABS_SAMPLE: f64 = 1e60;

/// Fastest shaft an analysis may name, rev/min. The fastest rolling bearings (dental air
/// turbines) turn at about 400 000 rev/min; 1e12 used to be accepted.
pub const MAX_SHAFT_RPM: f64 = 1e6;

/// Problems that make the request meaningless; `speed_field` is the field the shaft speed
/// was given in (`shaft_hz` or `shaft_rpm`). Expects a finite positive sample rate and
/// shaft speed and a valid geometry (checked before).
pub fn senseless(input: &AnalysisInput, samples: &[f64], speed_field: &str) -> Vec<FieldProblem> {
    let mut errs = Vec::new();
    if let Some(k) = samples.iter().position(|x| x.abs() > MAX_ABS_SAMPLE) {
        errs.push(FieldProblem {
            path: format!("samples[{k}]"),
            message: format!(
                "magnitude {:e} is over {MAX_ABS_SAMPLE:e}: its fourth power overflows the kurtosis",
                samples[k]
            ),
        });
    }
    // compared in Hz, as the request's rev/min were converted (r / 60)
    if input.shaft_hz > MAX_SHAFT_RPM / 60.0 {
        let rpm = input.shaft_hz * 60.0;
        errs.push(FieldProblem {
            path: speed_field.into(),
            message: format!(
                "{rpm:e} rev/min is over {MAX_SHAFT_RPM:e} rev/min, faster than any rolling bearing turns"
            ),
        });
        return errs;
    }
    // A line is seen when it lies between one bin of the whole signal and Nyquist.
    let fs = input.sample_rate;
    let nyquist = 0.5 * fs;
    let bin = fs / samples.len().max(1) as f64;
    let lines = characteristic_frequencies(&input.geometry, input.shaft_hz).named();
    if lines.iter().any(|(_, f)| *f >= bin && *f < nyquist) {
        return errs;
    }
    let listed = lines
        .iter()
        .map(|(name, f)| format!("{name} {f:.4} Hz"))
        .collect::<Vec<_>>()
        .join(", ");
    let lowest = lines.iter().map(|(_, f)| *f).fold(f64::INFINITY, f64::min);
    if lines.iter().all(|(_, f)| *f >= nyquist) {
        errs.push(FieldProblem {
            path: "sample_rate".into(),
            message: format!(
                "every fault line ({listed}) is at or above Nyquist ({nyquist} Hz): none can be seen; sample at more than {:.4} Hz",
                2.0 * lowest
            ),
        });
    } else {
        errs.push(FieldProblem {
            path: "samples".into(),
            message: format!(
                "no fault line ({listed}) is both above one spectral bin ({bin:.4} Hz for {} samples at {fs} Hz) and below Nyquist ({nyquist} Hz): the signal is too short to resolve them",
                samples.len()
            ),
        });
    }
    errs
}

#[cfg(test)]
mod tests {
    use super::*;
    use bearing_core::signal::analysis::AnalysisOptions;
    use bearing_core::signal::frequencies::kinematic_preset;

    fn input(sample_rate: f64, shaft_hz: f64) -> AnalysisInput {
        AnalysisInput {
            sample_rate,
            geometry: kinematic_preset("cwru6205").unwrap(),
            shaft_hz,
            options: AnalysisOptions::default(),
        }
    }

    fn paths(input: &AnalysisInput, samples: &[f64]) -> Vec<String> {
        senseless(input, samples, "shaft_rpm")
            .into_iter()
            .map(|p| p.path)
            .collect()
    }

    #[test]
    fn lines_the_spectrum_cannot_show_are_refused() {
        let x = vec![0.1; 4096];
        // the CWRU rig at 1797 rev/min: FTF 11.9 Hz ... BPFI 162 Hz
        assert!(paths(&input(12_000.0, 29.95), &x).is_empty());
        // the 1 Hz: every line is above Nyquist
        assert_eq!(paths(&input(1.0, 29.95), &x), ["sample_rate"]);
        // 16 samples at 12 kHz: 750 Hz bins, wider than every line
        assert_eq!(paths(&input(12_000.0, 29.95), &x[..16]), ["samples"]);
        // one line in range is enough (FTF 11.9 Hz under a 20 Hz Nyquist)
        assert!(paths(&input(40.0, 29.95), &x).is_empty());
    }

    #[test]
    fn overflowing_samples_and_impossible_speeds_are_refused() {
        let mut x = vec![0.1; 4096];
        x[7] = -1e308;
        assert_eq!(paths(&input(12_000.0, 29.95), &x), ["samples[7]"]);
        x[7] = -MAX_ABS_SAMPLE;
        assert!(paths(&input(12_000.0, 29.95), &x).is_empty());
        assert_eq!(paths(&input(12_000.0, 1e12 / 60.0), &x), ["shaft_rpm"]);
        assert!(paths(&input(1e6, MAX_SHAFT_RPM / 60.0), &x).is_empty());
    }
}
