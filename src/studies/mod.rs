//! Parameter studies, the service's part: the engine's `bearing_core::study` expands a
//! request into points and reads their table; here are the key identical points share a
//! run by ([`scene_key`], SHA-256) and the study's plots ([`charts`], plotters). The API
//! queues each point as a simulation job; the CLI runs them in-process.

pub mod charts;
pub mod scene_key;

pub use scene_key::scene_key;
