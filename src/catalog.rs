//! The list of scenes and the glue that runs one: compute (in [`crate::scenes`]), pick the
//! key numbers, render (in [`crate::render`]). Running one scene runs nothing else.

use crate::error::ParameterError;
use crate::render::{self, RenderError};
use crate::report::KeyNumbers;
use crate::scenes;
use std::path::Path;

/// How much work a scene does: the book's full resolution, or a reduced one for tests.
/// Scenes whose full resolution is already cheap ignore it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Resolution {
    /// As in the book.
    Book,
    /// Reduced, for the test suite.
    Test,
}

/// What a scene run produces.
#[derive(Debug, Clone)]
pub struct SceneOutput {
    /// Rounded key numbers (for `--json`, snapshots and the README).
    pub key_numbers: KeyNumbers,
    /// All computed data.
    pub data: serde_json::Value,
    /// A markdown table.
    pub table: String,
    /// Further markdown tables, written as `<name>.md` beside `table.md`.
    pub extra_tables: Vec<(&'static str, String)>,
    /// An SVG plot.
    pub svg: String,
}

/// A scene failure.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// Bad parameters.
    #[error(transparent)]
    Parameter(#[from] ParameterError),
    /// Drawing failed.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// A region flow could not be built.
    #[error(transparent)]
    Flow(#[from] crate::flow::FlowError),
    /// Writing files failed.
    #[error("could not write {path}: {source}")]
    Io {
        /// The file.
        path: String,
        /// The cause.
        source: std::io::Error,
    },
}

/// One entry of the catalogue.
pub struct SceneSpec {
    /// The name used on the command line.
    pub name: &'static str,
    /// Where in the paper.
    pub paper: &'static str,
    /// What it shows.
    pub summary: &'static str,
    /// Runs it.
    pub run: fn(Resolution) -> Result<SceneOutput, SceneError>,
}

/// Every scene, in the book's order.
pub fn all() -> &'static [SceneSpec] {
    &[
        SceneSpec {
            name: "spectrum",
            paper: "§2.1, eqs (3)-(4)",
            summary: "continuum roots beta_i (free, clamped-pinned, finite k) vs golden; k2/k1; small-k law",
            run: run_spectrum,
        },
        SceneSpec {
            name: "fig2",
            paper: "Fig 2, §2.3",
            summary: "eigenvalues of K+ for N = 1, 3, 10 vs exact (beta_i+)^4; lambda_N/(kN)",
            run: run_fig2,
        },
        SceneSpec {
            name: "fig3-abc",
            paper: "Fig 3(a)-(c), §4.1-4.3",
            summary: "one contact of the compliant model, k = eps^-2, vs r_e (eq 19) and [R]_N (eq 29), N = 1, 2, 3, 10",
            run: run_fig3abc,
        },
        SceneSpec {
            name: "fig3-d",
            paper: "Fig 3(d), §4.4, eq (30)",
            summary: "post-impact velocity profile for v- = e1, r_e = 1, N = 1..100: [R]_N and [R]_C",
            run: run_fig3d,
        },
        SceneSpec {
            name: "fig4",
            paper: "Fig 4, §5.3",
            summary: "periodic orbits for N = 1, 2, 3, 10 at k = 100 k1 vs the paper's (1,1), (2,4), (1,3), (1,1)",
            run: run_fig4,
        },
        SceneSpec {
            name: "fig5",
            paper: "Fig 5, §5.3",
            summary: "bifurcation diagrams in k (impact section), N = 1, 2, 3, 10, random starts",
            run: run_fig5,
        },
        SceneSpec {
            name: "work-precision",
            paper: "§5.2 (methods)",
            summary: "error against run time: exact simulator vs DP5 reference, Fig 4 model, N = 10",
            run: run_work_precision,
        },
    ]
}

/// Looks a scene up by name.
pub fn find(name: &str) -> Result<&'static SceneSpec, ParameterError> {
    all().iter().find(|s| s.name == name).ok_or_else(|| {
        let names: Vec<&str> = all().iter().map(|s| s.name).collect();
        ParameterError::new("scene NAME", name, &format!("one of {}", names.join(", ")))
    })
}

fn to_json<T: serde::Serialize>(data: &T) -> serde_json::Value {
    serde_json::to_value(data).expect("scene data serialises")
}

fn run_spectrum(_: Resolution) -> Result<SceneOutput, SceneError> {
    let d = scenes::spectrum::compute(&Default::default())?;
    let mut k = KeyNumbers::default();
    // Roots are resolved to ~1e-15 relative; 13 figures leave margin for libm differences.
    for c in d.free.iter().filter(|c| c.i <= 5) {
        k.float(format!("beta_free_{}", c.i), c.ours, 13);
    }
    for c in d.clamped_pinned.iter().filter(|c| c.i <= 5) {
        k.float(format!("beta_pinned_{}", c.i), c.ours, 13);
    }
    k.float("k1", d.k1, 12);
    k.float("k2_over_k1", d.k2_over_k1, 10);
    // The fitted order is a regression over 7 points; 3 figures are stable.
    k.float("small_k_fitted_order", d.small_k.fitted_order, 3);
    k.float("small_k_coefficient", d.small_k.fitted_coefficient, 4);
    k.float(
        "small_k_coefficient_theory",
        d.small_k.predicted_coefficient,
        4,
    );
    Ok(SceneOutput {
        extra_tables: Vec::new(),
        key_numbers: k,
        table: render::spectrum::table(&d),
        svg: render::spectrum::plot(&d)?,
        data: to_json(&d),
    })
}

fn run_fig2(_: Resolution) -> Result<SceneOutput, SceneError> {
    let d = scenes::fig2::compute(&Default::default())?;
    let mut k = KeyNumbers::default();
    for r in &d.table {
        let key = format!("N={} k/k1={} i={}", r.modes, r.k_over_k1, r.i);
        // λ from the secular equation and (β⁺)⁴ are both good to ~1e-14 relative.
        k.float(format!("{key} lambda"), r.lambda, 10);
        k.float(format!("{key} exact"), r.exact, 10);
        // The difference of two such numbers: its absolute accuracy is ~1e-13, so it is
        // shown to 3 figures, and as round-off when below 1e-11.
        if r.rel_error.abs() < 1e-11 {
            k.text(format!("{key} rel_error"), "below 1e-11");
        } else {
            k.float(format!("{key} rel_error"), r.rel_error, 3);
        }
        if let Some(s) = r.scaled_highest {
            k.float(format!("{key} lambda_N/(kN)"), s, 8);
        }
    }
    Ok(SceneOutput {
        extra_tables: Vec::new(),
        key_numbers: k,
        table: render::fig2::table(&d),
        svg: render::fig2::plot(&d)?,
        data: to_json(&d),
    })
}

fn run_fig3abc(_: Resolution) -> Result<SceneOutput, SceneError> {
    let d = scenes::fig3abc::compute(&Default::default())?;
    let mut k = KeyNumbers::default();
    for s in &d.series {
        let key = format!("N={}", s.modes);
        k.float(format!("{key} kappa"), s.kappa, 6);
        // a regression slope over 9 points: 3 figures
        k.float(format!("{key} observed_order"), s.observed_order, 3);
        for (i, e) in d.params.eps.iter().enumerate() {
            // exact simulation of one contact: the ratios are good to ~1e-12 relative;
            // 8 figures are safe
            for (j, v) in s.simulated[i].iter().take(2).enumerate() {
                k.float(format!("{key} eps={e:.3e} mode{} ratio", j + 1), *v, 8);
            }
            k.float(format!("{key} eps={e:.3e} gap"), s.gap[i], 3);
        }
    }
    Ok(SceneOutput {
        extra_tables: Vec::new(),
        key_numbers: k,
        table: render::fig3abc::table(&d),
        svg: render::fig3abc::plot(&d)?,
        data: to_json(&d),
    })
}

fn run_fig3d(_: Resolution) -> Result<SceneOutput, SceneError> {
    let d = scenes::fig3d::compute(&Default::default())?;
    let mut k = KeyNumbers::default();
    for p in &d.profiles {
        let key = format!("{} N={}", p.law, p.modes);
        if let Some(e) = &p.error {
            k.text(format!("{key} error"), e.clone());
            continue;
        }
        // sums of O(N) terms of size O(1): good to ~1e-13; 8 figures
        for (s, v) in d.params.probes.iter().zip(&p.at_probes) {
            k.float(format!("{key} w_t({s})"), *v, 8);
        }
        k.float(format!("{key} l2_norm"), p.l2_norm, 8);
        k.float(format!("{key} l2_distance_from_phi1"), p.l2_distance, 8);
        // sampled on 801 points: 3 figures
        k.float(format!("{key} max_distance_from_phi1"), p.max_distance, 3);
    }
    Ok(SceneOutput {
        extra_tables: Vec::new(),
        key_numbers: k,
        table: render::fig3d::table(&d),
        svg: render::fig3d::plot(&d)?,
        data: to_json(&d),
    })
}

fn run_fig4(resolution: Resolution) -> Result<SceneOutput, SceneError> {
    use scenes::fig4::{compute, Fig4Params};
    let params = match resolution {
        Resolution::Book => Fig4Params::book(),
        Resolution::Test => Fig4Params::test(),
    };
    let d = compute(&params)?;
    let mut k = KeyNumbers::default();
    for p in &d.panels {
        let key = format!("N={}", p.modes);
        k.text(format!("{key} orbit"), p.kind.to_string());
        k.text(format!("{key} paper"), p.paper.to_string());
        k.text(
            format!("{key} verdict"),
            if p.kind == p.paper {
                "reproduced"
            } else {
                "not reproduced"
            },
        );
        // on a stable periodic orbit these are converged to round-off; 6 figures are safe
        for (i, v) in p.impact_velocities.iter().enumerate() {
            k.float(format!("{key} impact_velocity_{}", i + 1), *v, 6);
        }
        // sampled at 400 points per period: resolved to ~0.5%, so 2 figures
        k.float(format!("{key} max_tip"), p.max_tip, 2);
        if let Some(depth) = p.dwell_depth {
            k.float(format!("{key} dwell_depth"), depth, 2);
        }
        k.text(
            format!("{key} long_transient"),
            p.evidence.long_transient.to_string(),
        );
        k.text(
            format!("{key} loose_tolerance"),
            p.evidence.loose_tolerance.to_string(),
        );
        if let Some((n, _)) = p.evidence.reference {
            k.integer(format!("{key} reference_entries_per_orbit"), n as i64);
        }
        for (kind, count) in &p.evidence.random_starts {
            k.integer(format!("{key} random_starts {kind}"), *count as i64);
        }
        k.text(
            format!("{key} literal_caption_damping"),
            p.evidence.literal_caption.to_string(),
        );
    }
    Ok(SceneOutput {
        extra_tables: Vec::new(),
        key_numbers: k,
        table: render::fig4::table(&d),
        svg: render::fig4::plot(&d)?,
        data: to_json(&d),
    })
}

fn run_fig5(resolution: Resolution) -> Result<SceneOutput, SceneError> {
    use scenes::fig5::{compute, Fig5Params};
    let params = match resolution {
        Resolution::Book => Fig5Params::book(),
        Resolution::Test => Fig5Params::test(),
    };
    // hidden when stderr is not a terminal (CI, pipes)
    let bar = indicatif::ProgressBar::new((params.points * params.modes.len()) as u64).with_style(
        indicatif::ProgressStyle::with_template(
            "fig5 {elapsed_precise} [{bar:30}] {pos}/{len} (N, k) points, eta {eta}",
        )
        .expect("template")
        .progress_chars("=> "),
    );
    let d = compute(&params, &|| bar.inc(1))?;
    bar.finish_and_clear();
    let mut k = KeyNumbers::default();
    for g in &d.diagrams {
        // the orbit sets along k, exactly (integers): the diagram's skeleton
        let sets: Vec<String> = (0..d.k_over_k1.len())
            .map(|i| {
                g.kinds(i)
                    .iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .join("+")
            })
            .collect();
        k.text(format!("N={} orbits along k", g.modes), sets.join(" "));
    }
    let c = &d.claims;
    k.text(
        "all (1,1) at smallest k",
        c.all_one_one_at_smallest_k.to_string(),
    );
    // the velocities at the smallest k agree to round-off across N only if the higher
    // modes are not excited; 2 figures of the spread are robust
    k.float(
        "velocity spread at smallest k",
        c.velocity_spread_at_smallest_k,
        2,
    );
    let opt = |v: Option<f64>| v.map_or("never".to_string(), |x| format!("{x:.4e}"));
    k.text(
        "first orbit difference N=10 vs N=1 (k/k1)",
        opt(c.first_orbit_difference),
    );
    k.text(
        "first velocity difference N=10 vs N=1 (k/k1)",
        opt(c.first_velocity_difference),
    );
    k.float("N=3 vs N=10 orbit agreement", c.n3_n10_agreement, 4);
    k.float("N=2 vs N=10 orbit agreement", c.n2_n10_agreement, 4);
    k.text("N=3 reaches (1,3) from (k/k1)", opt(c.n3_one_three_from));
    k.integer(
        "k values matching all four Fig 4 orbits",
        c.paper_figure4_set_at.len() as i64,
    );
    k.integer(
        "k values where all four Fig 4 orbits are attractors",
        c.paper_figure4_set_reachable_at.len() as i64,
    );
    Ok(SceneOutput {
        extra_tables: Vec::new(),
        key_numbers: k,
        table: render::fig5::table(&d),
        svg: render::fig5::plot(&d)?,
        data: to_json(&d),
    })
}

fn run_work_precision(resolution: Resolution) -> Result<SceneOutput, SceneError> {
    use scenes::work_precision::{compute, WorkPrecisionParams};
    let params = match resolution {
        Resolution::Book => WorkPrecisionParams::book(),
        Resolution::Test => WorkPrecisionParams::test(),
    };
    let d = compute(&params)?;
    let mut k = KeyNumbers::default();
    // Only machine-independent numbers: event counts and whether each run reproduces the
    // reference event sequence. Errors and timings are in the table and data.json.
    k.integer("periods", params.periods as i64);
    k.integer("reference_events", d.reference_events as i64);
    for p in &d.points {
        let key = format!("{} tol={:e}", p.method, p.tolerance);
        k.integer(format!("{key} events"), p.events as i64);
        k.text(format!("{key} same_sequence"), p.same_sequence.to_string());
    }
    // Work counters of the speed-target runs, per period; 2 figures, so a last-ulp
    // difference of libm between machines (which can move one step) does not show.
    for c in &d.costs {
        let per_period = |x: u64| x as f64 / c.periods as f64;
        k.float(
            format!("{} evaluations per period", c.label),
            per_period(c.stats.evaluations),
            2,
        );
        k.float(
            format!("{} certified steps per period", c.label),
            per_period(c.stats.steps),
            2,
        );
        k.float(
            format!("{} segments per period", c.label),
            per_period(c.stats.segments),
            2,
        );
    }
    Ok(SceneOutput {
        extra_tables: vec![("costs", render::work_precision::costs_table(&d))],
        key_numbers: k,
        table: render::work_precision::table(&d),
        svg: render::work_precision::plot(&d)?,
        data: to_json(&d),
    })
}

/// Writes `plot.svg`, `table.md` (and any further tables), `data.json` and
/// `key_numbers.json` into `dir`.
pub fn write(out: &SceneOutput, dir: &Path) -> Result<(), SceneError> {
    let io = |path: &Path| {
        let path = path.display().to_string();
        move |source| SceneError::Io { path, source }
    };
    std::fs::create_dir_all(dir).map_err(io(dir))?;
    let mut files = vec![
        ("plot.svg".to_string(), out.svg.clone()),
        ("table.md".to_string(), out.table.clone()),
        (
            "data.json".to_string(),
            serde_json::to_string_pretty(&out.data).expect("json"),
        ),
        (
            "key_numbers.json".to_string(),
            serde_json::to_string_pretty(&out.key_numbers.to_json()).expect("json"),
        ),
    ];
    for (name, table) in &out.extra_tables {
        files.push((format!("{name}.md"), table.clone()));
    }
    for (name, text) in files {
        let p = dir.join(name);
        std::fs::write(&p, text).map_err(io(&p))?;
    }
    Ok(())
}
