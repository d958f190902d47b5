//! `INPUT_FORMAT` moves with the stored job inputs. A queued job stores a resolved scene
//! (schema `Scene`) or an analysis request (`KinematicGeometry` and `AnalysisOptions`
//! beside two numbers); workers claim only the formats they run, so a change to those
//! schemas that an older worker would refuse must come with a new format number. This test
//! fingerprints the schemas, without their prose, and fails when they change under the
//! same number.
//!
//! What it does not see, and needs the bump by hand: the scene's validation bounds
//! (bearing-core's `scene/validate.rs`, checked when a stored scene is parsed; only a few
//! are in the schema), the analysis request's own two numbers (sample rate and shaft
//! rate), and the encoding of the stored signal blob.

use bearing_sim::store::INPUT_FORMAT;
use serde_json::Value;
use sha2::{Digest, Sha256};
use std::collections::{BTreeMap, BTreeSet};

/// The schemas a stored input is written in, as the service's OpenAPI document has them.
const ROOTS: [&str; 3] = ["Scene", "KinematicGeometry", "AnalysisOptions"];

/// Format number -> SHA-256 of its schemas. Append a line when you bump `INPUT_FORMAT`;
/// never edit an old one.
const FINGERPRINTS: &[(i64, &str)] = &[
    (
        1,
        "d02cbfcb839a4b409c7b2fa4eeeb5199fb951aa509e340324be92697fa11fdb8",
    ),
    // the rheology traction law, the `slip_implicit` integrator, exact Hertz by default
    (
        2,
        "6bee50198066d2df2e2f88a6ddf77a82dce5b8ae56b17a3b2eb07dd1a2b002da",
    ),
    // the `auto_slip` integrator; a zero clearance that rounds a few ulp below zero is valid
    (
        3,
        "101ca918439b7b7ccbb553961b30c3877ba1f8c4dcea534c0bade1605ad6219c",
    ),
    // `outputs.ball_pocket`: one ball's azimuth, lead on the cage and offset in its pocket
    (
        4,
        "0f41803eec0a0b47713e352e5f65bcaf9845d2b6dfae5763bdf9c9a79ffe634a",
    ),
    // `solver.traction_strips` optional: absent, the law's own (4 under the rheology law);
    // its schema bounds 1..=200 as validated (format 5 was not yet released when they
    // were added, so its fingerprint was replaced, not appended)
    (
        5,
        "85013d2d515774e116dec8e7f4e129ee0a01b8de00637ede3e6bdd83dd46dcc4",
    ),
    // `abcd`'s coefficients default to the paper's curve, so `{"model": "abcd"}` names it
    (
        6,
        "9778746895dd500bec95c468368f4e342e29daa0e8cf35a02b8a17a5e98834b7",
    ),
    // the `etd_rk4` and `auto_etd` integrators (an older worker cannot parse them)
    (
        7,
        "368fa02748d862044f7cbadfa6235e44a58ce9f2f344f4a4608562b02a9c7ef8",
    ),
];

/// Keys that document a schema without changing what parses.
const PROSE: [&str; 4] = ["description", "example", "examples", "title"];

/// The schema without its prose. Under `properties` the keys are field names, which are
/// kept whatever they are called (a field named `title` parses); only their schemas lose
/// their prose.
fn strip_prose(v: &Value) -> Value {
    match v {
        Value::Object(m) => Value::Object(
            m.iter()
                .filter(|(k, _)| !PROSE.contains(&k.as_str()))
                .map(|(k, v)| match (k.as_str(), v) {
                    ("properties", Value::Object(fields)) => (
                        k.clone(),
                        Value::Object(
                            fields
                                .iter()
                                .map(|(name, schema)| (name.clone(), strip_prose(schema)))
                                .collect(),
                        ),
                    ),
                    _ => (k.clone(), strip_prose(v)),
                })
                .collect(),
        ),
        Value::Array(a) => Value::Array(a.iter().map(strip_prose).collect()),
        other => other.clone(),
    }
}

fn refs(v: &Value, out: &mut Vec<String>) {
    match v {
        Value::Object(m) => {
            for (k, v) in m {
                match (k.as_str(), v) {
                    ("$ref", Value::String(r)) => {
                        out.push(r.trim_start_matches("#/components/schemas/").to_string())
                    }
                    _ => refs(v, out),
                }
            }
        }
        Value::Array(a) => a.iter().for_each(|v| refs(v, out)),
        _ => {}
    }
}

/// Every schema reachable from `ROOTS`, prose removed, keyed by name (sorted, so the JSON
/// text is canonical: serde_json's map keeps keys sorted).
fn stored_input_schemas() -> BTreeMap<String, Value> {
    let doc = serde_json::to_value(bearing_sim::api::openapi::document()).unwrap();
    let schemas = doc["components"]["schemas"].as_object().unwrap();
    let mut seen = BTreeSet::new();
    let mut todo: Vec<String> = ROOTS.iter().map(|s| s.to_string()).collect();
    let mut out = BTreeMap::new();
    while let Some(name) = todo.pop() {
        if !seen.insert(name.clone()) {
            continue;
        }
        let schema = schemas
            .get(&name)
            .unwrap_or_else(|| panic!("no schema {name} in the OpenAPI document"));
        refs(schema, &mut todo);
        out.insert(name, strip_prose(schema));
    }
    out
}

#[test]
fn input_format_is_bumped_with_the_stored_input_schemas() {
    let schemas = stored_input_schemas();
    // The roots reach the scene's sub-objects: a fingerprint of three names alone would
    // miss a new field of, say, the solver.
    for name in ["Solver", "Bearing", "Fault", "TractionQuadrature"] {
        assert!(schemas.contains_key(name), "{name} not reached");
    }
    let text = serde_json::to_string(&schemas).unwrap();
    let now = format!("{:x}", Sha256::digest(text.as_bytes()));
    let (latest, recorded) = *FINGERPRINTS.last().unwrap();
    assert_eq!(
        latest, INPUT_FORMAT,
        "FINGERPRINTS ends at format {latest}, INPUT_FORMAT is {INPUT_FORMAT}"
    );
    assert!(
        now == recorded,
        "the stored job inputs' schemas ({}) changed under INPUT_FORMAT = {INPUT_FORMAT}:\n\
         set INPUT_FORMAT = {} in src/store/model.rs and append ({}, \"{now}\") to\n\
         FINGERPRINTS in tests/checks/input_format.rs. Bump it for every change, even one an older\n\
         binary would accept: a bump only keeps new jobs away from older workers, which is safe.",
        ROOTS.join(", "),
        INPUT_FORMAT + 1,
        INPUT_FORMAT + 1,
    );
}

#[test]
fn fingerprints_are_listed_once_per_format_in_order() {
    for (i, (format, hex)) in FINGERPRINTS.iter().enumerate() {
        assert_eq!(*format, i as i64 + 1, "formats run 1, 2, 3, ...");
        assert_eq!(hex.len(), 64, "a SHA-256 in hex");
    }
}
