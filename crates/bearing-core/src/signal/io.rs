//! Reading a one-channel signal from raw f32le, single-column CSV or a JSON array.

use std::path::Path;

/// Sample file formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SignalFormat {
    /// Raw little-endian IEEE-754 float32, no header, one channel.
    F32le,
    /// One number per line; an optional non-numeric header line; blank lines ignored; if a
    /// line has several comma-separated fields, the first one is used.
    Csv,
    /// A JSON array of numbers.
    Json,
}

impl std::str::FromStr for SignalFormat {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "f32le" | "f32" | "raw" => Ok(SignalFormat::F32le),
            "csv" | "txt" => Ok(SignalFormat::Csv),
            "json" => Ok(SignalFormat::Json),
            other => Err(format!(
                "unknown format '{other}' (expected f32le, csv or json)"
            )),
        }
    }
}

impl SignalFormat {
    /// Guess from the file extension: `.f32le/.f32/.raw/.bin` -> f32le, `.csv/.txt` -> csv,
    /// `.json` -> json.
    pub fn from_extension(path: &Path) -> Option<Self> {
        match path.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "f32le" | "f32" | "raw" | "bin" => Some(SignalFormat::F32le),
            "csv" | "txt" => Some(SignalFormat::Csv),
            "json" => Some(SignalFormat::Json),
            _ => None,
        }
    }
}

/// A problem with a signal file; the message names the file and where it went wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{source_name}: {message}")]
pub struct SignalReadError {
    pub source_name: String,
    pub message: String,
}

fn err(source_name: &str, message: impl Into<String>) -> SignalReadError {
    SignalReadError {
        source_name: source_name.into(),
        message: message.into(),
    }
}

/// Parse `bytes` in `format`; `source_name` (e.g. the path) prefixes error messages.
pub fn parse_signal(
    bytes: &[u8],
    format: SignalFormat,
    source_name: &str,
) -> Result<Vec<f64>, SignalReadError> {
    let samples = match format {
        SignalFormat::F32le => {
            if !bytes.len().is_multiple_of(4) {
                return Err(err(
                    source_name,
                    format!(
                        "{} bytes is not a whole number of float32 samples (4 bytes each)",
                        bytes.len()
                    ),
                ));
            }
            bytes
                .chunks_exact(4)
                .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
                .collect()
        }
        SignalFormat::Csv => {
            let text = std::str::from_utf8(bytes)
                .map_err(|e| err(source_name, format!("not UTF-8 text: {e}")))?;
            let mut v = Vec::new();
            let mut seen_content = false;
            for (i, line) in text.lines().enumerate() {
                let field = line.split(',').next().unwrap_or("").trim();
                if field.is_empty() {
                    continue;
                }
                match field.parse::<f64>() {
                    Ok(x) => v.push(x),
                    // one header line is allowed before the first number
                    Err(_) if !seen_content => {}
                    Err(_) => {
                        return Err(err(
                            source_name,
                            format!("line {}: '{field}' is not a number", i + 1),
                        ))
                    }
                }
                seen_content = true;
            }
            v
        }
        SignalFormat::Json => {
            let v: Vec<serde_json::Value> = serde_json::from_slice(bytes).map_err(|e| {
                err(
                    source_name,
                    format!("expected a JSON array of numbers: {e}"),
                )
            })?;
            v.iter()
                .enumerate()
                .map(|(i, x)| {
                    x.as_f64().ok_or_else(|| {
                        err(source_name, format!("element [{i}] is not a number: {x}"))
                    })
                })
                .collect::<Result<_, _>>()?
        }
    };
    if let Some(i) = samples.iter().position(|x: &f64| !x.is_finite()) {
        return Err(err(
            source_name,
            format!("sample {i} is not a finite number"),
        ));
    }
    if samples.is_empty() {
        return Err(err(source_name, "holds no samples"));
    }
    Ok(samples)
}

/// Read a signal file; `format` `None` = guess from the extension.
pub fn read_signal(path: &Path, format: Option<SignalFormat>) -> Result<Vec<f64>, SignalReadError> {
    let name = path.display().to_string();
    let format = format
        .or_else(|| SignalFormat::from_extension(path))
        .ok_or_else(|| {
            err(
                &name,
                "cannot tell the format from the extension; pass --format f32le|csv|json",
            )
        })?;
    let bytes = std::fs::read(path).map_err(|e| err(&name, format!("cannot read: {e}")))?;
    parse_signal(&bytes, format, &name)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats() {
        let raw: Vec<u8> = [1.5f32, -2.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        assert_eq!(
            parse_signal(&raw, SignalFormat::F32le, "a").unwrap(),
            vec![1.5, -2.0]
        );
        assert!(parse_signal(&raw[..5], SignalFormat::F32le, "a")
            .unwrap_err()
            .to_string()
            .starts_with("a: 5 bytes"));
        let csv = b"accel_g\n0.5\n\n-1e-3, 7\n2\n";
        assert_eq!(
            parse_signal(csv, SignalFormat::Csv, "c").unwrap(),
            vec![0.5, -1e-3, 2.0]
        );
        let e = parse_signal(b"1\n2\nx\n", SignalFormat::Csv, "c.csv")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "c.csv: line 3: 'x' is not a number");
        assert_eq!(
            parse_signal(b"[1, 2.5]", SignalFormat::Json, "j").unwrap(),
            vec![1.0, 2.5]
        );
        assert!(parse_signal(b"[1, \"a\"]", SignalFormat::Json, "j")
            .unwrap_err()
            .to_string()
            .contains("[1]"));
        assert!(parse_signal(b"nan\n", SignalFormat::Csv, "c").is_err());
        assert_eq!(
            SignalFormat::from_extension(Path::new("x.F32LE")),
            Some(SignalFormat::F32le)
        );
    }
}
