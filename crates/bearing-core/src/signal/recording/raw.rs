//! Today's one-channel formats: raw little-endian f32 and a JSON array of numbers.

use super::contents::{
    check_sample_count, Channel, ReadResult, Recording, RecordingFormat, RecordingLimits,
};

fn one_channel(format: RecordingFormat, samples: Vec<f64>) -> Recording {
    Recording {
        format,
        channels: vec![Channel {
            name: "samples".into(),
            unit: None,
            samples,
        }],
        sample_rate: None,
        shaft_rpm: None,
        skipped: vec![],
    }
}

pub(super) fn read_f32le(bytes: &[u8], limits: &RecordingLimits) -> ReadResult<Recording> {
    if !bytes.len().is_multiple_of(4) {
        return Err((
            "file",
            format!(
                "{} bytes is not a whole number of float32 samples (4 bytes each)",
                bytes.len()
            ),
        ));
    }
    check_sample_count(bytes.len() / 4, limits)?;
    let samples = bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)
        .collect();
    Ok(one_channel(RecordingFormat::F32le, samples))
}

pub(super) fn read_json(bytes: &[u8], limits: &RecordingLimits) -> ReadResult<Recording> {
    let v: Vec<serde_json::Value> = serde_json::from_slice(bytes)
        .map_err(|e| ("file", format!("expected a JSON array of numbers: {e}")))?;
    check_sample_count(v.len(), limits)?;
    let samples = v
        .iter()
        .enumerate()
        .map(|(i, x)| {
            x.as_f64()
                .ok_or_else(|| ("samples", format!("element [{i}] is not a number: {x}")))
        })
        .collect::<Result<_, _>>()?;
    Ok(one_channel(RecordingFormat::Json, samples))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn raw_and_json() {
        let limits = RecordingLimits::LOCAL;
        let samples = |r: ReadResult<Recording>| r.unwrap().channels[0].samples.clone();
        let raw: Vec<u8> = [1.5f32, -2.0]
            .iter()
            .flat_map(|v| v.to_le_bytes())
            .collect();
        assert_eq!(samples(read_f32le(&raw, &limits)), vec![1.5, -2.0]);
        assert!(read_f32le(&raw[..5], &limits)
            .err()
            .unwrap()
            .1
            .starts_with("5 bytes"));
        assert_eq!(samples(read_json(b"[1, 2.5]", &limits)), vec![1.0, 2.5]);
        assert!(read_json(b"[1, \"a\"]", &limits)
            .err()
            .unwrap()
            .1
            .contains("[1]"));
        let small = RecordingLimits {
            max_samples: 1,
            ..limits
        };
        assert_eq!(read_f32le(&raw, &small).err().unwrap().0, "samples");
    }
}
