//! bearing-core: the bearing-sim engine. Dynamic simulation and vibration diagnosis of
//! angular contact ball bearings with localized inner/outer raceway defects.
//!
//! Plain synchronous Rust: no async runtime, HTTP or SQL (the crate's dependency list has
//! none). The `bearing-sim` service and command line wrap it.
//!
//! Layers, each importing only from the ones above it in this list:
//! - [`json_float`]: NaN-tolerant float fields in JSON (a helper every layer may use).
//! - [`json_doc`]: merge patches (RFC 7396) and JSON-pointer assignments (RFC 6901) on
//!   scene documents (study designs and requests that patch a preset).
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
//! - [`run_recording`]: a simulated run written as a measured recording (its channels,
//!   shaft angle and tachometer pulses as WAV, CSV or a MAT-file).
//! - [`study`]: parameter studies as data: a request and its designs (the paper's Figures
//!   23-28, Table 2, the lubricant sensitivity) expanded into validated points, and the
//!   table read from their runs. Running the points is the caller's.
//! - `stress` (feature `stress`, off by default): the stability stress suite: extreme scenes
//!   and the invariants their runs keep (or the field their refusal names).
//! - `stiffness` (feature `stress`): where the stiffness is, the eigenvalues of the
//!   Jacobian at a state of a run, whole and with chosen diagonal blocks taken out.

/// The engine's identity: 16 hex digits of a SHA-256 over its sources, its manifest, the
/// workspace's locked dependency versions, the compiler's version, the target and the
/// compiler flags (`build.rs`). Builds with the same digest are the same engine; on one
/// machine class they compute the same numbers (the FFT's vector code and the C library's
/// functions are chosen where the binary runs). The service's studies reuse a stored run
/// only for builds with its digest (the study scene key), and every simulation record
/// names the digest that computed it.
pub const ENGINE_DIGEST: &str = env!("BEARING_CORE_ENGINE_DIGEST");

pub mod dynamics;
pub mod json_doc;
pub mod json_float;
pub mod model;
pub mod ode;
pub mod physics;
pub mod quasi_static;
pub mod run_recording;
pub mod scene;
pub mod signal;
pub mod simulation;
pub mod simulation_analysis;
#[cfg(feature = "stress")]
pub mod stiffness;
#[cfg(feature = "stress")]
pub mod stress;
pub mod study;
