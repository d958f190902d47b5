//! Size bounds on every string, array and object of a JSON request body (scenes, overrides,
//! studies), checked on the parsed value before anything is resolved, echoed or stored.
//! Measured signals (`/v1/analyses` samples) are bounded by the body and job-size limits
//! instead. Bounds on meaning (a scene's name, a study's points) come after these.

use super::problem::{FieldProblem, Problem};
use bearing_core::scene::MAX_NAME_CHARS;
use serde_json::Value;

/// Longest string anywhere in a request, in characters: names, JSON pointers and enum
/// values all fit (a scene's and a study's name have the same bound).
pub const MAX_STRING_CHARS: usize = MAX_NAME_CHARS;

/// Most elements of an array, and members of an object: a study's factor takes up to 500
/// values (its points are at most 500).
pub const MAX_ITEMS: usize = 512;

/// Every string, array and object of `v` within the bounds; a 422 naming the first one
/// that is not (its path from `prefix`, which is the root when empty).
pub fn check_bounds(v: &Value, prefix: &str) -> Result<(), Problem> {
    match first_over(v, prefix) {
        None => Ok(()),
        Some(p) => Err(Problem::validation(vec![p])),
    }
}

fn first_over(v: &Value, path: &str) -> Option<FieldProblem> {
    let at = |message: String| {
        Some(FieldProblem {
            path: if path.is_empty() {
                "$".into()
            } else {
                path.into()
            },
            message,
        })
    };
    match v {
        Value::String(s) => {
            let n = s.chars().count();
            (n > MAX_STRING_CHARS)
                .then(|| at(format!("at most {MAX_STRING_CHARS} characters, got {n}")))
                .flatten()
        }
        Value::Array(items) => {
            if items.len() > MAX_ITEMS {
                return at(format!("at most {MAX_ITEMS} elements, got {}", items.len()));
            }
            items
                .iter()
                .enumerate()
                .find_map(|(i, x)| first_over(x, &format!("{path}[{i}]")))
        }
        Value::Object(members) => {
            if members.len() > MAX_ITEMS {
                return at(format!(
                    "at most {MAX_ITEMS} members, got {}",
                    members.len()
                ));
            }
            members.iter().find_map(|(k, x)| {
                let member = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                let n = k.chars().count();
                if n > MAX_STRING_CHARS {
                    // the name itself is what is too long: do not echo it
                    return at(format!(
                        "a member name of {n} characters: at most {MAX_STRING_CHARS}"
                    ));
                }
                first_over(x, &member)
            })
        }
        Value::Null | Value::Bool(_) | Value::Number(_) => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    fn path_of(v: Value) -> Option<String> {
        first_over(&v, "").map(|p| p.path)
    }

    #[test]
    fn the_first_string_array_or_object_over_its_bound_is_named() {
        let at_bound = "é".repeat(MAX_STRING_CHARS);
        let ok = json!({"scene": {"name": at_bound, "faults": vec![0; MAX_ITEMS]}});
        assert_eq!(path_of(ok), None);
        let long = json!({"overrides": {"name": "x".repeat(MAX_STRING_CHARS + 1)}});
        assert_eq!(path_of(long).as_deref(), Some("overrides.name"));
        let many = json!({"design": {"factors": [{"values": vec![1.0; MAX_ITEMS + 1]}]}});
        assert_eq!(path_of(many).as_deref(), Some("design.factors[0].values"));
        let key = json!({"overrides": {"x".repeat(MAX_STRING_CHARS + 1): 1}});
        let p = first_over(&key, "").unwrap();
        assert_eq!(p.path, "overrides");
        assert!(!p.message.contains("xxx"), "{}", p.message);
    }
}
