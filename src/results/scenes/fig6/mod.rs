//! Scene `fig6`: Figure 6 and §5.4 — the energetic coefficient of restitution r_E of the
//! 20-mode bilinear model (eq 39, [`crate::analysis::energetic`]) and the one-mode impact oscillator
//! with Newton's law r = r_E, for the paper's two panels at k = 1000k₁:
//! (a) d₀ = 0.8, ω = 1.15(β₁⁻)², ζ₁ = 0.1 (paper: a (1,1) orbit near grazing, r_E = 0.036,
//! good agreement with the one-mode model); (b) d₀ = 0, ω = 2(β₁⁻)², ζ₁ = 0.01 (paper:
//! multiple taps, r_E = 0.74, no agreement).
//!
//! With d₀ ≠ 0 the model is not positively homogeneous, so panel (a) depends on the forcing
//! amplitude, which the paper states two ways (errata E2). Scaling every length by the same
//! factor maps a forcing amplitude onto the ratio d₀/A_free of the stop's distance to the
//! free tip amplitude at the forcing frequency, so panel (a) is computed under each reading
//! as that ratio, and the ratio is also scanned.
//!
//! Every published r_E carries diagnostics (N = 10…40, a longer transient, a looser root
//! tolerance, random starts); its uncertainty is its truncation ± by the book's one rule
//! (Richardson over the three finest N, [`crate::analysis::convergence::truncation`]) plus
//! the largest change under the other diagnostics, all of which must keep the orbit.

mod branch;
mod compute;
pub mod render;

pub use compute::compute;

use crate::analysis::energetic::Coefficient;
use crate::error::Error;
use crate::analysis::orbit::OrbitKind;
use crate::base::report::{KeyNumbers, Uncertainty};
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct Fig6Params {
    /// N of the published values (the paper's 20).
    pub modes: usize,
    /// The truncations of the convergence diagnostic.
    pub convergence_modes: Vec<usize>,
    /// Periods discarded.
    pub transient: u64,
    /// Periods over which the orbit is labelled.
    pub window: u64,
    /// The longer transient of the diagnostic.
    pub long_transient: u64,
    /// The looser root tolerance of the diagnostic.
    pub loose_root_tolerance: f64,
    /// Random starts of the diagnostic.
    pub random_starts: usize,
    /// Their seed.
    pub seed: u64,
    /// Samples per period of the plotted orbits.
    pub samples_per_period: usize,
    /// The scanned d₀/A_free of panel (a).
    pub scan: Vec<f64>,
    /// N of the scan.
    pub scan_modes: usize,
}

impl Fig6Params {
    /// The book's resolution.
    pub fn book() -> Self {
        Self {
            modes: 20,
            convergence_modes: vec![10, 20, 30, 40],
            transient: 1000,
            window: 40,
            long_transient: 4000,
            loose_root_tolerance: 1e-8,
            random_starts: 4,
            seed: 2013,
            samples_per_period: 400,
            scan: (0..=60).map(|i| 0.02 + 0.025 * i as f64).collect(),
            scan_modes: 20,
        }
    }

    /// A reduced version for the tests.
    pub fn test() -> Self {
        Self {
            convergence_modes: vec![10, 20, 30],
            long_transient: 1500,
            random_starts: 2,
            samples_per_period: 100,
            scan: vec![0.06, 0.5, 0.8, 0.97, 1.1, 1.3],
            scan_modes: 10,
            ..Self::book()
        }
    }
}

/// How panel (a)'s forcing amplitude is read (panel (b), with d₀ = 0, is the same under
/// every reading).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Reading {
    /// Eq (37) as printed: 1/(4ζ₁²) times the amplitude the text describes.
    PrintedEq37,
    /// The text of eq (37): unit free tip amplitude at resonance, ω = (β₁⁻)² (errata E2).
    UnitAtResonance,
    /// Unit free tip amplitude at the forcing frequency.
    UnitAtForcingFrequency,
    /// d₀ = 0: no reading matters.
    Homogeneous,
}

impl Reading {
    /// A label for tables.
    pub fn label(&self) -> &'static str {
        match self {
            Reading::PrintedEq37 => "eq (37) as printed",
            Reading::UnitAtResonance => "unit free amplitude at resonance (text of eq 37)",
            Reading::UnitAtForcingFrequency => "unit free amplitude at the forcing frequency",
            Reading::Homogeneous => "d₀ = 0 (any amplitude)",
        }
    }

    /// A short label for table cells.
    pub fn short(&self) -> &'static str {
        match self {
            Reading::PrintedEq37 => "as printed",
            Reading::UnitAtResonance => "unit at resonance",
            Reading::UnitAtForcingFrequency => "unit at ω",
            Reading::Homogeneous => "",
        }
    }

    /// A short key.
    pub fn key(&self) -> &'static str {
        match self {
            Reading::PrintedEq37 => "printed",
            Reading::UnitAtResonance => "resonance",
            Reading::UnitAtForcingFrequency => "forcing-frequency",
            Reading::Homogeneous => "any",
        }
    }
}

/// One run's orbit and r_E.
#[derive(Debug, Clone, Serialize)]
pub struct Probe {
    /// The orbit.
    pub kind: OrbitKind,
    /// Eq (39) when periodic.
    pub coefficient: Option<Coefficient>,
}

impl Probe {
    /// r_E, when real.
    pub fn value(&self) -> Option<f64> {
        self.coefficient.and_then(|c| c.value())
    }
}

/// The convergence diagnostics of one published r_E.
#[derive(Debug, Clone, Serialize)]
pub struct Diagnostics {
    /// (N, orbit and r_E) for each truncation.
    pub by_modes: Vec<(usize, Probe)>,
    /// With the longer transient.
    pub long_transient: Probe,
    /// With the looser root tolerance.
    pub loose_tolerance: Probe,
    /// From random starts.
    pub random_starts: Vec<Probe>,
}

/// The one-mode impact oscillator with Newton's law r = r_E.
#[derive(Debug, Clone, Serialize)]
pub struct OneMode {
    /// r.
    pub restitution: f64,
    /// Its orbit (m, impacts per period).
    pub kind: OrbitKind,
    /// Chatters in its recorded window.
    pub chatters: usize,
    /// Impact phases in one period (t/T).
    pub impact_phases: Vec<f64>,
    /// Impact velocities / (ωA_free).
    pub impact_velocities: Vec<f64>,
    /// Largest and smallest tip displacement / A_free over the period.
    pub extremes: (f64, f64),
    /// (t/T, d/A_free) over one period.
    pub samples: Vec<(f64, f64)>,
}

/// One panel under one reading.
#[derive(Debug, Clone, Serialize)]
pub struct Case {
    /// "a" or "b".
    pub panel: &'static str,
    /// The reading of the forcing amplitude.
    pub reading: Reading,
    /// The paper's r_E.
    pub paper_r_e: f64,
    /// d₀/A_free(ω).
    pub gap_over_free_amplitude: f64,
    /// A_free(ω) and ωA_free in the model's units under this reading.
    pub free_amplitude: (f64, f64),
    /// The orbit at N = `modes` from rest.
    pub kind: OrbitKind,
    /// Its stroboscopic residual.
    pub residual: f64,
    /// Eq (39).
    pub coefficient: Option<Coefficient>,
    /// The variant charging the impact with mode 1's whole energy change during contact.
    pub energy_change_coefficient: Option<Coefficient>,
    /// Eq (38) per contact of the period (None: no real value).
    pub contact_coefficients: Vec<Option<f64>>,
    /// Contact intervals in the period (t/T from its start).
    pub contacts: Vec<(f64, f64)>,
    /// Tip velocities at the entries / (ωA_free).
    pub entry_velocities: Vec<f64>,
    /// Largest and smallest tip displacement / A_free.
    pub extremes: (f64, f64),
    /// The diagnostics.
    pub diagnostics: Diagnostics,
    /// The uncertainty of r_E: its truncation ± plus the largest change under the other
    /// diagnostics (None when a diagnostic changes the orbit, or there is no r_E).
    pub uncertainty: Option<f64>,
    /// The truncation ± from the diagnostic's N (Richardson over the three finest).
    pub truncation: Option<crate::analysis::convergence::TruncationError>,
    /// The one-mode comparison (when r_E exists).
    pub one_mode: Option<OneMode>,
    /// (t/T, d/A_free, mode-1 part φ₁(1)η₁/A_free, in contact) over one period.
    pub samples: Vec<(f64, f64, f64, bool)>,
}

/// One point of the panel (a) scan.
#[derive(Debug, Clone, Serialize)]
pub struct ScanPoint {
    /// d₀/A_free.
    pub gap_over_free_amplitude: f64,
    /// From rest.
    pub rest: Probe,
    /// From a random start.
    pub random: Probe,
    /// The largest tip velocity at an entry / (ωA_free) on the orbit from rest.
    pub entry_velocity: Option<f64>,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct Fig6Data {
    /// The parameters used.
    pub params: Fig6Params,
    /// Panel (a) under each reading, then panel (b).
    pub cases: Vec<Case>,
    /// The scan of panel (a) over d₀/A_free.
    pub scan: Vec<ScanPoint>,
    /// The scan's (1,1) orbit continued in d₀ (None: the scan found none).
    pub gap_branch: Option<branch::GapBranch>,
}

/// The scene.
pub struct Fig6;

fn r_text(c: &Option<Coefficient>) -> String {
    match c {
        None => "none (not periodic)".into(),
        Some(Coefficient::Value(r)) => format!("{r:.4}"),
        Some(Coefficient::NoRealValue(r2)) => format!("no real value (r² = {r2:.3})"),
        Some(Coefficient::NoContact) => "none (no contact)".into(),
    }
}

impl Scene for Fig6 {
    const NAME: &'static str = "fig6";
    const PAPER: &'static str = "Fig 6, §5.4, eqs (38)-(39)";
    const TITLE: &'static str = "Fig 6: r_E at two gaps";
    const GIST: &'static str = "r_E = 0.036 (a) and 0.74 (b)";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str = "energetic restitution r_E of the 20-mode model and the one-mode impact oscillator, panels (a) and (b), k = 1000 k1";
    const CLAIM: &'static str = "(a) $d_0 = 0.8$: a (1,1) orbit near grazing with $r_E = 0.036$, matched by the one-mode model; (b) $d_0 = 0$: multiple taps, $r_E = 0.74$, not matched.";
    const CHAPTER: &'static str = "fig6.md";
    const METHOD: &'static str = "the 20-mode compliant model from rest, 1000 periods discarded, simulated exactly; the orbit labelled on the stroboscopic map; eq (39) over one period of the orbit with the work of the contact force on mode 1 in closed form (mode 1's energy balance); diagnostics N = 10-40, a 4000-period transient, root tolerance 1e-8 and random starts; the one-mode impact oscillator by the rigid-impact model with Newton's law r = r_E";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        ("(b) r_E", "b r_E"),
        ("(b) orbit", "b orbit"),
        ("(a) r_E, unit free amplitude at the forcing frequency", "a forcing-frequency r_E"),
        ("(a) smallest r_E over the scan of d₀/A_free", "a scan smallest r_E"),
    ];
    type Params = Fig6Params;
    type Data = Fig6Data;

    fn params(resolution: Resolution) -> Fig6Params {
        match resolution {
            Resolution::Book => Fig6Params::book(),
            Resolution::Test => Fig6Params::test(),
        }
    }

    fn compute(p: &Fig6Params, progress: &dyn Progress) -> Result<Fig6Data, Error> {
        compute(p, progress)
    }

    fn key_numbers(d: &Fig6Data) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        let p = &d.params;
        let others = format!(
            "plus the largest change under a {}-period transient, root tolerance {:e} and {} random starts",
            p.long_transient, p.loose_root_tolerance, p.random_starts
        );
        let basis_of = |c: &Case| {
            c.truncation
                .as_ref()
                .map_or(String::new(), |t| format!("{}; {others}", t.basis()))
        };
        for c in &d.cases {
            let key = if c.panel == "b" {
                "b".to_string()
            } else {
                format!("a {}", c.reading.key())
            };
            k.free_amplitude(&format!("{key} "), c.free_amplitude);
            k.cited(
                format!("{key} d0/A_free"),
                c.gap_over_free_amplitude,
                6,
                Uncertainty::round_off(c.gap_over_free_amplitude, 1e-15, "closed form"),
                "",
            );
            k.text(format!("{key} orbit"), c.kind.to_string());
            match (c.coefficient.and_then(|r| r.value()), c.uncertainty) {
                (Some(r), Some(u)) => k.cited(
                    format!("{key} r_E"),
                    r,
                    4,
                    Uncertainty::new(u.max(1e-12), basis_of(c)),
                    "",
                ),
                _ => k.text(format!("{key} r_E"), r_text(&c.coefficient)),
            }
            k.text(
                format!("{key} r_E from mode-1 energy change"),
                r_text(&c.energy_change_coefficient),
            );
            for (i, r) in c.contact_coefficients.iter().enumerate() {
                k.text(
                    format!("{key} contact {} r_E", i + 1),
                    r.map_or("no real value".into(), |r| format!("{r:.4}")),
                );
            }
            for (n, probe) in &c.diagnostics.by_modes {
                k.text(
                    format!("{key} N={n}"),
                    format!("{} {}", probe.kind, r_text(&probe.coefficient)),
                );
            }
            if let Some(o) = &c.one_mode {
                k.text(format!("{key} one-mode orbit"), o.kind.to_string());
                k.integer(format!("{key} one-mode chatters"), o.chatters as i64);
                if let (Some(v20), Some(v1)) = (c.entry_velocities.first(), o.impact_velocities.first()) {
                    let settled = |v: f64| Uncertainty::new(v.abs() * 1e-9 + 1e-12, "orbits settled to 1e-9");
                    k.cited(format!("{key} impact velocity"), *v20, 4, settled(*v20), "ωA_free");
                    k.cited(format!("{key} one-mode impact velocity"), *v1, 4, settled(*v1), "ωA_free");
                }
            }
        }
        let reals: Vec<(f64, f64)> = d
            .scan
            .iter()
            .filter_map(|s| s.rest.value().map(|r| (s.gap_over_free_amplitude, r)))
            .collect();
        // The scan runs at N = scan_modes only: each of its points borrows the largest
        // uncertainty of the panel (a) cases, the scan's neighbours, each a convergence
        // estimate over N (settling alone, 1e-9, would claim far more).
        let widest = d
            .cases
            .iter()
            .filter(|c| c.panel != "b")
            .filter_map(|c| c.uncertainty.map(|u| (u, c)))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        let cite_scan = |k: &mut KeyNumbers, key: &str, r: f64| match widest {
            Some((u, c)) => k.cited(
                key,
                r,
                3,
                Uncertainty::new(
                    u,
                    format!("the largest uncertainty of the panel (a) cases: {}", basis_of(c)),
                ),
                "",
            ),
            None => k.text(key, format!("{r:.3} (no panel (a) case has a convergence estimate)")),
        };
        if let Some(&(rho, r)) = reals.iter().min_by(|a, b| a.1.total_cmp(&b.1)) {
            cite_scan(&mut k, "a scan smallest r_E", r);
            // a scan point: the parameter itself, exact
            k.text("a scan smallest r_E at d0/A_free", format!("{rho:.3}"));
        }
        if let Some(&(_, r)) = reals.iter().max_by(|a, b| a.1.total_cmp(&b.1)) {
            cite_scan(&mut k, "a scan largest r_E", r);
        }
        let rhos: Vec<f64> = d.scan.iter().map(|s| s.gap_over_free_amplitude).collect();
        let one_one: Vec<usize> = (0..d.scan.len())
            .filter(|&i| d.scan[i].rest.kind == OrbitKind::Periodic { m: 1, n: 1 })
            .collect();
        let slowest = d
            .scan
            .iter()
            .filter(|s| s.rest.kind == OrbitKind::Periodic { m: 1, n: 1 })
            .filter_map(|s| s.entry_velocity)
            .fold(f64::INFINITY, f64::min);
        if slowest.is_finite() {
            k.cited(
                "a scan (1,1) smallest impact velocity",
                slowest,
                3,
                Uncertainty::new(slowest * 1e-9, "orbits settled to 1e-9"),
                "ωA_free",
            );
        }
        // where the (1,1) orbits begin and end: between two adjacent scanned ratios, cited
        // as their midpoint ± half their distance
        let mut between = |name: &str, a: usize, b: usize| {
            let (lo, hi) = (rhos[a], rhos[b]);
            k.cited(
                name,
                0.5 * (lo + hi),
                3,
                Uncertainty::new(
                    0.5 * (hi - lo).max(1e-12),
                    format!("between adjacent scanned ratios {lo:.4} and {hi:.4}"),
                ),
                "",
            );
        };
        if let (Some(&lo), Some(&hi)) = (one_one.first(), one_one.last()) {
            between("a scan (1,1) from d0/A_free", lo.saturating_sub(1), lo);
            between("a scan (1,1) up to d0/A_free", hi, (hi + 1).min(rhos.len() - 1));
        }
        k.integer(
            "a scan points with one orbit from rest and a random start",
            d.scan.iter().filter(|s| s.rest.kind == s.random.kind).count() as i64,
        );
        k.integer("a scan points", d.scan.len() as i64);
        branch_keys(&mut k, d);
        k
    }

    fn verdict(d: &Fig6Data) -> Verdict {
        let paper_a = |c: &&Case| c.panel == "a";
        let within = |c: &Case| {
            c.coefficient
                .and_then(|r| r.value())
                .is_some_and(|r| (r - c.paper_r_e).abs() <= 0.0005 + c.uncertainty.unwrap_or(0.0))
        };
        let a_any = d
            .cases
            .iter()
            .filter(paper_a)
            .any(|c| c.kind == OrbitKind::Periodic { m: 1, n: 1 } && within(c));
        let scan_reaches = d.scan.iter().any(|s| {
            s.rest.value().is_some_and(|r| (r - 0.036).abs() <= 0.0005)
        });
        let b = d.cases.iter().find(|c| c.panel == "b");
        let b_taps = b.is_some_and(|c| c.contacts.len() >= 2);
        let b_value = b.is_some_and(|c| {
            c.coefficient
                .and_then(|r| r.value())
                .is_some_and(|r| (r - c.paper_r_e).abs() <= 0.005 + c.uncertainty.unwrap_or(0.0))
        });
        let outcome = match (a_any || scan_reaches, b_taps && b_value) {
            (true, true) => Outcome::Reproduced,
            (false, false) if !b_taps => Outcome::NotReproduced,
            _ => Outcome::Partly,
        };
        let b_text = b.map_or("(b) not computed".to_string(), |c| {
            format!(
                "(b): {} with {} contacts per period, r_E = {} (paper 0.74)",
                c.kind,
                c.contacts.len(),
                r_text(&c.coefficient)
            )
        });
        let (lo, hi) = d
            .scan
            .iter()
            .filter_map(|s| s.rest.value())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| (a.min(r), b.max(r)));
        Verdict {
            outcome,
            evidence: format!(
                "(a): {} reading of the forcing gives the paper's (1,1) orbit with r_E = 0.036; over d₀/A_free from {:.2} to {:.2}, r_E lies in [{lo:.3}, {hi:.3}]; {b_text}",
                if a_any { "a" } else { "no" },
                d.scan.first().map_or(f64::NAN, |s| s.gap_over_free_amplitude),
                d.scan.last().map_or(f64::NAN, |s| s.gap_over_free_amplitude),
            ),
        }
    }

    fn render(d: &Fig6Data) -> Result<Rendered, crate::results::render::RenderError> {
        let mut r = Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?;
        r.extra_tables.push(("diagnostics", render::diagnostics_table(d)));
        r.extra_tables.push(("comparison", render::comparison_table(d)));
        Ok(r)
    }
}

/// The key numbers of the (1,1) branch in d₀: where it folds and grazes, and how small r_E
/// and the entry velocity become on it (stable part and whole branch).
fn branch_keys(k: &mut KeyNumbers, d: &Fig6Data) {
    let Some(b) = &d.gap_branch else {
        k.text("a (1,1) branch in d0", "none (no (1,1) orbit from rest in the scan)");
        return;
    };
    let at = |kind: &str| -> String {
        let xs: Vec<String> = b
            .bifurcations
            .iter()
            .filter(|f| f.kind == kind)
            .map(|f| format!("{:.3}", f.gap_over_free_amplitude))
            .collect();
        if xs.is_empty() {
            "none".into()
        } else {
            xs.join(", ")
        }
    };
    k.text("a (1,1) branch in d0 folds at d0/A_free", at("fold"));
    k.text("a (1,1) branch in d0 grazings at d0/A_free", at("grazing"));
    k.text("a (1,1) branch in d0 period doublings at d0/A_free", at("period doubling"));
    // the (1,1) part of the branch (past a grazing it gains contacts per period)
    let ones: Vec<&branch::GapPoint> = b.points.iter().filter(|q| q.contacts == 1).collect();
    let span = |pts: &[&branch::GapPoint]| -> String {
        let lo = pts.iter().map(|q| q.gap_over_free_amplitude).fold(f64::INFINITY, f64::min);
        let hi = pts.iter().map(|q| q.gap_over_free_amplitude).fold(f64::NEG_INFINITY, f64::max);
        if pts.is_empty() {
            "none".into()
        } else {
            format!("{lo:.3} to {hi:.3}")
        }
    };
    let stable: Vec<&branch::GapPoint> = ones.iter().copied().filter(|q| q.stable).collect();
    k.text("a (1,1) branch in d0 stable (1,1) orbits at d0/A_free", span(&stable));
    k.text("a (1,1) branch in d0 (1,1) orbits at d0/A_free", span(&ones));
    let r = ones.iter().filter_map(|q| q.r_e).fold(f64::INFINITY, f64::min);
    if r.is_finite() {
        k.text("a (1,1) branch in d0 smallest r_E of a (1,1) orbit", format!("{r:.3}"));
    }
    // the most nearly grazing (1,1) orbit: its entry velocity and r_E
    if let Some(g) = ones
        .iter()
        .filter(|q| q.smallest_entry_velocity.is_some())
        .min_by(|a, b| a.smallest_entry_velocity.partial_cmp(&b.smallest_entry_velocity).unwrap_or(std::cmp::Ordering::Equal))
    {
        k.text(
            "a (1,1) branch in d0 nearest grazing",
            format!(
                "entry velocity {:.1e} ωA_free at d₀/A_free = {:.4}, r_E = {}",
                g.smallest_entry_velocity.unwrap_or(f64::NAN),
                g.gap_over_free_amplitude,
                g.r_e.map_or("no real value".to_string(), |r| format!("{r:.4}"))
            ),
        );
    }
    k.text("a (1,1) branch in d0 ends", b.ends.join("; "));
}
