//! `bearing-sim quasi-static` (placeholder until implemented).

use super::CliResult;

#[derive(clap::Args, Debug)]
pub struct QuasiStaticArgs {}

pub fn main(_args: QuasiStaticArgs) -> CliResult {
    Err("not implemented yet".into())
}
