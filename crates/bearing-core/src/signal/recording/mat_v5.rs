//! MATLAB level-5 MAT-files (what `save` writes by default from MATLAB 7 on, compressed
//! variables included, and what the CWRU data centre ships), read and written.
//!
//! Read with a parser of our own over `flate2`'s inflater: the crates measured
//! (docs/reference/recordings.md) either returned no variables from a truncated file
//! without an error, refused a whole file over one text variable, or could not read
//! SciPy-written files; none bounded what a compressed variable may expand to.
//!
//! A variable becomes a channel when it is a real numeric vector; a real numeric scalar
//! named like a sample rate (`fs`, `Fs`, `sample_rate`, `fs_hz`) gives the sample rate, one
//! whose name ends in `RPM` (CWRU's `X105RPM`) the shaft speed. Everything else is listed
//! as skipped, with the reason.

use std::io::Read;

use super::contents::{
    check_channel_count, check_sample_count, stated, Channel, ReadResult, Recording,
    RecordingFormat, RecordingLimits, Skipped, Stated,
};

const HEADER: usize = 128;
// element types
const MI_INT8: u32 = 1;
const MI_UINT8: u32 = 2;
const MI_INT16: u32 = 3;
const MI_UINT16: u32 = 4;
const MI_INT32: u32 = 5;
const MI_UINT32: u32 = 6;
const MI_SINGLE: u32 = 7;
const MI_DOUBLE: u32 = 9;
const MI_INT64: u32 = 12;
const MI_UINT64: u32 = 13;
const MI_MATRIX: u32 = 14;
const MI_COMPRESSED: u32 = 15;
// array classes
const MX_DOUBLE: u8 = 6;
const MX_UINT64: u8 = 15;

/// Scalar names that state the sample rate, Hz.
const RATE_NAMES: &[&str] = &["fs", "fs_hz", "sample_rate", "samplerate", "sampling_rate"];

/// One data element: its type and bytes, and where the next one starts.
struct Element<'a> {
    ty: u32,
    data: &'a [u8],
    next: usize,
}

fn u32_at(b: &[u8], p: usize) -> u32 {
    u32::from_le_bytes([b[p], b[p + 1], b[p + 2], b[p + 3]])
}

/// The element at `p`; `what` names it in the error when the bytes run out.
fn element<'a>(b: &'a [u8], p: usize, what: &str) -> ReadResult<Element<'a>> {
    let truncated = |need: usize| {
        (
            "file",
            format!(
                "truncated: the {what} at byte {p} needs {need} bytes, {} remain",
                b.len().saturating_sub(p)
            ),
        )
    };
    if p + 8 > b.len() {
        return Err(truncated(8));
    }
    let w0 = u32_at(b, p);
    if w0 >> 16 != 0 {
        // small data element: type and size in one word, up to 4 bytes of data
        let n = (w0 >> 16) as usize;
        if n > 4 {
            return Err(("file", format!("corrupt: the {what} at byte {p} declares {n} bytes in a small element (at most 4)")));
        }
        return Ok(Element {
            ty: w0 & 0xffff,
            data: &b[p + 4..p + 4 + n],
            next: p + 8,
        });
    }
    let n = u32_at(b, p + 4) as usize;
    let start = p + 8;
    if n > b.len() - start {
        return Err(truncated(8 + n));
    }
    // compressed elements are not padded to 8 bytes; all others are
    let next = if w0 == MI_COMPRESSED {
        start + n
    } else {
        (start + n).div_ceil(8) * 8
    };
    Ok(Element {
        ty: w0,
        data: &b[start..start + n],
        next: next.min(b.len()),
    })
}

/// Numbers of an element's type, as f64.
fn numbers(e: &Element, what: &str) -> ReadResult<Vec<f64>> {
    macro_rules! conv {
        ($t:ty) => {{
            const W: usize = std::mem::size_of::<$t>();
            if !e.data.len().is_multiple_of(W) {
                return Err((
                    "file",
                    format!(
                        "corrupt: {what} has {} bytes, not a whole number of {W}-byte values",
                        e.data.len()
                    ),
                ));
            }
            e.data
                .chunks_exact(W)
                .map(|c| <$t>::from_le_bytes(c.try_into().expect("chunk of W bytes")) as f64)
                .collect()
        }};
    }
    Ok(match e.ty {
        MI_INT8 => conv!(i8),
        MI_UINT8 => conv!(u8),
        MI_INT16 => conv!(i16),
        MI_UINT16 => conv!(u16),
        MI_INT32 => conv!(i32),
        MI_UINT32 => conv!(u32),
        MI_SINGLE => conv!(f32),
        MI_DOUBLE => conv!(f64),
        MI_INT64 => conv!(i64),
        MI_UINT64 => conv!(u64),
        t => {
            return Err((
                "file",
                format!("corrupt: {what} has data type {t}, not a number type"),
            ))
        }
    })
}

/// A variable as read: a vector, a scalar, or something skipped.
enum Variable {
    Vector(String, Vec<f64>),
    Scalar(String, f64),
    Skipped(Skipped),
}

fn class_name(c: u8) -> &'static str {
    match c {
        1 => "a cell array",
        2 => "a struct",
        3 => "an object",
        4 => "text",
        5 => "a sparse matrix",
        _ => "an array of an unknown class",
    }
}

/// The variable in a miMATRIX element's bytes.
fn variable(b: &[u8], limits: &RecordingLimits) -> ReadResult<Variable> {
    let flags = element(b, 0, "array flags")?;
    if flags.ty != MI_UINT32 || flags.data.len() < 8 {
        return Err((
            "file",
            "corrupt: a variable's array flags are missing".into(),
        ));
    }
    let class = flags.data[0];
    let complex = flags.data[1] & 0x08 != 0;
    let dims_el = element(b, flags.next, "dimensions")?;
    let dims: Vec<usize> = numbers(&dims_el, "the dimensions")?
        .into_iter()
        .map(|d| d.max(0.0) as usize)
        .collect();
    let name_el = element(b, dims_el.next, "variable name")?;
    let name = String::from_utf8_lossy(name_el.data).into_owned();
    let skip = |reason: String| {
        Ok(Variable::Skipped(Skipped {
            name: name.clone(),
            reason,
        }))
    };
    let shape = dims
        .iter()
        .map(|d| d.to_string())
        .collect::<Vec<_>>()
        .join("x");
    if !(MX_DOUBLE..=MX_UINT64).contains(&class) {
        return skip(format!("{}, not numbers", class_name(class)));
    }
    if complex {
        return skip(format!("complex numbers ({shape})"));
    }
    let numel = dims.iter().try_fold(1usize, |a, &d| a.checked_mul(d));
    let Some(numel) = numel else {
        return Err((
            "file",
            format!("corrupt: variable '{name}' has dimensions {shape}"),
        ));
    };
    if numel == 0 {
        return skip("empty".into());
    }
    if dims.iter().filter(|&&d| d > 1).count() > 1 {
        return skip(format!(
            "a {shape} matrix; only vectors and scalars are read"
        ));
    }
    check_sample_count(numel, limits).map_err(|(f, m)| (f, format!("variable '{name}': {m}")))?;
    let real = element(b, name_el.next, "variable data")?;
    let values = numbers(&real, &format!("variable '{name}'"))?;
    if values.len() != numel {
        return Err((
            "file",
            format!(
                "corrupt: variable '{name}' is {shape} but holds {} values",
                values.len()
            ),
        ));
    }
    Ok(if numel == 1 {
        Variable::Scalar(name, values[0])
    } else {
        Variable::Vector(name, values)
    })
}

/// Inflate a compressed element, refusing to expand past what one channel may hold.
fn inflate(data: &[u8], limits: &RecordingLimits) -> ReadResult<Vec<u8>> {
    // a vector of max_samples doubles, with room for its tags and name
    let cap = limits.max_samples.saturating_mul(8).saturating_add(1 << 16);
    let mut out = Vec::new();
    flate2::read::ZlibDecoder::new(data)
        .take(cap as u64 + 1)
        .read_to_end(&mut out)
        .map_err(|e| {
            (
                "file",
                format!("corrupt or truncated compressed variable: {e}"),
            )
        })?;
    if out.len() > cap {
        return Err((
            "samples",
            format!(
                "a compressed variable expands past {cap} bytes, more than {} samples",
                limits.max_samples
            ),
        ));
    }
    Ok(out)
}

/// The one scalar of a kind, or an error listing them when there are several.
fn one_stated(found: Vec<(String, f64)>, what: &str) -> ReadResult<Option<Stated>> {
    match found.len() {
        0 => Ok(None),
        1 => Ok(Some(stated(found[0].1, format!("variable {}", found[0].0)))),
        _ => Err((
            "file",
            format!(
                "holds several {what} variables, cannot tell which applies: {}",
                found
                    .iter()
                    .map(|(n, v)| format!("{n} = {v}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        )),
    }
}

pub(super) fn read(b: &[u8], limits: &RecordingLimits) -> ReadResult<Recording> {
    if b.len() < HEADER {
        return Err((
            "file",
            format!(
                "truncated: {} bytes, shorter than a MAT-file's 128-byte header",
                b.len()
            ),
        ));
    }
    if b.starts_with(b"MATLAB 7.3") {
        return Err((
            "file",
            "a MATLAB v7.3 (HDF5) file, which is not read; save it with `save -v7`".into(),
        ));
    }
    match &b[126..128] {
        b"IM" => {}
        b"MI" => return Err(("file", "a big-endian MAT-file, which is not read".into())),
        _ => {
            return Err((
                "file",
                "not a MATLAB level-5 MAT-file (no 'IM' byte-order mark at byte 126)".into(),
            ))
        }
    }
    let (mut channels, mut skipped, mut rates, mut rpms) = (vec![], vec![], vec![], vec![]);
    let mut p = HEADER;
    while p < b.len() {
        let e = element(b, p, "variable")?;
        p = e.next;
        let var = match e.ty {
            MI_MATRIX => variable(e.data, limits)?,
            MI_COMPRESSED => {
                let inner = inflate(e.data, limits)?;
                let m = element(&inner, 0, "compressed variable")?;
                if m.ty != MI_MATRIX {
                    continue;
                }
                variable(m.data, limits)?
            }
            // subsystem data and the like: not variables
            _ => continue,
        };
        match var {
            Variable::Vector(name, samples) => {
                check_channel_count(channels.len() + 1, limits)?;
                channels.push(Channel {
                    name,
                    unit: None,
                    samples,
                });
            }
            Variable::Scalar(name, v)
                if RATE_NAMES.contains(&name.to_ascii_lowercase().as_str()) =>
            {
                rates.push((name, v))
            }
            Variable::Scalar(name, v) if name.to_ascii_uppercase().ends_with("RPM") => {
                rpms.push((name, v))
            }
            Variable::Scalar(name, v) => skipped.push(Skipped {
                name,
                reason: format!("a scalar ({v}), not a channel"),
            }),
            Variable::Skipped(s) => skipped.push(s),
        }
    }
    Ok(Recording {
        format: RecordingFormat::Mat,
        channels,
        sample_rate: one_stated(rates, "sample-rate")?,
        shaft_rpm: one_stated(rpms, "shaft-speed (…RPM)")?,
        skipped,
    })
}

/// A variable to write: a column vector, or a scalar when it holds one value.
pub(super) struct MatVariable<'a> {
    pub name: &'a str,
    pub values: &'a [f64],
}

fn put_tag(out: &mut Vec<u8>, ty: u32, n: usize) {
    out.extend_from_slice(&ty.to_le_bytes());
    out.extend_from_slice(&(n as u32).to_le_bytes());
}

fn pad8(out: &mut Vec<u8>) {
    out.resize(out.len().div_ceil(8) * 8, 0);
}

/// An uncompressed level-5 MAT-file of double column vectors (MATLAB and SciPy read it).
pub(super) fn write(vars: &[MatVariable]) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let mut text = b"MATLAB 5.0 MAT-file, written by bearing-sim".to_vec();
    text.resize(116, b' ');
    out.extend_from_slice(&text);
    out.extend_from_slice(&[0; 8]); // no subsystem data
    out.extend_from_slice(&0x0100u16.to_le_bytes());
    out.extend_from_slice(b"IM");
    for v in vars {
        if v.name.is_empty() || v.name.len() > 63 {
            return Err(format!(
                "variable name '{}' must be 1-63 characters",
                v.name
            ));
        }
        if v.values.len() > i32::MAX as usize {
            return Err(format!(
                "variable '{}' is longer than a MAT-file holds",
                v.name
            ));
        }
        let mut m = Vec::new();
        put_tag(&mut m, MI_UINT32, 8);
        m.extend_from_slice(&[MX_DOUBLE, 0, 0, 0, 0, 0, 0, 0]);
        put_tag(&mut m, MI_INT32, 8);
        m.extend_from_slice(&(v.values.len() as i32).to_le_bytes());
        m.extend_from_slice(&1i32.to_le_bytes());
        put_tag(&mut m, MI_INT8, v.name.len());
        m.extend_from_slice(v.name.as_bytes());
        pad8(&mut m);
        put_tag(&mut m, MI_DOUBLE, v.values.len() * 8);
        v.values
            .iter()
            .for_each(|x| m.extend_from_slice(&x.to_le_bytes()));
        pad8(&mut m);
        put_tag(&mut out, MI_MATRIX, m.len());
        out.extend_from_slice(&m);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_refusals() {
        let x: Vec<f64> = (0..50).map(|i| (i as f64 * 0.3).sin()).collect();
        let bytes = write(&[
            MatVariable {
                name: "X105_DE_time",
                values: &x,
            },
            MatVariable {
                name: "X105RPM",
                values: &[1797.0],
            },
            MatVariable {
                name: "fs",
                values: &[12000.0],
            },
        ])
        .unwrap();
        let r = read(&bytes, &RecordingLimits::LOCAL).unwrap();
        assert_eq!(r.channels.len(), 1);
        assert_eq!(r.channels[0].name, "X105_DE_time");
        assert_eq!(r.channels[0].samples, x);
        assert_eq!(r.shaft_rpm.unwrap().value, 1797.0);
        assert_eq!(r.sample_rate.unwrap().value, 12000.0);
        // cut anywhere inside the data: an error naming the truncation, never a panic
        for cut in [0, 100, 130, 200, bytes.len() - 1] {
            let e = read(&bytes[..cut], &RecordingLimits::LOCAL).err().unwrap();
            assert!(e.1.contains("truncated"), "{cut}: {}", e.1);
        }
        let tight = RecordingLimits {
            max_samples: 10,
            ..RecordingLimits::LOCAL
        };
        assert_eq!(read(&bytes, &tight).err().unwrap().0, "samples");
    }
}
