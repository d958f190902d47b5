//! Channels and spectra as stored artifacts (little-endian f32 with typed metadata).

use crate::store::blob::encode_f32le;
use crate::store::{Artifact, ArtifactMeta};
use bearing_core::signal::analysis::AnalysisOutput;
use bearing_core::simulation::Channels;

/// Name of the artifact holding a channel's samples.
pub fn channel_artifact_name(channel: &str) -> String {
    format!("channel:{channel}")
}

/// Name of the artifact holding the raw envelope spectrum (`None`) or a DTCWT level's.
pub fn spectrum_artifact_name(level: Option<usize>) -> String {
    match level {
        None => "spectrum:raw".into(),
        Some(l) => format!("spectrum:level:{l}"),
    }
}

/// Every recorded channel.
pub fn channel_artifacts(ch: &Channels) -> Vec<Artifact> {
    ch.channels
        .iter()
        .map(|c| Artifact {
            name: channel_artifact_name(&c.name),
            meta: ArtifactMeta::Channel {
                name: c.name.clone(),
                unit: c.unit.clone(),
                sample_rate: ch.sample_rate,
                start_time: ch.start_time,
                samples: c.data.len(),
            },
            data: encode_f32le(&c.data),
        })
        .collect()
}

/// Name of the artifact holding a run's shaft angle, rad per sample.
pub const SHAFT_ANGLE_ARTIFACT: &str = "shaft_angle";

/// A run's shaft angle as an artifact shaped like a channel.
pub fn shaft_angle_artifact(ch: &Channels, radians: &[f64]) -> Artifact {
    Artifact {
        name: SHAFT_ANGLE_ARTIFACT.into(),
        meta: ArtifactMeta::Channel {
            name: SHAFT_ANGLE_ARTIFACT.into(),
            unit: "rad".into(),
            sample_rate: ch.sample_rate,
            start_time: ch.start_time,
            samples: radians.len(),
        },
        data: encode_f32le(radians),
    }
}

/// Raw envelope spectrum and one per DTCWT level, with their bin width.
pub fn spectrum_artifacts(out: &AnalysisOutput) -> Vec<Artifact> {
    let spectrum = |name: String, s: &bearing_core::signal::Spectrum| Artifact {
        name,
        meta: ArtifactMeta::Spectrum {
            df: s.df,
            bins: s.amplitude.len(),
        },
        data: encode_f32le(&s.amplitude),
    };
    let mut v = vec![spectrum(spectrum_artifact_name(None), &out.raw_spectrum)];
    for (i, s) in out.level_spectra.iter().enumerate() {
        if let Some(s) = s {
            v.push(spectrum(spectrum_artifact_name(Some(i + 1)), s));
        }
    }
    v
}
