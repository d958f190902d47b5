//! bearing-sim: dynamic simulation and vibration diagnosis of angular contact ball
//! bearings with localized inner/outer raceway defects.
//!
//! This library is plain synchronous Rust (no async runtime, HTTP or SQL): the
//! `bearing-sim` binary wraps it in a CLI and an HTTP service.
//!
//! - [`scene`]: the input (geometry, materials, lubricant, operating point, faults, solver), validation, presets.
//! - [`physics`]: frames, contact geometry, Hertz, traction, cage interactions, defects.
//! - [`quasi_static`]: Jones-Harris quasi-static equilibrium (reference and initial state).
//! - [`dynamics`]: state layout, equations of motion, integrators, sampling.
//! - [`simulation`]: one call from a scene to a result.
//! - [`signal`]: characteristic frequencies, envelope spectra, DTCWT, identification.

pub mod dynamics;
pub mod physics;
pub mod quasi_static;
pub mod scene;
pub mod signal;
pub mod simulation;
