//! Foundations every other band uses: numerics, refinement studies, cited numbers and their
//! provenance, reference values, seeded random starts, progress and cancellation.

pub mod golden;
pub mod newton;
pub mod numerics;
pub mod progress;
pub mod provenance;
pub mod random;
pub mod report;
pub mod verification;
