//! The atlas's boundary curves in the scene: their key numbers (how many edges of the
//! regions they account for, which are left, their codimension-two points) and their table.

use super::label;
use crate::analysis::atlas::curves::{self, left, BoundaryCurves, Edge, EdgeClass, Label, Left};
use crate::analysis::atlas::AtlasData;
use crate::analysis::curves::CurveKind;
use crate::base::report::{pretty, KeyNumbers, Uncertainty};
use crate::results::render::markdown_table;
use std::collections::BTreeMap;

/// "a of b (p %)".
fn share(a: usize, b: usize) -> String {
    format!("{a} of {b} ({:.0} %)", 100.0 * a as f64 / b.max(1) as f64)
}

/// An unordered pair of labels as text, "(1,1)–(1,2)".
fn pair(e: &Edge) -> String {
    let (a, b): (Label, Label) = if e.labels.0 <= e.labels.1 {
        e.labels
    } else {
        (e.labels.1, e.labels.0)
    };
    format!("{}–{}", label(a), label(b))
}

/// The edges no curve accounts for, by pair of labels, most frequent first: (pair, edges,
/// of which basin edges).
pub fn unaccounted(edges: &[Edge]) -> Vec<(String, usize, usize)> {
    let mut by: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for e in edges.iter().filter(|e| e.curve.is_none()) {
        let x = by.entry(pair(e)).or_default();
        x.0 += 1;
        if e.class == EdgeClass::Basin {
            x.1 += 1;
        }
    }
    let mut v: Vec<(String, usize, usize)> = by.into_iter().map(|(k, (n, b))| (k, n, b)).collect();
    v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    v
}

/// Why a seed gave no curve, in words common to many seeds (its reason without the numbers).
pub fn failure_kind(why: &str) -> &'static str {
    if why.contains("meets no bifurcation") {
        "no bifurcation met between the two cells"
    } else if why.contains("could not be polished") {
        "the curve's first point could not be polished"
    } else if why.contains("no fold point found") {
        "no fold point near the one-parameter estimate"
    } else if why.contains("converged to an orbit of period") {
        "the orbit's least period halved on the curve"
    } else if why.contains("Newton steps") {
        "shooting did not converge at the curve's first point"
    } else if why.contains("stalls within one grid step") {
        "the curve stalls within a grid step of its start"
    } else if why.contains("does not pass between its cells") {
        "the curve located does not pass between the cells"
    } else {
        "other"
    }
}

/// Digits a bracketed value supports: its leading digit and the first the half-width
/// touches.
fn digits(x: f64, half: f64) -> usize {
    if half <= 0.0 || x == 0.0 {
        return 6;
    }
    ((x.abs() / half).log10().floor() as i64 + 1).clamp(2, 9) as usize
}

/// The key numbers of the curves.
pub fn key_numbers(k: &mut KeyNumbers, d: &AtlasData, c: &BoundaryCurves) {
    let edges = curves::edges(d, c);
    if d.rows.is_empty() {
        return;
    }
    k.integer("boundary curves", c.curves.len() as i64);
    let bands: Vec<String> = c
        .bands
        .iter()
        .map(|b| {
            let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
            for cv in c.curves.iter().filter(|cv| {
                let row = cv.seed.0 .0;
                (b.rows.0..b.rows.1).contains(&row)
            }) {
                *kinds.entry(cv.kind.as_str()).or_default() += 1;
            }
            let kinds: Vec<String> = kinds.iter().map(|(kind, n)| format!("{n} {kind}")).collect();
            format!(
                "N = {} for k/k₁ from {} to {} (rows {} to {}): {}",
                b.modes,
                pretty(d.rows[b.rows.0].k_over_k1, 3),
                pretty(d.rows[b.rows.1 - 1].k_over_k1, 3),
                b.rows.0 + 1,
                b.rows.1,
                if kinds.is_empty() { "none".to_string() } else { kinds.join(", ") }
            )
        })
        .collect();
    k.text(
        "boundary curves: where",
        format!(
            "{}; ω/(β₁⁻)² from {} to {}",
            bands.join("; "),
            pretty(d.params.omega_range.0, 3),
            pretty(d.params.omega_range.1, 3),
        ),
    );
    k.text(
        "boundary curve seeds",
        format!(
            "{} tried, {} gave a new curve, {} gave none or a curve already traced",
            c.curves.len() + c.failed.len() + c.duplicates,
            c.curves.len(),
            c.failed.len() + c.duplicates
        ),
    );
    let near = |f: &dyn Fn(&Edge) -> bool| {
        let of: Vec<&Edge> = edges.iter().filter(|e| f(e)).collect();
        share(of.iter().filter(|e| e.curve.is_some()).count(), of.len())
    };
    k.integer("boundary edges", edges.len() as i64);
    k.text("boundary edges within one grid step of a curve", near(&|_| true));
    k.text(
        "bifurcation edges within one grid step of a curve",
        near(&|e| e.class == EdgeClass::Bifurcation),
    );
    k.text(
        "basin edges within one grid step of a curve",
        near(&|e| e.class == EdgeClass::Basin),
    );
    k.text(
        "edges next to a cell without a stable orbit, within one step of a curve",
        near(&|e| e.labels.0.is_none() || e.labels.1.is_none()),
    );
    for reason in Left::ALL {
        let n = edges.iter().filter(|e| left(d, c, e) == Some(reason)).count();
        k.integer(format!("edges left: {}", reason.key()), n as i64);
    }
    let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
    for f in &c.failed {
        *kinds.entry(failure_kind(&f.why)).or_default() += 1;
    }
    let mut kinds: Vec<(&str, usize)> = kinds.into_iter().collect();
    kinds.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    k.text(
        "seeds without a curve, by reason",
        if kinds.is_empty() {
            "none".to_string()
        } else {
            kinds
                .iter()
                .map(|(why, n)| format!("{why} ({n})"))
                .collect::<Vec<_>>()
                .join(", ")
        },
    );
    let left = unaccounted(&edges);
    k.text(
        "edges no curve accounts for, by pair",
        left.iter()
            .take(12)
            .map(|(p, n, b)| format!("{p} {n} ({b} basin)"))
            .collect::<Vec<_>>()
            .join(", ")
            + &format!(
                "; {} further pairs with {} edges",
                left.len().saturating_sub(12),
                left.iter().skip(12).map(|x| x.1).sum::<usize>()
            ),
    );
    let crossed = curves::crossings(d, c);
    k.text(
        "curve crossings: orbit from rest differs",
        share(crossed.iter().filter(|x| x.rest_differs).count(), crossed.len()),
    );
    k.text(
        "curve crossings: stable orbits found differ",
        share(crossed.iter().filter(|x| x.stable_differs).count(), crossed.len()),
    );
    let (orbit, test) = c
        .curves
        .iter()
        .fold((0.0f64, 0.0f64), |r, cv| (r.0.max(cv.residuals.0), r.1.max(cv.residuals.1)));
    k.text(
        "boundary curves: largest residuals",
        format!("orbit {orbit:.1e}, test condition {test:.1e}"),
    );
    // a fold's condition is met only to ~1e-5 (the multiplier goes as the square root of
    // the distance from the fold): the other curves' largest test residual on its own
    let off_folds = c
        .curves
        .iter()
        .enumerate()
        .filter(|(_, cv)| cv.kind != CurveKind::Fold.to_string())
        .max_by(|a, b| a.1.residuals.1.total_cmp(&b.1.residuals.1));
    if let Some((i, cv)) = off_folds {
        k.text(
            "boundary curves: largest test residual off fold curves",
            format!(
                "{:.1e} (curve {}, {} of {})",
                cv.residuals.1,
                i + 1,
                cv.kind,
                label(Some(cv.orbit))
            ),
        );
    }
    let bracket = "interpolated along the curve between its two points that bracket it: half their distance";
    let mut n = 0;
    for (i, cv) in c.curves.iter().enumerate() {
        for m in &cv.meetings {
            n += 1;
            let name = format!(
                "codimension-two point {n} (curve {}, {} of {}, meets {})",
                i + 1,
                cv.kind,
                label(Some(cv.orbit)),
                m.meets
            );
            for (what, (x, half), unit) in [("omega", m.omega, "(β₁⁻)²"), ("k", m.k_over_k1, "k₁")] {
                let bracketed = Uncertainty::new(half, bracket);
                k.cited(format!("{name}: {what}"), x, digits(x, half), bracketed, unit);
            }
        }
    }
    k.integer("codimension-two points on the curves", n as i64);
}

/// One row per curve: kind and orbit, extent, edges it accounts for, codimension-two points,
/// residuals, ends.
pub fn table(d: &AtlasData, c: &BoundaryCurves) -> String {
    let edges = curves::edges(d, c);
    let rows: Vec<Vec<String>> = c
        .curves
        .iter()
        .enumerate()
        .map(|(i, cv)| {
            let range = |f: &dyn Fn(&(f64, f64)) -> f64| {
                cv.points
                    .iter()
                    .map(f)
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
            };
            let (w0, w1) = range(&|p| p.0);
            let (k0, k1) = range(&|p| p.1);
            let accounted = edges.iter().filter(|e| e.curve.map(|x| x.0) == Some(i)).count();
            let ends = |e: &str| {
                if e.starts_with("left") {
                    "map edge"
                } else if e.starts_with("closed") {
                    "closed"
                } else if e.starts_with("corrector") {
                    "stalled"
                } else if e.starts_with("the model's orbit") {
                    "off its condition"
                } else {
                    "point cap"
                }
            };
            vec![
                format!("{} {} of {}", i + 1, cv.kind, label(Some(cv.orbit))),
                format!("{:.2}–{:.2}", w0, w1),
                format!("{}–{}", pretty(k0, 3), pretty(k1, 3)),
                accounted.to_string(),
                cv.meetings.len().to_string(),
                format!("{:.0e}, {:.0e}", cv.residuals.0, cv.residuals.1),
                if cv.ends.0 == cv.ends.1 {
                    ends(&cv.ends.0).to_string()
                } else {
                    format!("{}; {}", ends(&cv.ends.0), ends(&cv.ends.1))
                },
            ]
        })
        .collect();
    markdown_table(
        &[
            "curve",
            "$\\omega/(\\beta_1^-)^2$",
            "$k/k_1$",
            "edges within a step",
            "codim-2 points",
            "residuals: orbit, test",
            "ends",
        ],
        &rows,
    )
}

/// One row per codimension-two point: its curve, what it meets, ω and k with their brackets.
pub fn meetings_table(c: &BoundaryCurves) -> String {
    let mut rows: Vec<Vec<String>> = Vec::new();
    for (i, cv) in c.curves.iter().enumerate() {
        for m in &cv.meetings {
            let with = |(x, h): (f64, f64)| {
                let places = (-(h.log10().floor()) as i64 + 1).clamp(0, 9) as usize;
                format!("{x:.places$} ± {h:.1e}")
            };
            rows.push(vec![
                format!("{} ({} of {})", i + 1, cv.kind, label(Some(cv.orbit))),
                m.meets.clone(),
                with(m.omega),
                with(m.k_over_k1),
            ]);
        }
    }
    if rows.is_empty() {
        return String::new();
    }
    markdown_table(
        &["curve", "meets", "$\\omega/(\\beta_1^-)^2$", "$k/k_1$"],
        &rows,
    )
}
