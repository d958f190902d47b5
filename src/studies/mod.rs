//! Parameter studies: a request (a base scene and a design) expanded into validated points
//! ([`plan`]), the table read from the points' runs ([`table`]) and its plots ([`charts`]).
//! The API queues each point as a simulation job; the CLI runs them in-process.

pub mod charts;
pub mod plan;
pub mod request;
pub mod scene_key;
pub mod table;

pub use plan::{plan, DesignSummary, FactorInfo, FactorValue, Plan, PlanProblem, PointSpec};
pub use request::{DesignSpec, FactorSpec, NamedDesign, StudyBase, StudyRequest};
pub use table::{to_csv, PointResult, RunDigest, StudyTable, StudyTableRow};
