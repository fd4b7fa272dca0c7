//! The integration tests, compiled as one test binary (one link of the library and its
//! dependencies instead of one per file, and one pool of test threads for all of them, so
//! a slow file no longer runs alone on two cores). Each file of `tests/` is a module here;
//! `cargo test --test suite NAME` runs the tests whose path contains NAME (`cli::`,
//! `scenes::figure_4`). Kept apart: `published.rs` (its own harness, one trial per scene)
//! and `book.rs` (it moves the process's current folder).

mod common;

mod adversarial;
mod adversarial_recheck;
mod adversarial_round3;
mod adversarial_round3_errors;
mod adversarial_round3_files;
mod api;
mod archive;
mod atlas;
mod atlas_curves;
mod basins;
mod cli;
mod cli_orbits;
mod continuation;
mod continuum;
mod convergence;
mod critical_damping;
mod curves;
mod curves_neimark_sacker;
mod diff;
mod energetic;
mod files_recheck;
mod files_round4;
mod flow;
mod galerkin;
mod harmonics;
mod layers;
mod layout;
mod lyapunov;
mod motion;
mod names;
mod observation;
mod peers;
mod properties;
mod restitution;
mod rigid;
mod rigid_orbits;
mod scenes;
mod shooting;
mod simulator;
mod speed_bound;
mod two_basis;
mod what_if;
