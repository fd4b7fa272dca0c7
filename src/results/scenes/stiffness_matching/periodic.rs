//! Where the forced run settles to a periodic orbit: its label (m, n), its largest impact
//! velocity and its certified maximum tip displacement, against N (Galerkin and two-basis)
//! and the element count, at each k and ω of the study.

use super::MatchingParams;
use crate::analysis::convergence::{self, Discretisation, PeriodicObservables, Setup, Study};
use crate::error::Error;
use crate::analysis::orbit::OrbitKind;
use rayon::prelude::*;
use serde::Serialize;

/// One observable of the orbit refined three ways, where the orbit's label is the same on
/// the three finest resolutions of each.
#[derive(Debug, Clone, Serialize)]
pub struct OrbitStudies {
    /// Galerkin, against N.
    pub galerkin: Study,
    /// Finite elements, against the element count.
    pub elements: Study,
    /// Two-basis, against N (`None` for the maximum tip, not certified there).
    pub two_basis: Option<Study>,
    /// Galerkin and element limits agree within their uncertainties, and so do the
    /// Galerkin and two-basis ones.
    pub agree: bool,
}

/// The orbits at one (k, ω).
#[derive(Debug, Clone, Serialize)]
pub struct OrbitsAt {
    /// k/k₁.
    pub k_over_k1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// Per discretisation.
    pub runs: Vec<(Discretisation, PeriodicObservables)>,
    /// The label on the finest three resolutions of every discretisation, if one.
    pub label: Option<OrbitKind>,
    /// The largest impact velocity (where `label` is periodic).
    pub impact_velocity: Option<OrbitStudies>,
    /// The maximum tip displacement (where `label` is periodic).
    pub max_tip: Option<OrbitStudies>,
}

/// A refinement ladder: the discretisation of a size, and the sizes.
type Ladder<'a> = (fn(usize) -> Discretisation, &'a [usize]);

fn ladders(p: &MatchingParams) -> [Ladder<'_>; 3] {
    [
        (Discretisation::Galerkin, &p.orbit_modes),
        (Discretisation::Elements, &p.orbit_elements),
        (Discretisation::TwoBasis, &p.orbit_modes),
    ]
}

/// Every (k, ω) of `p`.
///
/// # Errors
/// The errors of [`convergence::periodic`] for any (k, ω, size), or `Error::Unsupported` for
/// a size ladder without its finest n, n/2 and n/4.
pub fn compute(p: &MatchingParams) -> Result<Vec<OrbitsAt>, Error> {
    let mut jobs = Vec::new();
    for &k in &p.k_over_k1 {
        for &w in &p.omegas {
            for (kind, sizes) in ladders(p) {
                jobs.extend(sizes.iter().map(|&n| (k, w, kind(n))));
            }
        }
    }
    let runs: Vec<(f64, f64, Discretisation, PeriodicObservables)> = jobs
        .par_iter()
        .map(|&(k, w, d)| {
            let setup = Setup {
                k_over_k1: k,
                zeta1: p.zeta1,
                omega_over_w1: w,
                periods: p.periods,
            };
            convergence::periodic(d, &setup).map(|o| (k, w, d, o))
        })
        .collect::<Result<_, Error>>()?;
    let mut out = Vec::new();
    for &k in &p.k_over_k1 {
        for &w in &p.omegas {
            let here: Vec<(Discretisation, PeriodicObservables)> = runs
                .iter()
                .filter(|r| r.0 == k && r.1 == w)
                .map(|r| (r.2, r.3))
                .collect();
            out.push(at(k, w, here, p)?);
        }
    }
    Ok(out)
}

fn at(
    k: f64,
    w: f64,
    runs: Vec<(Discretisation, PeriodicObservables)>,
    p: &MatchingParams,
) -> Result<OrbitsAt, Error> {
    let get = |d: Discretisation| runs.iter().find(|r| r.0 == d).map(|r| r.1);
    // the label of the three finest of every ladder
    let mut labels = Vec::new();
    for (kind, sizes) in ladders(p) {
        for &n in sizes.iter().rev().take(3) {
            labels.extend(get(kind(n)).map(|o| o.kind));
        }
    }
    let label = labels
        .iter()
        .all(|l| Some(l) == labels.first())
        .then(|| labels.first().copied())
        .flatten();
    let periodic = matches!(label, Some(OrbitKind::Periodic { .. }));
    let study = |kind: fn(usize) -> Discretisation,
                 sizes: &[usize],
                 f: fn(&PeriodicObservables) -> Option<f64>|
     -> Result<Option<Study>, Error> {
        let values: Option<Vec<f64>> = sizes.iter().map(|&n| get(kind(n)).and_then(|o| f(&o))).collect();
        match values {
            Some(v) if v.iter().all(|x| x.is_finite()) => {
                let scale = v.last().map_or(1.0, |x| x.abs());
                Ok(Some(Study::new(sizes.to_vec(), v, scale)?))
            }
            _ => Ok(None),
        }
    };
    let within = |a: &Study, b: &Study| (a.limit - b.limit).abs() <= a.uncertainty + b.uncertainty;
    let studies = |f: fn(&PeriodicObservables) -> Option<f64>| -> Result<Option<OrbitStudies>, Error> {
        if !periodic {
            return Ok(None);
        }
        let [g, e, t] = ladders(p);
        let (Some(galerkin), Some(elements)) = (study(g.0, g.1, f)?, study(e.0, e.1, f)?) else {
            return Ok(None);
        };
        let two_basis = study(t.0, t.1, f)?;
        let agree = within(&galerkin, &elements) && two_basis.as_ref().is_none_or(|t| within(&galerkin, t));
        Ok(Some(OrbitStudies {
            galerkin,
            elements,
            two_basis,
            agree,
        }))
    };
    Ok(OrbitsAt {
        k_over_k1: k,
        omega_over_w1: w,
        impact_velocity: studies(|o| Some(o.impact_velocity))?,
        max_tip: studies(|o| o.max_tip)?,
        runs,
        label,
    })
}
