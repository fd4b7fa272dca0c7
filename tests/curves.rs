//! Two-parameter continuation of codimension-one points (issue: the atlas's boundaries),
//! checked against things the continuation did not compute: closed forms of the one-mode
//! oscillator, and one-parameter continuation runs that cross the curves.

use impacting_cantilever::analysis::continuation::Parameter;
use impacting_cantilever::analysis::curves::{self, CurveKind, CurveSettings, Family2};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::model::problems::{self, Forced};
use nalgebra::DVector;

/// The one-mode oscillator's steady tip amplitude without the stop, in units of its value
/// at resonance: η̈ + 2ζω₁η̇ + ω₁²η = F cos ωt has amplitude F/√((ω₁² − ω²)² + (2ζω₁ω)²),
/// so with r = ω/ω₁ the ratio to r = 1 is 2ζ/√((1 − r²)² + (2ζr)²).
fn linear_amplitude(zeta: f64, r: f64) -> f64 {
    2.0 * zeta / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt()
}

/// The non-impacting orbit grazes the stop where d₀ equals its amplitude: along the whole
/// grazing curve in (d₀, ω) the computed d₀ is the closed form's. Tolerance: the corrector
/// stops at 1e-9 (test and orbit residual, relative to A_free) and the polished orbit's
/// own test residual is reported; 1e-8 leaves a factor 10 over both.
#[test]
fn the_one_mode_grazing_curve_is_the_linear_response_amplitude() {
    let zeta = 0.05;
    let base = Forced {
        modes: 1,
        zeta1: zeta,
        gap: 1.0,
        ..problems::figure4(1)
    };
    let family = Family2::forced(base, Parameter::Gap, Parameter::Frequency).unwrap();
    let omega0 = 0.8;
    // the non-impacting orbit at d₀ 20 % above its amplitude
    let d_start = 1.2 * linear_amplitude(zeta, omega0);
    let x0 = DVector::zeros(2);
    let settings = CurveSettings::new((1e-3, 10.0), (0.5, 1.6));
    let curve = curves::trace_curve(
        &family,
        CurveKind::Grazing,
        &x0,
        (d_start, omega0),
        1,
        &settings,
        &Silent,
    )
    .unwrap();
    eprintln!("{} points, ends {:?}", curve.points.len(), curve.ends);
    assert!(curve.points.len() > 20, "{} points", curve.points.len());
    let (lo, hi) = curve
        .points
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), p| {
            (a.min(p.q), b.max(p.q))
        });
    assert!(lo < 0.55 && hi > 1.55, "ω covered only {lo}…{hi}");
    for p in &curve.points {
        let exact = linear_amplitude(zeta, p.q);
        assert!(
            (p.p - exact).abs() <= 1e-8 * exact,
            "ω = {}: d₀ = {} against {exact}",
            p.q,
            p.p
        );
        assert!(p.test_residual <= 1e-8, "{}", p.test_residual);
        assert!(p.orbit_residual <= 1e-12, "{}", p.orbit_residual);
    }
}

/// The Figure 4 orbit of N modes (k = 100k₁, ω = 2(β₁⁻)², 1000 periods from rest) continued
/// in `parameter` towards `to`: its branch.
fn branch(
    n: usize,
    k: f64,
    parameter: Parameter,
    from: f64,
    to: f64,
) -> impacting_cantilever::analysis::continuation::Branch {
    use impacting_cantilever::analysis::continuation::{self, Family, Settings};
    let base = Forced {
        k_over_k1: k,
        ..problems::figure4(n)
    };
    let fam = Family::forced(base, parameter);
    let x = fam
        .simulator(from)
        .unwrap()
        .run(&DVector::zeros(2 * n), 1000, &mut ())
        .unwrap()
        .state;
    let s = Settings::new((from.min(to), from.max(to)));
    continuation::continue_branch(&fam, &x, from, 1, (to - from).signum(), &s).unwrap()
}

/// The leading real negative multiplier's modulus of the period-1 orbit near `x` (shooting,
/// not the bordered system the curve solves).
fn flip_modulus(n: usize, k: f64, omega: f64, x: &[f64]) -> f64 {
    crate::common::curves::multipliers_at(n, k, omega, x)
        .iter()
        .filter(|z| z[1].abs() < 1e-9 && z[0] < 0.0)
        .map(|z| z[0].abs())
        .fold(0.0, f64::max)
}

/// The period-doubling curve of the one-mode model in (ω, k), started from the period
/// doubling a one-parameter run in ω reports at k = 100k₁, is checked where it was not
/// started: at k = 400k₁ a second one-parameter run in ω brackets its own period doubling,
/// and the curve's ω there (interpolated in ln k) lies in that bracket; shooting 1e-5
/// either side of it finds the leading negative multiplier on either side of −1.
#[test]
fn a_period_doubling_curve_passes_through_the_one_parameter_period_doublings() {
    use impacting_cantilever::analysis::continuation::BifurcationKind;
    let b100 = branch(1, 100.0, Parameter::Frequency, 2.0, 3.0);
    let pd = b100
        .bifurcations
        .iter()
        .find(|b| b.kind == BifurcationKind::PeriodDoubling)
        .expect("a period doubling in ω at k = 100k₁");
    let start = &b100.points[pd.index];
    let family = Family2::forced(
        problems::figure4(1),
        Parameter::Frequency,
        Parameter::StopStiffness,
    )
    .unwrap();
    let settings = CurveSettings::new((1.0, 4.0), (20.0, 2000.0));
    let curve = curves::trace_curve(
        &family,
        CurveKind::PeriodDoubling,
        &DVector::from_vec(start.state.clone()),
        (start.parameter, 100.0),
        1,
        &settings,
        &Silent,
    )
    .unwrap();
    assert_eq!(
        curve.ends,
        (
            "left the parameter rectangle".to_string(),
            "left the parameter rectangle".to_string()
        )
    );
    for p in &curve.points {
        // the multiplier at −1 to the eigensolver's accuracy on a polished orbit
        assert!(p.test_residual <= 1e-9, "k = {}: {}", p.q, p.test_residual);
    }
    let at_100 = curve
        .points
        .iter()
        .find(|p| (p.q - 100.0).abs() < 1e-12 * 100.0)
        .unwrap();
    assert!(pd.between.0 <= at_100.p && at_100.p <= pd.between.1);

    let b400 = branch(1, 400.0, Parameter::Frequency, 2.0, 3.0);
    let pd400 = b400
        .bifurcations
        .iter()
        .find(|b| b.kind == BifurcationKind::PeriodDoubling)
        .expect("a period doubling in ω at k = 400k₁");
    let i = curve
        .points
        .windows(2)
        .position(|w| (w[0].q - 400.0) * (w[1].q - 400.0) <= 0.0)
        .expect("the curve crosses k = 400k₁");
    let (a, b) = (&curve.points[i], &curve.points[i + 1]);
    let s = (400f64.ln() - a.q.ln()) / (b.q.ln() - a.q.ln());
    let omega = a.p + s * (b.p - a.p);
    assert!(
        pd400.between.0 <= omega && omega <= pd400.between.1,
        "curve ω = {omega}, one-parameter bracket {:?}",
        pd400.between
    );
    // linear interpolation between curve points ~0.05 apart in arclength is good to
    // ~1e-4 in ω here (the curve's curvature); at 1e-3 either side the multiplier has
    // moved by ~1e-2, far beyond that
    let below = flip_modulus(1, 400.0, omega - 1e-3, &a.state);
    let above = flip_modulus(1, 400.0, omega + 1e-3, &a.state);
    assert!(
        (below - 1.0) * (above - 1.0) < 0.0,
        "|μ| = {below} at ω − 1e-3, {above} at ω + 1e-3"
    );
}

/// The grazing curve of the three-mode model in (k, ω) through the grazing that a
/// one-parameter run in k finds at ω = 2(β₁⁻)² (placed there by bisection on the number of
/// contacts, to a bracket 1e-8 wide): the curve's point at ω = 2 (Newton on the signed
/// distance of the extremum to the stop) lies in that bracket.
#[test]
fn a_grazing_curve_passes_through_the_one_parameter_grazing() {
    use impacting_cantilever::analysis::continuation::BifurcationKind;
    let b = branch(3, 100.0, Parameter::StopStiffness, 100.0, 140.0);
    let g = b
        .bifurcations
        .iter()
        .find(|b| b.kind == BifurcationKind::Grazing)
        .expect("a grazing between k = 100k₁ and 140k₁");
    let start = &b.points[g.index];
    let family = Family2::forced(
        problems::figure4(3),
        Parameter::StopStiffness,
        Parameter::Frequency,
    )
    .unwrap();
    let settings = CurveSettings {
        max_points: 40,
        ..CurveSettings::new((10.0, 1000.0), (1.9, 2.1))
    };
    let curve = curves::trace_curve(
        &family,
        CurveKind::Grazing,
        &DVector::from_vec(start.state.clone()),
        (start.parameter, 2.0),
        1,
        &settings,
        &Silent,
    )
    .unwrap();
    let at_2 = curve
        .points
        .iter()
        .find(|p| (p.q - 2.0).abs() < 1e-12 * 2.0)
        .unwrap();
    assert!(
        g.between.0 <= at_2.p && at_2.p <= g.between.1,
        "curve k = {}, bracket {:?}",
        at_2.p,
        g.between
    );
    assert!(curve.points.len() > 10);
    for p in &curve.points {
        assert!(p.test_residual <= 1e-9 && p.orbit_residual <= 1e-12);
    }
}

/// The fold curve of the one-mode model with a soft stop (k = 0.5k₁, d₀ = 0.5) in (ω, k),
/// started at the fold a one-parameter run in ω finds at k = 0.5k₁: located again at
/// k = 2k₁ (Newton on the extended system from the nearest curve point), it is the turning
/// point of a separate one-parameter run at k = 2k₁: beyond its points around the fold it
/// reports, and within 1e-6 of the nearest. The curve also has a cusp (two fold curves meet) below k = 0.5k₁.
#[test]
fn a_fold_curve_passes_through_the_one_parameter_folds_and_has_a_cusp() {
    use impacting_cantilever::analysis::continuation::BifurcationKind;
    let soft = |k: f64| Forced {
        modes: 1,
        gap: 0.5,
        k_over_k1: k,
        ..problems::figure4(1)
    };
    let fold_at = |k: f64| {
        use impacting_cantilever::analysis::continuation::{self, Family, Settings};
        let fam = Family::forced(soft(k), Parameter::Frequency);
        let x = fam
            .simulator(2.0)
            .unwrap()
            .run(&DVector::zeros(2), 1000, &mut ())
            .unwrap()
            .state;
        let s = Settings::new((0.9, 2.0));
        let b = continuation::continue_branch(&fam, &x, 2.0, 1, -1.0, &s).unwrap();
        let f = b
            .bifurcations
            .iter()
            .find(|b| b.kind == BifurcationKind::Fold)
            .expect("a fold")
            .clone();
        (b, f)
    };
    let (branch, fold) = fold_at(0.5);
    let start = &branch.points[fold.index];
    let family =
        Family2::forced(soft(1.0), Parameter::Frequency, Parameter::StopStiffness).unwrap();
    let curve = curves::trace_curve(
        &family,
        CurveKind::Fold,
        &DVector::from_vec(start.state.clone()),
        (start.parameter, 0.5),
        1,
        &CurveSettings::new((0.5, 2.0), (0.05, 5.0)),
        &Silent,
    )
    .unwrap();
    for p in &curve.points {
        assert!(p.test_residual <= 1e-9, "k = {}: {}", p.q, p.test_residual);
    }
    let cusps: Vec<_> = curve
        .codim_two
        .iter()
        .filter(|c| c.meets == curves::Meets::Cusp)
        .collect();
    assert_eq!(cusps.len(), 1, "{:?}", curve.codim_two);
    assert!(cusps[0].q < 0.5);

    let (branch2, fold2) = fold_at(2.0);
    let near = curve
        .points
        .iter()
        .min_by(|a, b| {
            let d = |p: &curves::CurvePoint| {
                (p.q / 2.0).ln().abs() + (p.p / fold2.parameter).ln().abs()
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let located = curves::locate_point(
        &family,
        CurveKind::Fold,
        &DVector::from_vec(near.state.clone()),
        (near.p, 2.0),
        1,
    )
    .unwrap();
    // the fold is the branch's extreme in ω: the located ω lies beyond every branch point
    // around the bracket (not between them: a turning point is not interpolated), and
    // within 1e-6 of the nearest
    let around: Vec<f64> = branch2.points[fold2.index.saturating_sub(3)..fold2.index + 4]
        .iter()
        .map(|p| p.parameter)
        .collect();
    let (lo, hi) = around
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &w| (a.min(w), b.max(w)));
    let minimum = around[0] > fold2.parameter;
    let beyond = if minimum {
        lo - located.p
    } else {
        located.p - hi
    };
    assert!(
        (0.0..1e-6).contains(&beyond),
        "located ω = {}, branch around the fold {around:?}",
        located.p
    );
}

/// `continue2` is `curve_from` serialised: its JSON carries the curve the library traces
/// for the same inputs, its CSV one row per point, and bad input exits 2 naming the option.
#[test]
fn continue2_prints_the_librarys_curve_and_refuses_bad_input() {
    use crate::common::cli::cantilever;
    let base = [
        "continue2",
        "--modes",
        "1",
        "--zeta1",
        "0.05",
        "--omega",
        "0.8",
        "--gap",
        "1",
        "--kind",
        "grazing",
        "--parameter",
        "gap",
        "--second",
        "omega",
        "--range",
        "0.01",
        "10",
        "--second-range",
        "0.7",
        "0.9",
    ];
    let (code, out, err) = cantilever(&[&base[..], &["--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    let points = doc["curve"]["points"].as_array().unwrap();
    assert!(points.len() > 5);
    for p in points {
        let (d0, omega) = (p["p"].as_f64().unwrap(), p["q"].as_f64().unwrap());
        let exact = linear_amplitude(0.05, omega);
        assert!((d0 - exact).abs() <= 1e-8 * exact, "{d0} against {exact}");
    }
    let (code, csv, _) = cantilever(&[&base[..], &["--csv"]].concat());
    assert_eq!(code, 0);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("gap,omega,contacts,orbit_residual,test_residual,spectral_radius")
    );
    assert_eq!(lines.count(), points.len());
    for (extra, names) in [
        (&["--max-step", "0.5"][..], "--max-step"),
        (&["--max-points", "1"][..], "--max-points"),
        (&["--range", "1", "2"][..], "--range"),
        (&["--json", "--csv"][..], "--csv"),
    ] {
        let (code, _, err) = cantilever(&[&base[..], extra].concat());
        assert_eq!(code, 2, "{extra:?}: {err}");
        assert!(err.contains(names), "{extra:?}: {err}");
    }
    let mut same = base.to_vec();
    same[14] = "gap";
    let (code, _, err) = cantilever(&same);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--second"), "{err}");
    // the one-mode orbit without contact has its pair at |μ| = exp(−ζ₁ω₁T) whatever the
    // parameters: no Neimark–Sacker point, reported as such; the two-mode orbit of Figure 5
    // has one, and its curve is traced
    let mut ns = base.to_vec();
    ns[10] = "neimark-sacker";
    let (code, _, err) = cantilever(&ns);
    assert_ne!(code, 0);
    assert!(err.contains("no Neimark–Sacker point"), "{err}");
    let figure5 = [
        "continue2",
        "--modes",
        "2",
        "--stop-stiffness",
        "7.5",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--kind",
        "neimark-sacker",
        "--parameter",
        "stop-stiffness",
        "--second",
        "omega",
        "--range",
        "2",
        "40",
        "--second-range",
        "1.9",
        "2.1",
        "--json",
    ];
    let (code, out, err) = cantilever(&figure5);
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(doc["curve"]["kind"], "neimark_sacker");
    for p in doc["curve"]["points"].as_array().unwrap() {
        assert!(p["test_residual"].as_f64().unwrap() <= 1e-9);
    }
}

/// The rigid impact oscillator's period-doubling curve in (ω, r), traced on the exact map
/// with its saltation matrices, against the closed form of its (1,1) orbit
/// (`tests/common/impact.rs`: free flight in closed form between impacts at phase τ with
/// velocity v, and the monodromy Φ(T)S): at every point of the curve the closed-form
/// monodromy has a multiplier at −1, 1 + tr M + det M = 0, to 1e-8 (the corrector's 1e-11
/// and the polish, with |∂(tr M)/∂ω| of order 1; the closed form itself is exact to
/// round-off).
#[test]
fn the_rigid_oscillators_period_doubling_curve_is_the_closed_forms() {
    use crate::common::impact::{parameters, ClosedForm};
    use impacting_cantilever::engine::map::PeriodMap;
    use impacting_cantilever::engine::rigid::RigidImpact;
    let family = Family2::of_maps(("ω", "r"), |omega, r| {
        let model = RigidImpact::oscillator(&parameters(omega), r)?;
        Ok(Box::new(model) as Box<dyn PeriodMap + Send + Sync>)
    });
    // started next to the doubling: the closed form's at r = 0.8 by bisection in ω
    let crossing = |omega: f64| {
        let c = ClosedForm { omega, r: 0.8 };
        let (tau, v) = c.orbits()[0];
        let m = c.monodromy(tau, v);
        1.0 + m.trace() + m.determinant()
    };
    let (mut a, mut b) = (2.6, 2.7);
    for _ in 0..40 {
        let mid = 0.5 * (a + b);
        if crossing(a) * crossing(mid) <= 0.0 {
            b = mid;
        } else {
            a = mid;
        }
    }
    let omega0 = 0.5 * (a + b) - 0.01;
    let start = ClosedForm {
        omega: omega0,
        r: 0.8,
    };
    let (tau, v) = start.orbits()[0];
    let settings = CurveSettings {
        max_points: 40,
        ..CurveSettings::new((2.0, 4.0), (0.5, 0.95))
    };
    let curve = curves::trace_curve(
        &family,
        CurveKind::PeriodDoubling,
        &start.state(tau, v),
        (omega0, 0.8),
        1,
        &settings,
        &Silent,
    )
    .unwrap();
    assert!(
        curve.points.len() > 20,
        "{} points, {:?}",
        curve.points.len(),
        curve.ends
    );
    let (lo, hi) = curve
        .points
        .iter()
        .fold((1.0f64, 0.0f64), |(a, b), p| (a.min(p.q), b.max(p.q)));
    assert!(lo < 0.7 && hi > 0.9, "r covered only {lo}…{hi}");
    for p in &curve.points {
        let exact = ClosedForm { omega: p.p, r: p.q };
        let state = DVector::from_vec(p.state.clone());
        let (tau, v) = exact
            .orbits()
            .into_iter()
            .min_by(|a, b| {
                let d = |o: &(f64, f64)| (exact.state(o.0, o.1) - &state).norm();
                d(a).total_cmp(&d(b))
            })
            .expect("an admissible (1,1) orbit at the curve's point");
        assert!((exact.state(tau, v) - &state).amax() <= 1e-9 * state.amax());
        let m = exact.monodromy(tau, v);
        let g = 1.0 + m.trace() + m.determinant();
        assert!(
            g.abs() <= 1e-8,
            "(ω, r) = ({}, {}): 1 + tr M + det M = {g:e}",
            p.p,
            p.q
        );
        assert_eq!(p.impacts_n, 1);
    }
    // grazing curves read the compliant tip: refused for this family
    let e = curves::trace_curve(
        &family,
        CurveKind::Grazing,
        &start.state(tau, v),
        (omega0, 0.8),
        1,
        &settings,
        &Silent,
    )
    .unwrap_err();
    assert!(e.to_string().contains("compliant"), "{e}");
}
