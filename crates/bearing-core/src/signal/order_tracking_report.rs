//! What an order-tracked analysis reports about its resampling: the speed range, the
//! resolution in angle and the fault lines as shaft orders
//! ([`super::order_tracking::analyze_tracked`]).

use serde::{Deserialize, Serialize};

/// Fault lines as shaft orders (events per shaft revolution), -.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct FaultOrders {
    pub bpfo: f64,
    pub bpfi: f64,
    pub bsf: f64,
    pub ftf: f64,
}

/// How an order-tracked analysis resampled its signal. Its report's frequencies (sample
/// rate, resolution, every line) are orders times `mean_shaft_hz`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
pub struct OrderTracking {
    /// Mean shaft frequency over the window, Hz: a report frequency `f` is order `f / mean_shaft_hz`.
    pub mean_shaft_hz: f64,
    /// Slowest and fastest shaft frequency over the window, Hz.
    pub shaft_hz_range: [f64; 2],
    /// Shaft revolutions in the window.
    pub revolutions: f64,
    /// Samples per revolution after resampling.
    pub samples_per_revolution: f64,
    /// The fault lines as orders.
    pub orders: FaultOrders,
}

impl OrderTracking {
    /// One clause for the plain summary.
    pub fn clause(&self) -> String {
        let [lo, hi] = self.shaft_hz_range;
        format!(
            "order tracked over {:.1} revolutions at {:.0}-{:.0} rpm; lines in Hz at the mean {:.0} rpm (BPFO {:.3}, BPFI {:.3} orders)",
            self.revolutions,
            lo * 60.0,
            hi * 60.0,
            self.mean_shaft_hz * 60.0,
            self.orders.bpfo,
            self.orders.bpfi
        )
    }
}
