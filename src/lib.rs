//! # impacting-cantilever
//!
//! A verification-and-validation suite for the dynamics of a cantilever whose tip strikes
//! a stop, reproducing Melcher, Champneys & Wagg, *The impacting cantilever: modal
//! non-convergence and the importance of stiffness matching*, Phil. Trans. R. Soc. A 371
//! (2013) 20120434 — "the paper" throughout.
//!
//! Modules follow the paper's concepts:
//! - [`continuum`]: the beam eigenproblem with a compliant stop (§2.1, eqs 1–4);
//! - [`galerkin`]: the N-mode Galerkin compliant (bilinear) model (§2.2, §5.1, eqs 5–9,
//!   31–35);
//! - [`scenes`]: one computation per figure or analytic result, returning plain data;
//! - [`render`]: plots and tables of scene data (no numerics);
//! - [`numerics`], [`error`], [`report`]: shared building blocks.

pub mod asymptotics;
pub mod continuum;
pub mod dopri5;
pub mod error;
pub mod flow;
pub mod galerkin;
pub mod golden;
pub mod numerics;
pub mod orbit;
pub mod problems;
pub mod render;
pub mod report;
pub mod restitution;
pub mod rigid;
pub mod scene;
pub mod scenes;
pub mod sim;
pub mod verification;

#[cfg(feature = "book")]
pub mod book;
