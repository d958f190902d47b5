//! Parameter studies of the fault frequencies: the paper's Figures 23-28 as a design of
//! points ([`design`]), each point run and read into one table row ([`row`]).
//!
//! Above [`crate::simulation_analysis`]: a row is a simulation plus its envelope analysis.

pub mod design;
pub mod reading;
pub mod row;

pub use design::{
    lubricant_variants, paper_trends, sensitivity, Factor, LubricantVariant, StudyPoint,
    TABLE2_GROUPS,
};
pub use reading::{read_line, FaultLine, LineReading, PeakReading};
pub use row::{run_point, PointError, StudyRow};
