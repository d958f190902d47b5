//! Physics of the bearing parts, as small pure functions: frames (eq. 1), Hertz
//! contact (eq. 8), EHL traction (eqs. 9-18), ball-race geometry (eqs. 2-7), ball-cage
//! pocket (eqs. 19-22), cage-land (eqs. 23-28) and raceway defects (eqs. 33-36).

pub mod cage_land;
pub mod cage_pocket;
pub mod cage_pocket_lanes;
pub mod cpu;
pub mod defect;
pub mod drag;
pub mod exp;
pub mod frames;
pub mod hertz;
pub mod kinematics;
pub mod lanes;
pub mod race_contact;
pub mod race_contact_lanes;
pub mod rheology_traction;
pub mod rolling_resistance;
pub mod strips;
pub mod traction;

pub use nalgebra::{Matrix3, Vector3};
