//! `bearing-sim run SCENE [--fault ...] [--duration S] --out FILE [--export FILE.wav|csv|mat]`.

use super::result::CliResult;
use super::scene_arg::load_scene;
use bearing_core::run_recording::export_run;
use bearing_core::scene::FaultCase;
use bearing_core::signal::recording::ExportFormat;
use bearing_core::simulation::{simulate, RunControl};
use indicatif::{ProgressBar, ProgressStyle};

#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Scene file (JSON) or preset name (h7005c).
    pub scene: String,
    /// Fault case for a preset: none, inner, outer or compound.
    #[arg(long)]
    pub fault: Option<FaultCase>,
    /// Override the simulated duration, s.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Record the cage speed channel.
    #[arg(long)]
    pub cage_speed: bool,
    /// Record the inner-ring displacement channels.
    #[arg(long)]
    pub inner_ring: bool,
    /// Record the contact loads of this ball (0-based).
    #[arg(long)]
    pub contact_loads_ball: Option<usize>,
    /// Record where this ball (0-based) runs against its cage pocket: its azimuth, its
    /// orbital speed less the cage's and its offset in the pocket.
    #[arg(long)]
    pub ball_pocket: Option<usize>,
    /// Output JSON file.
    #[arg(long)]
    pub out: std::path::PathBuf,
    /// Also write the run as a measured recording (.wav, .csv or .mat, by the extension):
    /// its channels, the shaft angle (`shaft_angle`, rad) and a once-per-revolution
    /// tachometer (`tachometer`), for `analyze --channel ... --tacho-channel tachometer`.
    #[arg(long)]
    pub export: Option<std::path::PathBuf>,
}

pub fn main(args: RunArgs) -> CliResult {
    let mut scene = load_scene(&args.scene, args.fault)?;
    if let Some(d) = args.duration {
        scene.solver.duration = d;
    }
    scene.outputs.cage_speed |= args.cage_speed;
    scene.outputs.inner_ring_displacement |= args.inner_ring;
    if args.contact_loads_ball.is_some() {
        scene.outputs.contact_loads_ball = args.contact_loads_ball;
    }
    if args.ball_pocket.is_some() {
        scene.outputs.ball_pocket = args.ball_pocket;
    }
    let export_format = match &args.export {
        None => None,
        Some(p) => Some(export_format(p)?),
    };
    let scene = scene.validated()?;
    let bar = ProgressBar::new(1000);
    bar.set_style(
        ProgressStyle::with_template("{spinner} [{elapsed_precise}] {bar:40} {msg}")
            .expect("static template"),
    );
    let duration = scene.solver.duration;
    let mut on_progress = |f: f64| {
        bar.set_position((f * 1000.0) as u64);
        bar.set_message(format!("t = {:.4} / {duration} s", f * duration));
    };
    let result = simulate(
        &scene,
        RunControl {
            cancel: None,
            progress: Some(&mut on_progress),
        },
    );
    bar.finish_and_clear();
    let result = result?;
    let s = &result.summary;
    eprintln!(
        "{}: {} accepted / {} rejected steps, {} RHS evaluations, step {:.3e}..{:.3e} s, wall {:.2} s; cage {:.2} rad/s (slip {:.3} %)",
        scene.name,
        s.stats.accepted_steps,
        s.stats.rejected_steps,
        s.stats.rhs_evaluations,
        s.stats.min_step,
        s.stats.max_step,
        s.stats.wall_time,
        s.mean_cage_speed,
        100.0 * s.cage_slip
    );
    let out = serde_json::json!({ "scene": scene, "summary": result.summary, "channels": result.channels });
    let file = std::fs::File::create(&args.out)
        .map_err(|e| format!("--out {}: {e}", args.out.display()))?;
    serde_json::to_writer(std::io::BufWriter::new(file), &out)?;
    if let (Some(path), Some(format)) = (&args.export, export_format) {
        let bytes = export_run(&result, &scene, format)
            .map_err(|e| format!("--export {}: {e}", path.display()))?;
        std::fs::write(path, bytes).map_err(|e| format!("--export {}: {e}", path.display()))?;
    }
    Ok(())
}

/// The export format a file's extension names.
fn export_format(path: &std::path::Path) -> Result<ExportFormat, String> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    ext.parse()
        .map_err(|e| format!("--export {}: {e} (from the extension)", path.display()))
}
