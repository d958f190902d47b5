//! A simulated run written as a measured recording: its channels, the shaft angle and a
//! once-per-revolution tachometer channel, as WAV, CSV or a MAT-file. Read back, the file
//! is analysed like any lab's (`--channel`, `--tacho-channel`), which is how a simulated
//! run-up is checked against what order tracking makes of a measured one.

use crate::scene::Scene;
use crate::signal::recording::{
    pulses_from_angle, write_csv, write_mat_v5, write_wav, ExportChannel, ExportFormat,
};
use crate::simulation::SimResult;
use crate::simulation_analysis::run_shaft_angle;

/// Name of the tachometer channel in an exported run.
pub const TACHOMETER_CHANNEL: &str = "tachometer";
/// Name of the shaft angle channel in an exported run.
pub const SHAFT_ANGLE_CHANNEL: &str = "shaft_angle";

/// The run's channels, then `shaft_angle` (rad) and `tachometer` (V, once per
/// revolution), in `format`.
pub fn export_run(
    result: &SimResult,
    scene: &Scene,
    format: ExportFormat,
) -> Result<Vec<u8>, String> {
    let ch = &result.channels;
    let angle = run_shaft_angle(result, scene)?;
    let channels: Vec<ExportChannel> = ch
        .channels
        .iter()
        .map(|c| ExportChannel {
            name: &c.name,
            unit: Some(&c.unit),
            samples: &c.data,
        })
        .collect();
    export_with_angle(&channels, angle.radians(), ch.sample_rate, format)
}

/// `channels`, then the shaft angle `radians` and the tachometer pulses made from it,
/// in `format`: the export of a run whose channels were stored apart (the service's).
pub fn export_with_angle(
    channels: &[ExportChannel],
    radians: &[f64],
    sample_rate: f64,
    format: ExportFormat,
) -> Result<Vec<u8>, String> {
    let pulses = pulses_from_angle(radians);
    let mut all = channels.to_vec();
    all.push(ExportChannel {
        name: SHAFT_ANGLE_CHANNEL,
        unit: Some("rad"),
        samples: radians,
    });
    all.push(ExportChannel {
        name: TACHOMETER_CHANNEL,
        unit: Some("V"),
        samples: &pulses,
    });
    match format {
        ExportFormat::Wav => write_wav(&all, sample_rate),
        ExportFormat::Csv => write_csv(&all, sample_rate),
        ExportFormat::Mat => write_mat_v5(&all, sample_rate, None),
    }
}
