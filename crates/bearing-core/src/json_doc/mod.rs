//! Operations on JSON documents that requests describe scenes with: merge patches
//! (RFC 7396; for scenes with a rule for their tagged unions) over a preset, and
//! assignments at JSON pointers (RFC 6901) for study designs.

pub mod merge_patch;
pub mod pointer;

pub use merge_patch::{merge_patch, merge_patch_tagged};
pub use pointer::{put_member, set_at_pointer, PointerError};
