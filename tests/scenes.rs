//! Every scene's key numbers at the tests' reduced resolution, snapshotted (insta), and
//! backed by assertions against independent values so that a changed digit is explained
//! rather than re-accepted. The numbers at the book's resolution are in `published.rs`
//! (scenes that are cheap at full resolution are snapshotted there only).
#![cfg(feature = "plots")]

use impacting_cantilever::base::provenance::Provenance;
use impacting_cantilever::base::report::{Cited, KeyNumbers, KeyValue};
use impacting_cantilever::results::scene::{self, Resolution, Scene, SceneOutput, Silent};
use impacting_cantilever::results::scenes::energetic_map::EnergeticMap;
use impacting_cantilever::results::scenes::fig4::Fig4;
use impacting_cantilever::results::scenes::fig5::Fig5;
use impacting_cantilever::results::scenes::fig6::Fig6;
use impacting_cantilever::results::scenes::fig9::Fig9;
use impacting_cantilever::results::scenes::{self, fig2, spectrum};
use std::sync::OnceLock;

/// A scene's data at the tests' resolution, computed once for every test that reads it
/// (the snapshot and the claims of Figures 4, 5, 6 and 9 and of the energetic map read the
/// same data).
fn cached<S: Scene>(cell: &'static OnceLock<S::Data>) -> &'static S::Data {
    cell.get_or_init(|| S::compute(&S::params(Resolution::Test), &Silent).unwrap())
}

static FIG4: OnceLock<<Fig4 as Scene>::Data> = OnceLock::new();
static FIG5: OnceLock<<Fig5 as Scene>::Data> = OnceLock::new();
static FIG6: OnceLock<<Fig6 as Scene>::Data> = OnceLock::new();
static FIG9: OnceLock<<Fig9 as Scene>::Data> = OnceLock::new();
static MAP: OnceLock<<EnergeticMap as Scene>::Data> = OnceLock::new();

/// The output of a scene whose data are [`cached`].
fn output_of_cached<S: Scene>(cell: &'static OnceLock<S::Data>) -> SceneOutput {
    let provenance = Provenance::of_scene(scene::module_of::<S>(), "test");
    scene::output_of::<S>(&S::params(Resolution::Test), cached::<S>(cell), provenance).unwrap()
}

/// One scene at the tests' resolution: it has key numbers, a plot, a table with data and
/// evidence; where that resolution is reduced, its key numbers match the snapshot.
fn scene_at_test_resolution(name: &str) {
    let spec = scenes::find(name).unwrap();
    let out = match name {
        "fig4" => output_of_cached::<Fig4>(&FIG4),
        "fig5" => output_of_cached::<Fig5>(&FIG5),
        "fig6" => output_of_cached::<Fig6>(&FIG6),
        "fig9" => output_of_cached::<Fig9>(&FIG9),
        "energetic-map" => output_of_cached::<EnergeticMap>(&MAP),
        _ => spec.run(Resolution::Test, &Silent).unwrap(),
    };
    assert!(!out.key_numbers.0.is_empty(), "{name} has key numbers");
    assert!(out.rendered.svg.starts_with("<svg"), "{name} draws a plot");
    // a table with a header, its separator and at least one data row
    let rows = out
        .rendered
        .table
        .lines()
        .filter(|l| l.starts_with('|'))
        .count();
    assert!(rows >= 3, "{name} has a table with data ({rows} rows)");
    assert!(
        !out.verdict.evidence.is_empty(),
        "{name} states its evidence"
    );
    printed_values_lie_within_their_uncertainty(name, &out.key_numbers);
    if spec.reduced_for_tests() {
        // named as when this file was its own test binary (`scenes__NAME.snap`, which
        // `cantilever diff` reads), not by its module path in the suite
        insta::with_settings!({ prepend_module_to_snapshot => false }, {
            insta::assert_snapshot!(format!("scenes__{name}"), out.key_numbers.to_snapshot());
        });
    }
}

/// A number as the book's prose writes it: `0.0123`, `1.60 × 10⁻³`, `10⁴`.
fn parse_prose_number(text: &str) -> f64 {
    let superscript = |t: &str| -> i32 {
        t.chars()
            .map(|c| match c {
                '⁻' => '-',
                '⁰' => '0',
                '¹' => '1',
                '²' => '2',
                '³' => '3',
                '⁴' => '4',
                '⁵' => '5',
                '⁶' => '6',
                '⁷' => '7',
                '⁸' => '8',
                '⁹' => '9',
                other => other,
            })
            .collect::<String>()
            .parse()
            .unwrap_or_else(|_| panic!("exponent of {text}"))
    };
    if let Some((m, e)) = text.split_once(" × 10") {
        m.parse::<f64>().unwrap() * 10f64.powi(superscript(e))
    } else if let Some(e) = text
        .strip_prefix("10")
        .filter(|e| e.starts_with(|c: char| !c.is_ascii_digit() && c != '.'))
    {
        10f64.powi(superscript(e))
    } else {
        text.parse().unwrap_or_else(|_| panic!("a number: {text}"))
    }
}

/// Every float key number, as the snapshots and `cite` print it and as the book's prose
/// prints it, lies within its printed uncertainty of the value computed (the issue: 6
/// figures of a number known to 2e-12 were printed as "± 2e-12", 10⁶ of it off).
fn printed_values_lie_within_their_uncertainty(scene: &str, keys: &KeyNumbers) {
    for (key, value) in &keys.0 {
        let cited: Vec<&Cited> = match value {
            KeyValue::Float(c) => vec![c],
            KeyValue::Series(v) => v.iter().collect(),
            _ => continue,
        };
        for c in cited {
            let one = KeyValue::Float(c.clone());
            // snapshot / cite: "1.23e0 ± 4e-6 unit" or "1.23e0 (exact) unit"
            let text = one.to_string();
            let (v, rest) = text.split_once(' ').unwrap();
            let v: f64 = v.parse().unwrap();
            let u: f64 = match rest.strip_prefix("± ") {
                Some(r) => r.split(' ').next().unwrap().parse().unwrap(),
                None => 0.0,
            };
            // (parsing a decimal back is good to half an ulp)
            let slack = 2.0 * f64::EPSILON * c.computed.abs();
            assert!(
                (v - c.computed).abs() <= u + slack,
                "{scene}/{key}: printed {text} but computed {:e}",
                c.computed
            );
            // the book's prose: "1.60201 ± 4 × 10⁻⁶ unit"
            let prose = one.prose(true);
            let body = if c.unit.is_empty() {
                prose.as_str()
            } else {
                prose
                    .strip_suffix(&format!(" {}", c.unit))
                    .unwrap_or_else(|| panic!("{scene}/{key}: {prose} ends in its unit"))
            };
            let (pv, pu) = match body.split_once(" ± ") {
                Some((pv, pu)) => (parse_prose_number(pv), parse_prose_number(pu)),
                None => (parse_prose_number(body), 0.0),
            };
            assert!(
                (pv - c.computed).abs() <= pu + slack + 1e-12 * pu,
                "{scene}/{key}: the book prints {prose} but computed {:e}",
                c.computed
            );
        }
    }
}

/// One test per scene, so that they run in parallel and fail separately; a test below
/// checks that the list is the registry.
macro_rules! per_scene {
    ($($test:ident => $name:literal),* $(,)?) => {
        $(
            #[test]
            fn $test() {
                scene_at_test_resolution($name);
            }
        )*

        #[test]
        fn every_registered_scene_has_its_test() {
            let listed = [$($name),*];
            let registered: Vec<&str> = scenes::all().iter().map(|s| s.name()).collect();
            assert_eq!(registered, listed, "add the scene to per_scene! in tests/scenes.rs");
        }
    };
}

per_scene! {
    scene_spectrum => "spectrum",
    scene_fig2 => "fig2",
    scene_restitution => "restitution",
    scene_fig3_abc => "fig3-abc",
    scene_fig3_d => "fig3-d",
    scene_fig4 => "fig4",
    scene_fig5 => "fig5",
    scene_fig6 => "fig6",
    scene_energetic_map => "energetic-map",
    scene_fig9 => "fig9",
    scene_experiment => "experiment",
    scene_stiffness_matching => "stiffness-matching",
    scene_atlas => "atlas",
    scene_basins => "basins",
    scene_boundaries => "boundaries",
    scene_work_precision => "work-precision",
    scene_side_by_side => "side-by-side",
}

#[test]
fn spectrum_scene_agrees_with_golden_everywhere() {
    let d = spectrum::compute(&Default::default()).unwrap();
    let all = d
        .free
        .iter()
        .chain(&d.clamped_pinned)
        .chain(d.finite_k.iter().map(|p| &p.1));
    for c in all {
        // the root accuracy target
        assert!(c.rel_diff < 1e-13, "i={} {} vs {}", c.i, c.ours, c.golden);
    }
    // frequency curves rise monotonically from the free to the clamped-pinned value
    for (i, f) in d.frequency.iter().enumerate() {
        assert!(f.windows(2).all(|w| w[1] >= w[0]));
        assert!(*f.last().unwrap() <= d.frequency_pinned[i] * (1.0 + 1e-12));
    }
}

#[test]
fn fig2_claims_of_section_2_3() {
    let d = fig2::compute(&Default::default()).unwrap();
    for t in &d.truncations {
        let n = t.modes;
        // "the highest-order mode diverges from the exact solution as k → ∞":
        // at k = 1e6 k₁ the top Galerkin eigenvalue exceeds the continuum one by > 10×
        let last = d.k_over_k1.len() - 1;
        assert!(t.lambda[n - 1][last] > 10.0 * d.exact[n - 1][last], "N={n}");
        // "λ_N = kN": within O(k_N/(kN)) at the top of the grid
        let kn = d.exact[n - 1][0];
        assert!((t.scaled_highest[last] - 1.0).abs() < 2.0 * kn / (1e6 * d.k1 * n as f64));
        // Galerkin eigenvalues bound the continuum ones from above (Rayleigh–Ritz), for
        // every k; allow round-off of 1e-13 relative.
        for i in 0..n {
            for (p, &l) in t.lambda[i].iter().enumerate() {
                assert!(l >= d.exact[i][p] * (1.0 - 1e-13), "N={n} i={i} p={p}");
            }
        }
    }
    // "for fixed k, modal convergence as N → ∞": at k = k₁ the error of λ₁ falls with N
    let row = |n, r: f64, i| {
        d.table
            .iter()
            .find(|x| x.modes == n && x.k_over_k1 == r && x.i == i)
            .unwrap()
            .rel_error
    };
    assert!(row(1, 1.0, 1) > row(3, 1.0, 1) && row(3, 1.0, 1) > row(10, 1.0, 1));
}

#[test]
fn verdict_numbers_quoted_in_the_book() {
    // book/src/fig2.md and spectrum.md quote these; if one moves, the chapter must change.
    let d = fig2::compute(&Default::default()).unwrap();
    let row = |n, r: f64, i| {
        d.table
            .iter()
            .find(|x| x.modes == n && x.k_over_k1 == r && x.i == i)
            .unwrap()
            .clone()
    };
    let quoted = |x: f64, printed: f64, figures: i32| {
        // a number printed to `figures` significant figures: ± half a unit in the last one
        let unit = 10f64.powi(printed.abs().log10().floor() as i32 - figures + 1);
        (x - printed).abs() <= 0.5 * unit
    };
    assert!(quoted(row(10, 1000.0, 10).rel_error * 100.0, 0.16, 2));
    assert!(quoted(
        row(3, 1000.0, 3).lambda / row(3, 1000.0, 3).exact,
        3.8,
        2
    ));
    assert!(quoted(row(1, 1.0, 1).rel_error, 1.6e-2, 2));
    assert!(quoted(row(3, 1.0, 1).rel_error, 7.1e-4, 2));
    assert!(quoted(row(10, 1.0, 1).rel_error, 2.0e-5, 2));
    let s = spectrum::compute(&Default::default()).unwrap();
    assert!(quoted(s.k2_over_k1, 39.2739, 6));
    assert!(quoted(s.small_k.fitted_order, 2.00, 3));
    assert!(quoted(s.small_k.fitted_coefficient, -2.497e-3, 4));
}

#[test]
fn work_precision_methods_agree_and_the_exact_one_is_at_round_off() {
    use impacting_cantilever::results::scenes::work_precision::{compute, WorkPrecisionParams};
    let d = compute(&WorkPrecisionParams::test()).unwrap();
    assert!(
        d.points.iter().all(|p| p.same_sequence),
        "every run finds the same events"
    );
    let tightest_dp5 = d.points.iter().rfind(|p| p.method != "exact").unwrap();
    // the cross-verification bound, 1e-8, for the reference at its tightest rtol
    assert!(
        tightest_dp5.event_error < 1e-8,
        "{:e}",
        tightest_dp5.event_error
    );
    // the exact method at root tolerance 1e-6 is already at round-off (Newton converges
    // quadratically past the tolerance): within 1e-12 of its 1e-15 run
    let exact_1e6 = d
        .points
        .iter()
        .find(|p| p.method == "exact" && p.tolerance == 1e-6)
        .unwrap();
    assert!(exact_1e6.event_error < 1e-12 && exact_1e6.state_error < 1e-12);
}

#[test]
fn figure_4_verdicts_and_their_evidence() {
    use impacting_cantilever::analysis::orbit::OrbitKind;
    let d = cached::<Fig4>(&FIG4);
    for p in &d.panels {
        // N = 1, 2, 10 reproduce the paper; N = 3 does not (a known, documented mismatch:
        // if it starts to agree, the Figure 4 chapter and the errata must change)
        if p.modes == 3 {
            assert_eq!(p.kind, OrbitKind::Periodic { m: 1, n: 1 });
            assert_ne!(p.kind, p.paper);
            // the near-grazing dwell that separates (1,1) from the paper's (1,3): positive
            // (one contact, not several) and, by the chapter's definition of near-grazing,
            // shallower than a tenth of the peak penetration (d₀ = 0: the max tip)
            let depth = p.dwell_depth.unwrap();
            assert!(
                depth > 0.0 && depth < 0.1 * p.max_tip,
                "dwell depth {depth}, peak {}",
                p.max_tip
            );
        } else {
            assert_eq!(p.kind, p.paper, "N={}", p.modes);
        }
        // the relative periodicity residual is at round-off, far below the 1e-9 threshold
        assert!(p.residual < 1e-12);
        let e = &p.evidence;
        assert_eq!(e.long_transient, p.kind, "N={}: longer transient", p.modes);
        assert_eq!(
            e.loose_tolerance, p.kind,
            "N={}: looser root tolerance",
            p.modes
        );
        let (n_ref, dt) = e.reference.unwrap();
        let OrbitKind::Periodic { n, .. } = p.kind else {
            panic!("periodic")
        };
        assert_eq!(
            n_ref, n,
            "N={}: DP5 finds the same contacts per period",
            p.modes
        );
        // DP5 at rtol 1e-10 over ~1040 periods: event times within 1e-8 of the exact ones
        assert!(dt.unwrap() < 1e-8, "N={}: {:?}", p.modes, dt);
        assert!(
            e.random_starts.iter().all(|(k, _)| *k == p.kind),
            "no coexisting attractor seen"
        );
    }
}

#[test]
fn figure_5_is_deterministic_whatever_the_thread_count() {
    use impacting_cantilever::results::scenes::fig5::{compute, Fig5Params};
    let p = Fig5Params {
        modes: vec![1, 3],
        points: 4,
        transient: 150,
        recorded: 36,
        ..Fig5Params::test()
    };
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| compute(&p, &|| {}).unwrap())
    };
    let (one, two) = (run(1), run(2));
    for (a, b) in one.diagrams.iter().zip(&two.diagrams) {
        for (ca, cb) in a.columns.iter().zip(&b.columns) {
            for (sa, sb) in ca.iter().zip(cb) {
                assert_eq!(sa.kind, sb.kind);
                // bitwise: same seeds, same arithmetic, no reduction across threads
                assert_eq!(sa.impact_velocities, sb.impact_velocities);
            }
        }
    }
}

#[test]
fn figure_5_claims_at_test_resolution() {
    use impacting_cantilever::analysis::orbit::OrbitKind;
    let d = cached::<Fig5>(&FIG5);
    let c = &d.claims;
    // "for small k each model predicts a stable (1,1) orbit with quantitative agreement".
    // The truncations differ only through how well they resolve the contact: at the
    // smallest k (= k₁) the coarsest, N = 1, misplaces the lowest contact eigenvalue by
    // its Figure 2 relative error; the impact velocities may differ by no more than that.
    assert!(c.all_one_one_at_smallest_k);
    let f2 = fig2::compute(&Default::default()).unwrap();
    let n1_error = f2
        .table
        .iter()
        .find(|r| r.modes == 1 && r.k_over_k1 == d.k_over_k1[0] && r.i == 1)
        .unwrap()
        .rel_error;
    assert!(
        c.velocity_spread_at_smallest_k < n1_error,
        "{} vs {n1_error}",
        c.velocity_spread_at_smallest_k
    );
    // the N = 3 orbit at the grid point k = 100 k₁ is (1,1) and at 215 k₁ it is (1,3)
    let n3 = d.diagrams.iter().find(|g| g.modes == 3).unwrap();
    let at = |k: f64| {
        d.k_over_k1
            .iter()
            .position(|x| (x / k - 1.0).abs() < 0.01)
            .unwrap()
    };
    assert_eq!(
        n3.columns[at(100.0)][0].kind,
        OrbitKind::Periodic { m: 1, n: 1 }
    );
    assert_eq!(
        n3.columns[at(215.443)][0].kind,
        OrbitKind::Periodic { m: 1, n: 3 }
    );
    // no k on the grid shows all four of the paper's Figure 4 orbits from rest, but
    // between ~159 and ~277 k₁ (book resolution) all four are attractors: on this grid, 215
    assert!(c.paper_figure4_set_at.is_empty());
    assert_eq!(c.paper_figure4_set_reachable_at.len(), 1);
    assert!((c.paper_figure4_set_reachable_at[0] / 215.443 - 1.0).abs() < 1e-3);
}

#[test]
fn figure_3abc_one_contact_against_the_impact_laws() {
    use impacting_cantilever::results::scenes::fig3abc::{compute, Fig3abcParams};
    let d = compute(&Fig3abcParams::default()).unwrap();
    let n1 = d.series.iter().find(|s| s.modes == 1).unwrap();
    let one = n1.one_mode.as_ref().unwrap();
    for (sim, exact) in one.simulated.iter().zip(&one.exact) {
        // the exact simulator against the closed-form 1-DOF passage: round-off
        assert!((sim - exact).abs() < 1e-12, "{sim} vs {exact}");
    }
    let k1 = impacting_cantilever::model::galerkin::first_modal_stiffness();
    for s in &d.series {
        // the gap to [R]_N(r_e) closes like ε², the first-order theory's remainder. The
        // fit runs over ε ∈ [1e-4, 1e-3], where the next term of the expansion is at most
        // 4% of the remainder (N = 1: απk₁ε/2 against α²π²/2 at ε = 1e-3), so the slope is
        // 2 within 0.05
        assert!(
            (s.observed_order - 2.0).abs() < 0.05,
            "N={}: {}",
            s.modes,
            s.observed_order
        );
        // the contact lasts π/√λ_N, λ_N the top eigenvalue of K⁺ = diag(k_j) + k𝟙𝟙ᵀ:
        // λ_N = kN + mean(k_j) + O(1/k), so the ratio to eq (18)'s π/√(kN) is
        // 1 − mean(k_j)/(2kN) + O(α²/(kN)); twice that bounds it at ε = 1e-4
        let k = d.params.eps[0].powi(-2);
        let n = s.modes as f64;
        let mean_kj: f64 = (1..=s.modes)
            .map(|j| impacting_cantilever::model::continuum::modal_stiffness(j).unwrap())
            .sum::<f64>()
            / n;
        let bound = (mean_kj + d.params.alpha.powi(2) + k1) / (k * n);
        assert!(
            (s.passage_ratio[0] - 1.0).abs() < bound,
            "N={}: passage ratio {} (bound {bound:e})",
            s.modes,
            s.passage_ratio[0]
        );
    }
    // "the effective coefficient of restitution of the first mode tends to zero" (N = 2)
    let n2 = d.series.iter().find(|s| s.modes == 2).unwrap();
    assert!(n2.simulated[0][0].abs() < 2e-5 && n2.simulated[0][1] > 0.9999);
}

#[test]
fn figure_3d_profiles_converge_in_l2_to_the_pre_impact_profile_but_not_uniformly() {
    use impacting_cantilever::results::scenes::fig3d::compute;
    let d = compute(&Default::default()).unwrap();
    for p in d.profiles.iter().filter(|p| p.law == "stiffness-limit") {
        let n = p.modes as f64;
        // exact identities of −[R]_N e₁ = e₁ − (2/N)𝟙 at r_e = 1: |·| = 1, |· − e₁| = 2/√N
        assert!((p.l2_norm - 1.0).abs() < 1e-12);
        assert!((p.l2_distance - 2.0 / n.sqrt()).abs() < 1e-12);
        // the tip always rebounds: w_t(1) = −2 while φ₁(1) = 2, so the sup distance is 4
        assert!((p.at_probes[3] + 2.0).abs() < 1e-11);
        assert!((p.max_distance - 4.0).abs() < 1e-9);
    }
}

#[test]
fn figure_6_energetic_restitution_and_the_one_mode_model() {
    use impacting_cantilever::analysis::orbit::OrbitKind;
    use impacting_cantilever::results::scenes::fig6::Reading;
    let d = cached::<Fig6>(&FIG6);
    let case = |panel: &str, reading: Reading| {
        d.cases
            .iter()
            .find(|c| c.panel == panel && (panel == "b" || c.reading == reading))
            .unwrap()
    };
    // (b): the paper's multiple taps (two contact intervals per period) …
    let b = case("b", Reading::Homogeneous);
    assert_eq!(b.kind, OrbitKind::Periodic { m: 1, n: 2 });
    let r = b.coefficient.unwrap().value().unwrap();
    let u = b.uncertainty.unwrap();
    // … and r_E converged in N to well within the paper's printed precision (±0.005) …
    assert!(u < 0.005, "uncertainty {u}");
    // … but not the paper's 0.74: a documented mismatch (if it starts to agree, the
    // chapter and the errata must change)
    assert!((r - 0.74).abs() > 0.005 + u, "r_E = {r}");
    // the one-mode oscillator with r = r_E does not follow the 20-mode orbit: one impact
    // per period where there are two contacts, at several times the impact velocity
    let one = b.one_mode.as_ref().unwrap();
    assert_eq!(one.kind, OrbitKind::Periodic { m: 1, n: 1 });
    assert!(one.impact_velocities[0] > 2.0 * b.entry_velocities[0]);
    // (a): the text's amplitude (unit at resonance) leaves the stop out of reach at
    // ω = 1.15(β₁⁻)² (the free amplitude there is about half the resonant one)
    let text = case("a", Reading::UnitAtResonance);
    assert!(text.gap_over_free_amplitude > 1.5);
    assert_eq!(text.kind, OrbitKind::Periodic { m: 1, n: 0 });
    // no reading gives the paper's (1,1) with r_E = 0.036, and the scan stays far from it
    for c in d.cases.iter().filter(|c| c.panel == "a") {
        let matches = c.kind == OrbitKind::Periodic { m: 1, n: 1 }
            && c.coefficient
                .and_then(|r| r.value())
                .is_some_and(|r| (r - 0.036).abs() < 0.0005);
        assert!(!matches, "{:?}", c.reading);
    }
    assert!(d
        .scan
        .iter()
        .filter_map(|s| s.rest.value())
        .all(|r| (r - 0.036).abs() > 0.05));
}

#[test]
fn the_energetic_restitution_map_is_converged_where_it_is_coloured_and_thread_independent() {
    use impacting_cantilever::results::scenes::energetic_map::{
        compute, matched_modes, Cell, MapParams,
    };
    // the book's one rule: at least 10 modes, and as many as one contact needs for 1 %
    // (the same N as `cantilever modes-needed --tolerance 1e-2` reports, 25 at 10⁴k₁)
    assert_eq!(matched_modes(10.0, 0.01).unwrap(), 10);
    let needed =
        impacting_cantilever::analysis::convergence::modes_needed(1e4, 1e-2, 0.01).unwrap();
    let n = matched_modes(1e4, 0.01).unwrap();
    assert_eq!(n as f64, needed.needed.modes().ceil().max(10.0));
    assert!(n > 10, "{n}");
    let p = MapParams::test();
    let whole = cached::<EnergeticMap>(&MAP);
    // a part of the map on one thread (on a one-core machine, on two): each point is a
    // function of its own (ω, k) alone, so its cells are bitwise those of the whole map's
    // run on the global pool, whatever the thread count and the grid around it
    let part = MapParams {
        omega_over_w1: vec![2.0],
        k_over_k1: vec![10.0, 1000.0],
        ..p.clone()
    };
    let threads = if rayon::current_num_threads() >= 2 {
        1
    } else {
        2
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| compute(&part, &impacting_cantilever::results::scene::Silent).unwrap());
    assert_eq!(one.points.len(), 2);
    for a in &one.points {
        let b = whole
            .points
            .iter()
            .find(|q| q.omega_over_w1 == a.omega_over_w1 && q.k_over_k1 == a.k_over_k1)
            .unwrap();
        assert_eq!(a.cell, b.cell, "bitwise the same whatever the thread count");
    }
    // every coloured point agrees with N + 10 modes to the stated tolerance
    for q in &whole.points {
        if let Cell::Value(r) = q.cell {
            let fine = q.refined.1.unwrap().value().unwrap();
            assert!((r - fine).abs() <= p.convergence_tolerance);
            assert_eq!(q.refined.0, q.kind);
        }
    }
    // at (ω, k) = (2, 1000k₁) the map and Figure 6(b) compute the same model (N = 15
    // here, 20 there): their r_E agree within the map's convergence tolerance
    let b = whole
        .points
        .iter()
        .find(|q| q.omega_over_w1 == 2.0 && q.k_over_k1 == 1000.0)
        .unwrap();
    let Cell::Value(r) = b.cell else {
        panic!("{:?}", b.cell)
    };
    let f6 = impacting_cantilever::analysis::energetic::orbit_coefficient(
        &impacting_cantilever::engine::sim::Simulator::new(
            impacting_cantilever::model::problems::figure6b(20)
                .model()
                .unwrap(),
        )
        .unwrap(),
        &nalgebra::DVector::zeros(40),
        1000,
        40,
    )
    .unwrap();
    assert!((r - f6.coefficient.unwrap().value().unwrap()).abs() < p.convergence_tolerance);
}

#[test]
fn figure_9_contacts_and_spectrum() {
    use impacting_cantilever::analysis::orbit::OrbitKind;
    let d = cached::<Fig9>(&FIG9);
    // at d₀ = 0: four contact intervals, five penetration maxima, for every truncation
    assert_eq!(d.count.kind, OrbitKind::Periodic { m: 1, n: 4 });
    assert_eq!(d.count.maxima, Some(5.0));
    for (n, c) in &d.by_modes {
        assert_eq!(c.kind, d.count.kind, "N = {n}");
    }
    // the exact spectrum agrees with the finer DFT within that DFT's error estimate
    let (error, richardson) = d.dft_check;
    assert!(
        error <= 2.0 * richardson + 1e-12,
        "{error:e} vs {richardson:e}"
    );
    // the peaks beyond the fundamental belong to modes 2, 3 and 4
    let modes: Vec<usize> = d.peaks.iter().map(|p| p.mode).collect();
    assert_eq!(modes, vec![2, 3, 4]);
    // "significant energy in the higher modes"
    assert!(d.higher_harmonic_share > 0.1);
}
