//! Command-line subcommands (synchronous, except `serve`, which starts its own runtime).

pub mod analyze;
pub mod bench;
mod bench_comparison;
mod bench_fidelity;
mod bench_stiffness;
mod bench_stress;
mod command;
pub mod inspect;
pub mod quasi_static;
mod result;
pub mod run;
pub mod scene_arg;
pub mod scene_cmd;
pub mod serve_cmd;
pub mod signal_input;
pub mod study;
mod token_cmd;
mod worker_cmd;

pub use command::Cli;
pub use result::CliResult;
