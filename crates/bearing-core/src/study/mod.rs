//! Parameter studies of the fault frequencies: the paper's Figures 23-28 as a design of
//! points ([`design`]), each point run and read into one table row ([`row`]).
//!
//! Above [`crate::simulation_analysis`]: a row is a simulation plus its envelope analysis.

pub mod design;
pub mod row;

pub use design::{
    lubricant_variants, paper_trends, sensitivity, Factor, LubricantVariant, StudyPoint,
};
pub use row::{run_point, PointError, StudyRow};
