//! Continuation of periodic orbits in k at Figure 4's parameters: each bifurcation the
//! continuation reports is checked independently — grazings against brute-force
//! transients on either side, period doublings against the multipliers and a settled
//! period-2 orbit, Neimark–Sacker against the multipliers and an unsettled transient,
//! folds against two coexisting orbits found by shooting.

use impacting_cantilever::analysis::continuation::{
    self, BifurcationKind, Branch, Family, Parameter, Settings,
};
use impacting_cantilever::analysis::orbit::{settle, OrbitKind};
use impacting_cantilever::model::problems;
use nalgebra::DVector;

fn family(n: usize) -> Family<'static> {
    Family::forced(problems::figure4(n), Parameter::StopStiffness)
}

/// The Figure 4 orbit (k = 100k₁ from rest, 1000 periods), continued towards `to`.
fn from_figure4(n: usize, to: f64, max_step: f64) -> Branch {
    let fam = family(n);
    let x = fam
        .simulator(100.0)
        .unwrap()
        .run(&DVector::zeros(2 * n), 1000, &mut ())
        .unwrap()
        .state;
    let s = Settings {
        max_step,
        ..Settings::new((to.min(100.0), to.max(100.0)))
    };
    continuation::continue_branch(&fam, &x, 100.0, 1, (to - 100.0).signum(), &s).unwrap()
}

fn kind_from_rest(n: usize, k: f64) -> OrbitKind {
    let sim = family(n).simulator(k).unwrap();
    settle(&sim, &DVector::zeros(2 * n), 1000, 40, 0)
        .unwrap()
        .kind
}

#[test]
fn n3_gains_its_second_and_third_contacts_at_grazings() {
    let b = from_figure4(3, 300.0, 0.02);
    assert!(b.end.contains("left the parameter range"), "{}", b.end);
    // every point is a converged, stable orbit
    assert!(b.points.iter().all(|p| p.residual <= 1e-12 && p.stable));
    let grazings: Vec<_> = b
        .bifurcations
        .iter()
        .filter(|f| f.kind == BifurcationKind::Grazing)
        .collect();
    assert_eq!(grazings.len(), 2, "{:?}", b.bifurcations);
    assert_eq!(grazings[0].impacts, (1, 2));
    assert_eq!(grazings[1].impacts, (2, 3));
    // no fold, period doubling or Neimark–Sacker on the way: the (1,3) orbit is the
    // Figure 4 (1,1) orbit after two grazings
    assert_eq!(b.bifurcations.len(), 2);
    // the brute-force transient agrees on either side of each grazing: its bracket,
    // bisected from the continuation's step (2.5 %), is at most 2e-7 wide in k, and the
    // transient is checked 1e-4 outside it
    for (g, before, after) in [(grazings[0], 1, 2), (grazings[1], 2, 3)] {
        let (lo, hi) = g.between;
        assert!(
            hi / lo < 1.0 + 2e-7 && (lo..=hi).contains(&g.parameter),
            "{g:?}"
        );
        assert_eq!(
            kind_from_rest(3, lo * (1.0 - 1e-4)),
            OrbitKind::Periodic { m: 1, n: before }
        );
        assert_eq!(
            kind_from_rest(3, hi * (1.0 + 1e-4)),
            OrbitKind::Periodic { m: 1, n: after }
        );
    }
    // the grazing distance tends to 0 at the located grazing (linear in k on each side)
    let near = b
        .points
        .iter()
        .filter(|p| (p.parameter / grazings[0].parameter).ln().abs() < 0.03)
        .map(|p| p.shape.grazing_distance.unwrap())
        .fold(f64::INFINITY, f64::min);
    let far = b.points[0].shape.grazing_distance.unwrap();
    assert!(near < 0.1 * far, "{near} vs {far}");
}

#[test]
fn n2_period_doubles_below_k2_and_the_doubled_branch_is_the_attractor() {
    let fam = family(2);
    let x = fam
        .simulator(20.0)
        .unwrap()
        .run(&DVector::zeros(4), 1000, &mut ())
        .unwrap()
        .state;
    let s = Settings {
        max_period: 2,
        ..Settings::new((20.0, 40.0))
    };
    let branches = continuation::trace(&fam, &x, 20.0, 1, &s).unwrap();
    let pds: Vec<_> = branches[0]
        .bifurcations
        .iter()
        .filter(|f| f.kind == BifurcationKind::PeriodDoubling)
        .collect();
    assert_eq!(pds.len(), 2, "{:?}", branches[0].bifurcations);
    // the crossing multiplier is real and passes −1
    for f in &pds {
        let (a, b) = (
            &branches[0].points[f.index],
            &branches[0].points[f.index + 1],
        );
        let lead = |p: &continuation::BranchPoint| p.multipliers[0];
        assert!(lead(a)[1] == 0.0 && lead(b)[1] == 0.0);
        assert!((lead(a)[0] + 1.0) * (lead(b)[0] + 1.0) < 0.0);
    }
    // between them the period-1 orbit is unstable, and a transient settles to period 2
    let mid = (pds[0].parameter * pds[1].parameter).sqrt();
    assert_eq!(kind_from_rest(2, mid), OrbitKind::Periodic { m: 2, n: 2 });
    // the doubled branch was found and is stable there
    let doubled: Vec<_> = branches.iter().filter(|b| b.period_m == 2).collect();
    assert!(!doubled.is_empty());
    assert!(doubled.iter().any(|b| b
        .points
        .iter()
        .any(|p| p.stable && (p.parameter / mid).ln().abs() < 0.02)));
}

#[test]
fn n3_loses_stability_in_a_neimark_sacker_pair() {
    let b = from_figure4(3, 5.0, 0.02);
    let ns: Vec<_> = b
        .bifurcations
        .iter()
        .filter(|f| f.kind == BifurcationKind::NeimarkSacker)
        .collect();
    assert_eq!(ns.len(), 2, "{:?}", b.bifurcations);
    let mid = (ns[0].parameter * ns[1].parameter).sqrt();
    let p = b
        .points
        .iter()
        .min_by(|a, c| {
            (a.parameter / mid)
                .ln()
                .abs()
                .total_cmp(&(c.parameter / mid).ln().abs())
        })
        .unwrap();
    // a complex pair outside the unit circle
    assert!(!p.stable && p.multipliers[0][1] != 0.0);
    assert!((p.multipliers[0][1] + p.multipliers[1][1]).abs() < 1e-12);
    // the transient from near the unstable orbit does not settle on a period-1 orbit
    let sim = family(3).simulator(p.parameter).unwrap();
    let x = DVector::from_vec(p.state.clone()) * 1.001;
    assert_ne!(
        settle(&sim, &x, 1000, 40, 0).unwrap().kind,
        OrbitKind::Periodic { m: 1, n: 1 }
    );
}

#[test]
fn a_fold_joins_two_coexisting_orbits() {
    // N = 1's period-3 orbit near k = 2.9k₁ (a start of the Figure 5 diagram) lies on a
    // closed branch with two folds
    let fam = family(1);
    let sim = fam.simulator(2.9).unwrap();
    let mut found = None;
    for s in 0..64u64 {
        let mut rng = impacting_cantilever::analysis::orbit::SplitMix64::for_point(7, 1, 0, s);
        let (amp, _) = sim.model().free_tip_amplitude();
        let x0 = impacting_cantilever::analysis::orbit::random_state(
            &mut rng,
            1,
            4.0 * amp,
            sim.omega(),
        );
        let o = settle(&sim, &x0, 1000, 40, 0).unwrap();
        if let OrbitKind::Periodic { m: 3, .. } = o.kind {
            found = Some(o.state);
            break;
        }
    }
    let x = found.expect("a period-3 attractor at 2.9k₁");
    let b =
        continuation::continue_branch(&fam, &x, 2.9, 3, 1.0, &Settings::new((1.0, 10.0))).unwrap();
    let folds: Vec<_> = b
        .bifurcations
        .iter()
        .filter(|f| f.kind == BifurcationKind::Fold)
        .collect();
    assert!(folds.len() >= 2, "{:?}", b.bifurcations);
    // on the inner side of a fold the branch has two orbits at the same k: shoot each
    // from its branch point's state at a common k and find two distinct orbits
    let f = folds[0];
    let k = if b.points[f.index].tangent_u > 0.0 {
        f.between.0.min(f.between.1) / 1.01
    } else {
        f.between.0.max(f.between.1) * 1.01
    };
    let sim = fam.simulator(k).unwrap();
    let side = |i: usize| {
        let q = &b.points[i];
        impacting_cantilever::analysis::shooting::shoot(
            &sim,
            &DVector::from_vec(q.state.clone()),
            3,
        )
        .unwrap()
    };
    let (lo, hi) = (
        f.index.saturating_sub(2),
        (f.index + 3).min(b.points.len() - 1),
    );
    let (a, c) = (side(lo), side(hi));
    let (xa, xc) = (DVector::from_vec(a.state), DVector::from_vec(c.state));
    assert!(
        (&xa - &xc).amax() > 1e-4 * xa.amax(),
        "the two sides of the fold converge to one orbit"
    );
}

#[test]
fn continuation_in_omega_finds_a_grazing_and_a_neimark_sacker_pair() {
    // N = 3's Figure 4 orbit (k = 100k₁, ω = 2(β₁⁻)²) continued up in ω to 2.2
    let fam = Family::forced(problems::figure4(3), Parameter::Frequency);
    let x = fam
        .simulator(2.0)
        .unwrap()
        .run(&DVector::zeros(6), 1000, &mut ())
        .unwrap()
        .state;
    let b =
        continuation::continue_branch(&fam, &x, 2.0, 1, 1.0, &Settings::new((2.0, 2.2))).unwrap();
    assert!(b.points.iter().all(|p| p.residual <= 1e-12));
    let of =
        |k: BifurcationKind| -> Vec<_> { b.bifurcations.iter().filter(|f| f.kind == k).collect() };
    let (grazing, ns) = (
        of(BifurcationKind::Grazing),
        of(BifurcationKind::NeimarkSacker),
    );
    assert_eq!(grazing.len(), 1, "{:?}", b.bifurcations);
    assert_eq!(grazing[0].impacts, (1, 2));
    assert_eq!(ns.len(), 1, "{:?}", b.bifurcations);
    assert!(grazing[0].parameter < ns[0].parameter);
    // brute force from rest on either side of the grazing (bracket ≤ 1% wide in ω,
    // transients 1% outside it) and between it and the Neimark–Sacker point
    let from_rest = |w: f64| {
        settle(&fam.simulator(w).unwrap(), &DVector::zeros(6), 1000, 40, 0)
            .unwrap()
            .kind
    };
    let (lo, hi) = grazing[0].between;
    assert!(hi / lo < 1.01 && (lo..=hi).contains(&grazing[0].parameter));
    assert_eq!(from_rest(lo / 1.01), OrbitKind::Periodic { m: 1, n: 1 });
    assert_eq!(from_rest(hi * 1.01), OrbitKind::Periodic { m: 1, n: 2 });
    // past the Neimark–Sacker point: a complex pair outside the unit circle, and a
    // transient started near the orbit that does not settle on it
    let p = b.points.last().unwrap();
    assert!(p.parameter > ns[0].between.1 && !p.stable);
    assert!(p.multipliers[0][1] != 0.0 && p.spectral_radius() > 1.0);
    let sim = fam.simulator(p.parameter).unwrap();
    let near = DVector::from_vec(p.state.clone()) * 1.001;
    assert_ne!(
        settle(&sim, &near, 1000, 40, 0).unwrap().kind,
        OrbitKind::Periodic { m: 1, n: 2 }
    );
}

/// A branch that runs into the end of the model's supported range (|d₀| ≤ 1e6) says so,
/// not that its corrector failed (the fourth adversarial round's item 7).
#[test]
fn a_branch_ending_at_the_supported_range_says_so() {
    use impacting_cantilever::analysis::continuation::{continue_from, ContinueOptions};
    use impacting_cantilever::analysis::find_orbit::OrbitOptions;
    use impacting_cantilever::base::progress::Silent;
    use impacting_cantilever::model::spec::{ModelSpec, Start};
    let spec = ModelSpec::from(problems::Forced {
        gap: 1e5,
        ..problems::figure4(2)
    });
    let options = ContinueOptions {
        parameter: Parameter::Gap,
        to: 1e4,
        one_way: false,
        max_step: 0.2,
        doubling_up_to: 1,
    };
    let c = continue_from(
        &spec,
        &Start::Rest,
        &OrbitOptions::default(),
        &options,
        &Silent,
    )
    .unwrap();
    let up = &c.branches[1];
    assert!(
        up.end.contains("supported range ends") && up.end.contains("gap (d₀)"),
        "{}",
        up.end
    );
}
