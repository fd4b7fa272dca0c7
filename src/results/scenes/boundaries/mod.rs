//! Scene `boundaries`: beyond the paper — the paper's question (how many modes does a result
//! need?) asked of the curves that bound the atlas's regions. The period doubling that ends
//! the (1,1) orbit of Figure 4 and the grazing where it gains a second contact are followed
//! in (k, ω) by two-parameter continuation ([`crate::analysis::curves`]) for several N, each
//! started from the bifurcation a one-parameter run in ω finds at k = 100k₁; their ω at a
//! few k are located exactly and compared across N, and against the N that stiffness
//! matching (the book's one criterion, 1 %) gives at that k.

pub mod render;

use crate::analysis::continuation::{
    self, BifurcationKind, Family, Parameter, Settings as BranchSettings,
};
use crate::analysis::convergence::matched_modes;
use crate::analysis::curves::{self, CurveKind, CurvePoint, CurveSettings, Family2};
use crate::base::report::{pretty, KeyNumbers, Uncertainty};
use crate::error::Error;
use crate::model::problems::{self, Forced};
use crate::results::scene::{Group, Outcome, Progress, Rendered, Resolution, Scene, Verdict};
use nalgebra::DVector;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// What the scene computes.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BoundariesParams {
    /// Truncations N (the stiffness-matched N at each tabulated k are added).
    pub modes: Vec<usize>,
    /// ζ₁ (Figure 4's).
    pub zeta1: f64,
    /// The k/k₁ where the curves are started, from the orbit from rest at ω/(β₁⁻)² = 2.
    pub seed_k: f64,
    /// The one-parameter run goes from ω/(β₁⁻)² = 2 up to this.
    pub seed_omega_to: f64,
    /// The rectangle the curves are traced in: k/k₁ …
    pub k_range: (f64, f64),
    /// … and ω/(β₁⁻)².
    pub omega_range: (f64, f64),
    /// The k/k₁ at which each curve's ω is located and compared.
    pub table_k: Vec<f64>,
    /// The book's criterion: relative accuracy (stiffness matching at 1 %).
    pub tolerance: f64,
    /// Points each way along a curve at most.
    pub max_points: usize,
}

impl BoundariesParams {
    /// The book's resolution.
    pub fn book() -> Self {
        Self {
            modes: vec![1, 2, 3, 5, 10, 20],
            zeta1: 0.01,
            seed_k: 100.0,
            seed_omega_to: 2.7,
            k_range: (30.0, 300.0),
            omega_range: (1.9, 3.2),
            table_k: vec![50.0, 100.0, 200.0],
            tolerance: 1e-2,
            max_points: 120,
        }
    }

    /// The fast tier's: fewer N and coarser curves, the same tabulated k (the chapter
    /// names each of them).
    pub fn test() -> Self {
        Self {
            modes: vec![1, 2, 3, 5],
            max_points: 40,
            ..Self::book()
        }
    }

    fn forced(&self, modes: usize, k: f64) -> Forced {
        Forced {
            modes,
            k_over_k1: k,
            zeta1: self.zeta1,
            ..problems::figure4(modes)
        }
    }
}

/// One curve at one N.
#[derive(Debug, Clone, Serialize)]
pub struct Boundary {
    /// N.
    pub modes: usize,
    /// Where the one-parameter run found the bifurcation at k = seed_k (ω), if it did.
    pub seed_omega: Option<f64>,
    /// The curve's points (ω, k/k₁), in arclength order (empty without a seed).
    pub points: Vec<(f64, f64)>,
    /// ω located at each tabulated k (None: the curve does not reach it).
    pub at_k: Vec<Option<f64>>,
    /// The largest orbit and test residuals over the curve and located points.
    pub residuals: (f64, f64),
    /// Why the curve ends, or why there is none.
    pub note: String,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct BoundariesData {
    /// The parameters used.
    pub params: BoundariesParams,
    /// The truncations computed (the parameters' and the matched ones), ascending.
    pub modes: Vec<usize>,
    /// N*(k) at each tabulated k (stiffness matching to the tolerance, no floor).
    pub matched: Vec<usize>,
    /// The period doubling of the (1,1) orbit, per N.
    pub period_doubling: Vec<Boundary>,
    /// The grazing where the (1,1) orbit gains a second contact, per N.
    pub grazing: Vec<Boundary>,
}

/// The first crossing of k = `target` along the curve from point `from`, either way
/// (nearest in arclength): the point before it.
fn crossing(points: &[CurvePoint], from: usize, target: f64) -> Option<usize> {
    let crosses = |i: usize| (points[i].q - target) * (points[i + 1].q - target) <= 0.0;
    let up = (from..points.len().saturating_sub(1)).find(|&i| crosses(i));
    let down = (0..from).rev().find(|&i| crosses(i));
    match (up, down) {
        (Some(u), Some(d)) => Some(if u - from <= from - d { u } else { d }),
        (u, d) => u.or(d),
    }
}

/// The curve of `kind` at N modes, started from the bifurcation of the (1,1) orbit the
/// one-parameter run in ω finds at k = seed_k.
fn boundary(
    p: &BoundariesParams,
    modes: usize,
    kind: CurveKind,
    progress: &dyn Progress,
) -> Result<Boundary, Error> {
    let none = |note: String| Boundary {
        modes,
        seed_omega: None,
        points: Vec::new(),
        at_k: vec![None; p.table_k.len()],
        residuals: (0.0, 0.0),
        note,
    };
    if progress.cancelled() {
        return Err(Error::Interrupted);
    }
    let family = Family::forced(p.forced(modes, p.seed_k), Parameter::Frequency);
    let x = family
        .simulator(2.0)?
        .run(&DVector::zeros(2 * modes), 1000, &mut ())?
        .state;
    let settings = BranchSettings::new((2.0, p.seed_omega_to));
    let branch = continuation::continue_branch(&family, &x, 2.0, 1, 1.0, &settings)?;
    // the (1,1) orbit's own bifurcations: the doubling that ends it as ω rises (the last
    // one below seed_omega_to that keeps one contact on both sides: at N = 2 an earlier one
    // doubles a (1,1) orbit of another family), and the first grazing from one contact to
    // two
    let chosen = match kind {
        CurveKind::PeriodDoubling => branch
            .bifurcations
            .iter()
            .filter(|b| b.kind == BifurcationKind::PeriodDoubling && b.impacts == (1, 1))
            .max_by(|a, b| a.parameter.total_cmp(&b.parameter)),
        CurveKind::Grazing => branch
            .bifurcations
            .iter()
            .filter(|b| b.kind == BifurcationKind::Grazing && b.impacts == (1, 2))
            .min_by(|a, b| a.parameter.total_cmp(&b.parameter)),
        CurveKind::Fold | CurveKind::NeimarkSacker => None,
    };
    let Some(bif) = chosen else {
        return Ok(none(format!(
            "no {kind} of the (1,1) orbit between ω = 2 and {} at k = {}k₁",
            p.seed_omega_to, p.seed_k
        )));
    };
    let start = &branch.points[bif.index];
    let family2 = Family2::forced(
        p.forced(modes, p.seed_k),
        Parameter::Frequency,
        Parameter::StopStiffness,
    )?;
    let settings = CurveSettings {
        max_points: p.max_points,
        ..CurveSettings::new(p.omega_range, p.k_range)
    };
    let state = DVector::from_vec(start.state.clone());
    let curve = curves::trace_curve(
        &family2,
        kind,
        &state,
        (start.parameter, p.seed_k),
        1,
        &settings,
        progress,
    )?;
    // the first point is the one located at k = seed_k
    let from = curve
        .points
        .iter()
        .position(|q| (q.q / p.seed_k - 1.0).abs() < 1e-12)
        .unwrap_or(0);
    let mut residuals = curve.points.iter().fold((0.0f64, 0.0f64), |r, q| {
        (r.0.max(q.orbit_residual), r.1.max(q.test_residual))
    });
    let mut at_k = Vec::new();
    for &k in &p.table_k {
        let located = match crossing(&curve.points, from, k) {
            Some(i) => {
                let a = &curve.points[i];
                let pt = curves::locate_point(
                    &family2,
                    kind,
                    &DVector::from_vec(a.state.clone()),
                    (a.p, k),
                    1,
                )?;
                residuals = (residuals.0.max(pt.orbit_residual), residuals.1.max(pt.test_residual));
                Some(pt.p)
            }
            None => None,
        };
        at_k.push(located);
    }
    Ok(Boundary {
        modes,
        seed_omega: Some(bif.parameter),
        points: curve.points.iter().map(|q| (q.p, q.q)).collect(),
        at_k,
        residuals,
        note: if curve.ends.0 == curve.ends.1 {
            curve.ends.0
        } else {
            format!("{}; {}", curve.ends.0, curve.ends.1)
        },
    })
}

/// Runs the scene: every (N, curve) pair in parallel.
///
/// # Errors
/// A model out of range, a failed one-parameter run or curve, or [`Error::Interrupted`].
pub fn compute(p: &BoundariesParams, progress: &dyn Progress) -> Result<BoundariesData, Error> {
    let matched = p
        .table_k
        .iter()
        .map(|&k| matched_modes(k, p.tolerance, p.zeta1, 1))
        .collect::<Result<Vec<_>, _>>()?;
    let mut modes: Vec<usize> = p.modes.iter().chain(&matched).copied().collect();
    modes.sort_unstable();
    modes.dedup();
    let task = progress.task("boundaries: curves", 2 * modes.len() as u64);
    let jobs: Vec<(usize, CurveKind)> = modes
        .iter()
        .flat_map(|&n| [(n, CurveKind::PeriodDoubling), (n, CurveKind::Grazing)])
        .collect();
    let done = jobs
        .par_iter()
        .map(|&(n, kind)| {
            let b = boundary(p, n, kind, progress);
            task.advance(1);
            b
        })
        .collect::<Result<Vec<_>, _>>()?;
    let (period_doubling, grazing) = done.into_iter().enumerate().fold(
        (Vec::new(), Vec::new()),
        |(mut pd, mut g), (i, b)| {
            if i % 2 == 0 {
                pd.push(b);
            } else {
                g.push(b);
            }
            (pd, g)
        },
    );
    Ok(BoundariesData {
        params: p.clone(),
        modes,
        matched,
        period_doubling,
        grazing,
    })
}

/// The relative distance of each N's ω at tabulated k `j` from the largest N's.
pub fn relative_to_finest(curves: &[Boundary], j: usize) -> Vec<Option<f64>> {
    let finest = curves.last().and_then(|b| b.at_k[j]);
    curves
        .iter()
        .map(|b| match (b.at_k[j], finest) {
            (Some(w), Some(f)) => Some((w - f).abs() / f),
            _ => None,
        })
        .collect()
}

/// The smallest N from which every computed N's ω at tabulated k `j` lies within the
/// tolerance of the largest N's (None when even the second largest does not).
pub fn converged_from(d: &BoundariesData, curves: &[Boundary], j: usize) -> Option<usize> {
    let rel = relative_to_finest(curves, j);
    let mut from = None;
    for (b, r) in curves.iter().zip(&rel).rev().skip(1) {
        match r {
            Some(r) if *r <= d.params.tolerance => from = Some(b.modes),
            _ => break,
        }
    }
    from
}

/// The ω of N's curve at tabulated k `j`.
fn omega_at(curves: &[Boundary], n: usize, j: usize) -> Option<f64> {
    curves.iter().find(|b| b.modes == n).and_then(|b| b.at_k[j])
}

/// Whether the matched N*(k) gives each curve's ω within the tolerance of the largest N's,
/// at every tabulated k: (checked, within).
pub fn matched_suffices(d: &BoundariesData) -> (usize, usize) {
    let mut checked = 0;
    let mut within = 0;
    for curves in [&d.period_doubling, &d.grazing] {
        for (j, &n) in d.matched.iter().enumerate() {
            let finest = curves.last().and_then(|b| b.at_k[j]);
            if let (Some(w), Some(f)) = (omega_at(curves, n, j), finest) {
                checked += 1;
                if (w - f).abs() / f <= d.params.tolerance {
                    within += 1;
                }
            }
        }
    }
    (checked, within)
}

/// A tabulated k/k₁ as the table and the key numbers name it ("50", not "50.0").
pub fn k_label(k: f64) -> String {
    if k.fract() == 0.0 && k.abs() < 1e15 {
        format!("{k:.0}")
    } else {
        pretty(k, 3)
    }
}

/// The scene.
pub struct Boundaries;

/// Located points: Newton on the extended system to residuals 1e-11, polished by shooting;
/// the multiplier or the extremum then within ~1e-9 of its condition, which moves ω by
/// about as much (dμ/dω is of order 1 on these curves).
fn located(w: f64) -> Uncertainty {
    Uncertainty::round_off(
        w,
        1e-8,
        "located on the extended system; the test condition holds to 1e-9 at the polished orbit",
    )
}

impl Scene for Boundaries {
    const NAME: &'static str = "boundaries";
    const PAPER: &'static str = "beyond §5.3";
    const TITLE: &'static str = "The atlas's boundaries in N";
    const GIST: &'static str = "— (not asked of bifurcation curves)";
    const GROUP: Group = Group::Beyond;
    const SUMMARY: &'static str =
        "period-doubling and grazing curves of the (1,1) orbit in (k, ω) for several N";
    const CLAIM: &'static str = "None: the paper asks how many modes an orbit needs, not how many the boundaries between orbits need.";
    const CHAPTER: &'static str = "boundaries.md";
    const METHOD: &'static str = "for each N, a one-parameter continuation in ω at k = 100k₁ from Figure 4's orbit finds the (1,1) orbit's period doubling and its grazing into two contacts; each is followed in (ω, k) by pseudo-arclength on the shooting problem closed by a bordered test function (period doubling) or the signed distance of the tip's extremum from the stop (grazing); at each tabulated k the curve's point is located by Newton at that k and polished by shooting";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        ("period doubling at k = 100k₁, largest N", "period doubling omega at k=100, finest N"),
        ("matched N within 1 % of the largest N", "matched N suffices"),
    ];
    type Params = BoundariesParams;
    type Data = BoundariesData;

    fn params(resolution: Resolution) -> BoundariesParams {
        match resolution {
            Resolution::Book => BoundariesParams::book(),
            Resolution::Test => BoundariesParams::test(),
        }
    }

    fn compute(p: &BoundariesParams, progress: &dyn Progress) -> Result<BoundariesData, Error> {
        compute(p, progress)
    }

    fn key_numbers(d: &BoundariesData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        let mut modes: Vec<String> = d.modes.iter().map(|n| n.to_string()).collect();
        let last = modes.pop().unwrap_or_default();
        k.text(
            "modes",
            if modes.is_empty() {
                last
            } else {
                format!("{} and {last}", modes.join(", "))
            },
        );
        for (name, curves) in [("period doubling", &d.period_doubling), ("grazing", &d.grazing)] {
            for (j, &kk) in d.params.table_k.iter().enumerate() {
                for b in curves.iter() {
                    if let Some(w) = b.at_k[j] {
                        k.cited(
                            format!("{name} omega at k={}, N={}", k_label(kk), b.modes),
                            w,
                            9,
                            located(w),
                            "(β₁⁻)²",
                        );
                    }
                }
                if let Some(w) = curves.last().and_then(|b| b.at_k[j]) {
                    if kk == d.params.seed_k && name == "period doubling" {
                        k.cited(
                            format!("{name} omega at k={}, finest N", k_label(kk)),
                            w,
                            9,
                            located(w),
                            "(β₁⁻)²",
                        );
                    }
                }
                k.text(
                    format!("{name} converged from N at k={}", k_label(kk)),
                    converged_from(d, curves, j)
                        .map_or("not within the computed N".to_string(), |n| n.to_string()),
                );
            }
            let absent: Vec<String> = curves
                .iter()
                .filter(|b| b.points.is_empty())
                .map(|b| b.modes.to_string())
                .collect();
            k.text(
                format!("{name}: N without the curve"),
                if absent.is_empty() {
                    "none".to_string()
                } else {
                    absent.join(", ")
                },
            );
        }
        for (j, &kk) in d.params.table_k.iter().enumerate() {
            k.integer(format!("matched N at k={}", k_label(kk)), d.matched[j] as i64);
        }
        let (checked, within) = matched_suffices(d);
        k.text("matched N suffices", format!("{within} of {checked}"));
        let worst = [&d.period_doubling, &d.grazing]
            .iter()
            .flat_map(|c| c.iter())
            .fold((0.0f64, 0.0f64), |r, b| (r.0.max(b.residuals.0), r.1.max(b.residuals.1)));
        k.text(
            "largest residuals (orbit, test)",
            format!("{:.0e}, {:.0e}", worst.0.max(1e-16), worst.1.max(1e-16)),
        );
        k
    }

    fn verdict(d: &BoundariesData) -> Verdict {
        let (checked, within) = matched_suffices(d);
        let finest = d.modes.last().copied().unwrap_or(0);
        Verdict {
            outcome: Outcome::Extension,
            evidence: format!(
                "with the stiffness-matched N (N* = {} at k/k₁ = {}), the period-doubling and grazing curves lie within {} % of the N = {finest} curves at {within} of {checked} tabulated points",
                d.matched
                    .iter()
                    .map(|n| n.to_string())
                    .collect::<Vec<_>>()
                    .join(", "),
                d.params
                    .table_k
                    .iter()
                    .map(|k| k_label(*k))
                    .collect::<Vec<_>>()
                    .join(", "),
                100.0 * d.params.tolerance,
            ),
        }
    }

    fn render(d: &BoundariesData) -> Result<Rendered, crate::results::render::RenderError> {
        Ok(Rendered {
            extra_tables: vec![("grazing", render::grazing_table(d))],
            ..Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?
        })
    }
}
