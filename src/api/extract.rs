//! Request decoding that reports problems as problem+json with field paths.

use super::input_bounds::check_bounds;
use super::problem::{join_path, FieldProblem, Problem};
use super::strict_json::StrictValue;
use axum::http::{header, HeaderMap};
use serde::de::DeserializeOwned;
use serde_json::Value;

/// Is the request body declared as JSON (`application/json` or `application/*+json`)?
pub fn is_json(headers: &HeaderMap) -> bool {
    content_type(headers).is_some_and(|ct| {
        ct == "application/json" || (ct.starts_with("application/") && ct.ends_with("+json"))
    })
}

/// Media type without parameters, lower-cased.
pub fn content_type(headers: &HeaderMap) -> Option<String> {
    let v = headers.get(header::CONTENT_TYPE)?.to_str().ok()?;
    Some(
        v.split(';')
            .next()
            .unwrap_or("")
            .trim()
            .to_ascii_lowercase(),
    )
}

pub fn require_json(headers: &HeaderMap) -> Result<(), Problem> {
    if is_json(headers) {
        Ok(())
    } else {
        Err(Problem::unsupported_media(format!(
            "expected Content-Type: application/json, got {}",
            content_type(headers).unwrap_or_else(|| "none".into())
        )))
    }
}

/// Parse JSON text into a value: a syntax error, or a member given twice in one object, is
/// a 400.
///
/// A syntax error inside the document names the member where it stopped (`NaN`,
/// `Infinity` and out-of-range numbers such as `1e400` are not JSON numbers), as a 400 with
/// that path in `errors[]`, not only a line and column.
pub fn parse_value(body: &[u8]) -> Result<Value, Problem> {
    let mut de = serde_json::Deserializer::from_slice(body);
    let parsed: Result<StrictValue, _> = serde_path_to_error::deserialize(&mut de);
    let v = parsed.map_err(|e| {
        // `?` stands for a member whose name was not read yet: name its parent instead
        let full = e.path().to_string();
        let path = full.trim_end_matches('?').trim_end_matches('.').to_string();
        let inner = e.into_inner();
        if path.is_empty() || path == "." {
            return Problem::bad_request(format!("request body is not valid JSON: {inner}"));
        }
        let number = inner.to_string().contains("number out of range")
            || body_token_at(body, inner.line(), inner.column()).is_some_and(|t| {
                let t = t.trim_start_matches(['-', '+']);
                t.starts_with("NaN") || t.starts_with("Infinity") || t.starts_with("inf")
            });
        let message = if number {
            format!("not a finite JSON number ({inner}); NaN, Infinity and numbers beyond 1.8e308 are not JSON")
        } else {
            format!("not valid JSON here ({inner})")
        };
        let mut p = Problem::bad_request(format!("request body is not valid JSON at {path}: {message}"));
        p.errors = Some(vec![FieldProblem { path, message }]);
        p
    })?;
    let StrictValue(v) = v;
    de.end()
        .map_err(|e| Problem::bad_request(format!("request body is not valid JSON: {e}")))?;
    Ok(v)
}

/// A request body of names and numbers (a scene, a study; not a measured signal): parsed,
/// then every string, array and object checked against its size bound (422 naming it).
pub fn parse_bounded(body: &[u8]) -> Result<Value, Problem> {
    let v = parse_value(body)?;
    check_bounds(&v, "")?;
    Ok(v)
}

/// The text of `body` from 1-based `line` and `column` (serde_json's error position, one past
/// the offending character or at it) back to the start of the token there.
fn body_token_at(body: &[u8], line: usize, column: usize) -> Option<&str> {
    let text = std::str::from_utf8(body).ok()?;
    let line_text = text.lines().nth(line.checked_sub(1)?)?;
    let end = column.min(line_text.len());
    let start = line_text[..end]
        .rfind(|c: char| c == ':' || c == ',' || c == '[' || c.is_whitespace())
        .map_or(0, |i| i + 1);
    Some(&line_text[start..])
}

/// Convert a JSON value into `T`; a type or unknown-field error is a 422 naming its path
/// (prefixed with `prefix`, e.g. `scene`).
pub fn from_value<T: DeserializeOwned>(v: Value, prefix: &str) -> Result<T, Problem> {
    serde_path_to_error::deserialize(v).map_err(|e| {
        let path = join_path(prefix, &e.path().to_string());
        Problem::validation(vec![FieldProblem {
            path,
            message: e.into_inner().to_string(),
        }])
    })
}

/// The top level of a JSON request body must be an object.
pub fn as_object(v: Value) -> Result<serde_json::Map<String, Value>, Problem> {
    match v {
        Value::Object(m) => Ok(m),
        other => Err(Problem::field(
            "$",
            format!("must be a JSON object, got {}", kind_of(&other)),
        )),
    }
}

pub fn kind_of(v: &Value) -> &'static str {
    match v {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// Decoded query parameters; each handler reads the ones it knows (others are ignored).
#[derive(Debug, Default, Clone)]
pub struct QueryParams(std::collections::BTreeMap<String, String>);

impl QueryParams {
    /// Percent-decode `raw`; a parameter given twice is a 400.
    pub fn parse(raw: Option<&str>) -> Result<QueryParams, Problem> {
        let mut map = std::collections::BTreeMap::new();
        for kv in raw.unwrap_or("").split('&').filter(|s| !s.is_empty()) {
            let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
            let (k, v) = (percent_decode(k), percent_decode(v));
            if map.insert(k.clone(), v).is_some() {
                return Err(Problem::bad_request(format!(
                    "query parameter '{k}' given more than once"
                )));
            }
        }
        Ok(QueryParams(map))
    }

    pub fn str(&self, name: &str) -> Option<&str> {
        self.0.get(name).map(String::as_str)
    }

    /// Parse a parameter; a malformed value is a 400 naming the parameter.
    pub fn get<T: std::str::FromStr>(&self, name: &str) -> Result<Option<T>, Problem>
    where
        T::Err: std::fmt::Display,
    {
        match self.0.get(name) {
            None => Ok(None),
            Some(v) => v.trim().parse::<T>().map(Some).map_err(|e| {
                Problem::bad_request(format!("query parameter '{name}' = '{v}': {e}"))
            }),
        }
    }

    /// A finite float parameter.
    pub fn f64(&self, name: &str) -> Result<Option<f64>, Problem> {
        match self.get::<f64>(name)? {
            Some(x) if !x.is_finite() => Err(Problem::bad_request(format!(
                "query parameter '{name}' must be a finite number"
            ))),
            x => Ok(x),
        }
    }
}

fn percent_decode(s: &str) -> String {
    let bytes = s.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        if b == b'+' {
            out.push(b' ');
        } else if b == b'%' && i + 2 < bytes.len() {
            match std::str::from_utf8(&bytes[i + 1..i + 3])
                .ok()
                .and_then(|h| u8::from_str_radix(h, 16).ok())
            {
                Some(x) => {
                    out.push(x);
                    i += 2;
                }
                None => out.push(b),
            }
        } else {
            out.push(b);
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}
