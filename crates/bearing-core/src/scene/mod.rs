//! Scene: the one serde-typed input of a simulation.
//!
//! Every quantity is SI (m, kg, s, N, Pa, rad) unless the field name says otherwise
//! (`*_rpm` is rev/min because that is how spindle speeds are specified).
//! Frames follow the paper (section 2.1): X is the bearing axis, Y and Z are radial;
//! an azimuth angle `theta` is measured from +Z towards -Y, so a point at azimuth
//! `theta` on a circle of radius `r` sits at `(y, z) = (-r sin theta, r cos theta)` (eq. 3).

pub mod cost;
mod definition;
mod overrides;
mod presets;
mod valid;
mod validate;

pub use definition::*;
pub use overrides::{apply_overrides, VARIANT_TAG};
pub use presets::{
    fault_case_scene, preset_names, preset_scene, table2_groups, FaultCase, Table2Group,
};
pub use valid::ValidScene;
pub use validate::{FieldError, ValidationErrors, MAX_LOAD_PER_STATIC_CAPACITY, MAX_NAME_CHARS};
