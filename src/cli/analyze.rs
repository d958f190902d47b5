//! `bearing-sim analyze` (placeholder until implemented).

use super::CliResult;

#[derive(clap::Args, Debug)]
pub struct AnalyzeArgs {}

pub fn main(_args: AnalyzeArgs) -> CliResult {
    Err("not implemented yet".into())
}
