//! The atlas's boundary curves in the scene: their key numbers (how many edges of the
//! regions they account for, which are left, their codimension-two points) and their table.

use super::label;
use crate::analysis::atlas::curves::{self, left, BoundaryCurves, Edge, EdgeClass, Label, Left};
use crate::analysis::atlas::across::EdgeCheck;
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

/// The Wilson score interval of a share `a` of `n` at 95 % confidence, in per cent.
fn wilson(a: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 100.0);
    }
    let (z, n) = (1.96f64, n as f64);
    let p = a as f64 / n;
    let centre = (p + z * z / (2.0 * n)) / (1.0 + z * z / n);
    let half = z * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt() / (1.0 + z * z / n);
    (100.0 * (centre - half).max(0.0), 100.0 * (centre + half).min(1.0))
}

/// "kind n, kind n" of the checked edges that meet a bifurcation, most frequent first.
fn by_kind<'a>(checked: impl Iterator<Item = &'a EdgeCheck>) -> String {
    let mut kinds: BTreeMap<&str, usize> = BTreeMap::new();
    for x in checked {
        if let Some((kind, _)) = &x.meets {
            *kinds.entry(kind.as_str()).or_default() += 1;
        }
    }
    let mut kinds: Vec<(&str, usize)> = kinds.into_iter().collect();
    kinds.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(b.0)));
    kinds
        .iter()
        .map(|(kind, n)| format!("{kind} {n}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The key numbers of the edges checked across ([`crate::analysis::atlas::across`]).
fn checked_numbers(k: &mut KeyNumbers, d: &AtlasData, c: &BoundaryCurves, edges: &[Edge]) {
    let pool = edges
        .iter()
        .filter(|e| {
            matches!(
                left(d, c, e),
                Some(Left::NotPeriodic | Left::SeedFailed | Left::NotSeeded)
            )
        })
        .count();
    let n = c.checked.len();
    k.text(
        "edges left, checked across",
        format!(
            "{n} of the {pool} edges left for the last three reasons, drawn at random with \
             the atlas's seed"
        ),
    );
    let located = c.checked.iter().filter(|x| x.meets.is_some()).count();
    let (lo, hi) = wilson(located, n);
    k.text(
        "checked edges: a bifurcation located between the two cells",
        format!(
            "{located} of {n} ({:.0} %; of all {pool}, {lo:.0} to {hi:.0} % at 95 % confidence)",
            100.0 * located as f64 / n.max(1) as f64
        ),
    );
    k.text(
        "checked edges: the bifurcation located, by kind",
        by_kind(c.checked.iter()),
    );
    for reason in [Left::NotPeriodic, Left::SeedFailed, Left::NotSeeded] {
        let of: Vec<&EdgeCheck> = c.checked.iter().filter(|x| x.left == reason.key()).collect();
        let found = of.iter().filter(|x| x.meets.is_some()).count();
        k.text(
            format!("checked edges, {}: located", reason.key()),
            if of.is_empty() {
                "none checked".to_string()
            } else {
                format!(
                    "{} of {} ({})",
                    found,
                    of.len(),
                    if found == 0 { "none".to_string() } else { by_kind(of.into_iter()) }
                )
            },
        );
    }
    let mut none: BTreeMap<String, usize> = BTreeMap::new();
    for x in c.checked.iter().filter(|x| x.meets.is_none()) {
        let why = x.why.as_deref().unwrap_or("");
        let why = if why.contains("points reached") {
            "the continuation did not reach the neighbour within its points"
        } else {
            why
        };
        *none.entry(why.to_string()).or_default() += 1;
    }
    k.text(
        "checked edges: none located, why",
        if none.is_empty() {
            "none".to_string()
        } else {
            none.iter()
                .map(|(why, n)| format!("{why} ({n})"))
                .collect::<Vec<_>>()
                .join("; ")
        },
    );
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
    if c.search.edge_sample > 0 {
        checked_numbers(k, d, c, &edges);
    }
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
    let same: Vec<_> = crossed.iter().filter(|x| !x.stable_differs).collect();
    k.text(
        "curve crossings where the stable orbits found do not differ: the curve's orbit unstable",
        share(
            same.iter().filter(|x| x.orbit_unstable == Some(true)).count(),
            same.len(),
        ),
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
    let away = c
        .curves
        .iter()
        .enumerate()
        .filter(|(_, cv)| cv.kind != CurveKind::Fold.to_string())
        .max_by(|a, b| {
            a.1.test_residual_off_folds
                .total_cmp(&b.1.test_residual_off_folds)
        });
    if let Some((i, cv)) = away {
        k.text(
            format!(
                "boundary curves: largest test residual off fold curves, at points with no \
                 multiplier within {:.0e} of 1",
                curves::NEAR_FOLD
            ),
            format!(
                "{:.1e} (curve {}, {} of {})",
                cv.test_residual_off_folds,
                i + 1,
                cv.kind,
                label(Some(cv.orbit)),
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

#[cfg(test)]
mod tests {
    use super::wilson;

    #[test]
    fn the_wilson_interval_is_the_textbook_one() {
        // Newcombe (1998), Statistics in Medicine 17, 857–872, table II, method 3 (the
        // score interval without continuity correction), printed to 4 decimals: 0.005 %
        // is their rounding, 0.01 % leaves room for z = 1.96 against their 1.959964
        let close = |(a, b): (f64, f64), (x, y): (f64, f64)| {
            assert!((a - x).abs() < 0.01 && (b - y).abs() < 0.01, "({a}, {b}) vs ({x}, {y})");
        };
        close(wilson(81, 263), (25.53, 36.62));
        close(wilson(15, 148), (6.24, 16.05));
        close(wilson(0, 20), (0.0, 16.11));
        close(wilson(1, 29), (0.61, 17.18));
    }
}
