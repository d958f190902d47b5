//! `bearing-sim quasi-static SCENE`: the Jones-Harris equilibrium as JSON.

use super::result::CliResult;
use super::scene_arg::load_scene;

#[derive(clap::Args, Debug)]
pub struct QuasiStaticArgs {
    /// Scene file (JSON) or preset name (h7005c).
    pub scene: String,
    /// Shaft speed, rev/min (default: the scene's steady speed).
    #[arg(long)]
    pub rpm: Option<f64>,
}

pub fn main(args: QuasiStaticArgs) -> CliResult {
    let scene = load_scene(&args.scene, None)?.validated()?;
    let rpm = args.rpm.unwrap_or(scene.operating.speed.steady_rpm);
    let sol = bearing_core::quasi_static::solve(&scene, rpm)?;
    println!("{}", serde_json::to_string_pretty(&sol)?);
    Ok(())
}
