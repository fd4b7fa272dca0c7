//! The atlas's boundary curves: the edge and crossing geometry on a hand-made atlas (exact);
//! on a small atlas, each curve checked where it crosses a row by a one-parameter run in ω
//! of the orbit on the curve's side (it meets the same kind of bifurcation between the two
//! cells, where the curve says); the curves do not depend on the thread count; each edge
//! checked across is one the curves leave, and what its check meets lies between its cells,
//! where a full run across the edge finds it too.

use impacting_cantilever::analysis::atlas::curves::{
    self, left, Band, BoundaryCurve, BoundaryCurves, CurveSearch, EdgeClass, FailedSeed, Left,
};
use impacting_cantilever::analysis::atlas::{
    self, cell::CellSearch, AtlasData, AtlasParams, Attractor, Cell, ModesRule, Row,
};
use impacting_cantilever::analysis::continuation::{
    self, BifurcationKind, Family, Parameter, Settings,
};
use impacting_cantilever::analysis::curves::{self as curves2, CurveKind, CurveSettings, Family2};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::sim::Simulator;
use nalgebra::DVector;

fn orbit(m: u64, n: usize) -> Attractor {
    Attractor {
        period_m: m,
        impacts_n: n,
        spectral_radius: 0.5,
        continued: false,
        starts: vec![0],
        impact_velocities: vec![1.0; n],
    }
}

/// A cell whose orbit from rest is the first of `orbits`.
fn cell(orbits: &[(u64, usize)]) -> Cell {
    Cell {
        attractors: orbits.iter().map(|&(m, n)| orbit(m, n)).collect(),
        from_rest: Some(0),
        unsettled_starts: 0,
        check: None,
        motion: None,
    }
}

#[test]
fn edges_and_crossings_on_a_hand_made_atlas() {
    // 2 k × 3 ω; from rest:   row 0: (1,1) (1,1) (1,2)
    //                         row 1: (1,1) (2,2) (1,2), where (1,1) is stable too
    let params = AtlasParams {
        modes: ModesRule::Fixed(2),
        k_over_k1_range: (1.0, 10.0),
        k_points: 2,
        omega_range: (1.0, 3.0),
        omega_points: 3,
        ..AtlasParams::test()
    };
    let row = |index, k, cells| Row {
        index,
        k_over_k1: k,
        modes: 2,
        cells,
    };
    let d = AtlasData {
        omega_over_w1: vec![1.0, 2.0, 3.0],
        rows: vec![
            row(
                0,
                1.0,
                vec![cell(&[(1, 1)]), cell(&[(1, 1)]), cell(&[(1, 2)])],
            ),
            row(
                1,
                10.0,
                vec![cell(&[(1, 1)]), cell(&[(2, 2), (1, 1)]), cell(&[(1, 2)])],
            ),
        ],
        params,
        curves: None,
    };
    // a straight curve at ω = 2.6 (grid column 1.6) over both rows, with a point between
    let curve = BoundaryCurve {
        kind: "grazing".into(),
        modes: 2,
        orbit: (1, 1),
        seed: ((0, 1), (0, 2)),
        points: vec![(2.6, 1.0), (2.6, 3.0), (2.6, 10.0)],
        residuals: (0.0, 0.0),
        test_residual_off_folds: 0.0,
        // its orbit unstable from its second point on
        unstable: vec![false, true, true],
        meetings: Vec::new(),
        ends: (
            "left the parameter rectangle".into(),
            "left the parameter rectangle".into(),
        ),
    };
    let c = BoundaryCurves {
        search: CurveSearch {
            max_curves: 1,
            max_seeds: 1,
            max_points: 2,
            round: 1,
            edge_sample: 0,
        },
        bands: vec![Band {
            rows: (0, 2),
            modes: 2,
        }],
        curves: vec![curve],
        failed: Vec::new(),
        duplicates: 0,
        checked: Vec::new(),
    };
    let edges = curves::edges(&d, &c);
    let find = |a, b| edges.iter().find(|e| e.a == a && e.b == b).unwrap();
    assert_eq!(edges.len(), 4, "{edges:?}");
    // (1,1)|(1,2): neither stable on the other side; the curve passes 0.1 steps from its
    // midpoint (column 1.5)
    assert_eq!(find((0, 1), (0, 2)).class, EdgeClass::Bifurcation);
    let (n, dist) = find((0, 1), (0, 2)).curve.unwrap();
    assert!(n == 0 && (dist - 0.1).abs() < 1e-12, "{dist}");
    assert_eq!(find((1, 1), (1, 2)).class, EdgeClass::Bifurcation);
    // rest moves from (1,1) to (2,2) while (1,1) stays stable: basin edges; the one along
    // ω has its midpoint at column 0.5, 1.1 steps from the curve (not within one step),
    // the one along k at (1, 0.5), 0.6 steps from it
    let along_omega = find((1, 0), (1, 1));
    assert_eq!(along_omega.class, EdgeClass::Basin);
    assert_eq!(along_omega.curve, None);
    let along_k = find((0, 1), (1, 1));
    assert_eq!(along_k.class, EdgeClass::Basin);
    let (n, dist) = along_k.curve.unwrap();
    assert_eq!(n, 0);
    assert!((dist - 0.6).abs() < 1e-12, "{dist}");
    // the curve crosses the two edges along ω between columns 1 and 2, nothing else
    let crossed = curves::crossings(&d, &c);
    let cells: Vec<_> = crossed.iter().map(|x| x.cells).collect();
    assert_eq!(cells, vec![((0, 1), (0, 2)), ((1, 1), (1, 2))]);
    assert!(crossed.iter().all(|x| x.rest_differs && x.stable_differs));
    // row 0 is crossed by the segment from its first point (stable) to its second, row 1
    // by the one between two unstable points
    let unstable: Vec<_> = crossed.iter().map(|x| x.orbit_unstable).collect();
    assert_eq!(unstable, vec![Some(false), Some(true)]);
}

#[test]
fn bands_of_one_n_and_why_each_edge_is_left_on_a_hand_made_atlas() {
    // 3 k × 4 ω, N = 2 on rows 0 and 1, N = 3 on row 2; from rest ("-": no stable orbit;
    // in row 0's last cell (1,2) is stable too):
    //   row 0: (1,1) (1,2) (1,2) (2,2)
    //   row 1: (1,1)  -   (1,2) (1,2)
    //   row 2: (2,2)  -   (1,2) (3,3)
    let params = AtlasParams {
        modes: ModesRule::Fixed(2),
        k_over_k1_range: (1.0, 100.0),
        k_points: 3,
        omega_range: (1.0, 2.5),
        omega_points: 4,
        ..AtlasParams::test()
    };
    let none = Cell {
        from_rest: None,
        ..cell(&[])
    };
    let row = |index, k, modes, cells| Row {
        index,
        k_over_k1: k,
        modes,
        cells,
    };
    let d = AtlasData {
        omega_over_w1: vec![1.0, 1.5, 2.0, 2.5],
        rows: vec![
            row(
                0,
                1.0,
                2,
                vec![
                    cell(&[(1, 1)]),
                    cell(&[(1, 2)]),
                    cell(&[(1, 2)]),
                    cell(&[(2, 2), (1, 2)]),
                ],
            ),
            row(
                1,
                10.0,
                2,
                vec![
                    cell(&[(1, 1)]),
                    none.clone(),
                    cell(&[(1, 2)]),
                    cell(&[(1, 2)]),
                ],
            ),
            row(
                2,
                100.0,
                3,
                vec![cell(&[(2, 2)]), none, cell(&[(1, 2)]), cell(&[(3, 3)])],
            ),
        ],
        params,
        curves: None,
    };
    let bands = curves::bands(&d);
    assert_eq!(
        bands,
        vec![
            Band {
                rows: (0, 2),
                modes: 2
            },
            Band {
                rows: (2, 3),
                modes: 3
            }
        ]
    );
    // no curve; the seed of (1,1)|(1,2) in row 0 failed
    let c = BoundaryCurves {
        search: CurveSearch {
            max_curves: 1,
            max_seeds: 1,
            max_points: 2,
            round: 1,
            edge_sample: 0,
        },
        bands,
        curves: Vec::new(),
        failed: vec![FailedSeed {
            seed: ((0, 0), (0, 1)),
            why: "none met".into(),
        }],
        duplicates: 0,
        checked: Vec::new(),
    };
    let edges = curves::edges(&d, &c);
    assert_eq!(edges.len(), 11, "{edges:?}");
    let changes: Vec<_> = edges
        .iter()
        .filter(|e| e.modes_change)
        .map(|e| (e.a, e.b))
        .collect();
    assert_eq!(changes, vec![((1, 0), (2, 0)), ((1, 3), (2, 3))]);
    let why = |a, b| {
        let e = edges.iter().find(|e| e.a == a && e.b == b).unwrap();
        left(&d, &c, e).unwrap()
    };
    assert_eq!(why((0, 0), (0, 1)), Left::SeedFailed);
    assert_eq!(why((0, 2), (0, 3)), Left::Basin);
    assert_eq!(why((0, 3), (1, 3)), Left::Basin);
    assert_eq!(why((0, 1), (1, 1)), Left::NotPeriodic);
    assert_eq!(why((1, 0), (2, 0)), Left::ModesChange);
    assert_eq!(why((2, 2), (2, 3)), Left::NotSeeded);
    let count = |r| edges.iter().filter(|e| left(&d, &c, e) == Some(r)).count();
    assert_eq!(
        Left::ALL.map(count),
        [2, 2, 5, 1, 1],
        "modes change, basin, not periodic, seed failed, not seeded"
    );
}

/// A small atlas at N = 2 over the rectangle of the `boundaries` chapter, where the (1,1)
/// orbit of Figure 4 doubles its period and grazes.
fn small() -> AtlasParams {
    AtlasParams {
        modes: ModesRule::Fixed(2),
        k_over_k1_range: (30.0, 300.0),
        k_points: 6,
        omega_range: (1.9, 3.2),
        omega_points: 12,
        starts: 2,
        check_stride: 4096,
        check_starts: 1,
        curves: CurveSearch {
            max_curves: 3,
            max_seeds: 6,
            max_points: 40,
            round: 2,
            edge_sample: 4,
        },
        ..AtlasParams::test()
    }
}

fn bifurcation_kind(kind: &str) -> BifurcationKind {
    match kind {
        "grazing" => BifurcationKind::Grazing,
        "period doubling" => BifurcationKind::PeriodDoubling,
        "fold" => BifurcationKind::Fold,
        _ => BifurcationKind::NeimarkSacker,
    }
}

/// The curve's ω where it crosses k (linear in ln k between its two points that bracket it).
fn omega_at(curve: &BoundaryCurve, k: f64) -> Vec<f64> {
    curve
        .points
        .windows(2)
        .filter(|w| (w[0].1 - k) * (w[1].1 - k) <= 0.0 && w[0].1 != w[1].1)
        .map(|w| {
            let t = (k / w[0].1).ln() / (w[1].1 / w[0].1).ln();
            w[0].0 + t * (w[1].0 - w[0].0)
        })
        .collect()
}

/// The orbit from rest of cell `at` of atlas `p` at (k, ω) with N modes, continued in
/// `parameter` from p0 to p1 with the seeds' steps (at least four points between): its
/// (m, n) and the branch.
fn continued_across(
    p: &AtlasParams,
    modes: usize,
    at: (usize, usize),
    (k, omega): (f64, f64),
    parameter: Parameter,
    (p0, p1): (f64, f64),
) -> ((u64, usize), continuation::Branch) {
    let forced = p.model(modes, k, omega).unwrap();
    let sim = Simulator::new(forced.model().unwrap()).unwrap();
    let o = CellSearch::new(p, &sim, at).from_start(0).unwrap().unwrap();
    let range = (p0.min(p1), p0.max(p1));
    let settings = Settings {
        max_step: (range.1 / range.0).ln() / 4.0,
        initial_step: (range.1 / range.0).ln() / 8.0,
        ..Settings::new(range)
    };
    let branch = continuation::continue_branch(
        &Family::forced(forced, parameter),
        &DVector::from_vec(o.state),
        p0,
        o.period_m,
        if p1 > p0 { 1.0 } else { -1.0 },
        &settings,
    )
    .unwrap();
    ((o.period_m, o.impacts_n), branch)
}

#[test]
fn every_curve_is_where_a_one_parameter_run_finds_its_bifurcation() {
    let p = small();
    let d = atlas::compute(&p, &Silent).unwrap();
    let c = d.curves.as_ref().unwrap();
    assert!(!c.curves.is_empty(), "no curve traced: {:?}", c.failed);
    let step = d.omega_over_w1[1] - d.omega_over_w1[0];
    let mut checked = 0;
    for (n, curve) in c.curves.iter().enumerate() {
        // every point solves its condition: polished orbits, test residuals near round-off
        // (a fold's multiplier approaches 1 as the square root of the distance: 1e-5)
        assert!(curve.residuals.0 <= 1e-11, "{curve:?}");
        let allowed = if curve.kind == "fold" { 1e-5 } else { 1e-9 };
        assert!(curve.residuals.1 <= allowed, "{curve:?}");
        for x in curves::crossings(&d, c).iter().filter(|x| x.curve == n) {
            let ((i, j0), (i1, j1)) = x.cells;
            if i != i1 || !x.rest_differs {
                continue;
            }
            // the side whose orbit from rest is the curve's, continued towards the other
            let label = |j: usize| curves::label(&d.rows[i].cells[j]);
            let (from, to) = if label(j0) == Some(curve.orbit) {
                (j0, j1)
            } else if label(j1) == Some(curve.orbit) {
                (j1, j0)
            } else {
                continue;
            };
            let k = d.rows[i].k_over_k1;
            let (w0, w1) = (d.omega_over_w1[from], d.omega_over_w1[to]);
            let (_, branch) =
                continued_across(&p, 2, (i, from), (k, w0), Parameter::Frequency, (w0, w1));
            let kind = bifurcation_kind(&curve.kind);
            let found: Vec<f64> = branch
                .bifurcations
                .iter()
                .filter(|b| b.kind == kind)
                .map(|b| b.parameter)
                .collect();
            let on_curve = omega_at(curve, k);
            // the run meets the curve's bifurcation between the cells, within one step of
            // where the curve crosses this row
            assert!(
                found.iter().any(|w| on_curve.iter().any(|c| (c - w).abs() <= step)),
                "curve {n} ({}) at k = {k}: the run finds {found:?}, the curve crosses at {on_curve:?}",
                curve.kind
            );
            checked += 1;
        }
    }
    assert!(checked >= 2, "only {checked} crossings checked");
}

#[test]
fn curves_do_not_depend_on_the_thread_count() {
    let p = AtlasParams {
        k_points: 4,
        omega_points: 8,
        ..small()
    };
    let rows = atlas::merge(vec![
        atlas::compute_shard(&p, atlas::Shard::WHOLE, &Silent).unwrap()
    ])
    .unwrap();
    let two = atlas::with_curves(rows.clone(), &Silent).unwrap();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| atlas::with_curves(rows, &Silent).unwrap());
    assert_eq!(
        serde_json::to_string(&one.curves).unwrap(),
        serde_json::to_string(&two.curves).unwrap()
    );
    let two = two.curves.unwrap();
    assert!(!two.curves.is_empty());
    assert_eq!(
        two.checked.len(),
        4,
        "the edges checked across are compared too"
    );
}

#[test]
fn each_checked_edge_is_left_by_the_curves_and_meets_its_bifurcation_between_its_cells() {
    let p = AtlasParams {
        curves: CurveSearch {
            max_curves: 1,
            edge_sample: 6,
            ..small().curves
        },
        ..small()
    };
    let d = atlas::compute(&p, &Silent).unwrap();
    let c = d.curves.as_ref().unwrap();
    let edges = curves::edges(&d, c);
    let pool: Vec<_> = edges
        .iter()
        .filter(|e| {
            matches!(
                left(&d, c, e),
                Some(Left::NotPeriodic | Left::SeedFailed | Left::NotSeeded)
            )
        })
        .collect();
    assert!(pool.len() > 6, "only {} edges to sample", pool.len());
    assert_eq!(c.checked.len(), 6);
    let mut located = 0;
    for (n, x) in c.checked.iter().enumerate() {
        let (from, to) = x.cells;
        assert!(
            c.checked[..n].iter().all(|y| y.cells != x.cells),
            "{x:?} drawn twice"
        );
        let e = pool
            .iter()
            .find(|e| (e.a, e.b) == (from, to) || (e.a, e.b) == (to, from))
            .unwrap_or_else(|| panic!("{x:?} is not an edge the curves leave"));
        assert_eq!(x.left, left(&d, c, e).unwrap().key());
        let cell = |(i, j): (usize, usize)| &d.rows[i].cells[j];
        // the side continued: its orbit from rest is not stable on the other side
        assert_eq!(x.orbit, curves::label(cell(from)), "{x:?}");
        let orbit = x.orbit.unwrap();
        assert!(
            !cell(to)
                .attractors
                .iter()
                .any(|a| (a.period_m, a.impacts_n) == orbit),
            "{x:?}"
        );
        let Some((kind, at)) = &x.meets else { continue };
        located += 1;
        let (parameter, p0, p1) = if from.0 == to.0 {
            let w = &d.omega_over_w1;
            (Parameter::Frequency, w[from.1], w[to.1])
        } else {
            let k = |i: usize| d.rows[i].k_over_k1;
            (Parameter::StopStiffness, k(from.0), k(to.0))
        };
        assert!(
            (p0.min(p1)..=p0.max(p1)).contains(at),
            "{x:?}: {at} not between {p0} and {p1}"
        );
        // a run of the whole edge, not stopped at its first bifurcation, finds it there
        let at_cell = (d.rows[from.0].k_over_k1, d.omega_over_w1[from.1]);
        let (_, branch) = continued_across(&p, 2, from, at_cell, parameter, (p0, p1));
        let first = branch.bifurcations.first().unwrap();
        assert_eq!(first.kind.to_string(), *kind, "{x:?}");
        // the same run up to its first bifurcation: the same point, to round-off
        assert!(
            (first.parameter - at).abs() <= 1e-12 * at,
            "{x:?}: the whole run finds it at {}",
            first.parameter
        );
    }
    assert!(located >= 3, "only {located} of 6 located: {:?}", c.checked);
}

/// The book atlas's grazing curve of the (1,1) orbit seeded at row 43, columns 59 to 60
/// (N = 10): it stalls at both ends where another extremum of the tip comes as near the
/// stop as the grazing one. Its points' test residuals were 1e-7 at a few points near the
/// ends while the search for the extremum nearest the stop refined only the bracket whose
/// samples were nearest the stop, which there can be the other extremum's.
#[test]
fn a_grazing_curve_where_two_extrema_near_the_stop_keeps_its_condition_to_round_off() {
    let p = AtlasParams::book();
    let (row, from, to) = (43, 59, 60);
    let k = p.k_over_k1(row);
    let (w0, w1) = (p.omega_over_w1(from), p.omega_over_w1(to));
    let (label, branch) =
        continued_across(&p, 10, (row, from), (k, w0), Parameter::Frequency, (w0, w1));
    assert_eq!(label, (1, 1));
    let bif = &branch.bifurcations[0];
    assert_eq!(bif.kind, BifurcationKind::Grazing);
    let forced = p.model(10, k, w0).unwrap();
    let family = Family2::forced(forced, Parameter::Frequency, Parameter::StopStiffness).unwrap();
    let band = (p.k_over_k1(0), p.k_over_k1(88));
    let curve = curves2::trace_curve(
        &family,
        CurveKind::Grazing,
        &DVector::from_vec(branch.points[bif.index].state.clone()),
        (bif.parameter, k),
        1,
        &CurveSettings {
            max_points: 120,
            max_step: 0.2,
            ..CurveSettings::new(p.omega_range, band)
        },
        &Silent,
    )
    .unwrap();
    assert!(curve.points.len() > 40, "{} points", curve.points.len());
    // the orbit's shooting residual and the condition, as on the small atlas's curves
    for q in &curve.points {
        assert!(q.orbit_residual <= 1e-11, "{q:?}");
        assert!(
            q.test_residual <= 1e-9,
            "at (ω, k) = ({}, {}): the tip's extremum is {:e} of A_free from the stop",
            q.p,
            q.q,
            q.test_residual
        );
    }
}
