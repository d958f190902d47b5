//! RIFF WAVE files through `hound`: PCM 8/16/24/32-bit and 32-bit float, any number of
//! channels, the sample rate from the header. PCM samples are scaled to full scale
//! (-1 to 1), since the file carries no physical unit.

use super::contents::{
    check_channel_count, check_sample_count, stated, Channel, ReadResult, Recording,
    RecordingFormat, RecordingLimits,
};

pub(super) fn read(bytes: &[u8], limits: &RecordingLimits) -> ReadResult<Recording> {
    let mut reader = hound::WavReader::new(bytes)
        .map_err(|e| ("file", format!("not a WAV file hound can read: {e}")))?;
    let spec = reader.spec();
    let n_ch = spec.channels as usize;
    check_channel_count(n_ch, limits)?;
    let declared = reader.len() as usize; // samples of all channels together
    let bytes_per_sample = spec.bits_per_sample.div_ceil(8) as usize;
    // a header that claims more data than the file has is caught before anything is read
    if declared.saturating_mul(bytes_per_sample) > bytes.len() {
        return Err((
            "file",
            format!(
                "the header declares {declared} samples ({} bytes) but the file is {} bytes: truncated, or the header lies about its length",
                declared.saturating_mul(bytes_per_sample),
                bytes.len()
            ),
        ));
    }
    check_sample_count(declared / n_ch.max(1), limits)?;
    let interleaved: Vec<f64> = match spec.sample_format {
        hound::SampleFormat::Float => reader
            .samples::<f32>()
            .map(|s| s.map(f64::from))
            .collect::<Result<_, _>>(),
        hound::SampleFormat::Int => {
            let full_scale = 2f64.powi(spec.bits_per_sample as i32 - 1);
            reader
                .samples::<i32>()
                .map(|s| s.map(|v| v as f64 / full_scale))
                .collect::<Result<_, _>>()
        }
    }
    .map_err(|e| {
        (
            "file",
            format!("the header declares {declared} samples but reading them failed: {e}"),
        )
    })?;
    if interleaved.len() != declared || !declared.is_multiple_of(n_ch) {
        return Err((
            "file",
            format!(
                "the header declares {declared} samples in {n_ch} channels, the data holds {}",
                interleaved.len()
            ),
        ));
    }
    let channels = (0..n_ch)
        .map(|c| Channel {
            name: format!("ch{c}"),
            unit: match spec.sample_format {
                hound::SampleFormat::Int => Some("full scale".into()),
                hound::SampleFormat::Float => None,
            },
            samples: interleaved.iter().skip(c).step_by(n_ch).copied().collect(),
        })
        .collect();
    let kind = match spec.sample_format {
        hound::SampleFormat::Int => format!("{}-bit PCM", spec.bits_per_sample),
        hound::SampleFormat::Float => format!("{}-bit float", spec.bits_per_sample),
    };
    Ok(Recording {
        format: RecordingFormat::Wav,
        channels,
        sample_rate: Some(stated(
            spec.sample_rate as f64,
            format!("WAV header ({kind})"),
        )),
        shaft_rpm: None,
        skipped: vec![],
    })
}

/// A WAV file of 32-bit float channels (any values; WAV float is not limited to -1..1).
pub(super) fn write(channels: &[&[f64]], sample_rate: u32) -> Result<Vec<u8>, String> {
    let spec = hound::WavSpec {
        channels: channels.len() as u16,
        sample_rate,
        bits_per_sample: 32,
        sample_format: hound::SampleFormat::Float,
    };
    let mut out = std::io::Cursor::new(Vec::new());
    let mut w = hound::WavWriter::new(&mut out, spec).map_err(|e| e.to_string())?;
    let n = channels.first().map_or(0, |c| c.len());
    for k in 0..n {
        for c in channels {
            w.write_sample(c[k] as f32).map_err(|e| e.to_string())?;
        }
    }
    w.finalize().map_err(|e| e.to_string())?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stereo_round_trip_and_a_lying_header() {
        let a: Vec<f64> = (0..100).map(|i| i as f64 * 0.01).collect();
        let b: Vec<f64> = a.iter().map(|x| -x).collect();
        let bytes = write(&[&a, &b], 8000).unwrap();
        let r = read(&bytes, &RecordingLimits::LOCAL).unwrap();
        assert_eq!(r.sample_rate.unwrap().value, 8000.0);
        assert_eq!(r.channels.len(), 2);
        // f32 round trip
        assert!((r.channels[1].samples[99] + 0.99).abs() < 1e-6);
        // cut the data short but leave the header's length
        let e = read(&bytes[..bytes.len() - 40], &RecordingLimits::LOCAL)
            .err()
            .unwrap();
        assert!(e.1.contains("header declares 200 samples"), "{}", e.1);
        let one = RecordingLimits {
            max_channels: 1,
            ..RecordingLimits::LOCAL
        };
        assert_eq!(read(&bytes, &one).err().unwrap().0, "channels");
    }
}
