//! `bearing-sim scene PRESET [--fault CASE]`: print a preset scene as JSON, to edit and run.

use super::result::CliResult;
use super::scene_arg::load_scene;
use bearing_core::scene::FaultCase;

#[derive(clap::Args, Debug)]
pub struct SceneArgs {
    /// Preset name (h7005c).
    pub preset: String,
    /// Fault case: none, inner, outer or compound.
    #[arg(long)]
    pub fault: Option<FaultCase>,
}

pub fn main(args: SceneArgs) -> CliResult {
    let scene = load_scene(&args.preset, Some(args.fault.unwrap_or(FaultCase::None)))?;
    println!("{}", serde_json::to_string_pretty(&scene)?);
    Ok(())
}
