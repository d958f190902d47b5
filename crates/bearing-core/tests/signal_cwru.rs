//! Real data: 1.5 s excerpts (first 18000 samples) of the CWRU 12 kHz drive-end recordings
//! IR007 (inner race, 0.007 in) and OR007@6 (outer race, centred), 0 hp, committed under
//! tests/fixtures/cwru/ with the manifest facts the test needs.
//!
//! Criterion (issue): BPFI resp. BPFO detected within 1 % of the manifest's expected
//! frequency. The manifest rpm is hand-written; the true shaft speed differs by a few tenths of
//! a percent (we find BPFI -0.32 %, BPFO +0.32 %, as peers do), so 1 % is the right bound.
//! df = 0.67 Hz is 0.4 % of BPFI, and sub-bin interpolation keeps the frequency error well
//! under half of that.

mod common;

use bearing_core::signal::{
    analyze, kinematic_preset, AnalysisOptions, AnalysisReport, Identification,
};

const TOL_PCT: f64 = 1.0;

fn manifest() -> serde_json::Value {
    let p =
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/cwru/manifest.json");
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

fn analyse(id: &str) -> (AnalysisReport, serde_json::Value) {
    let m = manifest()[id].clone();
    let x = common::read_f32le(&format!("tests/fixtures/cwru/{id}.f32le"));
    assert_eq!(x.len(), m["n_samples"].as_u64().unwrap() as usize);
    let fs = m["fs_hz"].as_f64().unwrap();
    let shaft = m["rpm"].as_f64().unwrap() / 60.0;
    let g = kinematic_preset("cwru6205").unwrap();
    let out = analyze(&x, fs, &g, shaft, &AnalysisOptions::default()).unwrap();
    (out.report, m)
}

fn fundamental<'a>(ids: &'a [Identification], name: &str) -> &'a Identification {
    ids.iter()
        .find(|i| i.name == name && i.harmonic == 1)
        .unwrap()
}

fn check(id: &str, name: &str) {
    let (r, m) = analyse(id);
    let expected = m["expected_fault_frequencies_hz"][name].as_f64().unwrap();
    for (what, ids) in [
        ("raw", &r.raw),
        ("best component", &r.best_component.identifications),
    ] {
        let i = fundamental(ids, name);
        let err = (i.identified_hz - expected) / expected * 100.0;
        eprintln!(
            "{id} {what}: {name} {:.3} Hz vs {expected:.3} ({err:+.3} %), {:.1} dB",
            i.identified_hz, i.prominence_db
        );
        assert!(i.detected, "{id} {what}: {name} not detected: {i:?}");
        assert!(err.abs() < TOL_PCT, "{id} {what}: {name} off by {err} %");
    }
    // the harmonics agree with the fundamental (same shaft-speed error): 2x and 3x detected too
    for h in [2, 3] {
        let i = r
            .raw
            .iter()
            .find(|i| i.name == name && i.harmonic == h)
            .unwrap();
        let err = (i.identified_hz - h as f64 * expected) / (h as f64 * expected) * 100.0;
        assert!(
            i.detected && err.abs() < TOL_PCT,
            "{id}: {name} x{h}: {i:?}"
        );
    }
}

#[test]
fn inner_race_007_shows_bpfi() {
    check("cwru_ir007_0hp_12k_de", "BPFI");
}

#[test]
fn outer_race_007_shows_bpfo() {
    check("cwru_or007c_0hp_12k_de", "BPFO");
}

#[test]
fn outer_race_record_does_not_report_bpfi() {
    // the line near BPFI on the outer-race record is BPFO + 2 x shaft, not an inner-race fault
    let (r, _) = analyse("cwru_or007c_0hp_12k_de");
    let i = fundamental(&r.raw, "BPFI");
    assert!(!i.detected, "{i:?}");
    assert_eq!(i.nearer_line.as_deref(), Some("BPFO x1 +2 shaft"));
}

#[test]
fn inner_race_record_shows_shaft_sidebands_around_bpfi() {
    // load-zone modulation: BPFI +/- shaft lines are present on the inner-race record
    let (r, _) = analyse("cwru_ir007_0hp_12k_de");
    let sb: Vec<_> = r
        .raw_bpfi_sidebands
        .iter()
        .filter(|s| s.harmonic == 1 && s.detected)
        .collect();
    assert!(!sb.is_empty(), "{:?}", r.raw_bpfi_sidebands);
}

/// The kurtogram's band on the same two recordings: the fault line's peak is found there
/// within the same 1 % (the band and the peak's prominence are printed for comparison with
/// the best DTCWT level).
#[test]
fn the_kurtogram_band_shows_the_fault_line_too() {
    for (id, name) in [
        ("cwru_ir007_0hp_12k_de", "BPFI"),
        ("cwru_or007c_0hp_12k_de", "BPFO"),
    ] {
        let m = manifest()[id].clone();
        let x = common::read_f32le(&format!("tests/fixtures/cwru/{id}.f32le"));
        let fs = m["fs_hz"].as_f64().unwrap();
        let shaft = m["rpm"].as_f64().unwrap() / 60.0;
        let g = kinematic_preset("cwru6205").unwrap();
        let opts = AnalysisOptions {
            kurtogram_levels: Some(6),
            ..AnalysisOptions::default()
        };
        let r = analyze(&x, fs, &g, shaft, &opts).unwrap().report;
        let k = r.kurtogram.as_ref().unwrap();
        let i = fundamental(&k.identifications, name);
        let expected = m["expected_fault_frequencies_hz"][name].as_f64().unwrap();
        let err = (i.identified_hz - expected) / expected * 100.0;
        eprintln!(
            "{id}: kurtogram band {:.0}-{:.0} Hz (level {:.1}, SK {:.2}); best DTCWT level {} ({:.0}-{:.0} Hz); {name} {err:+.3} %, {:.1} dB",
            k.band_hz[0],
            k.band_hz[1],
            k.level,
            k.kurtosis,
            r.best_component.level,
            r.best_component.band_hz[0],
            r.best_component.band_hz[1],
            i.prominence_db
        );
        // Measured (docs/reference/model.md, "Kurtogram"): on IR007 the band chosen is 5.5-6 kHz and
        // BPFI reads 11.3 dB there, under the 12 dB detection threshold, where the best
        // DTCWT level detects it; so only the line's frequency is asserted here.
        assert!(err.abs() < TOL_PCT, "{id}: {name} off by {err} %");
    }
}
