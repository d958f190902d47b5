//! `bearing-sim worker`: job workers on a shared database, without the HTTP API.

use super::result::CliResult;
use crate::config::WorkerConfig;

#[derive(clap::Args, Debug)]
pub struct WorkerArgs {
    #[command(flatten)]
    pub config: WorkerConfig,
}

pub fn main(args: WorkerArgs) -> CliResult {
    let config = args.config;
    super::serve_cmd::init_logging(&config.log_format);
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .enable_all()
        // one blocking thread per engine run, and a margin for the store
        .max_blocking_threads(config.worker_count() + 4)
        .build()?;
    runtime.block_on(crate::serve::run_worker_node(config))?;
    Ok(())
}
