//! The `bearing-sim` command line: its subcommands and their dispatch.

use super::result::CliResult;
use super::{
    analyze, bench, inspect, quasi_static, run, scene_cmd, serve_cmd, study, token_cmd, worker_cmd,
};
use clap::{Parser, Subcommand};
use std::sync::LazyLock;

/// `--version`: the package's version and the build's digests: the engine's
/// (`bearing_core::ENGINE_DIGEST`, which every simulation record names) and the record
/// code's (`studies::scene_key::RECORD_DIGEST`); studies reuse runs only of the same two.
static VERSION_TEXT: LazyLock<String> = LazyLock::new(|| {
    format!(
        "{} (engine {}, records {})",
        env!("CARGO_PKG_VERSION"),
        bearing_core::ENGINE_DIGEST,
        crate::studies::scene_key::RECORD_DIGEST
    )
});

#[derive(Parser)]
#[command(
    name = "bearing-sim",
    version = VERSION_TEXT.as_str(),
    about = "Angular contact ball bearing dynamics and fault diagnosis"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene (file or preset name) and write a JSON result.
    Run(run::RunArgs),
    /// Print the quasi-static (Jones-Harris) solution of a scene as JSON.
    QuasiStatic(quasi_static::QuasiStaticArgs),
    /// Print a preset scene as JSON (a starting point for your own scene files).
    Scene(scene_cmd::SceneArgs),
    /// Analyse a measured or simulated vibration signal.
    Analyze(analyze::AnalyzeArgs),
    /// List the channels of a recording (.mat, .wav, .csv, ...): names, lengths, sample rate.
    Inspect(inspect::InspectArgs),
    /// Run the HTTP service.
    Serve(serve_cmd::ServeArgs),
    /// Run job workers only, on a database shared with API nodes (`serve --workers 0`).
    Worker(worker_cmd::WorkerArgs),
    /// Make an API token: prints the token and the line for the service's --tokens-file.
    Token(token_cmd::TokenArgs),
    /// Time the engine and the analysis on this machine.
    Bench(bench::BenchArgs),
    /// Run a parameter study (the paper's Figures 23-28) and write its table and plots.
    Study(study::StudyArgs),
}

impl Cli {
    pub fn run(self) -> CliResult {
        match self.command {
            Command::Run(a) => run::main(a),
            Command::QuasiStatic(a) => quasi_static::main(a),
            Command::Scene(a) => scene_cmd::main(a),
            Command::Analyze(a) => analyze::main(a),
            Command::Inspect(a) => inspect::main(a),
            Command::Serve(a) => serve_cmd::main(a),
            Command::Worker(a) => worker_cmd::main(a),
            Command::Token(a) => token_cmd::main(a),
            Command::Bench(a) => bench::main(a),
            Command::Study(a) => study::main(a),
        }
    }
}
