//! What is computed from runs: periodic orbits, stability, branches, maps, spectra and refinement studies.

pub mod atlas;
pub mod continuation;
pub mod convergence;
pub mod curves;
pub mod energetic;
pub mod find_orbit;
pub mod harmonics;
pub mod impact_section;
pub mod lyapunov;
pub mod motion;
pub mod orbit;
pub mod shooting;
pub mod simulate;
pub mod speed_bound;
