//! What a subcommand returns.

/// Error type of the CLI: a message for the user.
pub type CliResult = Result<(), Box<dyn std::error::Error>>;
