//! `bearing-sim bench` (placeholder until implemented).

use super::CliResult;

#[derive(clap::Args, Debug)]
pub struct BenchArgs {}

pub fn main(_args: BenchArgs) -> CliResult {
    Err("not implemented yet".into())
}
