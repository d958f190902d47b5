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
    /// Also the cage speed by the pocket cycle (`pocket_cycle` in the output): one ball run
    /// round its orbit in a pocket turning with the cage; under the paper's curve and the
    /// preset's physics closer to a running cage than the steady traction balance (within
    /// 0.21 % at the paper's point under the preset's; docs/reference/model.md, "Cage speed
    /// by the pocket cycle"). At 10000 rpm about 0.5 s under the paper's curve and 4-6 s
    /// under the preset's physics; it grows with the orbit's period (4.5 s at 1000 rpm under
    /// the curve; 9-17 s at 2000 rpm and 26-30 s at 1000 rpm under the preset's physics).
    #[arg(long)]
    pub pocket_cycle: bool,
}

pub fn main(args: QuasiStaticArgs) -> CliResult {
    let scene = load_scene(&args.scene, None)?.validated()?;
    let rpm = args.rpm.unwrap_or(scene.operating.speed.steady_rpm);
    let mut sol = bearing_core::quasi_static::solve(&scene, rpm)?;
    if args.pocket_cycle {
        sol.pocket_cycle = Some(bearing_core::quasi_static::pocket_cycle(&scene, rpm)?);
    }
    println!("{}", serde_json::to_string_pretty(&sol)?);
    Ok(())
}
