//! The whole pipeline on one signal: window, envelope spectrum of the raw signal, DTCWT
//! decomposition, per-level kurtosis, envelope spectra of the components, and identification
//! of the characteristic frequencies in the raw spectrum and in the two components with the
//! largest kurtosis (paper, section 3: the second fault of a compound pair often sits in the
//! runner-up level).

use serde::{Deserialize, Serialize};
use std::sync::atomic::{AtomicBool, Ordering};

use super::dtcwt::{biort, min_length, qshift, Dtcwt1d, DtcwtError};
use super::frequencies::{
    characteristic_frequencies, CharacteristicFrequencies, KinematicGeometry,
};
use super::identify::{bpfi_sidebands, identify, IdentifyOptions, DEFAULT_THRESHOLD_DB};
use super::kurtosis::kurtosis;
use super::order_tracking_report::OrderTracking;
use super::spectrum::EnvelopeSpectrumPlan;
use super::summary::summary;
use super::verdict::{
    verdict, CandidateSpectrum, FaultType, Verdict, VerdictSettings, DEFAULT_FALSE_ALARM_RATE,
    DEFAULT_VERDICT_HARMONICS,
};

pub use super::identify::{Identification, Sideband};
pub use super::spectrum::Spectrum;

/// Analysis settings. Missing JSON fields take the defaults.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(default, deny_unknown_fields)]
pub struct AnalysisOptions {
    /// DTCWT levels, 1..=16 (default 5).
    #[cfg_attr(feature = "openapi", schema(minimum = 1, maximum = 16))]
    pub levels: usize,
    /// Analysis window `[t0, t1]`, s from the first sample; `None` = the whole signal.
    /// Use it to leave out a speed ramp or a bad stretch of a recording.
    pub window: Option<[f64; 2]>,
    /// Ideal band-pass `[f0, f1]`, Hz, applied to the raw signal before its envelope;
    /// `None` = no filter. The wavelet components are band-passed by construction.
    pub band: Option<[f64; 2]>,
    /// Half-width of the peak search band, % of the target frequency (default 5).
    pub search_band_pct: f64,
    /// Harmonics searched per characteristic frequency, 1..=50 (default 3).
    #[cfg_attr(feature = "openapi", schema(minimum = 1, maximum = 50))]
    pub harmonics: usize,
    /// Level-1 filter set (default `near_sym_b`).
    pub biort: String,
    /// Filter set of levels >= 2 (default `qshift_b`).
    pub qshift: String,
    /// Minimum prominence of a detection, dB (default 12).
    pub detection_threshold_db: f64,
    /// Also report the identifications of every level (band-pass by wavelet level), not only
    /// the best and runner-up (default false).
    pub report_all_levels: bool,
    /// Choose the band by the kurtogram over this many levels, 1..=12: the envelope spectrum
    /// of that band is reported as `kurtogram`, that of the best band not overlapping it as
    /// `kurtogram_runner_up`, and the verdict reads them (with the raw spectrum) instead of
    /// the best two DTCWT components (default none: the kurtogram is
    /// not computed and the verdict reads the DTCWT components).
    #[cfg_attr(feature = "openapi", schema(minimum = 1, maximum = 12))]
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kurtogram_levels: Option<usize>,
    /// False-alarm rate of the fault verdict per fault type, in (0, 0.5] (default 1e-3):
    /// the chance that a fault type is named on a spectrum whose lines are unrelated to it.
    #[cfg_attr(feature = "openapi", schema(exclusive_minimum = 0.0, maximum = 0.5))]
    pub false_alarm_rate: f64,
    /// Harmonics of each fault family the verdict tests, 2..=20 (default 4; the rolling
    /// element's family takes twice as many of BSF). More harmonics give an impulse train's
    /// long series more weight; docs/lab/cwru.md shows what 3 to 10 give on the evaluation set.
    #[cfg_attr(feature = "openapi", schema(minimum = 2, maximum = 20))]
    pub verdict_harmonics: usize,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        AnalysisOptions {
            levels: 5,
            window: None,
            band: None,
            search_band_pct: 5.0,
            harmonics: 3,
            biort: "near_sym_b".into(),
            qshift: "qshift_b".into(),
            detection_threshold_db: DEFAULT_THRESHOLD_DB,
            report_all_levels: false,
            kurtogram_levels: None,
            false_alarm_rate: DEFAULT_FALSE_ALARM_RATE,
            verdict_harmonics: DEFAULT_VERDICT_HARMONICS,
        }
    }
}

/// Identification results of one DTCWT level's component.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct ComponentReport {
    /// DTCWT level, 1-based (1 = finest, highest frequencies).
    pub level: usize,
    /// Pearson kurtosis of the component, -.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub kurtosis: f64,
    /// Nominal pass band of the level, Hz.
    pub band_hz: [f64; 2],
    pub identifications: Vec<Identification>,
    /// Shaft-rate sidebands around the BPFI harmonics.
    pub bpfi_sidebands: Vec<Sideband>,
}

/// The band the kurtogram chose and what its envelope spectrum shows.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct KurtogramReport {
    /// Level of the band in the 1/3-binary tree (0, 1, 1.6, 2, ...), -.
    pub level: f64,
    /// Band edges, Hz.
    pub band_hz: [f64; 2],
    /// Spectral kurtosis of the band, -.
    pub kurtosis: f64,
    pub identifications: Vec<Identification>,
    /// Shaft-rate sidebands around the BPFI harmonics.
    pub bpfi_sidebands: Vec<Sideband>,
}

/// Everything the analysis found.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct AnalysisReport {
    /// Hz.
    pub sample_rate: f64,
    /// Samples analysed (inside the window).
    pub n_samples: usize,
    /// Window analysed, s from the first sample of the input.
    pub window: [f64; 2],
    /// Shaft frequency, Hz.
    pub shaft_hz: f64,
    /// Characteristic frequencies from the geometry given, Hz.
    pub theory: CharacteristicFrequencies,
    /// Envelope-spectrum resolution, Hz.
    pub df: f64,
    /// Band-pass applied to the raw signal, Hz.
    pub band: Option<[f64; 2]>,
    /// Pearson kurtosis of the windowed raw signal, -.
    #[serde(deserialize_with = "crate::json_float::f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(nullable))]
    pub raw_kurtosis: f64,
    /// Pearson kurtosis of each level's component, index 0 = level 1.
    #[serde(deserialize_with = "crate::json_float::vec_f64_or_nan")]
    #[cfg_attr(feature = "openapi", schema(value_type = Vec<Option<f64>>))]
    pub level_kurtosis: Vec<f64>,
    /// Identifications in the raw (optionally band-passed) envelope spectrum.
    pub raw: Vec<Identification>,
    /// Shaft-rate sidebands around BPFI in the raw envelope spectrum.
    pub raw_bpfi_sidebands: Vec<Sideband>,
    /// The level with the largest kurtosis.
    pub best_component: ComponentReport,
    /// The level with the second-largest kurtosis.
    pub runner_up_component: ComponentReport,
    /// Every level, index 0 = level 1, when `report_all_levels` was asked for (else empty).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub all_levels: Vec<ComponentReport>,
    /// The kurtogram's band, when `kurtogram_levels` was asked for.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kurtogram: Option<KurtogramReport>,
    /// The kurtogram's band of largest kurtosis that does not overlap `kurtogram`'s and is
    /// wide enough for the harmonics searched (as `kurtogram`'s must be), when
    /// `kurtogram_levels` was asked for and such a band exists.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kurtogram_runner_up: Option<KurtogramReport>,
    /// Fault types indicated and the evidence, read from the raw spectrum and the best and
    /// runner-up components, or the kurtogram's two bands when it was asked for (method in
    /// docs/reference/model.md, "Verdict"). Absent only in
    /// reports stored before the verdict existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verdict: Option<Verdict>,
    /// Present when the signal was resampled to constant shaft angle because its speed
    /// varies ([`super::order_tracking::analyze_tracked`]): every frequency of the report is
    /// then an order times `order_tracking.mean_shaft_hz`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub order_tracking: Option<OrderTracking>,
}

/// Report plus the spectra it was read from.
#[derive(Debug, Clone)]
pub struct AnalysisOutput {
    pub report: AnalysisReport,
    /// Envelope spectrum of the windowed (optionally band-passed) signal.
    pub raw_spectrum: Spectrum,
    /// Envelope spectrum of each level's component, index 0 = level 1; `None` for the levels
    /// whose spectrum was not kept ([`LevelSpectra::Chosen`]).
    pub level_spectra: Vec<Option<Spectrum>>,
}

/// Which level spectra an analysis keeps in its [`AnalysisOutput`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LevelSpectra {
    /// Every level's (a service that serves any level's spectrum).
    All,
    /// Only those the report reads: the best and runner-up levels' (every level's when
    /// `report_all_levels` is set). Saves `levels - 2` spectra of `n / 2` values.
    Chosen,
}

/// Why an analysis could not run. Messages start with the offending input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalysisError {
    /// A scalar input or option is out of range.
    #[error("{field}: {message}")]
    Invalid { field: String, message: String },
    #[error("samples[{index}]: not a finite number")]
    NonFinite { index: usize },
    #[error("samples: {n} samples is too short for {levels} levels (need >= {need})")]
    TooShort {
        n: usize,
        levels: usize,
        need: usize,
    },
    /// The caller's cancel flag was set (a client gone away, a job cancelled or out of time).
    #[error("cancelled")]
    Cancelled,
}

fn invalid(field: &str, message: impl Into<String>) -> AnalysisError {
    AnalysisError::Invalid {
        field: field.into(),
        message: message.into(),
    }
}

impl From<DtcwtError> for AnalysisError {
    fn from(e: DtcwtError) -> Self {
        match e {
            DtcwtError::UnknownFilter {
                field,
                name,
                expected,
            } => invalid(
                field,
                format!(
                    "unknown filter set '{name}' (expected one of {})",
                    expected.join(", ")
                ),
            ),
            DtcwtError::Levels { levels } => {
                invalid("levels", format!("must be >= 1 (got {levels})"))
            }
            DtcwtError::TooShort { n, levels, need } => AnalysisError::TooShort { n, levels, need },
        }
    }
}

/// Largest number of levels accepted (a 2^17-fold decimation is beyond any practical record).
pub const MAX_LEVELS: usize = 16;

/// Analyse `signal` sampled at `fs` Hz from a bearing of geometry `geometry` turning at
/// `shaft_hz` Hz.
pub fn analyze(
    signal: &[f64],
    fs: f64,
    geometry: &KinematicGeometry,
    shaft_hz: f64,
    opts: &AnalysisOptions,
) -> Result<AnalysisOutput, AnalysisError> {
    analyze_with(
        signal,
        fs,
        geometry,
        shaft_hz,
        opts,
        None,
        LevelSpectra::All,
    )
}

/// [`analyze`], stopping with [`AnalysisError::Cancelled`] soon after `cancel` is set
/// (it is checked between levels, so within one level's transform and spectrum), keeping
/// the level spectra `spectra` asks for (a service that serves every level's spectrum
/// wants [`LevelSpectra::All`]).
pub fn analyze_with(
    signal: &[f64],
    fs: f64,
    geometry: &KinematicGeometry,
    shaft_hz: f64,
    opts: &AnalysisOptions,
    cancel: Option<&AtomicBool>,
    spectra: LevelSpectra,
) -> Result<AnalysisOutput, AnalysisError> {
    let check = || match cancel {
        Some(c) if c.load(Ordering::Relaxed) => Err(AnalysisError::Cancelled),
        _ => Ok(()),
    };
    if !(fs.is_finite() && fs > 0.0) {
        return Err(invalid("sample_rate", format!("must be > 0 Hz (got {fs})")));
    }
    if !(shaft_hz.is_finite() && shaft_hz > 0.0) {
        return Err(invalid(
            "shaft_hz",
            format!("must be > 0 Hz (got {shaft_hz})"),
        ));
    }
    geometry
        .validate()
        .map_err(|(f, m)| invalid(&format!("geometry.{f}"), m))?;
    validate_options(opts, fs)?;
    if let Some(index) = signal.iter().position(|v| !v.is_finite()) {
        return Err(AnalysisError::NonFinite { index });
    }

    let (i0, i1) = window_range(opts, fs, signal.len())?;
    let x = &signal[i0..i1];

    let theory = characteristic_frequencies(geometry, shaft_hz);
    let id_opts = IdentifyOptions {
        search_band_pct: opts.search_band_pct,
        harmonics: opts.harmonics,
        detection_threshold_db: opts.detection_threshold_db,
    };

    check()?;
    let transform = Dtcwt1d::new(&opts.biort, &opts.qshift)?;
    let pyramid = transform.forward(x, opts.levels)?;
    let mut level_kurtosis: Vec<f64> = Vec::with_capacity(opts.levels);
    let mut level_spectra: Vec<Option<Spectrum>> = vec![None; opts.levels];
    let keep_all = spectra == LevelSpectra::All || opts.report_all_levels;
    let (mut plan, raw_spectrum) = if keep_all {
        // One level's full-length component at a time: its kurtosis and envelope spectrum
        // are all that is kept (holding every component took levels x n x 8 bytes, 384 MB
        // for 3e6 samples at 16 levels).
        let mut plan = EnvelopeSpectrumPlan::new(x.len());
        let raw_spectrum = plan.compute(x, fs, opts.band);
        for l in 1..=opts.levels {
            check()?;
            let component = transform.level_component(&pyramid, l);
            level_kurtosis.push(kurtosis(&component));
            level_spectra[l - 1] = Some(plan.compute(&component, fs, None));
        }
        drop(pyramid);
        (plan, raw_spectrum)
    } else {
        // Only the two components of largest kurtosis are read further: keep those two,
        // drop the transform, and only then plan the spectra (the plan's buffers and the
        // pyramid are never held at once; 2^20 samples peaked at 129 MB, now under 100).
        let mut kept: Vec<(usize, Vec<f64>)> = Vec::with_capacity(3);
        for l in 1..=opts.levels {
            check()?;
            let component = transform.level_component(&pyramid, l);
            level_kurtosis.push(kurtosis(&component));
            kept.push((l - 1, component));
            // the order the report uses: kurtosis descending, ties to the lower level
            kept.sort_by(|a, b| {
                level_kurtosis[b.0]
                    .total_cmp(&level_kurtosis[a.0])
                    .then(a.0.cmp(&b.0))
            });
            kept.truncate(2);
        }
        drop(pyramid);
        let mut plan = EnvelopeSpectrumPlan::new(x.len());
        let raw_spectrum = plan.compute(x, fs, opts.band);
        for (i, component) in kept {
            check()?;
            level_spectra[i] = Some(plan.compute(&component, fs, None));
        }
        (plan, raw_spectrum)
    };

    let mut order: Vec<usize> = (0..opts.levels).collect();
    order.sort_by(|&a, &b| level_kurtosis[b].total_cmp(&level_kurtosis[a]));
    let level_spectrum = |idx: usize| -> &Spectrum {
        level_spectra[idx]
            .as_ref()
            .expect("the best, runner-up (or, on request, every) level's spectrum is kept")
    };
    let component_report = |idx: usize| {
        let ids = identify(level_spectrum(idx), &theory, &id_opts);
        let sidebands = bpfi_sidebands(level_spectrum(idx), &theory, &ids, &id_opts);
        ComponentReport {
            level: idx + 1,
            kurtosis: level_kurtosis[idx],
            band_hz: super::dtcwt::nominal_band(idx + 1, fs),
            identifications: ids,
            bpfi_sidebands: sidebands,
        }
    };
    let mut best_component = component_report(order[0]);
    // With a single level there is no runner-up: the best one is repeated.
    let mut runner_up_component = component_report(*order.get(1).unwrap_or(&order[0]));
    let mut all_levels = if opts.report_all_levels {
        (0..opts.levels).map(component_report).collect()
    } else {
        Vec::new()
    };

    // The kurtogram's band and its runner-up, each with its envelope spectrum.
    let mut kurtogram_spectra: Vec<Spectrum> = Vec::new();
    let mut kurtogram_reports: Vec<KurtogramReport> = Vec::new();
    if let Some(levels) = opts.kurtogram_levels {
        check()?;
        // only bands wide enough for every harmonic searched of the highest fault
        // frequency: an envelope shows modulation only up to its band's width
        let widest_line = opts.harmonics as f64 * theory.bpfi.max(theory.bpfo);
        let kg = super::kurtogram::kurtogram(x, fs, levels)
            .map_err(|e| invalid("kurtogram_levels", e.to_string()))?;
        let best = kg.best_at_least(widest_line);
        let second = kg.runner_up_at_least(widest_line, &best);
        for band in std::iter::once(best).chain(second) {
            let spectrum = plan.compute(x, fs, Some([band.low_hz, band.high_hz]));
            let ids = identify(&spectrum, &theory, &id_opts);
            let sidebands = bpfi_sidebands(&spectrum, &theory, &ids, &id_opts);
            kurtogram_spectra.push(spectrum);
            kurtogram_reports.push(KurtogramReport {
                level: band.level,
                band_hz: [band.low_hz, band.high_hz],
                kurtosis: band.kurtosis,
                identifications: ids,
                bpfi_sidebands: sidebands,
            });
        }
    }
    let mut raw = identify(&raw_spectrum, &theory, &id_opts);
    let raw_bpfi_sidebands = bpfi_sidebands(&raw_spectrum, &theory, &raw, &id_opts);
    let level_candidate = |c: &ComponentReport| CandidateSpectrum {
        label: format!("level {}", c.level),
        band_hz: Some(c.band_hz),
        spectrum: level_spectrum(c.level - 1),
    };
    // The verdict reads the raw spectrum and the bands of the band-selection method asked
    // for: the kurtogram's band and its runner-up when `kurtogram_levels` is given, else the
    // two DTCWT components of largest kurtosis.
    let mut candidates = vec![CandidateSpectrum {
        label: "raw".into(),
        band_hz: opts.band,
        spectrum: &raw_spectrum,
    }];
    if !kurtogram_reports.is_empty() {
        for (i, (k, s)) in kurtogram_reports.iter().zip(&kurtogram_spectra).enumerate() {
            candidates.push(CandidateSpectrum {
                label: if i == 0 {
                    "kurtogram".into()
                } else {
                    "kurtogram runner-up".into()
                },
                band_hz: Some(k.band_hz),
                spectrum: s,
            });
        }
    } else {
        candidates.push(level_candidate(&best_component));
        if runner_up_component.level != best_component.level {
            candidates.push(level_candidate(&runner_up_component));
        }
    }
    let verdict = verdict(
        &candidates,
        &theory,
        geometry.ball_count,
        &VerdictSettings {
            search_band_pct: opts.search_band_pct,
            false_alarm_rate: opts.false_alarm_rate,
            harmonics: opts.verdict_harmonics,
        },
    );
    let mut verdict = verdict;
    verdict.summary = summary(&verdict);
    // per-line flags carry the verdict: which lines belong to a fault type it names
    let named = |ids: &mut Vec<Identification>| {
        for id in ids.iter_mut() {
            id.in_verdict =
                FaultType::of_line(&id.name).is_some_and(|f| verdict.faults.contains(&f));
        }
    };
    named(&mut raw);
    named(&mut best_component.identifications);
    named(&mut runner_up_component.identifications);
    for c in all_levels.iter_mut() {
        named(&mut c.identifications);
    }
    for k in kurtogram_reports.iter_mut() {
        named(&mut k.identifications);
    }
    let mut kurtogram_reports = kurtogram_reports.into_iter();
    let kurtogram = kurtogram_reports.next();
    let kurtogram_runner_up = kurtogram_reports.next();
    let report = AnalysisReport {
        sample_rate: fs,
        n_samples: x.len(),
        window: [i0 as f64 / fs, i1 as f64 / fs],
        shaft_hz,
        theory,
        df: raw_spectrum.df,
        band: opts.band,
        raw_kurtosis: kurtosis(x),
        level_kurtosis,
        raw,
        raw_bpfi_sidebands,
        best_component,
        runner_up_component,
        all_levels,
        kurtogram,
        kurtogram_runner_up,
        verdict: Some(verdict),
        order_tracking: None,
    };
    Ok(AnalysisOutput {
        report,
        raw_spectrum,
        level_spectra,
    })
}

/// Sample range `[i0, i1)` of the analysis window in a signal of `n` samples at `fs` Hz,
/// long enough for the DTCWT levels asked for.
pub(super) fn window_range(
    opts: &AnalysisOptions,
    fs: f64,
    n: usize,
) -> Result<(usize, usize), AnalysisError> {
    let duration = n as f64 / fs;
    let (i0, i1) = match opts.window {
        None => (0, n),
        Some([t0, t1]) => {
            if !(t0.is_finite() && t1.is_finite() && t0 >= 0.0 && t1 > t0) {
                return Err(invalid(
                    "window",
                    format!("must be [t0, t1] s with 0 <= t0 < t1 (got [{t0}, {t1}])"),
                ));
            }
            if t0 >= duration {
                return Err(invalid(
                    "window",
                    format!("starts at {t0} s, after the end of the signal ({duration} s)"),
                ));
            }
            let i0 = (t0 * fs).round() as usize;
            let i1 = ((t1 * fs).round() as usize).min(n);
            (i0, i1)
        }
    };
    let need = min_length(opts.levels);
    if i1 - i0 < need {
        return Err(if opts.window.is_some() {
            invalid(
                "window",
                format!(
                    "holds {} samples, too short for {} levels (need >= {need})",
                    i1 - i0,
                    opts.levels
                ),
            )
        } else {
            AnalysisError::TooShort {
                n: i1 - i0,
                levels: opts.levels,
                need,
            }
        });
    }
    if let Some(kl) = opts.kurtogram_levels {
        let need = super::kurtogram::min_length(kl);
        if i1 - i0 < need {
            return Err(invalid(
                "kurtogram_levels",
                format!(
                    "the signal holds {} samples, too short for {kl} kurtogram levels (need >= {need})",
                    i1 - i0
                ),
            ));
        }
    }
    Ok((i0, i1))
}

/// Every check `analyze` makes of its options, for `n` samples at `fs` Hz, without
/// analysing: a service can refuse a request up front instead of failing its job later.
pub fn check_options(opts: &AnalysisOptions, fs: f64, n: usize) -> Result<(), AnalysisError> {
    validate_options(opts, fs)?;
    biort(&opts.biort)?;
    qshift(&opts.qshift)?;
    window_range(opts, fs, n).map(|_| ())
}

fn validate_options(opts: &AnalysisOptions, fs: f64) -> Result<(), AnalysisError> {
    if opts.levels == 0 || opts.levels > MAX_LEVELS {
        return Err(invalid(
            "levels",
            format!("must be in 1..={MAX_LEVELS} (got {})", opts.levels),
        ));
    }
    if !(opts.search_band_pct.is_finite()
        && opts.search_band_pct > 0.0
        && opts.search_band_pct <= 50.0)
    {
        return Err(invalid(
            "search_band_pct",
            format!("must be in (0, 50] % (got {})", opts.search_band_pct),
        ));
    }
    if let Some(kl) = opts.kurtogram_levels {
        if !(1..=12).contains(&kl) {
            return Err(invalid(
                "kurtogram_levels",
                format!("must be in 1..=12 (got {kl})"),
            ));
        }
    }
    if !(opts.false_alarm_rate > 0.0 && opts.false_alarm_rate <= 0.5) {
        return Err(invalid(
            "false_alarm_rate",
            format!("must be in (0, 0.5] (got {})", opts.false_alarm_rate),
        ));
    }
    if !(2..=20).contains(&opts.verdict_harmonics) {
        return Err(invalid(
            "verdict_harmonics",
            format!("must be in 2..=20 (got {})", opts.verdict_harmonics),
        ));
    }
    if opts.harmonics == 0 || opts.harmonics > 50 {
        return Err(invalid(
            "harmonics",
            format!("must be in 1..=50 (got {})", opts.harmonics),
        ));
    }
    if !opts.detection_threshold_db.is_finite() {
        return Err(invalid(
            "detection_threshold_db",
            "must be a finite number of dB",
        ));
    }
    if let Some([f0, f1]) = opts.band {
        let nyq = fs / 2.0;
        if !(f0.is_finite() && f1.is_finite() && f0 >= 0.0 && f1 > f0 && f0 < nyq) {
            return Err(invalid(
                "band",
                format!("must be [f0, f1] Hz with 0 <= f0 < f1 and f0 below Nyquist {nyq} Hz (got [{f0}, {f1}])"),
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geometry() -> KinematicGeometry {
        super::super::frequencies::kinematic_preset("cwru6205").unwrap()
    }

    #[test]
    fn errors_name_the_input() {
        let g = geometry();
        let o = AnalysisOptions::default();
        let x = vec![0.0; 1000];
        let msg = |r: Result<AnalysisOutput, AnalysisError>| r.unwrap_err().to_string();
        assert_eq!(
            msg(analyze(&x, 0.0, &g, 30.0, &o)),
            "sample_rate: must be > 0 Hz (got 0)"
        );
        assert!(msg(analyze(&x, 1e3, &g, -1.0, &o)).starts_with("shaft_hz:"));
        assert_eq!(
            msg(analyze(&x[..12], 1e3, &g, 30.0, &o)),
            "samples: 12 samples is too short for 5 levels (need >= 64)"
        );
        let mut y = x.clone();
        y[17] = f64::NAN;
        assert_eq!(
            msg(analyze(&y, 1e3, &g, 30.0, &o)),
            "samples[17]: not a finite number"
        );
        let bad = AnalysisOptions {
            window: Some([0.5, 0.2]),
            ..o.clone()
        };
        assert!(msg(analyze(&x, 1e3, &g, 30.0, &bad)).starts_with("window:"));
        let bad = AnalysisOptions {
            biort: "nope".into(),
            ..o.clone()
        };
        assert!(
            msg(analyze(&x, 1e3, &g, 30.0, &bad)).starts_with("biort: unknown filter set 'nope'")
        );
        let bad = AnalysisOptions {
            verdict_harmonics: 1,
            ..o.clone()
        };
        assert_eq!(
            msg(analyze(&x, 1e3, &g, 30.0, &bad)),
            "verdict_harmonics: must be in 2..=20 (got 1)"
        );
        let bad = AnalysisOptions {
            false_alarm_rate: 0.0,
            ..o.clone()
        };
        assert!(msg(analyze(&x, 1e3, &g, 30.0, &bad)).starts_with("false_alarm_rate:"));
        let bad = AnalysisOptions {
            band: Some([600.0, 700.0]),
            ..o.clone()
        };
        assert!(msg(analyze(&x, 1e3, &g, 30.0, &bad)).starts_with("band:"));
        let bad_g = KinematicGeometry {
            pitch_diameter: 0.001,
            ..g
        };
        assert!(msg(analyze(&x, 1e3, &bad_g, 30.0, &o)).starts_with("geometry.pitch_diameter:"));
    }

    #[test]
    fn window_selects_samples_and_is_reported() {
        let g = geometry();
        let x: Vec<f64> = (0..4000)
            .map(|i| ((i * 37 % 101) as f64 - 50.0) / 50.0)
            .collect();
        let o = AnalysisOptions {
            window: Some([1.0, 3.0]),
            ..Default::default()
        };
        let out = analyze(&x, 1000.0, &g, 30.0, &o).unwrap();
        assert_eq!(out.report.n_samples, 2000);
        assert_eq!(out.report.window, [1.0, 3.0]);
        assert_eq!(out.level_spectra.len(), 5);
        assert_eq!(out.report.level_kurtosis.len(), 5);
    }

    #[test]
    fn all_levels_on_request() {
        let x: Vec<f64> = (0..4096)
            .map(|i| ((i * 37 % 101) as f64 - 50.0) / 50.0)
            .collect();
        let o = AnalysisOptions {
            report_all_levels: true,
            levels: 4,
            ..Default::default()
        };
        let r = analyze(&x, 1000.0, &geometry(), 30.0, &o).unwrap().report;
        assert_eq!(
            r.all_levels.iter().map(|c| c.level).collect::<Vec<_>>(),
            vec![1, 2, 3, 4]
        );
        let r = analyze(&x, 1000.0, &geometry(), 30.0, &AnalysisOptions::default())
            .unwrap()
            .report;
        assert!(r.all_levels.is_empty());
    }

    #[test]
    fn keeping_only_the_chosen_spectra_changes_nothing_in_the_report() {
        // the same levels chosen, the same spectra read, the same verdict; only the
        // unread levels' spectra are dropped
        let x: Vec<f64> = (0..8192)
            .map(|i| {
                let t = i as f64 / 12_000.0;
                ((i * 7919 % 1013) as f64 / 1013.0 - 0.5)
                    + (-800.0 * (t * 107.3).fract() / 107.3).exp()
                        * (2.0 * std::f64::consts::PI * 3000.0 * t).sin()
            })
            .collect();
        let g = geometry();
        let o = AnalysisOptions::default();
        let all = analyze(&x, 12_000.0, &g, 29.93, &o).unwrap();
        let chosen = analyze_with(&x, 12_000.0, &g, 29.93, &o, None, LevelSpectra::Chosen).unwrap();
        assert_eq!(all.report, chosen.report);
        assert!(all.level_spectra.iter().all(Option::is_some));
        let kept: Vec<usize> = chosen
            .level_spectra
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.as_ref().map(|_| i + 1))
            .collect();
        let mut want = vec![
            chosen.report.best_component.level,
            chosen.report.runner_up_component.level,
        ];
        want.sort();
        assert_eq!(kept, want);
        for l in kept {
            assert_eq!(chosen.level_spectra[l - 1], all.level_spectra[l - 1]);
        }
    }

    #[test]
    fn options_json_defaults() {
        let o: AnalysisOptions = serde_json::from_str(r#"{"levels": 4}"#).unwrap();
        assert_eq!(o.levels, 4);
        assert_eq!(o.qshift, "qshift_b");
        assert_eq!(o.search_band_pct, 5.0);
    }
}
