//! Helpers shared by the service's integration tests.
#![allow(dead_code)]

mod app;
mod postgres;
mod server;
#[allow(unused_imports)]
pub use app::TestApp;
#[allow(unused_imports)]
pub use postgres::{pg_cluster, PgCluster};
#[allow(unused_imports)]
pub use server::*;
