//! Parameter studies of the fault frequencies, as data: a request (a base scene and a
//! design, [`request`]) expanded into validated points ([`plan`] over what a [`design`]
//! gives: [`factor_design`] for
//! designs over JSON pointers, [`named`] for the paper's Figures 23-28, Table 2 and the
//! sensitivity design, [`variant`] for the lubricant variants they run under), and the
//! table read from the points' runs ([`table`], one fault line by [`reading`]).
//!
//! Nothing here runs a point: the service queues each as a simulation job, the command
//! line runs them in-process; both read the same table.

pub mod design;
pub mod factor_design;
pub mod named;
pub mod plan;
pub mod reading;
pub mod request;
pub mod table;
pub mod variant;

pub use design::{DesignSummary, FactorInfo, FactorValue, PlanProblem, PointSpec, MAX_POINTS};
pub use named::{
    Factor, TABLE2_GROUPS, TREND_AXIAL_LOADS, TREND_RADIAL_LINE_AXIAL_LOAD, TREND_RADIAL_LOADS,
    TREND_SPEEDS,
};
pub use plan::{plan, Plan, PlannedPoint};
pub use reading::{read_line, FaultLine, LineReading, PeakReading};
pub use request::{DesignSpec, FactorSpec, NamedDesign, StudyBase, StudyRequest};
pub use table::{
    to_csv, CageReading, PointResult, PointState, RunDigest, StudyTable, StudyTableRow,
};
pub use variant::{lubricant_variant, lubricant_variants, LubricantVariant};
