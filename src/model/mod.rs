//! The paper's models as mathematics (§2–4): parameters in, matrices, modes and laws out. Nothing here integrates in time.

pub mod asymptotics;
pub mod continuum;
pub mod experiment;
pub mod fe;
pub mod forcing;
pub mod galerkin;
pub mod problems;
pub mod ranges;
pub mod restitution;
pub mod spec;
