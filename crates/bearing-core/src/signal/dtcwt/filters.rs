//! Kingsbury filter tables for the 1-D dual-tree complex wavelet transform.
//!
//! The coefficients (`filters.json`, float64) are the tables shipped with the Python `dtcwt`
//! 0.14 package (BSD-2-Clause, N. Kingsbury / R. Wareham); `scripts/fixtures/gen_signal_fixtures.py`
//! extracts them and checks them against the package. Only the sets the 1-D transform can use
//! are kept (the `_bp` variants add 2-D band-pass filters).

use std::collections::HashMap;
use std::sync::OnceLock;

use super::error::DtcwtError;

/// Biorthogonal level-1 filter sets, in the order they are documented.
pub const BIORT_NAMES: &[&str] = &["near_sym_b", "near_sym_a", "antonini", "legall"];
/// Q-shift filter sets for levels >= 2.
pub const QSHIFT_NAMES: &[&str] = &[
    "qshift_b",
    "qshift_a",
    "qshift_c",
    "qshift_d",
    "qshift_06",
    "qshift_32",
];

/// Level-1 (biorthogonal, odd-length) analysis `h*` and synthesis `g*` filters.
#[derive(Debug, Clone, PartialEq)]
pub struct BiortFilters {
    pub name: String,
    /// Analysis low-pass.
    pub h0o: Vec<f64>,
    /// Synthesis low-pass.
    pub g0o: Vec<f64>,
    /// Analysis high-pass.
    pub h1o: Vec<f64>,
    /// Synthesis high-pass.
    pub g1o: Vec<f64>,
}

/// Q-shift (even-length) filters of trees a and b for levels >= 2.
#[derive(Debug, Clone, PartialEq)]
pub struct QshiftFilters {
    pub name: String,
    pub h0a: Vec<f64>,
    pub h0b: Vec<f64>,
    pub g0a: Vec<f64>,
    pub g0b: Vec<f64>,
    pub h1a: Vec<f64>,
    pub h1b: Vec<f64>,
    pub g1a: Vec<f64>,
    pub g1b: Vec<f64>,
}

type Table = HashMap<String, HashMap<String, Vec<f64>>>;

fn table() -> &'static Table {
    static TABLE: OnceLock<Table> = OnceLock::new();
    TABLE.get_or_init(|| {
        serde_json::from_str(include_str!("filters.json")).expect("embedded filters.json is valid")
    })
}

fn get(set: &HashMap<String, Vec<f64>>, key: &str) -> Vec<f64> {
    set.get(key)
        .cloned()
        .expect("embedded filter set is complete")
}

/// Look up a level-1 filter set by name (case-insensitive).
pub fn biort(name: &str) -> Result<BiortFilters, DtcwtError> {
    let key = name.to_ascii_lowercase();
    let set = BIORT_NAMES
        .iter()
        .find(|n| **n == key)
        .and_then(|n| table().get(*n))
        .ok_or_else(|| DtcwtError::UnknownFilter {
            field: "biort",
            name: name.into(),
            expected: BIORT_NAMES,
        })?;
    Ok(BiortFilters {
        name: key,
        h0o: get(set, "h0o"),
        g0o: get(set, "g0o"),
        h1o: get(set, "h1o"),
        g1o: get(set, "g1o"),
    })
}

/// Look up a Q-shift filter set by name (case-insensitive).
pub fn qshift(name: &str) -> Result<QshiftFilters, DtcwtError> {
    let key = name.to_ascii_lowercase();
    let set = QSHIFT_NAMES
        .iter()
        .find(|n| **n == key)
        .and_then(|n| table().get(*n))
        .ok_or_else(|| DtcwtError::UnknownFilter {
            field: "qshift",
            name: name.into(),
            expected: QSHIFT_NAMES,
        })?;
    Ok(QshiftFilters {
        name: key,
        h0a: get(set, "h0a"),
        h0b: get(set, "h0b"),
        g0a: get(set, "g0a"),
        g0b: get(set, "g0b"),
        h1a: get(set, "h1a"),
        h1b: get(set, "h1b"),
        g1a: get(set, "g1a"),
        g1b: get(set, "g1b"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_named_set_loads_with_the_expected_parity() {
        for n in BIORT_NAMES {
            let f = biort(n).unwrap();
            for h in [&f.h0o, &f.g0o, &f.h1o, &f.g1o] {
                assert_eq!(h.len() % 2, 1, "{n}: level-1 filters are odd-length");
            }
        }
        for n in QSHIFT_NAMES {
            let f = qshift(n).unwrap();
            let l = f.h0a.len();
            for h in [
                &f.h0a, &f.h0b, &f.g0a, &f.g0b, &f.h1a, &f.h1b, &f.g1a, &f.g1b,
            ] {
                assert_eq!(h.len(), l);
                assert_eq!(l % 2, 0, "{n}: q-shift filters are even-length");
            }
        }
        assert_eq!(biort("near_sym_b").unwrap().h0o.len(), 13);
        assert_eq!(qshift("QSHIFT_B").unwrap().h0a.len(), 14);
    }

    #[test]
    fn lowpass_filters_have_the_expected_dc_gain() {
        // Level-1 analysis low-pass sums to 1, q-shift low-pass to sqrt(2). The q-shift sets are
        // numerically optimised designs whose published values miss sqrt(2) by up to 4e-11
        // (qshift_d), hence 1e-9; the biorthogonal ones are exact to rounding, hence 1e-12.
        for n in BIORT_NAMES {
            let s: f64 = biort(n).unwrap().h0o.iter().sum();
            assert!((s - 1.0).abs() < 1e-12, "{n}: sum h0o = {s}");
        }
        for n in QSHIFT_NAMES {
            let s: f64 = qshift(n).unwrap().h0a.iter().sum();
            assert!((s - 2f64.sqrt()).abs() < 1e-9, "{n}: sum h0a = {s}");
        }
    }

    #[test]
    fn unknown_names_are_rejected_with_the_list() {
        let e = biort("near_sym_z").unwrap_err().to_string();
        assert!(
            e.contains("biort") && e.contains("near_sym_z") && e.contains("near_sym_b"),
            "{e}"
        );
        assert!(qshift("nope").is_err());
    }
}
