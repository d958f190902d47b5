//! JSON Merge Patch (RFC 7396): objects merge recursively, `null` removes a member,
//! anything else replaces the target. [`merge_patch_tagged`] adds one rule for documents
//! with internally tagged unions.

use serde_json::Value;

pub fn merge_patch(target: &mut Value, patch: &Value) {
    merge(target, patch, None);
}

/// [`merge_patch`] for a document whose unions carry their variant in the member `tag`
/// (serde's internally tagged enums, e.g. `{"model": "abcd", "a": ...}`): where a patch
/// object names another variant than the target's, it replaces the target's object instead
/// of merging into it. The old variant's fields belong to it alone: merged, they would be
/// unknown fields of the new one (`{"model": "rheology"}` over the curve's
/// `{"model": "abcd", "a": ...}` would keep `a`), and a user who names a variant means that
/// variant with its own fields and defaults. A patch that repeats the target's variant, or
/// names none, merges as RFC 7396 says.
pub fn merge_patch_tagged(target: &mut Value, patch: &Value, tag: &str) {
    merge(target, patch, Some(tag));
}

/// RFC 7396, with the replacement rule of [`merge_patch_tagged`] when `tag` is given.
fn merge(target: &mut Value, patch: &Value, tag: Option<&str>) {
    let Value::Object(p) = patch else {
        *target = patch.clone();
        return;
    };
    let switches = tag.is_some_and(|tag| {
        matches!((target.get(tag), p.get(tag)), (Some(old), Some(new)) if !new.is_null() && old != new)
    });
    if !target.is_object() || switches {
        *target = Value::Object(Default::default());
    }
    let t = target.as_object_mut().expect("made an object above");
    for (k, v) in p {
        if v.is_null() {
            t.remove(k);
        } else {
            merge(t.entry(k.clone()).or_insert(Value::Null), v, tag);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn rfc7396_examples() {
        // Appendix A of RFC 7396, a selection.
        let cases = [
            (json!({"a": "b"}), json!({"a": "c"}), json!({"a": "c"})),
            (
                json!({"a": "b"}),
                json!({"b": "c"}),
                json!({"a": "b", "b": "c"}),
            ),
            (json!({"a": "b"}), json!({"a": null}), json!({})),
            (
                json!({"a": [{"b": "c"}]}),
                json!({"a": [1]}),
                json!({"a": [1]}),
            ),
            (
                json!({"a": {"b": "c"}}),
                json!({"a": {"b": "d", "c": null}}),
                json!({"a": {"b": "d"}}),
            ),
            (json!(["a", "b"]), json!({"a": "c"}), json!({"a": "c"})),
            (
                json!({"e": null}),
                json!({"a": 1}),
                json!({"e": null, "a": 1}),
            ),
            (
                json!({}),
                json!({"a": {"bb": {"ccc": null}}}),
                json!({"a": {"bb": {}}}),
            ),
        ];
        for (mut t, p, want) in cases {
            merge_patch(&mut t, &p);
            assert_eq!(t, want);
        }
    }

    #[test]
    fn a_patch_naming_another_variant_replaces_the_union() {
        let curve = json!({"lubricant": {"traction": {"model": "abcd", "a": -0.036, "d": 0.036}, "density": 870.0}});
        // another variant: its own fields only; the rest of the document still merges
        let mut t = curve.clone();
        merge_patch_tagged(
            &mut t,
            &json!({"lubricant": {"traction": {"model": "rheology"}, "density": 860.0}}),
            "model",
        );
        assert_eq!(
            t,
            json!({"lubricant": {"traction": {"model": "rheology"}, "density": 860.0}})
        );
        // the same variant, or none named: RFC 7396 (fields merge, null removes)
        let mut t = curve.clone();
        merge_patch_tagged(
            &mut t,
            &json!({"lubricant": {"traction": {"model": "abcd", "a": -0.03, "d": null}}}),
            "model",
        );
        assert_eq!(
            t,
            json!({"lubricant": {"traction": {"model": "abcd", "a": -0.03}, "density": 870.0}})
        );
        let mut t = curve.clone();
        merge_patch_tagged(
            &mut t,
            &json!({"lubricant": {"traction": {"a": 0.0}}}),
            "model",
        );
        assert_eq!(
            t["lubricant"]["traction"],
            json!({"model": "abcd", "a": 0.0, "d": 0.036})
        );
        // without a tag anywhere it is merge_patch
        for (t0, p) in [
            (
                json!({"a": {"b": "c"}}),
                json!({"a": {"b": "d", "c": null}}),
            ),
            (json!({"a": "b"}), json!({"a": [1]})),
        ] {
            let (mut x, mut y) = (t0.clone(), t0);
            merge_patch(&mut x, &p);
            merge_patch_tagged(&mut y, &p, "model");
            assert_eq!(x, y);
        }
    }
}
