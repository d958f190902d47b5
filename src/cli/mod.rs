//! Command-line subcommands (synchronous; they call the library directly).

pub mod analyze;
pub mod bench;
pub mod quasi_static;
pub mod run;
pub mod scene_arg;
pub mod scene_cmd;

/// Error type of the CLI: a message for the user.
pub type CliResult = Result<(), Box<dyn std::error::Error>>;
