//! Scene `stiffness-matching`: the convergence side of the paper's title claim (§2.3,
//! §7) — "for fixed k, we have modal convergence as N → ∞", with the criterion
//! (β_N⁺)³ ≫ k — shown for the dynamics, and checked code-to-code against an independent
//! finite-element beam ([`crate::analysis::convergence`], [`crate::model::fe`]).
//!
//! For each k: the observables of [`crate::analysis::convergence`] on a ladder of Galerkin
//! truncations N and of element counts n; each limit by Richardson extrapolation of the
//! three finest with Roache's grid convergence index as its uncertainty; the two limits
//! compared; N*(tol), the modes needed for a relative accuracy tol on every observable.
//! Then the contrast with the rigid limit: the post-contact velocity profile against N at
//! finite k (converging) and under the stiffness-limit law \[R\]_N (not, Figure 3(d)).

pub mod losses;
pub mod periodic;
pub mod render;
pub mod render_two_basis;

use crate::model::continuum;
use crate::analysis::convergence::{self, Discretisation, Needed, Observables, Setup, Study};
use crate::error::Error;
use crate::base::report::{KeyNumbers, Uncertainty};
use crate::model::restitution::stiffness_limit;
use crate::results::scene::{Outcome, Progress, Rendered, Resolution, Scene, Verdict, Group};
use crate::base::verification::fitted_slope_with_error;
use rayon::prelude::*;
use serde::Serialize;

/// What the scene computes.
#[derive(Debug, Clone, Serialize, serde::Deserialize)]
pub struct MatchingParams {
    /// k/k₁ values.
    pub k_over_k1: Vec<f64>,
    /// ζ₁.
    pub zeta1: f64,
    /// ω/(β₁⁻)² of the forced runs: the first is Figure 4's, the second another.
    pub omegas: [f64; 2],
    /// Forcing periods of the forced runs.
    pub periods: u64,
    /// Galerkin truncations N (with the largest, its half and its quarter).
    pub modes: Vec<usize>,
    /// Element counts (with the largest, its half and its quarter).
    pub elements: Vec<usize>,
    /// Two-basis truncations N (with the largest, its half and its quarter).
    pub two_basis_modes: Vec<usize>,
    /// Truncations N of the per-switch loss measurements.
    pub loss_modes: Vec<usize>,
    /// Truncations N (Galerkin and two-basis) of the periodic-orbit study.
    pub orbit_modes: Vec<usize>,
    /// Element counts of the periodic-orbit study.
    pub orbit_elements: Vec<usize>,
    /// Relative tolerances for N*.
    pub tolerances: Vec<f64>,
    /// k/k₁ of the velocity-profile contrast.
    pub profile_k: f64,
    /// Truncations of the contrast.
    pub profile_modes: Vec<usize>,
}

impl MatchingParams {
    /// The book's resolution.
    pub fn book() -> Self {
        Self {
            k_over_k1: vec![10.0, 100.0, 1000.0, 1e4],
            zeta1: 0.01,
            omegas: [2.0, 1.7],
            periods: 10,
            modes: vec![1, 2, 3, 4, 5, 6, 8, 10, 12, 16, 20, 25, 32, 40, 50, 64, 80, 100, 128, 160, 200],
            elements: vec![2, 4, 8, 16, 32, 64],
            two_basis_modes: vec![1, 2, 3, 4, 5, 6, 8, 10, 12, 16, 20, 25, 32, 40, 50, 64, 80, 100, 128, 160, 200],
            loss_modes: vec![1, 2, 4, 8, 16, 32, 64, 128],
            orbit_modes: vec![4, 8, 16, 32, 64, 128],
            orbit_elements: vec![4, 8, 16, 32],
            tolerances: vec![1e-2, 1e-3, 1e-6],
            profile_k: 1000.0,
            profile_modes: vec![5, 10, 20, 40, 80],
        }
    }

    /// Reduced for the tests: three stiffnesses, N ≤ 40, n ≤ 32.
    pub fn test() -> Self {
        Self {
            k_over_k1: vec![10.0, 100.0, 1000.0],
            modes: vec![1, 2, 3, 4, 5, 6, 8, 10, 16, 20, 32, 40],
            elements: vec![2, 4, 8, 16, 32],
            two_basis_modes: vec![1, 2, 3, 4, 5, 6, 8, 10, 16, 20, 32, 40],
            loss_modes: vec![1, 2, 4, 8, 16, 32],
            orbit_modes: vec![4, 8, 16, 32],
            orbit_elements: vec![4, 8, 16],
            profile_modes: vec![5, 10, 20],
            ..Self::book()
        }
    }
}

/// One observable at one k: both refinement studies and whether their limits agree.
#[derive(Debug, Clone, Serialize)]
pub struct Compared {
    /// Its name.
    pub name: String,
    /// Against N.
    pub galerkin: Study,
    /// Against the element count.
    pub elements: Study,
    /// |limit difference| ≤ the sum of the two uncertainties.
    pub agree: bool,
    /// Against N for the two-basis truncation.
    pub two_basis: Study,
    /// Its limit agrees with the Galerkin limit within the sum of the two uncertainties.
    pub two_basis_agree: bool,
}

/// The study at one k.
#[derive(Debug, Clone, Serialize)]
pub struct AtStiffness {
    /// k/k₁.
    pub k_over_k1: f64,
    /// Each observable.
    pub observables: Vec<Compared>,
    /// Per tolerance: N* over all observables, and the observable that sets it.
    pub needed: Vec<(f64, Needed, String)>,
    /// The smallest N with (β_N⁻)³ ≥ k.
    pub criterion: usize,
}

/// A velocity profile after the contact.
#[derive(Debug, Clone, Serialize)]
pub struct Profile {
    /// N, the number of modes.
    pub modes: usize,
    /// w_t(s) at finite k.
    pub compliant: Vec<f64>,
    /// w_t(s) under \[R\]_N (r_e = 1).
    pub rigid: Vec<f64>,
    /// L² change of the compliant profile from the previous N (none for the first).
    pub compliant_change: Option<f64>,
    /// … of the rigid one.
    pub rigid_change: Option<f64>,
}

/// The scene's result.
#[derive(Debug, Clone, Serialize)]
pub struct MatchingData {
    /// The parameters used.
    pub params: MatchingParams,
    /// One study per k.
    pub stiffness: Vec<AtStiffness>,
    /// Sample points s of the profiles.
    pub s: Vec<f64>,
    /// The contrast.
    pub profiles: Vec<Profile>,
    /// The element beam's eigenvalues against the continuum (eq 3): per element count of
    /// `params.elements`, the largest relative error of modes 1–3, free and with the stop
    /// held on at k = `profile_k`·k₁.
    pub eigen_errors: Vec<(usize, f64, f64)>,
    /// Observed orders of those errors in the element size (fit over the four finest),
    /// each with the standard error of its fit.
    pub eigen_orders: ((f64, f64), (f64, f64)),
    /// The two-basis truncation's losses per switch.
    pub losses: Vec<losses::Losses>,
    /// Their order in N.
    pub loss_orders: Vec<losses::LossOrder>,
    /// The periodic orbits of the forced runs, where they settle.
    pub orbits: Vec<periodic::OrbitsAt>,
}

/// All observables of one discretisation: the five of [`Observables`] at ω₁, then the
/// forced tip displacement and velocity at ω₂.
fn run(d: Discretisation, k: f64, p: &MatchingParams) -> Result<Vec<f64>, Error> {
    let setup = |omega| Setup {
        k_over_k1: k,
        zeta1: p.zeta1,
        omega_over_w1: omega,
        periods: p.periods,
    };
    let o: Observables = convergence::observe(d, &setup(p.omegas[0]))?;
    let (tip, vel) = convergence::observe_forced(d, &setup(p.omegas[1]))?;
    Ok(o.named().iter().map(|(_, v)| *v).chain([tip, vel]).collect())
}

/// The natural scale of each observable of [`run`] (`None`: its own magnitude).
fn scales(k: f64, p: &MatchingParams) -> Result<Vec<Option<f64>>, Error> {
    let setup = |omega| Setup { k_over_k1: k, zeta1: p.zeta1, omega_over_w1: omega, periods: p.periods };
    let (a1, v1) = convergence::free_amplitude(&setup(p.omegas[0]))?;
    let (a2, v2) = convergence::free_amplitude(&setup(p.omegas[1]))?;
    Ok(vec![None, Some(1.0), Some(0.5), Some(a1), Some(v1), Some(a2), Some(v2)])
}

fn names(p: &MatchingParams) -> Vec<String> {
    let base = Observables {
        contact_duration: 0.0,
        exit_tip_velocity: 0.0,
        exit_mode1_velocity: 0.0,
        forced_tip: 0.0,
        forced_tip_velocity: 0.0,
    };
    let (w1, w2) = (p.omegas[0], p.omegas[1]);
    base.named()
        .iter()
        .enumerate()
        .map(|(i, (n, _))| if i >= 3 { format!("{n}, ω = {w1}") } else { n.to_string() })
        .chain([format!("forced tip displacement, ω = {w2}"), format!("forced tip velocity, ω = {w2}")])
        .collect()
}

/// Runs the scene.
///
/// # Errors
/// A discretisation or model out of range (`Error::Parameter`), a flow or eigenproblem that
/// cannot be built or solved, a run that fails, or `Error::Unsupported` for a size ladder
/// without its finest n, n/2 and n/4.
pub fn compute(p: &MatchingParams, progress: &dyn Progress) -> Result<MatchingData, Error> {
    let mut jobs = Vec::new();
    for (ki, &k) in p.k_over_k1.iter().enumerate() {
        jobs.extend(p.modes.iter().map(|&n| (ki, k, Discretisation::Galerkin(n))));
        jobs.extend(p.elements.iter().map(|&n| (ki, k, Discretisation::Elements(n))));
        jobs.extend(p.two_basis_modes.iter().map(|&n| (ki, k, Discretisation::TwoBasis(n))));
    }
    // the most expensive first, so the two cores finish together
    jobs.sort_by_key(|j| std::cmp::Reverse(j.2.size() * if matches!(j.2, Discretisation::Elements(_)) { 2 } else { 1 }));
    let task = progress.task("stiffness-matching refinements", jobs.len() as u64);
    let results: Vec<_> = jobs
        .par_iter()
        .map(|&(ki, k, d)| {
            let r = run(d, k, p);
            task.advance(1);
            r.map(|v| (ki, d, v))
        })
        .collect::<Result<_, Error>>()?;
    drop(task);
    let names = names(p);
    let mut stiffness = Vec::new();
    for (ki, &k) in p.k_over_k1.iter().enumerate() {
        let scales = scales(k, p)?;
        let series = |kind: fn(usize) -> Discretisation, sizes: &[usize], o: usize| -> Result<Study, Error> {
            let values = sizes
                .iter()
                .map(|&n| {
                    let want = kind(n);
                    results.iter().find(|r| r.0 == ki && r.1 == want).map(|r| r.2[o]).unwrap_or(f64::NAN)
                })
                .collect::<Vec<f64>>();
            // the contact duration is its own scale
            let scale = scales[o].unwrap_or_else(|| values.last().map_or(1.0, |v| v.abs()));
            Study::new(sizes.to_vec(), values, scale)
        };
        let mut observables = Vec::new();
        for (o, name) in names.iter().enumerate() {
            let galerkin = series(Discretisation::Galerkin, &p.modes, o)?;
            let elements = series(Discretisation::Elements, &p.elements, o)?;
            let two_basis = series(Discretisation::TwoBasis, &p.two_basis_modes, o)?;
            let within = |a: &Study, b: &Study| (a.limit - b.limit).abs() <= a.uncertainty + b.uncertainty;
            let (agree, two_basis_agree) = (within(&galerkin, &elements), within(&galerkin, &two_basis));
            observables.push(Compared { name: name.clone(), galerkin, elements, agree, two_basis, two_basis_agree });
        }
        let needed = p
            .tolerances
            .iter()
            .map(|&tol| {
                let all = observables.iter().map(|c| (c.name.as_str(), &c.galerkin));
                let (n, by) = Needed::hardest(all, tol);
                (tol, n, by)
            })
            .collect();
        let k_abs = k * crate::model::galerkin::first_modal_stiffness();
        stiffness.push(AtStiffness {
            k_over_k1: k,
            observables,
            needed,
            criterion: convergence::criterion_modes(k_abs, 1.0)?,
        });
    }
    let (s, profiles) = contrast(p)?;
    let eigen_errors = p
        .elements
        .iter()
        .filter(|&&n| n >= 2)
        .map(|&n| eigen_error(n, p.profile_k))
        .collect::<Result<Vec<_>, Error>>()?;
    let fit = |which: usize| {
        let pts: Vec<(f64, f64)> = eigen_errors.iter().rev().take(4).map(|e| (1.0 / e.0 as f64, if which == 0 { e.1 } else { e.2 })).collect();
        let (h, e): (Vec<f64>, Vec<f64>) = pts.into_iter().map(|(h, e)| (h.ln(), e.ln())).unzip();
        fitted_slope_with_error(&h, &e)
    };
    let eigen_orders = (fit(0), fit(1));
    let (losses, loss_orders) = losses::compute(p)?;
    let orbits = periodic::compute(p)?;
    Ok(MatchingData { params: p.clone(), stiffness, s, profiles, eigen_errors, eigen_orders, losses, loss_orders, orbits })
}

/// The largest relative eigenvalue error of modes 1–3 with n elements: free, and with the
/// stop k·k₁ held on, against the continuum roots of eq (3).
fn eigen_error(n: usize, k_over_k1: f64) -> Result<(usize, f64, f64), Error> {
    let beam = crate::model::fe::FeBeam::new(n)?;
    let k = k_over_k1 * crate::model::galerkin::first_modal_stiffness();
    let held = beam.contact_eigenvalues(k).ok_or_else(|| Error::Unsupported("element eigenproblem".into()))?;
    let (mut free, mut contact) = (0.0_f64, 0.0_f64);
    for i in 1..=3.min(2 * n) {
        let (f, c) = (continuum::free_root(i)?.powi(4), continuum::root(i, k)?.powi(4));
        free = free.max((beam.eigenvalues()[i - 1] - f).abs() / f);
        contact = contact.max((held[i - 1] - c).abs() / c);
    }
    Ok((n, free, contact))
}

/// The velocity profiles after one contact at finite k and under \[R\]_N, per unit entry
/// tip velocity (pre-impact profile φ₁/2).
fn contrast(p: &MatchingParams) -> Result<(Vec<f64>, Vec<Profile>), Error> {
    let s: Vec<f64> = (0..=100).map(|i| i as f64 / 100.0).collect();
    let setup = Setup { k_over_k1: p.profile_k, zeta1: p.zeta1, omega_over_w1: p.omegas[0], periods: p.periods };
    let nmax = p.profile_modes.iter().copied().max().unwrap_or(1);
    let modes: Vec<_> = (1..=nmax).map(continuum::free_mode).collect::<Result<_, _>>()?;
    let profile = |v: &[f64]| -> Vec<f64> {
        s.iter().map(|&x| v.iter().zip(&modes).map(|(c, m)| c * m.value(x)).sum()).collect()
    };
    let change = |a: &[f64], b: &[f64]| -> f64 {
        let n = a.len().max(b.len());
        let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(0.0);
        (0..n).map(|i| (at(a, i) - at(b, i)).powi(2)).sum::<f64>().sqrt()
    };
    let computed: Vec<(usize, Vec<f64>, Vec<f64>)> = p
        .profile_modes
        .par_iter()
        .map(|&n| -> Result<_, Error> {
            let compliant = convergence::post_contact_velocities(n, &setup)?;
            let r = stiffness_limit(n, 1.0)?;
            let rigid: Vec<f64> = (0..n).map(|j| -0.5 * r[(j, 0)]).collect();
            Ok((n, compliant, rigid))
        })
        .collect::<Result<_, Error>>()?;
    let mut out: Vec<Profile> = Vec::new();
    for (i, (n, c, r)) in computed.iter().enumerate() {
        let prev = i.checked_sub(1).map(|j| &computed[j]);
        out.push(Profile {
            modes: *n,
            compliant: profile(c),
            rigid: profile(r),
            compliant_change: prev.map(|q| change(c, &q.1)),
            rigid_change: prev.map(|q| change(r, &q.2)),
        });
    }
    Ok((s, out))
}

/// The scene.
pub struct StiffnessMatching;

impl Scene for StiffnessMatching {
    const NAME: &'static str = "stiffness-matching";
    const PAPER: &'static str = "§2.3 and §7";
    const TITLE: &'static str = "Stiffness matching (§2.3)";
    const GIST: &'static str = "fixed k: converges as N → ∞";
    const GROUP: Group = Group::Paper;
    const SUMMARY: &'static str = "convergence in N at fixed k of one contact and of a forced run, against an independent finite-element beam; modes needed N*(k)";
    const CLAIM: &'static str = "\"For fixed k, we have modal convergence as N → ∞\", provided (β_N⁺)³ ≫ k (§2.3).";
    const CHAPTER: &'static str = "stiffness-matching.md";
    const METHOD: &'static str = "exact simulation of the N-mode Galerkin model and of a Hermite-cubic finite-element beam (all its modes) through one contact and over 10 forced periods; limits by Richardson extrapolation of the three finest resolutions, uncertainty by the grid convergence index (Roache, safety factor 1.25)";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        ("observables where the two limits agree", "limits that agree"),
        ("modes for 1 % at 10⁴k₁ (scanned)", "k=1e4 N* for 1e-2"),
    ];
    const SETTABLE: &'static [crate::results::settings::Setting] = &[crate::results::settings::ZETA1];
    type Params = MatchingParams;
    type Data = MatchingData;

    fn params(resolution: Resolution) -> MatchingParams {
        match resolution {
            Resolution::Book => MatchingParams::book(),
            Resolution::Test => MatchingParams::test(),
        }
    }

    fn compute(p: &MatchingParams, progress: &dyn Progress) -> Result<MatchingData, Error> {
        compute(p, progress)
    }

    fn key_numbers(d: &MatchingData) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        let total: usize = d.stiffness.iter().map(|a| a.observables.len()).sum();
        let agree: usize = d.stiffness.iter().map(|a| a.observables.iter().filter(|c| c.agree).count()).sum();
        k.text("limits that agree", format!("{agree} of {total}"));
        let tb = d.stiffness.iter().map(|a| a.observables.iter().filter(|c| c.two_basis_agree).count()).sum::<usize>();
        k.text("two-basis limits that agree", format!("{tb} of {total}"));
        for o in &d.loss_orders {
            let basis = "standard error of the least-squares slope of log(energy lost) against log N over the four finest N with losses above 1e-13";
            k.cited(format!("k={:e} two-basis loss order", o.k_over_k1), o.entry_energy.0, 2, Uncertainty::new(o.entry_energy.1, basis), "");
        }
        for l in d.losses.iter().filter(|l| l.modes == 16 || l.modes == 4) {
            k.text(
                format!("k={:e} N={} two-basis energy lost per switch", l.k_over_k1, l.modes),
                format!("{:.1e} entering (one contact), {:.1e} mean over {} switches (forced)", l.entry_energy, l.forced_mean_energy, l.forced_switches),
            );
        }
        let periodic: Vec<_> = d.orbits.iter().filter(|o| o.impact_velocity.is_some() && o.max_tip.is_some()).collect();
        let agreeing = periodic.iter().filter(|o| o.impact_velocity.as_ref().is_some_and(|s| s.agree) && o.max_tip.as_ref().is_some_and(|s| s.agree)).count();
        k.text("periodic orbits that agree", format!("{agreeing} of {}", periodic.len()));
        for o in &d.orbits {
            let label = o.label.map_or("label changes with resolution".to_string(), |l| l.to_string());
            k.text(format!("orbit at k={:e}, omega={}", o.k_over_k1, o.omega_over_w1), label);
        }
        for a in &d.stiffness {
            let key = format!("k={:e}", a.k_over_k1);
            for c in a.observables.iter().filter(|c| c.name == "exit tip velocity") {
                let (g, e) = (&c.galerkin, &c.elements);
                let basis = "grid convergence index of the Richardson extrapolation";
                k.cited(format!("{key} exit tip velocity (Galerkin limit)"), g.limit, 8, Uncertainty::new(g.uncertainty, basis), "× the entry velocity");
                k.cited(format!("{key} exit tip velocity (element limit)"), e.limit, 8, Uncertainty::new(e.uncertainty, basis), "× the entry velocity");
                for (what, st) in [("Galerkin", g), ("element", e)] {
                    if let (Some(p), Some(dp)) = (st.order, st.order_change) {
                        let basis = "change from the order observed one refinement coarser";
                        k.cited(format!("{key} {what} order"), p, 2, Uncertainty::new(dp, basis), "");
                    }
                }
            }
            for (tol, n, by) in &a.needed {
                k.text(format!("{key} N* for {tol:e}"), format!("{n} ({by})"));
            }
            k.integer(format!("{key} criterion N (beta_N^3 = k)"), a.criterion as i64);
        }
        let along: Vec<String> = d
            .stiffness
            .iter()
            .filter_map(|a| {
                let (_, n, _) = a.needed.iter().find(|(tol, _, _)| *tol == 1e-2)?;
                Some(format!("{n} at {}k₁", crate::base::report::pretty(a.k_over_k1, 2)))
            })
            .collect();
        k.text("N* for 1e-2 along k", along.join(", "));
        let basis = "standard error of the least-squares slope over the four finest element counts";
        let (free, held) = d.eigen_orders;
        k.cited("element eigenvalue order (free, modes 1-3)", free.0, 2, Uncertainty::new(free.1, basis), "");
        k.cited("element eigenvalue order (stop held on, modes 1-3)", held.0, 2, Uncertainty::new(held.1, basis), "");
        for pr in &d.profiles {
            if let (Some(c), Some(r)) = (pr.compliant_change, pr.rigid_change) {
                k.text(
                    format!("profile change at N={}", pr.modes),
                    format!("finite k {c:.1e}, rigid limit {r:.2}"),
                );
            }
        }
        if let [.., a, b] = d.profiles.as_slice() {
            if let (Some(c), Some(r)) = (b.compliant_change, b.rigid_change) {
                k.text(
                    "profile change between the last two N",
                    format!("{c:.1e} at finite k and {r:.2} in the rigid limit (N = {} to {}, L² norm)", a.modes, b.modes),
                );
            }
        }
        k
    }

    fn verdict(d: &MatchingData) -> Verdict {
        let total: usize = d.stiffness.iter().map(|a| a.observables.len()).sum();
        let agree: usize = d.stiffness.iter().map(|a| a.observables.iter().filter(|c| c.agree).count()).sum();
        let converging = d.profiles.last().and_then(|p| p.compliant_change).unwrap_or(f64::NAN);
        let rigid = d.profiles.last().and_then(|p| p.rigid_change).unwrap_or(f64::NAN);
        let orders: Vec<f64> = d
            .stiffness
            .iter()
            .flat_map(|a| a.observables.iter().filter_map(|c| c.galerkin.order))
            .collect();
        let (lo, hi) = orders.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &p| (a.min(p), b.max(p)));
        let tb = d.stiffness.iter().map(|a| a.observables.iter().filter(|c| c.two_basis_agree).count()).sum::<usize>();
        let slopes: Vec<f64> = d.loss_orders.iter().map(|o| o.entry_energy.0).collect();
        let (slo, shi) = slopes.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &p| (a.min(p), b.max(p)));
        // "3.0" rather than "3.0 to 3.0" where the range is one value at the printed digits
        let orders_text = {
            let (a, b) = (format!("{lo:.1}"), format!("{hi:.1}"));
            if a == b {
                format!("observed order {a}")
            } else {
                format!("observed orders {a} to {b}")
            }
        };
        let losses_text = if format!("{slo:.1}") == format!("{shi:.1}") {
            format!("$N^{{{slo:.1}}}$")
        } else {
            format!("$N^{{{slo:.1}}}$ to $N^{{{shi:.1}}}$")
        };
        Verdict {
            outcome: if agree == total && tb == total && converging < rigid { Outcome::Reproduced } else { Outcome::Partly },
            evidence: format!(
                "at every k the Galerkin model converges in N ({orders_text}, as the k/β_N³ tail predicts) and its limit agrees with the finite-element beam's in {agree} of {total} observables; the modes needed for 1 % (found in the scan) are {needed}; after one contact the velocity profile changes in L² by {converging:.1e} between the last two N at finite k (converging to the continuum's profile, tip included) and by {rigid:.2} under the rigid law (converging in L² only, to the pre-impact profile, like 2/√N, and not at the tip); the two-basis truncation converges to the same limits ({tb} of {total} agree), losing an energy fraction per switch into contact that falls like {losses_text}",
                needed = d
                    .stiffness
                    .iter()
                    .filter_map(|a| {
                        a.needed
                            .iter()
                            .find(|(tol, _, _)| *tol == 1e-2)
                            .map(|(_, n, _)| format!("{n} at {}k₁", crate::base::report::pretty(a.k_over_k1, 2)))
                    })
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        }
    }

    fn render(d: &MatchingData) -> Result<Rendered, crate::results::render::RenderError> {
        let mut r = Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?;
        r.extra_tables.push(("needed", render::needed_table(d)));
        r.extra_tables.push(("two-basis", render_two_basis::table(d)));
        r.extra_tables.push(("losses", render_two_basis::losses_table(d, false)));
        r.extra_tables.push(("losses-forced", render_two_basis::losses_table(d, true)));
        r.extra_tables.push(("orbits", render_two_basis::orbits_table(d)));
        Ok(r)
    }
}
