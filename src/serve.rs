//! `bearing-sim serve` (placeholder until implemented).

#[derive(clap::Args, Debug)]
pub struct ServeArgs {}

pub fn main(_args: ServeArgs) -> crate::cli::CliResult {
    Err("not implemented yet".into())
}
