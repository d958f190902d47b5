//! Assignment at a JSON pointer (RFC 6901) that must name an existing member or element:
//! a study factor that names no scene field is a mistake to report, not a member to add.

use serde_json::Value;

/// Why a pointer could not be assigned.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PointerError {
    #[error("'{0}' is not a JSON pointer: it must be empty or start with '/'")]
    Syntax(String),
    #[error("'{pointer}' names no field: '{missing}' does not exist")]
    Missing { pointer: String, missing: String },
}

/// Replace the value at `pointer` in `doc`. The empty pointer replaces the whole document.
pub fn set_at_pointer(doc: &mut Value, pointer: &str, value: Value) -> Result<(), PointerError> {
    if pointer.is_empty() {
        *doc = value;
        return Ok(());
    }
    let Some(rest) = pointer.strip_prefix('/') else {
        return Err(PointerError::Syntax(pointer.into()));
    };
    let mut target = doc;
    let mut walked = String::new();
    for raw in rest.split('/') {
        // RFC 6901: "~1" is "/" and "~0" is "~", in that order.
        let token = raw.replace("~1", "/").replace("~0", "~");
        walked.push('/');
        walked.push_str(raw);
        let missing = || PointerError::Missing {
            pointer: pointer.into(),
            missing: walked.clone(),
        };
        target = match target {
            Value::Object(map) => map.get_mut(&token).ok_or_else(missing)?,
            Value::Array(items) => {
                let index = token
                    .parse::<usize>()
                    .ok()
                    .filter(|_| token == "0" || !token.starts_with('0'));
                index.and_then(|i| items.get_mut(i)).ok_or_else(missing)?
            }
            _ => return Err(missing()),
        };
    }
    *target = value;
    Ok(())
}

/// Put `value` as the member the pointer's last token names, in the object its parent
/// names (which must exist), replacing or adding it: for members a design owns whatever the
/// base had (a defect list, a lubricant model the base left at its default).
pub fn put_member(doc: &mut Value, pointer: &str, value: Value) -> Result<(), PointerError> {
    let Some((parent, last)) = pointer.rsplit_once('/') else {
        return Err(PointerError::Syntax(pointer.into()));
    };
    let missing = || PointerError::Missing {
        pointer: pointer.into(),
        missing: parent.into(),
    };
    let target = if parent.is_empty() {
        Some(doc)
    } else {
        doc.pointer_mut(parent)
    };
    match target {
        Some(Value::Object(map)) => {
            map.insert(last.replace("~1", "/").replace("~0", "~"), value);
            Ok(())
        }
        _ => Err(missing()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn sets_existing_members_and_elements_only() {
        let mut d = json!({"a": {"b": 1, "c/d": 2, "e~f": 3}, "list": [10, 20]});
        set_at_pointer(&mut d, "/a/b", json!(5)).unwrap();
        set_at_pointer(&mut d, "/a/c~1d", json!(6)).unwrap();
        set_at_pointer(&mut d, "/a/e~0f", json!(7)).unwrap();
        set_at_pointer(&mut d, "/list/1", json!(21)).unwrap();
        assert_eq!(
            d,
            json!({"a": {"b": 5, "c/d": 6, "e~f": 7}, "list": [10, 21]})
        );
        for bad in ["/a/x", "/list/2", "/list/01", "/list/-", "/a/b/c"] {
            assert!(
                matches!(
                    set_at_pointer(&mut d, bad, json!(0)),
                    Err(PointerError::Missing { .. })
                ),
                "{bad}"
            );
        }
        assert!(matches!(
            set_at_pointer(&mut d, "a/b", json!(0)),
            Err(PointerError::Syntax(_))
        ));
    }

    #[test]
    fn puts_a_member_into_an_existing_object() {
        let mut d = json!({"a": {"b": 1}, "list": [10]});
        put_member(&mut d, "/a/b", json!({"x": 2})).unwrap();
        put_member(&mut d, "/a/new", json!(3)).unwrap();
        put_member(&mut d, "/top", json!(4)).unwrap();
        assert_eq!(
            d,
            json!({"a": {"b": {"x": 2}, "new": 3}, "list": [10], "top": 4})
        );
        for bad in ["/nope/x", "/list/x", "nope"] {
            assert!(put_member(&mut d, bad, json!(0)).is_err(), "{bad}");
        }
    }
}
