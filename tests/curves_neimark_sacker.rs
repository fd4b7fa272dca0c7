//! Neimark–Sacker curves in two parameters: the curve through one of Figure 5's pair of
//! Neimark–Sacker points (two modes, ω = 2) checked where it was not started, against a
//! one-parameter run and shooting either side of the located point.

use impacting_cantilever::analysis::continuation::Parameter;
use impacting_cantilever::analysis::curves::{self, CurveKind, CurveSettings, Family2};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::model::problems::{self, Forced};
use nalgebra::DVector;

/// The modulus of the complex multiplier nearest the unit circle of the period-1 orbit near
/// `x` at (k, ω) of Figure 4's N-mode model (shooting, not the curve's system).
fn pair_modulus(n: usize, k: f64, omega: f64, x: &[f64]) -> f64 {
    crate::common::curves::multipliers_at(n, k, omega, x)
        .iter()
        .filter(|z| z[1].abs() > 1e-9)
        .map(|z| z[0].hypot(z[1]))
        .min_by(|a, b| (a - 1.0).abs().total_cmp(&(b - 1.0).abs()))
        .unwrap()
}

/// The Neimark–Sacker curve of the two-mode model in (k, ω), started at the first of the
/// two Neimark–Sacker points a one-parameter run in k finds at ω = 2(β₁⁻)² (Figure 5's pair,
/// 7.78k₁ and 16.6k₁), comes back to ω = 2 at the second: located there (Newton on the
/// extended system from the nearest curve point), it lies in the one-parameter run's bracket
/// of the second point, and shooting 1e-3 either side finds the pair's modulus on either
/// side of 1. On every point the pair is on the unit circle to 1e-9.
#[test]
fn a_neimark_sacker_curve_joins_figure_5s_pair_of_neimark_sacker_points() {
    use impacting_cantilever::analysis::continuation::BifurcationKind;
    let base = Forced {
        k_over_k1: 5.0,
        ..problems::figure4(2)
    };
    let fam1 = impacting_cantilever::analysis::continuation::Family::forced(
        base,
        Parameter::StopStiffness,
    );
    let x = fam1
        .simulator(5.0)
        .unwrap()
        .run(&DVector::zeros(4), 1000, &mut ())
        .unwrap()
        .state;
    let s = impacting_cantilever::analysis::continuation::Settings::new((5.0, 25.0));
    let b =
        impacting_cantilever::analysis::continuation::continue_branch(&fam1, &x, 5.0, 1, 1.0, &s)
            .unwrap();
    let ns: Vec<_> = b
        .bifurcations
        .iter()
        .filter(|b| b.kind == BifurcationKind::NeimarkSacker)
        .collect();
    assert_eq!(ns.len(), 2, "{:?}", b.bifurcations);
    let start = &b.points[ns[0].index];
    let family = Family2::forced(
        problems::figure4(2),
        Parameter::StopStiffness,
        Parameter::Frequency,
    )
    .unwrap();
    let settings = CurveSettings::new((2.0, 40.0), (1.9, 2.1));
    let curve = curves::trace_curve(
        &family,
        CurveKind::NeimarkSacker,
        &DVector::from_vec(start.state.clone()),
        (start.parameter, 2.0),
        1,
        &settings,
        &Silent,
    )
    .unwrap();
    for p in &curve.points {
        assert!(
            p.test_residual <= 1e-9,
            "k = {}, ω = {}: {}",
            p.p,
            p.q,
            p.test_residual
        );
        assert!(p.orbit_residual <= 1e-12);
    }
    let first = curve
        .points
        .iter()
        .find(|p| (p.q - 2.0).abs() < 1e-12 * 2.0)
        .unwrap();
    assert!(ns[0].between.0 <= first.p && first.p <= ns[0].between.1);
    // the curve point nearest the second Neimark–Sacker point, located at ω = 2 exactly
    let near = curve
        .points
        .iter()
        .min_by(|a, b| {
            let d = |p: &curves::CurvePoint| (p.p / ns[1].parameter).ln().abs() + (p.q - 2.0).abs();
            d(a).total_cmp(&d(b))
        })
        .unwrap();
    let second = curves::locate_point(
        &family,
        CurveKind::NeimarkSacker,
        &DVector::from_vec(near.state.clone()),
        (near.p, 2.0),
        1,
    )
    .unwrap();
    assert!(
        ns[1].between.0 <= second.p && second.p <= ns[1].between.1,
        "located k = {}, one-parameter bracket {:?}",
        second.p,
        ns[1].between
    );
    let below = pair_modulus(2, second.p - 1e-3, 2.0, &second.state);
    let above = pair_modulus(2, second.p + 1e-3, 2.0, &second.state);
    assert!(
        (below - 1.0) * (above - 1.0) < 0.0,
        "|μ| = {below} at k − 1e-3, {above} at k + 1e-3"
    );
}
