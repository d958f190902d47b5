//! `bearing-sim`: CLI and HTTP service around the bearing_sim library.

mod api;
mod cli;
mod config;
mod jobs;
mod metrics;
mod serve;
mod store;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "bearing-sim",
    version,
    about = "Angular contact ball bearing dynamics and fault diagnosis"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Simulate a scene (file or preset name) and write a JSON result.
    Run(cli::run::RunArgs),
    /// Print the quasi-static (Jones-Harris) solution of a scene as JSON.
    QuasiStatic(cli::quasi_static::QuasiStaticArgs),
    /// Print a preset scene as JSON (a starting point for your own scene files).
    Scene(cli::scene_cmd::SceneArgs),
    /// Analyse a measured or simulated vibration signal.
    Analyze(cli::analyze::AnalyzeArgs),
    /// Run the HTTP service.
    Serve(serve::ServeArgs),
    /// Time the engine and the analysis on this machine.
    Bench(cli::bench::BenchArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Run(a) => cli::run::main(a),
        Command::QuasiStatic(a) => cli::quasi_static::main(a),
        Command::Scene(a) => cli::scene_cmd::main(a),
        Command::Analyze(a) => cli::analyze::main(a),
        Command::Serve(a) => serve::main(a),
        Command::Bench(a) => cli::bench::main(a),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
