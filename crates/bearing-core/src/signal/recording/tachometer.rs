//! The shaft's angle from what a measured rig records of its speed: a tachometer channel
//! (once- or n-per-revolution pulses) or a speed profile as (time, rpm) rows. Order
//! tracking resamples the vibration by this angle.

use std::f64::consts::TAU;

use super::contents::{ChannelChoice, Recording, RecordingError};
use crate::signal::shaft_angle::ShaftAngle;

/// How pulses are found in a tachometer channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PulseOptions {
    /// Pulses per shaft revolution (1 for a once-per-revolution key).
    pub pulses_per_rev: usize,
    /// Level a pulse's rising edge crosses; `None` = midway between the channel's
    /// smallest and largest value.
    pub threshold: Option<f64>,
    /// Hysteresis, as a fraction of the channel's range: after an edge the signal must fall
    /// this far below the threshold before the next edge counts, so noise on a flat top
    /// cannot count twice.
    pub hysteresis: f64,
}

impl Default for PulseOptions {
    fn default() -> Self {
        PulseOptions {
            pulses_per_rev: 1,
            threshold: None,
            hysteresis: 0.1,
        }
    }
}

/// Rising edges through `threshold`, as fractional sample indices (linear between samples).
fn rising_edges(x: &[f64], threshold: f64, band: f64) -> Vec<f64> {
    let (hi, lo) = (threshold + band / 2.0, threshold - band / 2.0);
    let mut armed = x.first().is_some_and(|&v| v < threshold);
    let mut edges = Vec::new();
    for k in 1..x.len() {
        if armed && x[k] >= hi {
            // the crossing of the threshold itself, at or before k
            let mut j = k;
            while j > 1 && x[j - 1] >= threshold {
                j -= 1;
            }
            let (a, b) = (x[j - 1], x[j]);
            let frac = if b > a {
                ((threshold - a) / (b - a)).clamp(0.0, 1.0)
            } else {
                1.0
            };
            edges.push((j - 1) as f64 + frac);
            armed = false;
        } else if !armed && x[k] <= lo {
            armed = true;
        }
    }
    edges
}

/// The shaft angle per sample of a tachometer channel: `2 pi / pulses_per_rev` between
/// successive rising edges, linear in between, continued at the first and last interval's
/// speed before the first and after the last pulse.
pub fn angle_from_pulses(pulses: &[f64], opts: &PulseOptions) -> Result<ShaftAngle, String> {
    if opts.pulses_per_rev == 0 {
        return Err("pulses per revolution must be at least 1".into());
    }
    if !(opts.hysteresis.is_finite() && (0.0..1.0).contains(&opts.hysteresis)) {
        return Err(format!(
            "hysteresis must be a fraction in [0, 1) (got {})",
            opts.hysteresis
        ));
    }
    let (min, max) = pulses
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    if max.partial_cmp(&min) != Some(std::cmp::Ordering::Greater) {
        return Err("the tachometer channel is flat: no pulses".into());
    }
    let threshold = opts.threshold.unwrap_or(0.5 * (min + max));
    let edges = rising_edges(pulses, threshold, opts.hysteresis * (max - min));
    if edges.len() < 2 {
        return Err(format!(
            "found {} rising edge(s) through {threshold}; need at least 2 to tell a speed",
            edges.len()
        ));
    }
    let step = TAU / opts.pulses_per_rev as f64;
    let mut seg = 0;
    let radians = (0..pulses.len())
        .map(|k| {
            let t = k as f64;
            while seg + 2 < edges.len() && t > edges[seg + 1] {
                seg += 1;
            }
            let (t0, t1) = (edges[seg], edges[seg + 1]);
            step * (seg as f64 + (t - t0) / (t1 - t0))
        })
        .collect();
    ShaftAngle::new(radians, pulses.len()).map_err(|e| e.to_string())
}

/// The shaft angle per sample from a speed profile: `rpm` at `times` (s from the first
/// sample, increasing), linear in between and held beyond the ends, integrated exactly.
pub fn angle_from_speed_profile(
    times: &[f64],
    rpm: &[f64],
    sample_rate: f64,
    n: usize,
) -> Result<ShaftAngle, String> {
    if times.len() != rpm.len() || times.is_empty() {
        return Err("a speed profile needs as many times as speeds, at least one".into());
    }
    if let Some(i) = times
        .windows(2)
        .position(|w| w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater))
    {
        return Err(format!("speed profile times must increase (row {})", i + 2));
    }
    if let Some(i) = rpm.iter().position(|r| !(r.is_finite() && *r >= 0.0)) {
        return Err(format!(
            "speed profile row {}: rpm must be finite and >= 0",
            i + 1
        ));
    }
    let hz = |t: f64| -> f64 {
        let i = times.partition_point(|&x| x <= t);
        if i == 0 {
            rpm[0] / 60.0
        } else if i == times.len() {
            rpm[i - 1] / 60.0
        } else {
            let w = (t - times[i - 1]) / (times[i] - times[i - 1]);
            (rpm[i - 1] + w * (rpm[i] - rpm[i - 1])) / 60.0
        }
    };
    // trapezoids between samples (exact for a linear profile between its breakpoints up
    // to the one sample interval a breakpoint falls in)
    let dt = 1.0 / sample_rate;
    let mut angle = 0.0;
    let mut radians = Vec::with_capacity(n);
    for k in 0..n {
        if k > 0 {
            let (a, b) = ((k - 1) as f64 * dt, k as f64 * dt);
            angle += TAU * 0.5 * (hz(a) + hz(b)) * dt;
        }
        radians.push(angle);
    }
    ShaftAngle::new(radians, n).map_err(|e| e.to_string())
}

impl Recording {
    /// The shaft angle for the `signal_len` samples of a channel, from the tachometer
    /// channel `choice` names in the same file.
    pub fn tachometer_angle(
        &self,
        choice: &ChannelChoice,
        opts: &PulseOptions,
        signal_len: usize,
        source_name: &str,
    ) -> Result<ShaftAngle, RecordingError> {
        let tach = self
            .channel(Some(choice), source_name)
            .map_err(|e| RecordingError {
                field: "tachometer",
                ..e
            })?;
        if tach.samples.len() != signal_len {
            return Err(RecordingError::new(
                source_name,
                "tachometer",
                format!(
                    "tachometer channel '{}' has {} samples, the signal {signal_len}",
                    tach.name,
                    tach.samples.len()
                ),
            ));
        }
        angle_from_pulses(&tach.samples, opts).map_err(|m| {
            RecordingError::new(
                source_name,
                "tachometer",
                format!("channel '{}': {m}", tach.name),
            )
        })
    }
}

/// A speed profile file: rows of `time (s), rpm`, separated by commas, tabs or spaces,
/// after an optional header line.
pub fn parse_speed_profile(text: &str) -> Result<(Vec<f64>, Vec<f64>), String> {
    let (mut times, mut rpm) = (vec![], vec![]);
    for (i, line) in text.lines().enumerate() {
        let fields: Vec<&str> = line
            .split([',', '\t', ' '])
            .filter(|f| !f.is_empty())
            .collect();
        if fields.is_empty() || line.trim_start().starts_with('#') {
            continue;
        }
        let nums: Vec<Option<f64>> = fields.iter().map(|f| f.parse().ok()).collect();
        match nums.as_slice() {
            [Some(t), Some(r)] => {
                times.push(*t);
                rpm.push(*r);
            }
            _ if times.is_empty() && i == 0 => {} // a header
            _ => {
                return Err(format!(
                    "line {}: expected two numbers, time (s) and rpm",
                    i + 1
                ))
            }
        }
    }
    Ok((times, rpm))
}

/// A once-per-revolution tachometer channel for a shaft angle: 5 (a TTL high) over the
/// first tenth of every revolution, 0 elsewhere.
pub fn pulses_from_angle(radians: &[f64]) -> Vec<f64> {
    radians
        .iter()
        .map(|a| {
            if (a / TAU).rem_euclid(1.0) < 0.1 {
                5.0
            } else {
                0.0
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pulses_give_back_a_run_up_angle() {
        // a run-up from 10 to 30 rev/s over 2 s at 5 kHz, with noise on the pulses
        let fs = 5000.0;
        let n = 10_000;
        let truth: Vec<f64> = (0..n)
            .map(|k| {
                let t = k as f64 / fs;
                TAU * (10.0 * t + 5.0 * t * t) + 0.3
            })
            .collect();
        let noisy: Vec<f64> = pulses_from_angle(&truth)
            .iter()
            .enumerate()
            .map(|(k, p)| p + 0.4 * ((k * 7919 % 101) as f64 / 101.0 - 0.5))
            .collect();
        let got = angle_from_pulses(&noisy, &PulseOptions::default()).unwrap();
        // the edges sit at whole revolutions of the truth (so the offset is a whole number of
        // turns); in between, a straight line through two edges misses a constant
        // acceleration's parabola by at most a T^2 / 8: 2 pi 10 rad/s^2 x (0.1 s)^2 / 8 =
        // 0.079 rad over the slowest revolution, plus edge timing within one sample at 30
        // rev/s and 5 kHz (0.038 rad)
        let offset = TAU * ((truth[n / 2] - got.radians()[n / 2]) / TAU).round();
        let worst = got
            .radians()
            .iter()
            .zip(&truth)
            .skip(500)
            .take(9000)
            .map(|(g, t)| (g + offset - t).abs())
            .fold(0.0, f64::max);
        assert!(worst < 0.079 + 0.038, "worst angle error {worst} rad");
    }

    #[test]
    fn speed_profile_integrates() {
        let a = angle_from_speed_profile(&[0.0, 1.0], &[600.0, 1800.0], 1000.0, 1001).unwrap();
        // 10 rev/s to 30 rev/s over 1 s: 20 revolutions
        assert!((a.revolutions() - 20.0).abs() < 1e-6);
        assert!(angle_from_speed_profile(&[1.0, 0.0], &[1.0, 1.0], 1000.0, 10).is_err());
    }
}
