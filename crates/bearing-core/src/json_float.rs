//! Floats that may be NaN or infinite, in JSON: serde_json writes them as `null`; these
//! read `null` back as NaN, so a stored result always parses back into its type.
//!
//! Use on fields that are NaN by design (e.g. the contact angle of a ball that was never
//! loaded) or can be for degenerate input (the kurtosis of a constant signal).

use serde::{Deserialize, Deserializer};

/// `#[serde(deserialize_with = "crate::json_float::f64_or_nan")]`: `null` -> NaN.
pub fn f64_or_nan<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

/// The same for every element of a list.
pub fn vec_f64_or_nan<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    Ok(Vec::<Option<f64>>::deserialize(d)?
        .into_iter()
        .map(|x| x.unwrap_or(f64::NAN))
        .collect())
}

#[cfg(test)]
mod tests {
    #[derive(serde::Serialize, serde::Deserialize, Debug)]
    struct T {
        #[serde(deserialize_with = "super::f64_or_nan")]
        x: f64,
        #[serde(deserialize_with = "super::vec_f64_or_nan")]
        v: Vec<f64>,
    }

    #[test]
    fn nan_survives_a_round_trip_through_json() {
        let t = T {
            x: f64::NAN,
            v: vec![1.0, f64::INFINITY],
        };
        let text = serde_json::to_string(&t).unwrap();
        assert_eq!(text, r#"{"x":null,"v":[1.0,null]}"#);
        let back: T = serde_json::from_str(&text).unwrap();
        assert!(back.x.is_nan() && back.v[0] == 1.0 && back.v[1].is_nan());
    }
}
