//! Scene `atlas`: beyond the paper — the multi-tap atlas ([`crate::analysis::atlas`]): the stable
//! periodic orbits (m, n) of the compliant model, with N matched to k by the book's one
//! stiffness-matching criterion, over k/k₁ 1…10⁴ and
//! ω/(β₁⁻)² 0.5…3 (Figure 4's ζ₁ = 0.01 and d₀ = 0), how many coexist, and how many
//! contacts per forcing period the beam makes ("drum rolls": n/m ≥ 2). The paper shows
//! multiple taps at single parameter points (Figures 4, 6(b), 9); the atlas maps where
//! they live, and its boundary curves by two-parameter continuation ([`boundaries`]) say
//! which bifurcations bound the regions.

pub mod boundaries;
pub mod render;
pub mod shards;

use crate::analysis::atlas::{self, AtlasData, AtlasParams, Cell};
use crate::analysis::motion::{Motion, MotionClass};
use crate::error::Error;
use crate::base::report::KeyNumbers;
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use std::collections::BTreeMap;

/// The scene.
pub struct Atlas;

/// Every cell of the atlas, row by row.
pub fn cells(d: &AtlasData) -> impl Iterator<Item = &Cell> {
    d.rows.iter().flat_map(|r| r.cells.iter())
}

/// Cells per (m, n) of the orbit from rest (None: rest reaches no stable orbit of
/// period ≤ max_m), most frequent first.
pub fn rest_labels(d: &AtlasData) -> Vec<(Option<(u64, usize)>, usize)> {
    let mut count: BTreeMap<Option<(u64, usize)>, usize> = BTreeMap::new();
    for c in cells(d) {
        *count
            .entry(c.rest().map(|a| (a.period_m, a.impacts_n)))
            .or_default() += 1;
    }
    let mut v: Vec<_> = count.into_iter().collect();
    v.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
    v
}

/// The classes of the motions from rest that reach no stable orbit of period ≤ max_m, with
/// their counts, in the order the book lists them.
pub fn motion_counts(d: &AtlasData) -> Vec<(MotionClass, usize)> {
    [
        MotionClass::QuasiPeriodic,
        MotionClass::Chaotic,
        MotionClass::Periodic,
        MotionClass::Undecided,
    ]
    .into_iter()
    .map(|class| {
        let n = cells(d)
            .filter(|c| c.motion.as_ref().is_some_and(|m| m.class == class))
            .count();
        (class, n)
    })
    .collect()
}

/// The evidence of one class, in words: the range of λ₁ (per unit time), the range of its
/// 95 % half-widths, and per class the rotation numbers or the periods found (None when no
/// cell has the class).
pub(super) fn motion_evidence_parts(d: &AtlasData, class: MotionClass) -> Option<[String; 3]> {
    let of: Vec<&Motion> = cells(d)
        .filter_map(|c| c.motion.as_ref())
        .filter(|m| m.class == class)
        .collect();
    if of.is_empty() {
        return None;
    }
    let range = |f: &dyn Fn(&Motion) -> f64| {
        of.iter()
            .map(|m| f(m))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)))
    };
    let span = |(a, b): (f64, f64), f: &dyn Fn(f64) -> String| {
        if a == b {
            f(a)
        } else {
            format!("{} to {}", f(a), f(b))
        }
    };
    let lambda = span(range(&|m| m.exponents[0]), &|v| format!("{v:.2e}"));
    let widths = span(range(&|m| m.half_widths[0]), &|v| format!("{v:.1e}"));
    let extra = match class {
        MotionClass::QuasiPeriodic => format!(
            "ρ {}, halves within {:.1e}",
            span(range(&|m| m.rotation.turns), &|v| format!("{v:.3}")),
            range(&|m| m.rotation.halves_differ).1
        ),
        MotionClass::Periodic => {
            let periods: Vec<u64> = of.iter().filter_map(|m| m.period_m).collect();
            let short: Vec<u64> = periods.iter().copied().filter(|&m| m <= d.params.max_period).collect();
            let long: Vec<u64> = periods.iter().copied().filter(|&m| m > d.params.max_period).collect();
            let mut count: BTreeMap<u64, usize> = BTreeMap::new();
            for m in &long {
                *count.entry(*m).or_default() += 1;
            }
            let most = count.iter().max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0)));
            let group = |v: &[u64]| {
                let (lo, hi) = (v.iter().min().copied().unwrap_or(0), v.iter().max().copied().unwrap_or(0));
                if lo == hi { format!("m = {lo}") } else { format!("m = {lo} to {hi}") }
            };
            let cells = |n: usize| format!("{n} cell{}", if n == 1 { "" } else { "s" });
            let mut parts = Vec::new();
            if !short.is_empty() {
                parts.push(format!("{} {} (a longer transient)", cells(short.len()), group(&short)));
            }
            if let Some((m, n)) = most {
                parts.push(format!(
                    "{} {}, most often {m} ({})",
                    cells(long.len()),
                    group(&long),
                    cells(*n)
                ));
            }
            parts.join("; ")
        }
        MotionClass::Chaotic | MotionClass::Undecided => String::new(),
    };
    Some([lambda, widths, extra])
}

/// The evidence of one class as one line of text.
fn motion_evidence(d: &AtlasData, class: MotionClass) -> String {
    match motion_evidence_parts(d, class) {
        None => "none".into(),
        Some([lambda, widths, extra]) => {
            let mut text = format!("λ₁ {lambda} (95 % half-widths {widths})");
            if !extra.is_empty() {
                text += &format!("; {extra}");
            }
            text
        }
    }
}

/// An (m, n) label as text.
pub fn label(l: Option<(u64, usize)>) -> String {
    l.map_or("none".to_string(), |(m, n)| format!("({m},{n})"))
}

/// The convergence check: cells checked, cells where the check's orbit from rest is one
/// of the cell's, orbits the further starts found that the cell missed, and the cells
/// where they did.
pub fn check_summary(d: &AtlasData) -> (usize, usize, usize, usize) {
    let tol = d.params.check_tolerance();
    let checked: Vec<&Cell> = cells(d).filter(|c| c.check.is_some()).collect();
    let agree = checked
        .iter()
        .filter(|c| c.check_agrees(tol) == Some(true))
        .count();
    let missed: usize = checked
        .iter()
        .filter_map(|c| c.check.as_ref().map(|k| k.missed))
        .sum();
    let missed_cells = checked
        .iter()
        .filter(|c| c.check.as_ref().is_some_and(|k| k.missed > 0))
        .count();
    (checked.len(), agree, missed, missed_cells)
}

/// The checked cells where the check's orbit from rest is not the cell's, as text.
fn check_disagreements(d: &AtlasData) -> String {
    let tol = d.params.check_tolerance();
    let mut v = Vec::new();
    for r in &d.rows {
        for (j, c) in r.cells.iter().enumerate() {
            if c.check_agrees(tol) != Some(false) {
                continue;
            }
            let Some(check) = c.check.as_ref() else {
                continue;
            };
            let change = check
                .impact_velocity_change
                .map(|x| format!(", impact velocities {:.1}% apart", 100.0 * x))
                .unwrap_or_default();
            v.push(format!(
                "N = {} {}, N = {} {}{change} at k/k₁ = {}, ω/(β₁⁻)² = {:.2}",
                check.modes,
                label(check.from_rest),
                r.modes,
                label(c.rest().map(|a| (a.period_m, a.impacts_n))),
                crate::base::report::pretty(r.k_over_k1, 3),
                d.omega_over_w1[j]
            ));
        }
    }
    if v.is_empty() {
        "none".into()
    } else {
        v.join("; ")
    }
}

/// N along k as runs "N from k".
fn modes_along_k(d: &AtlasData) -> String {
    let mut runs: Vec<String> = Vec::new();
    let mut previous = None;
    for r in &d.rows {
        if previous != Some(r.modes) {
            runs.push(format!(
                "{} from {}k₁",
                r.modes,
                crate::base::report::pretty(r.k_over_k1, 3)
            ));
            previous = Some(r.modes);
        }
    }
    runs.join(", ")
}

/// The largest k of the grid at which N = 10 meets the stiffness-matching criterion.
pub fn ten_modes_suffice_up_to(d: &AtlasData) -> Option<f64> {
    d.rows
        .iter()
        .filter(|r| r.modes <= 10)
        .map(|r| r.k_over_k1)
        .fold(None, |m: Option<f64>, k| Some(m.map_or(k, |m| m.max(k))))
}

/// The orbit from rest along k in the column nearest ω = 2(β₁⁻)² (Figure 5's), as runs
/// "from k: label".
fn column_near_two(d: &AtlasData) -> String {
    let Some(j) = (0..d.omega_over_w1.len())
        .min_by(|&a, &b| (d.omega_over_w1[a] - 2.0).abs().total_cmp(&(d.omega_over_w1[b] - 2.0).abs()))
    else {
        return String::new();
    };
    let mut runs: Vec<String> = Vec::new();
    let mut previous = None;
    for r in &d.rows {
        let l = label(r.cells[j].rest().map(|a| (a.period_m, a.impacts_n)));
        if previous.as_ref() != Some(&l) {
            runs.push(format!("{l} from {}", crate::base::report::pretty(r.k_over_k1, 3)));
            previous = Some(l);
        }
    }
    format!("ω = {:.3}: {}", d.omega_over_w1[j], runs.join(", "))
}

/// The rest labels along ω of one row, as text.
fn row_labels(d: &AtlasData, i: usize) -> String {
    d.rows[i]
        .cells
        .iter()
        .map(|c| label(c.rest().map(|a| (a.period_m, a.impacts_n))))
        .collect::<Vec<_>>()
        .join(" ")
}

impl Scene for Atlas {
    const NAME: &'static str = "atlas";
    const PAPER: &'static str = "beyond §5.3";
    const TITLE: &'static str = "Multi-tap atlas over (k, ω)";
    const GIST: &'static str = "— (taps at single points only)";
    const GROUP: Group = Group::Beyond;
    const SUMMARY: &'static str =
        "multi-tap atlas: stable orbits (m, n) and their coexistence over k and ω, N matched to k";
    const CLAIM: &'static str = "None: it shows multiple taps at single parameter points (Figures 4, 6(b), 9), not where in $(k, \\omega)$ they occur.";
    const CHAPTER: &'static str = "atlas.md";
    const METHOD: &'static str = "each row is one k with N matched to it (the fewest modes giving one contact's observables to 1 %, computed every 8th row, each row taking the next stiffer computed row's N), swept up in ω (128 × 128 cells, k/k₁ log-spaced 1–10⁴, ω/(β₁⁻)² linear 0.5–3): a cell's stable periodic orbits come from natural continuation of the previous cell's orbits and from three seeded starts (rest and two random states, transients of up to 300 periods, read after every 100), each converged by Newton shooting to a relative residual of 1e-12, reduced to its least period m ≤ 8, kept if its Floquet multipliers lie inside the unit circle, and counted once; every 16th row and column is checked from rest with 10 more modes (the same (m, n) and entry velocities within 1 %) and with 16 further random starts; up to 30 boundary curves (folds, period doublings, Neimark–Sacker points, grazings) are traced by two-parameter continuation from the bifurcations met between neighbouring cells, each at the N of its band of rows and within that band's k, and each boundary between cells is checked for a curve within one grid step";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        ("cells tapping more than once per forcing period (from rest)", "multi-tap cells"),
        ("cells with coexisting stable orbits (at least)", "coexisting cells (lower bound)"),
        ("check with 10 more modes: the same orbit from rest", "N+10 check agrees"),
    ];
    const SETTABLE: &'static [crate::results::settings::Setting] = &[crate::results::settings::ZETA1, crate::results::settings::GAP, crate::results::settings::SEED];
    type Params = AtlasParams;
    type Data = AtlasData;

    fn params(resolution: Resolution) -> AtlasParams {
        match resolution {
            Resolution::Book => AtlasParams::book(),
            Resolution::Test => AtlasParams::test(),
        }
    }

    fn compute(p: &AtlasParams, progress: &dyn Progress) -> Result<AtlasData, Error> {
        atlas::compute(p, progress)
    }

    fn key_numbers(d: &AtlasData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        // every number here is a count of cells or orbits: exact integers of the computed
        // atlas (each orbit converged to 1e-12 and its stability by its multipliers)
        let all: Vec<&Cell> = cells(d).collect();
        k.integer("cells", all.len() as i64);
        let count = |f: &dyn Fn(&Cell) -> bool| all.iter().filter(|c| f(c)).count() as i64;
        k.integer(
            "multi-tap cells",
            count(&|c| c.rest().is_some_and(|a| a.impacts_n > a.period_m as usize)),
        );
        k.integer(
            "drum-roll cells (n/m at least 2)",
            count(&|c| c.rest().is_some_and(|a| a.impacts_n >= 2 * a.period_m as usize)),
        );
        // the starts find orbits, they do not prove there are no others: counts are lower bounds
        k.integer("coexisting cells (lower bound)", count(&|c| c.attractors.len() > 1));
        k.integer(
            "most coexisting stable orbits in a cell (lower bound)",
            all.iter().map(|c| c.attractors.len()).max().unwrap_or(0) as i64,
        );
        k.integer("cells with no stable orbit from rest", count(&|c| c.from_rest.is_none()));
        // each cell's class follows from its own evidence by the stated rule (exact counts of
        // that rule; the rule's own limits are in the chapter)
        // ε of the rule: a quarter of mode 1's decay rate, the same at every k, ω and N
        if let Ok(model) = d
            .params
            .model(1, d.params.k_over_k1(0), d.params.omega_over_w1(0))
            .and_then(|f| f.model())
        {
            let eps = atlas::motion_options(&d.params, &model).resolution;
            k.text("classification resolution", format!("{eps:.2e} per unit time"));
        }
        for (class, n) in motion_counts(d) {
            k.integer(format!("no orbit from rest: {}", class.words()), n as i64);
            k.text(
                format!("no orbit from rest: {} evidence", class.words()),
                motion_evidence(d, class),
            );
        }
        k.integer(
            "cells with an unsettled start",
            count(&|c| c.unsettled_starts > 0),
        );
        let labels = rest_labels(d);
        k.integer("distinct (m,n) from rest", labels.iter().filter(|l| l.0.is_some()).count() as i64);
        k.text(
            "cells per (m,n) from rest",
            labels
                .iter()
                .map(|(l, n)| format!("{} {n}", label(*l)))
                .collect::<Vec<_>>()
                .join(", "),
        );
        if let Some((taps, at)) = d
            .rows
            .iter()
            .flat_map(|r| {
                r.cells.iter().enumerate().filter_map(move |(j, c)| {
                    c.rest().map(|a| (a.taps_per_period(), (r.k_over_k1, j)))
                })
            })
            .max_by(|a, b| a.0.total_cmp(&b.0))
        {
            k.text(
                "most taps per forcing period from rest",
                format!(
                    "{taps} at k/k₁ = {}, ω/(β₁⁻)² = {:.3}",
                    crate::base::report::pretty(at.0, 3),
                    d.omega_over_w1[at.1]
                ),
            );
        }
        k.text("modes along k", modes_along_k(d));
        if let Some(kmax) = ten_modes_suffice_up_to(d) {
            k.text(
                "N=10 suffices up to k",
                format!("{}k₁", crate::base::report::pretty(kmax, 3)),
            );
        }
        let (checked, agree, missed, missed_cells) = check_summary(d);
        k.text("N+10 check agrees", format!("{agree} of {checked}"));
        k.text("N+10 check disagreements", check_disagreements(d));
        k.text("orbits from rest along k near omega=2", column_near_two(d));
        k.text(
            "orbits missed (further starts)",
            format!("{missed} in {missed_cells} of {checked} cells"),
        );
        k.text("orbits from rest at the smallest k", row_labels(d, 0));
        k.text("orbits from rest at the largest k", row_labels(d, d.rows.len() - 1));
        if let Some(c) = &d.curves {
            boundaries::key_numbers(&mut k, d, c);
        }
        k
    }

    fn verdict(d: &AtlasData) -> Verdict {
        let all = cells(d).count();
        let multi = cells(d)
            .filter(|c| c.rest().is_some_and(|a| a.impacts_n > a.period_m as usize))
            .count();
        let coexist = cells(d).filter(|c| c.attractors.len() > 1).count();
        let (checked, agree, _, _) = check_summary(d);
        let pct = |x: usize| 100.0 * x as f64 / all.max(1) as f64;
        // the truncation as the atlas was computed (a merged or custom atlas may fix N)
        let with = match d.params.modes {
            crate::analysis::atlas::ModesRule::Fixed(n) => format!("With N = {n} at every k"),
            _ => "With N matched to k".to_string(),
        };
        Verdict {
            outcome: Outcome::Extension,
            evidence: format!(
                "{with}, from rest the beam taps more than once per forcing period in {multi} of the {all} cells ({:.0} %); at least {coexist} ({:.1} %, rounded down: a lower bound) have two or more coexisting stable orbits; with 10 more modes the orbit from rest is the same (m, n), its entry velocities within 1 %, in {agree} of {checked} checked cells",
                pct(multi),
                (pct(coexist) * 10.0).floor() / 10.0
            ),
        }
    }

    fn render(d: &AtlasData) -> Result<Rendered, crate::results::render::RenderError> {
        Ok(Rendered {
            extra_tables: vec![
                ("decades", render::decades_table(d)),
                ("motions", render::motions_table(d)),
                (
                    "curves",
                    d.curves
                        .as_ref()
                        .map_or_else(String::new, |c| boundaries::table(d, c)),
                ),
                (
                    "meetings",
                    d.curves
                        .as_ref()
                        .map_or_else(String::new, boundaries::meetings_table),
                ),
            ],
            ..Rendered::drawn(|layout| render::plot(d, layout), render::labels_table(d))?
        })
    }
}
