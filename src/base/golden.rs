//! Independent reference values, embedded from `golden/` so that scenes and tests read the
//! same file. Each value's source is named in the file itself.

use serde::Deserialize;
use std::collections::BTreeMap;

/// `golden/roots.json`: roots of eq (3) from mpmath at 50 digits
/// (`golden/generate_roots.py`), stored to 25 significant figures.
#[derive(Debug, Clone, Deserialize)]
pub struct GoldenRoots {
    /// Where the numbers come from.
    pub source: String,
    /// β_i^- by mode index i.
    pub free: BTreeMap<String, String>,
    /// β_i^∞ (clamped-pinned) by mode index i.
    pub clamped_pinned: BTreeMap<String, String>,
    /// k₁ = (β₁⁻)⁴.
    pub k1: String,
    /// β_i^+ by k/k₁ (as text) and i.
    pub finite_k: BTreeMap<String, BTreeMap<String, String>>,
}

impl GoldenRoots {
    /// Parses the embedded file.
    ///
    /// # Panics
    /// If the embedded `golden/roots.json` does not parse: never for the committed file, which the
    /// tests load.
    pub fn load() -> Self {
        serde_json::from_str(include_str!("../../golden/roots.json"))
            .expect("golden/roots.json parses")
    }

    /// (i, β) pairs of a table, sorted by i.
    ///
    /// # Panics
    /// If a key is not a mode index or a value not a number: never for the tables of
    /// [`GoldenRoots::load`], which the tests read.
    pub fn table(map: &BTreeMap<String, String>) -> Vec<(usize, f64)> {
        let mut v: Vec<(usize, f64)> = map
            .iter()
            .map(|(i, b)| (i.parse().expect("index"), b.parse().expect("value")))
            .collect();
        v.sort_by_key(|p| p.0);
        v
    }
}

/// Classical table of roots at its printed precision: Blevins, *Formulas for Natural
/// Frequency and Mode Shape* (1979), Table 8-1, clamped-free and clamped-pinned, i = 1..5.
/// Used to check the mpmath values independently of the computer algebra.
pub const BLEVINS_CLAMPED_FREE: [f64; 5] =
    [1.87510407, 4.69409113, 7.85475744, 10.9955407, 14.1371684];
/// See [`BLEVINS_CLAMPED_FREE`].
pub const BLEVINS_CLAMPED_PINNED: [f64; 5] =
    [3.92660231, 7.06858275, 10.2101761, 13.3517688, 16.4933614];
