//! bearing-core: the bearing-sim engine. Dynamic simulation and vibration diagnosis of
//! angular contact ball bearings with localized inner/outer raceway defects.
//!
//! Plain synchronous Rust: no async runtime, HTTP or SQL (the crate's dependency list has
//! none). The `bearing-sim` service and command line wrap it.
//!
//! Layers, each importing only from the ones above it in this list:
//! - [`json_float`]: NaN-tolerant float fields in JSON (a helper every layer may use).
//! - [`ode`]: a generic solver of initial value problems (problem, methods as tableau
//!   data, one step-size controller and error norm, the solver loop); it knows nothing of
//!   bearings.
//! - [`scene`]: the input (geometry, materials, lubricant, operating point, faults, solver),
//!   validation into a [`scene::ValidScene`], presets.
//! - [`physics`]: frames, contact geometry, Hertz, traction, cage interactions, defects,
//!   rolling kinematics.
//! - [`model`]: the constants of one bearing built from a valid scene, and the layout of
//!   the state vector.
//! - [`quasi_static`]: Jones-Harris equilibrium (reference solution and the dynamic
//!   initial state).
//! - [`dynamics`]: the bearing's equations of motion as a problem for [`ode`], the run
//!   loop, output sampling and averages (it does not know the quasi-static solver: it
//!   starts from a state vector it is given).
//! - [`simulation`]: one call from a valid scene to a result.
//! - [`signal`]: characteristic frequencies, envelope spectra, DTCWT, identification. It
//!   knows bearings (scene) but nothing of simulations.
//! - [`simulation_analysis`]: the glue that analyses a simulated signal (above both).
//! - [`study`]: parameter studies (the paper's Figures 23-28): designs as data, a point run
//!   and read into a table row.
//! - [`stress`]: the stability stress suite: extreme scenes and the invariants their runs
//!   keep (or the field their refusal names).

pub mod dynamics;
pub mod json_float;
pub mod model;
pub mod ode;
pub mod physics;
pub mod quasi_static;
pub mod scene;
pub mod signal;
pub mod simulation;
pub mod simulation_analysis;
pub mod stress;
pub mod study;
