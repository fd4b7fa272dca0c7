//! # impacting-cantilever
//!
//! A verification-and-validation suite for the dynamics of a cantilever whose tip strikes
//! a stop, reproducing Melcher, Champneys & Wagg, *The impacting cantilever: modal
//! non-convergence and the importance of stiffness matching*, Phil. Trans. R. Soc. A 371
//! (2013) 20120434 — "the paper" throughout.
//!
//! ```
//! use impacting_cantilever::prelude::*;
//! # fn main() -> Result<(), Error> {
//! // the paper's Figure 4 model with N = 3 modes, from rest, 100 forcing periods
//! let sim = Simulator::new(problems::figure4(3).model()?)?;
//! let (mut events, mut energy) = (Events::default(), Energy::default());
//! sim.run(&DVector::zeros(6), 100, &mut (&mut events, &mut energy))?;
//! assert!(!events.events.is_empty() && energy.budget.relative_imbalance() < 1e-12);
//! # Ok(())
//! # }
//! ```
//!
//! ## The layers
//!
//! The crate is five bands; a module uses only its own band (without cycles) and the bands
//! above it in this list, and [`error`] is a leaf every band may use (`tests/layers.rs`
//! checks both rules on every `crate::` path of the code).
//!
//! | band | modules | what |
//! |---|---|---|
//! | [`base`] | `numerics`, `newton`, `verification`, `report`, `provenance`, `golden`, `random`, `progress` | root finding and quadrature, the one Newton loop, refinement studies, cited numbers, build records, reference values, seeded random starts, progress and cancellation |
//! | [`model`] | `continuum`, `galerkin`, `fe`, `forcing`, `restitution`, `asymptotics`, `problems`, `experiment`, `ranges`, `spec` | the paper's models as mathematics: eq (3) and its modes, the Galerkin matrices, the finite-element beam, the restitution laws, the asymptotics, named parameter sets, the rig, the supported ranges and the model as a user specifies it |
//! | [`engine`] | `flow`, `sim`, `dopri5`, `rigid`, `two_basis`, `map`, `built`, `ticker` | time integration: the exact flow of one region, the certified simulator, an independent Dormand–Prince integrator, the rigid-impact and two-basis models, the one interface of every model and the model built from its specification, a run's progress in periods |
//! | [`analysis`] | `orbit`, `shooting`, `impact_section`, `continuation`, `curves`, `atlas`, `energetic`, `harmonics`, `convergence`, `find_orbit`, `simulate`, `speed_bound`, `lyapunov`, `motion` | what is computed from runs: periodic orbits and their stability, branches, curves of bifurcations in two parameters, the atlas, r_E, spectra, refinement in N, the simulation and orbit every front end runs, a bound on an orbit's tip speed, Lyapunov exponents, what a motion is (chaotic, quasi-periodic, periodic) |
//! | [`results`] | `scene`, `scenes`, `render`, `narrow`, `marker`, `schematic`, `citation`, `cite`, `names`, `archive`, `diff`, `record`, `files`, `output_set`, `settings`, `peers`, `book` | the paper's results: scenes, plots and tables, citations, key numbers and parameters in words, comparisons of key numbers, their full-precision records, output files, what-if settings, other tools' results, the book |
//!
//! The `cantilever` command line (feature `cli`, on by default) lives in
//! `src/bin/cantilever/`. The scenes and their plots need feature `plots` (on with `cli`);
//! a program that uses only the models and analyses depends on the crate with
//! `default-features = false` and compiles neither the CLI crates nor plotters.

#![warn(missing_docs)]

pub mod analysis;
pub mod base;
pub mod engine;
pub mod error;
pub mod model;
pub mod results;

/// The names a program using the library needs, in one `use`.
pub mod prelude {
    pub use crate::analysis::energetic::{orbit_coefficient, ContactWork};
    pub use crate::analysis::find_orbit::{find_orbit, FoundOrbit, OrbitOptions};
    pub use crate::analysis::orbit::{settle, settle_map, OrbitKind, Settled};
    pub use crate::analysis::shooting::{shoot, PeriodicOrbit};
    pub use crate::engine::map::PeriodMap;
    pub use crate::engine::rigid::{RigidEvent, RigidImpact, RigidRun};
    pub use crate::engine::sim::{
        Clock, Dense, Energy, EventView, Events, Observer, SegmentView, Settings, Simulator,
        Strobe, TipMax,
    };
    pub use crate::engine::two_basis::TwoBasisModel;
    pub use crate::error::{Error, ParameterError};
    pub use crate::model::galerkin::{
        first_frequency, first_modal_stiffness, Forcing, GalerkinModel, GalerkinParams, Region,
        SpatialProfile,
    };
    pub use crate::model::problems::{self, Forced};
    pub use crate::model::restitution;
    pub use nalgebra::{DMatrix, DVector};
    pub use num_complex::Complex64;
}
