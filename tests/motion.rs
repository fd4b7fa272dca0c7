//! Classifying motions (chaotic, quasi-periodic, periodic, undecided), checked against maps
//! whose answers are known without this project's code: the Hénon map's Lyapunov exponents
//! from the literature, a rotation attracted to the unit circle (exponents 0 and ln c,
//! rotation number ρ, period q for ρ = p/q), and the beam itself on Figure 5's torus and on a
//! stable orbit.

use impacting_cantilever::analysis::motion::{
    classify, decide, MotionClass, MotionOptions, Rotation,
};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::map::{PeriodMap, Periods};
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::error::Error;
use impacting_cantilever::model::problems;
use nalgebra::{DMatrix, DVector};

/// A map of the plane: its image and Jacobian at a point.
type Step = fn(&DVector<f64>) -> (DVector<f64>, DMatrix<f64>);

/// A smooth map of the plane as a period map with period 1.
struct PlaneMap {
    name: &'static str,
    f: Step,
}

impl PeriodMap for PlaneMap {
    fn name(&self) -> String {
        self.name.into()
    }
    fn dimension(&self) -> usize {
        2
    }
    fn period(&self) -> f64 {
        1.0
    }
    fn advance(
        &self,
        x: &DVector<f64>,
        _: i64,
        periods: u64,
        record: bool,
    ) -> Result<Periods, Error> {
        let mut out = Periods::default();
        let mut x = x.clone();
        if record {
            out.strobe.push(x.clone());
        }
        for _ in 0..periods {
            x = (self.f)(&x).0;
            if record {
                out.strobe.push(x.clone());
            }
        }
        out.state = x;
        Ok(out)
    }
    fn map_with_jacobian(
        &self,
        x: &DVector<f64>,
        m: u64,
    ) -> Result<(DVector<f64>, DMatrix<f64>, u64), Error> {
        let (mut x, mut j) = (x.clone(), DMatrix::identity(2, 2));
        for _ in 0..m {
            let (y, d) = (self.f)(&x);
            j = d * j;
            x = y;
        }
        Ok((x, j, 0))
    }
}

/// The Hénon map, a = 1.4, b = 0.3.
fn henon(x: &DVector<f64>) -> (DVector<f64>, DMatrix<f64>) {
    let (a, b) = (1.4, 0.3);
    (
        DVector::from_vec(vec![1.0 - a * x[0] * x[0] + x[1], b * x[0]]),
        DMatrix::from_row_slice(2, 2, &[-2.0 * a * x[0], 1.0, b, 0.0]),
    )
}

/// r ↦ 1 + c(r − 1), θ ↦ θ + 2πρ in Cartesian form, c = 1/2: the unit circle attracts and is
/// turned by ρ per step. Exponents 0 (along the circle) and ln c; rotation number ρ.
fn rotation_with(x: &DVector<f64>, rho: f64) -> (DVector<f64>, DMatrix<f64>) {
    let c = 0.5;
    let r = x[0].hypot(x[1]);
    let theta = x[1].atan2(x[0]);
    let (r2, t2) = (1.0 + c * (r - 1.0), theta + std::f64::consts::TAU * rho);
    let y = DVector::from_vec(vec![r2 * t2.cos(), r2 * t2.sin()]);
    // d(r2, t2)/d(r, θ) = diag(c, 1); chain through polar coordinates
    let polar =
        DMatrix::from_row_slice(2, 2, &[x[0] / r, x[1] / r, -x[1] / (r * r), x[0] / (r * r)]);
    let back = DMatrix::from_row_slice(2, 2, &[t2.cos(), -r2 * t2.sin(), t2.sin(), r2 * t2.cos()]);
    (
        y,
        back * DMatrix::from_diagonal(&DVector::from_vec(vec![c, 1.0])) * polar,
    )
}

fn golden(x: &DVector<f64>) -> (DVector<f64>, DMatrix<f64>) {
    rotation_with(x, (3.0 - 5f64.sqrt()) / 2.0)
}

fn three_sevenths(x: &DVector<f64>) -> (DVector<f64>, DMatrix<f64>) {
    rotation_with(x, 3.0 / 7.0)
}

fn options(resolution: f64) -> MotionOptions {
    MotionOptions {
        transient: 100,
        segments: 20,
        periods: 500,
        iterates: 4000,
        longest_period: 64,
        resolution,
    }
}

#[test]
fn the_henon_map_is_chaotic_with_its_published_exponent() {
    // λ₁ = 0.41922 per iteration (Sprott, Chaos and Time-Series Analysis, OUP 2003, Table
    // A.1; computed there from 10⁶ iterations and quoted to ±0.00001); λ₁ + λ₂ = ln b exactly,
    // since det J = −b everywhere
    let map = PlaneMap {
        name: "the Hénon map",
        f: henon,
    };
    let m = classify(
        &map,
        &DVector::from_vec(vec![0.1, 0.1]),
        &options(1e-3),
        &Silent,
    )
    .unwrap();
    assert_eq!(m.class, MotionClass::Chaotic);
    assert!(
        (m.exponents[0] - 0.41922).abs() <= m.half_widths[0] + 1e-5,
        "{m:?}"
    );
    assert!(m.half_widths[0] < 1e-2, "{m:?}");
    assert!(
        (m.exponents[0] + m.exponents[1] - 0.3f64.ln()).abs() < 1e-12,
        "{m:?}"
    );
    assert_eq!(m.period_m, None);
}

#[test]
fn an_irrational_rotation_on_an_attracting_circle_is_quasi_periodic() {
    let map = PlaneMap {
        name: "a rotation",
        f: golden,
    };
    let m = classify(
        &map,
        &DVector::from_vec(vec![0.3, 0.2]),
        &options(1e-3),
        &Silent,
    )
    .unwrap();
    assert_eq!(m.class, MotionClass::QuasiPeriodic, "{m:?}");
    // along the circle the map is an isometry: λ₁ = 0 to round-off per step
    assert!(m.exponents[0].abs() < 1e-12, "{m:?}");
    assert!((m.exponents[1] - 0.5f64.ln()).abs() < 1e-12, "{m:?}");
    // ρ = (3 − √5)/2 = 0.381966…: measured about the iterates' mean, not the circle's centre,
    // the angle turned over the record is within a turn of the true one's, so ρ is within
    // 1/(iterates) of it
    assert!(
        (m.rotation.turns - (3.0 - 5f64.sqrt()) / 2.0).abs() < 1.0 / 4000.0,
        "{m:?}"
    );
    assert!(m.rotation.halves_differ < 2.0 / 2000.0);
}

#[test]
fn a_rational_rotation_is_periodic_with_its_denominator() {
    let map = PlaneMap {
        name: "a rotation",
        f: three_sevenths,
    };
    let m = classify(
        &map,
        &DVector::from_vec(vec![0.3, 0.2]),
        &options(1e-3),
        &Silent,
    )
    .unwrap();
    assert_eq!(m.class, MotionClass::Periodic, "{m:?}");
    assert_eq!(m.period_m, Some(7));
    assert!((m.rotation.turns - 3.0 / 7.0).abs() < 1.0 / 4000.0, "{m:?}");
}

#[test]
fn the_rule_needs_a_narrow_interval_to_call_a_motion_quasi_periodic() {
    let ring = Rotation {
        turns: 0.3,
        halves_differ: 1e-4,
    };
    // λ₁ = 0 ± 0.01 with a resolution of 0.005: a torus and weak chaos are not told apart
    assert_eq!(
        decide([0.0, -0.1], [0.01, 0.01], None, ring, 5e-3),
        MotionClass::Undecided
    );
    assert_eq!(
        decide([0.0, -0.1], [0.004, 0.01], None, ring, 5e-3),
        MotionClass::QuasiPeriodic
    );
    // an interval off zero by round-off only is inside the resolution: still a torus
    assert_eq!(
        decide([1e-16, -0.1], [1e-18, 0.01], None, ring, 5e-3),
        MotionClass::QuasiPeriodic
    );
    // positive, but not resolved above the resolution: not called chaotic
    assert_eq!(
        decide([0.004, -0.1], [0.002, 0.01], None, ring, 5e-3),
        MotionClass::Undecided
    );
    // the transverse exponent not resolved below zero
    assert_eq!(
        decide([0.0, -0.004], [0.002, 0.002], None, ring, 5e-3),
        MotionClass::Undecided
    );
    // the halves of the record turning differently: no invariant curve
    let drifting = Rotation {
        turns: 0.3,
        halves_differ: 0.05,
    };
    assert_eq!(
        decide([0.0, -0.1], [0.004, 0.01], None, drifting, 5e-3),
        MotionClass::Undecided
    );
    // converging without a period found (a longer period or a slow transient)
    assert_eq!(
        decide([-0.05, -0.1], [0.004, 0.01], None, ring, 5e-3),
        MotionClass::Undecided
    );
    assert_eq!(
        decide([0.02, -0.1], [0.01, 0.01], None, ring, 5e-3),
        MotionClass::Chaotic
    );
    assert_eq!(
        decide([0.02, -0.1], [0.01, 0.01], Some(12), ring, 5e-3),
        MotionClass::Periodic
    );
}

#[test]
fn the_beam_in_figure_5s_band_is_quasi_periodic_and_on_a_stable_orbit_periodic() {
    // N = 10, ω = 2(β₁⁻)², k = 10k₁: between the (1,1) branch's Neimark–Sacker pair (8.31k₁
    // and 17.6k₁ in Figure 5), where the rotation numbers at the pair are 0.276 and 0.232
    let f = problems::Forced {
        k_over_k1: 10.0,
        ..problems::figure4(10)
    };
    let sim = Simulator::new(f.model().unwrap()).unwrap();
    let resolution = sim.model().damping()[0] / 8.0;
    let o = MotionOptions {
        transient: 300,
        segments: 20,
        periods: 50,
        iterates: 1000,
        longest_period: 64,
        resolution,
    };
    let m = classify(&sim, &sim.rest(), &o, &Silent).unwrap();
    assert_eq!(m.class, MotionClass::QuasiPeriodic, "{m:?}");
    assert!(m.rotation.turns > 0.2 && m.rotation.turns < 0.3, "{m:?}");
    // on the stable (1,1) orbit of Figure 4 at N = 3: period 1, every exponent negative
    let sim = Simulator::new(problems::figure4(3).model().unwrap()).unwrap();
    let m = classify(&sim, &sim.rest(), &o, &Silent).unwrap();
    assert_eq!(
        (m.class, m.period_m),
        (MotionClass::Periodic, Some(1)),
        "{m:?}"
    );
    assert!(m.exponents[0] + m.half_widths[0] < 0.0);
}

#[test]
fn bad_options_are_refused_naming_them() {
    let map = PlaneMap {
        name: "a rotation",
        f: golden,
    };
    let x = DVector::from_vec(vec![0.3, 0.2]);
    let bad = |o: MotionOptions| classify(&map, &x, &o, &Silent).unwrap_err().to_string();
    assert!(bad(MotionOptions {
        iterates: 10,
        ..options(1e-3)
    })
    .contains("iterates"));
    assert!(bad(MotionOptions {
        resolution: f64::NAN,
        ..options(1e-3)
    })
    .contains("resolution"));
    assert!(bad(MotionOptions {
        segments: 1,
        ..options(1e-3)
    })
    .contains("segments"));
}

#[test]
fn the_command_line_classifies_as_the_library_does_and_refuses_bad_options() {
    // Figure 5's band at k = 10k₁, N = 10, with the book's options (the atlas's)
    let f = problems::Forced {
        k_over_k1: 10.0,
        ..problems::figure4(10)
    };
    let sim = Simulator::new(f.model().unwrap()).unwrap();
    let book = MotionOptions::for_model(sim.model(), 300);
    let m = classify(&sim, &sim.rest(), &book, &Silent).unwrap();
    let args = [
        "motion",
        "--modes",
        "10",
        "--zeta1",
        "0.01",
        "--omega",
        "2",
        "--stop-stiffness",
        "10",
        "--json",
    ];
    let (code, out, err) = crate::common::cli::cantilever(&args);
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(doc["class"], "quasi-periodic");
    // the same computation: the same numbers to the bit
    assert_eq!(doc["exponents"][0].as_f64().unwrap(), m.exponents[0]);
    assert_eq!(doc["half_widths"][1].as_f64().unwrap(), m.half_widths[1]);
    assert_eq!(doc["rotation"]["turns"].as_f64().unwrap(), m.rotation.turns);
    assert_eq!(
        doc["options"]["resolution"].as_f64().unwrap(),
        book.resolution
    );
    // bad options: exit 2 and one line naming the flag
    for (flag, value) in [
        ("--transient", "1e9"),
        ("--segment-periods", "0"),
        ("--segments", "1"),
        ("--iterates", "2000000"),
        ("--resolution", "-1"),
    ] {
        let mut a: Vec<&str> = args[..9].to_vec();
        a.extend([flag, value]);
        let (code, _, err) = crate::common::cli::cantilever(&a);
        assert_eq!(code, 2, "{flag} {value}: {err}");
        assert!(
            err.contains(flag) && err.lines().count() == 1,
            "{flag}: {err}"
        );
    }
}
