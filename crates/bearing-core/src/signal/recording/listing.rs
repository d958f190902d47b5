//! What a recording holds, as `inspect` shows it and the page offers it before an upload:
//! each channel with its length, unit and (where the file states the rate) duration, the
//! sample rate and shaft speed with where they came from, and what was skipped and why.

use serde::Serialize;

use super::contents::{Recording, RecordingFormat, Stated};

#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct ChannelListing {
    /// 0-based; a channel is chosen by this or by its name.
    pub index: usize,
    pub name: String,
    pub samples: usize,
    pub unit: Option<String>,
    /// s, where the sample rate is known.
    pub duration: Option<f64>,
    /// Every k-th sample, at most the number asked for (see [`Recording::listing_with_preview`]):
    /// enough to plot the channel before it is analysed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub preview: Option<Vec<f64>>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct SkippedListing {
    pub name: String,
    pub reason: String,
}

/// A file's channels and what it says about them.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct Listing {
    /// `mat`, `wav`, `csv`, `tsv`, `f32le` or `json`.
    #[cfg_attr(feature = "openapi", schema(value_type = String))]
    pub format: RecordingFormat,
    /// Hz, and where in the file; absent when the file does not carry it.
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Object>))]
    pub sample_rate: Option<Stated>,
    /// rev/min, and where in the file.
    #[cfg_attr(feature = "openapi", schema(value_type = Option<Object>))]
    pub shaft_rpm: Option<Stated>,
    pub channels: Vec<ChannelListing>,
    /// Variables or columns that are not channels, with the reason.
    pub skipped: Vec<SkippedListing>,
}

impl Recording {
    /// The listing of this recording.
    pub fn listing(&self) -> Listing {
        self.listing_with_preview(0)
    }

    /// The listing with up to `points` samples of each channel (every k-th sample, k the
    /// smallest that fits), none when `points` is 0.
    pub fn listing_with_preview(&self, points: usize) -> Listing {
        let rate = self.sample_rate.as_ref().map(|s| s.value);
        Listing {
            format: self.format,
            sample_rate: self.sample_rate.clone(),
            shaft_rpm: self.shaft_rpm.clone(),
            channels: self
                .channels
                .iter()
                .enumerate()
                .map(|(index, c)| ChannelListing {
                    index,
                    name: c.name.clone(),
                    samples: c.samples.len(),
                    unit: c.unit.clone(),
                    duration: rate.map(|r| c.samples.len() as f64 / r),
                    preview: (points > 0).then(|| {
                        let k = c.samples.len().div_ceil(points).max(1);
                        c.samples.iter().step_by(k).copied().collect()
                    }),
                })
                .collect(),
            skipped: self
                .skipped
                .iter()
                .map(|s| SkippedListing {
                    name: s.name.clone(),
                    reason: s.reason.clone(),
                })
                .collect(),
        }
    }
}

impl std::fmt::Display for Listing {
    /// The listing as lines of text, for the command line.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let format = serde_json::to_value(self.format).unwrap_or_default();
        writeln!(f, "format: {}", format.as_str().unwrap_or("?"))?;
        match &self.sample_rate {
            Some(s) => writeln!(f, "sample rate: {} Hz (from the {})", s.value, s.from)?,
            None => writeln!(f, "sample rate: not in the file")?,
        }
        if let Some(s) = &self.shaft_rpm {
            writeln!(f, "shaft speed: {} rev/min (from the {})", s.value, s.from)?;
        }
        writeln!(f, "channels:")?;
        for c in &self.channels {
            write!(f, "  {}: {}  {} samples", c.index, c.name, c.samples)?;
            if let Some(d) = c.duration {
                write!(f, ", {d} s")?;
            }
            if let Some(u) = &c.unit {
                write!(f, ", unit {u}")?;
            }
            writeln!(f)?;
        }
        for s in &self.skipped {
            writeln!(f, "skipped: {} ({})", s.name, s.reason)?;
        }
        Ok(())
    }
}
