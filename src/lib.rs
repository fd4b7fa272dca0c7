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
//! The crate map, one module per model variant or concept:
//!
//! | module | what |
//! |---|---|
//! | [`continuum`] | §2.1, eqs (1)–(4): the beam with a compliant stop, roots of eq (3), mode shapes (2) |
//! | [`galerkin`] | §2.2, §5.1, eqs (5)–(9), (31)–(35): the N-mode Galerkin compliant (bilinear) model |
//! | [`two_basis`] | §2.2, first half: the two-basis switching truncation (constrained modes in contact, free modes out of it, projected at each switch) |
//! | [`fe`] | an independent Hermite-cubic finite-element beam (eqs 1, 31–33), simulated exactly in its own modes |
//! | [`convergence`] | §2.3: refinement studies at fixed k, Richardson limits, modes needed N*(k) |
//! | [`flow`] | eq (36): the exact solution inside one region |
//! | [`sim`] | §5.2: the exact simulator through its switches — clock, signal, certified crossing search, maximum, energy, observers, driver |
//! | [`dopri5`] | an independent Dormand–Prince 5(4) integrator with event location, for cross-verification |
//! | [`restitution`] | §3–4, eqs (12), (14), (28)–(29): the modal restitution laws |
//! | [`asymptotics`] | §4.1–4.3, eqs (18)–(19), (23): impact asymptotics as k → ∞ |
//! | [`rigid`] | §3: the rigid-impact N-mode model with any law, and its chattering policy |
//! | [`energetic`] | §5.4, eqs (38)–(39): the energetic coefficient of restitution |
//! | [`harmonics`] | Figure 9(b): the tip velocity's harmonic spectrum in closed form |
//! | [`experiment`] | §6: the rig in the model's terms by beam theory |
//! | [`orbit`] | §5.2: the stroboscopic map, period detection (m, n), seeded random starts |
//! | [`shooting`] | §5.2–5.3: periodic orbits by Newton shooting with the exact monodromy, Floquet multipliers |
//! | [`impact_section`] | §5.3: periodic orbits by Newton shooting on the impact section d = d₀, ḋ > 0 |
//! | [`continuation`] | periodic orbits continued in k or ω: folds, period doublings, Neimark–Sacker, grazing |
//! | [`atlas`] | the multi-tap atlas: stable orbits (m, n) and their coexistence over (k, ω), shardable |
//! | [`problems`] | the paper's parameter sets as named constructors (Figures 3, 4, 6, 9; the linear model) |
//! | [`verification`] | observed orders, Richardson extrapolation and GCI |
//! | [`numerics`] | Brent's root finder, Gauss–Legendre quadrature, a fast sine–cosine |
//! | [`golden`] | independent reference values (mpmath roots, Blevins' table) |
//! | [`citation`] | how to cite a number: software, version, paper, as text and BibTeX |
//! | [`provenance`] | version, commit, toolchain, date and resolution of generated numbers |
//! | [`scene`] | the Scene trait: one result of the paper from parameters to data, key numbers, verdict, plots |
//! | [`scenes`] | the registry and one folder per result |
//! | [`render`] | shared plotting and table helpers (no numerics) |
//! | [`report`] | key numbers rounded to the digits the method resolves |
//! | [`diff`] | which key numbers moved between two runs, judged against their uncertainties |
//! | [`error`] | the crate's error type and the parameter checks |
//! | [`prelude`] | what a program using the library needs in one `use` |
//! | `book` | (feature `book`) the mdBook build with LaTeX → MathML |
//!
//! The `cantilever` command line (feature `cli`, on by default) lives in
//! `src/bin/cantilever/`; a program that uses only the library can depend on the crate
//! with `default-features = false` and compiles no CLI crates.

#![warn(missing_docs)]

pub mod asymptotics;
pub mod atlas;
pub mod citation;
pub mod continuation;
pub mod continuum;
pub mod convergence;
pub mod diff;
pub mod dopri5;
pub mod energetic;
pub mod error;
pub mod experiment;
pub mod fe;
pub mod flow;
pub mod galerkin;
pub mod golden;
pub mod harmonics;
pub mod impact_section;
pub mod numerics;
pub mod orbit;
pub mod problems;
pub mod provenance;
pub mod render;
pub mod report;
pub mod restitution;
pub mod rigid;
pub mod scene;
pub mod scenes;
pub mod shooting;
pub mod sim;
pub mod two_basis;
pub mod verification;

#[cfg(feature = "book")]
pub mod book;

/// The names a program using the library needs, in one `use`.
pub mod prelude {
    pub use crate::error::{Error, ParameterError};
    pub use crate::galerkin::{
        first_frequency, first_modal_stiffness, Forcing, GalerkinModel, GalerkinParams, Region,
        SpatialProfile,
    };
    pub use crate::orbit::{settle, OrbitKind};
    pub use crate::problems::{self, Forced};
    pub use crate::restitution;
    pub use crate::rigid::{RigidEvent, RigidImpact, RigidRun};
    pub use crate::sim::{
        Clock, Dense, Energy, EventView, Events, Observer, SegmentView, Settings, Simulator,
        Strobe, TipMax,
    };
    pub use nalgebra::{DMatrix, DVector};
}
