//! `bearing-sim run` (placeholder until implemented).

use super::CliResult;

#[derive(clap::Args, Debug)]
pub struct RunArgs {}

pub fn main(_args: RunArgs) -> CliResult {
    Err("not implemented yet".into())
}
