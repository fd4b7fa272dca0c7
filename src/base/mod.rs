//! Foundations every other band uses: numerics, refinement studies, cited numbers and their provenance, reference values.

pub mod golden;
pub mod newton;
pub mod numerics;
pub mod provenance;
pub mod report;
pub mod verification;
