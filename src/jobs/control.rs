//! Shared between a job's blocking run and its async heartbeat loop.

use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;

/// Cancel flag and progress of one running job.
#[derive(Clone, Default)]
pub struct Control {
    pub cancel: Arc<AtomicBool>,
    /// f64 bits of the fraction done.
    pub progress: Arc<AtomicU64>,
}

impl Control {
    pub fn progress(&self) -> f64 {
        f64::from_bits(self.progress.load(Ordering::Relaxed))
    }
    pub fn set_progress(&self, f: f64) {
        self.progress.store(f.to_bits(), Ordering::Relaxed);
    }
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::SeqCst)
    }
}
