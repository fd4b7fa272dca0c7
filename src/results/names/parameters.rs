//! A scene's parameters in words and units, as a citation prints them: "stop stiffness k:
//! 100k₁" rather than `"k_over_k1":100.0`. Every field of every scene's parameters has an
//! entry below (a test fails for one without); the JSON stays what `--json` prints.

use serde_json::Value;

/// How a field's value is read: its name in words and the unit written after each number.
struct Field {
    code: &'static str,
    words: &'static str,
    unit: &'static str,
}

const fn f(code: &'static str, words: &'static str, unit: &'static str) -> Field {
    Field { code, words, unit }
}

/// Stiffness in units of k₁, frequency in units of (β₁⁻)², the gap in units of A_free.
const K: &str = "k₁";
const W: &str = "(β₁⁻)²";

/// The fields, by the name they have in the parameters' JSON. A name that means different
/// things in two scenes is listed as `scene/name` for the one that differs.
const FIELDS: &[Field] = &[
    f("modes", "modal truncations N", ""),
    f("atlas/modes", "modes N at each k", ""),
    f("basins/modes", "modes N", ""),
    f("fig6/modes", "modes N", ""),
    f("fig9/modes", "modes N", ""),
    f("work-precision/modes", "modes N", ""),
    f("Matched", "matched to the stop by stiffness matching", ""),
    f("tolerance", "to a relative accuracy", ""),
    f("stride", "recomputed every", " k values"),
    f("minimum", "at least", " modes"),
    f("k_over_k1", "stop stiffness k", K),
    f("k_over_k1_range", "stop stiffness k from … to", K),
    f("k_points", "k values", ""),
    f("k_range", "stop stiffness k from … to", K),
    f("omega_over_w1", "forcing frequency ω", W),
    f("omega_range", "forcing frequency ω from … to", W),
    f("omega_points", "ω values", ""),
    f("omegas", "forcing frequencies ω", W),
    f("zeta1", "modal damping ratio ζ₁", ""),
    f("gap", "gap d₀", " A_free"),
    f("starts", "starts per point (the first at rest)", ""),
    f("fig5/starts", "starts per k (the first at rest)", ""),
    f("transient", "periods discarded", ""),
    f("max_period", "longest period m searched", ""),
    f("seed", "random seed", ""),
    f("check_extra_modes", "modes added in the check", ""),
    f("check_stride", "checked every", " rows and columns"),
    f("check_starts", "further starts in the check", ""),
    f("curves", "boundary curves", ""),
    f("max_curves", "at most", " curves"),
    f("max_seeds", "at most", " seeds"),
    f("max_points", "points each way along a curve, at most", ""),
    f("round", "seeds traced together", ""),
    f(
        "edge_sample",
        "edges left by the curves checked one by one",
        "",
    ),
    f("atlas", "the atlas", ""),
    f("cell", "the cell (k index, ω index)", ""),
    f("points", "grid points per side", ""),
    f("fig5/points", "k values", ""),
    f(
        "extent",
        "starts within ± (in units of the orbit's size)",
        "",
    ),
    f("seed_k", "curves started at k", K),
    f("seed_omega_to", "the one-parameter run goes up to ω", W),
    f("table_k", "curves compared at k", K),
    f(
        "boundaries/tolerance",
        "convergence criterion (relative accuracy)",
        "",
    ),
    f("window", "periods over which the orbit is labelled", ""),
    f("extra_modes", "modes added for the convergence check", ""),
    f(
        "convergence_tolerance",
        "r_E changes above this mark a point unconverged",
        "",
    ),
    f("problem", "the problem", ""),
    f(
        "printed_eq37_amplitude",
        "eq (37)'s forcing amplitude as printed",
        "",
    ),
    f("settling", "the transient", ""),
    f("chunk", "periods per chunk of the transient", ""),
    f("max", "periods discarded at most", ""),
    f("harmonics", "harmonics of the spectrum", ""),
    f("samples_per_period", "samples per period of the plot", ""),
    f("points_per_decade", "grid points per decade", ""),
    f("table_k_over_k1", "table at k", K),
    f("eps", "ε", ""),
    f("restitution/eps", "ε", ""),
    f("alpha", "viscous damping α", ""),
    f("fit_range", "order fitted over ε from … to", ""),
    f("restitution", "coefficient of restitution r_e", ""),
    f("samples", "sample points along the beam", ""),
    f("probes", "values tabulated at s", ""),
    f(
        "cases",
        "truncations N with the paper's orbits (N, m, n)",
        "",
    ),
    f("dense_per_period", "samples per period for the plots", ""),
    f(
        "long_transient",
        "periods discarded in the longer-transient check",
        "",
    ),
    f(
        "loose_root_tolerance",
        "root tolerance of the looser check",
        "",
    ),
    f(
        "reference_rtol",
        "relative tolerance of the Dormand–Prince cross-check",
        "",
    ),
    f("random_starts", "random starts per case", ""),
    f(
        "literal_caption_zeta1",
        "ζ₁ of the caption's literal damping reading",
        "",
    ),
    f("recorded", "periods recorded", ""),
    f("branch_step", "largest continuation step (in ln k)", ""),
    f("branch_seeds", "attractors that seed a branch, at most", ""),
    f(
        "convergence_modes",
        "truncations N of the convergence check",
        "",
    ),
    f("scan", "scanned gaps d₀", " A_free"),
    f("scan_modes", "modes N of the scans", ""),
    f("fig6/scan_modes", "modes N of the scan", ""),
    f("max_transient", "periods discarded at most", ""),
    f("dft_samples", "samples per period of the spectrum", ""),
    f("scan_gap", "scanned gaps d₀", " A_free"),
    f("scan_k", "scanned stop stiffnesses k", K),
    f("scan_omega", "scanned forcing frequencies ω", W),
    f("scan_n", "modes N of the other scans", ""),
    f(
        "scan_max_transient",
        "periods discarded at most in a scan",
        "",
    ),
    f("nordmark_k", "stop stiffnesses k of the orbits", K),
    f("nordmark_omega", "forcing frequencies ω of the orbits", W),
    f("recompute", "problems recomputed by this project", ""),
    f("recompute_orbits", "orbits recomputed, N", ""),
    f("curve_modes", "modes drawn", ""),
    f("small_k_ladder", "small stop stiffnesses k of the fit", K),
    f("periods", "forcing periods simulated", ""),
    f("elements", "finite elements", ""),
    f("two_basis_modes", "modes N of the two-basis model", ""),
    f("loss_modes", "modes N of the energy-loss runs", ""),
    f("orbit_modes", "modes N of the periodic orbits", ""),
    f(
        "orbit_elements",
        "finite elements of the periodic orbits",
        "",
    ),
    f("tolerances", "relative accuracies for N*", ""),
    f("profile_k", "stiffness of the profile check k", K),
    f("profile_modes", "modes N of the profile check", ""),
    f("root_tolerances", "root tolerances of the exact engine", ""),
    f("rtols", "relative tolerances of Dormand–Prince", ""),
    f("repeats", "timing repeats", ""),
    f("cost_periods", "periods of the cost runs", ""),
    f("scaling", "the cost's scaling", ""),
    f("stiffness", "stop stiffnesses k", K),
];

/// The entry of field `code` in scene `scene`.
fn field(scene: &str, code: &str) -> Option<&'static Field> {
    let scoped = format!("{scene}/{code}");
    FIELDS
        .iter()
        .find(|f| f.code == scoped)
        .or_else(|| FIELDS.iter().find(|f| f.code == code))
}

/// A number as typed: 100 not 100.0, 0.01, 1e-8.
fn plain(x: f64) -> String {
    if x.fract() == 0.0 && x.abs() < 1e4 {
        format!("{x:.0}")
    } else if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e4) {
        super::number(&format!("{x:e}"))
    } else {
        format!("{x}")
    }
}

/// A value with its unit; a long list by its count and ends.
fn value(v: &Value, unit: &str, scene: &str, missing: &mut Vec<String>) -> String {
    match v {
        Value::Number(n) => n.as_f64().map_or(n.to_string(), plain) + unit,
        Value::Bool(b) => (if *b { "yes" } else { "no" }).to_string(),
        Value::String(s) => s.clone(),
        Value::Null => "none".to_string(),
        Value::Array(a) if a.len() > 8 && a.iter().all(Value::is_number) => format!(
            "{} values from {} to {}",
            a.len(),
            value(&a[0], unit, scene, missing),
            value(&a[a.len() - 1], unit, scene, missing)
        ),
        Value::Array(a) => {
            let items: Vec<String> = a
                .iter()
                .map(|x| match x {
                    Value::Array(_) => format!("({})", value(x, "", scene, missing)),
                    _ => value(x, unit, scene, missing),
                })
                .collect();
            items.join(", ")
        }
        Value::Object(o) => {
            let parts = fields(o, scene, missing);
            let joined: Vec<String> = parts
                .into_iter()
                .map(|(w, v)| if v.is_empty() { w } else { format!("{w} {v}") })
                .collect();
            joined.join("; ")
        }
    }
}

/// Each field of an object: (its words, its value).
fn fields(
    o: &serde_json::Map<String, Value>,
    scene: &str,
    missing: &mut Vec<String>,
) -> Vec<(String, String)> {
    o.iter()
        .map(|(code, v)| match field(scene, code) {
            Some(f) if matches!(v, Value::Object(_)) => (
                f.words.to_string(),
                format!("({})", value(v, f.unit, scene, missing)),
            ),
            Some(f) => (f.words.to_string(), value(v, f.unit, scene, missing)),
            None => {
                missing.push(code.clone());
                (code.clone(), value(v, "", scene, missing))
            }
        })
        .collect()
}

/// The parameters of scene `scene` as lines "words: value", and the fields without words
/// (empty for every scene: the test below).
pub fn in_words(scene: &str, params: &Value) -> (Vec<String>, Vec<String>) {
    let mut missing = Vec::new();
    let lines = match params {
        Value::Object(o) => fields(o, scene, &mut missing)
            .into_iter()
            .map(|(w, v)| match w.contains('…') {
                // "k from … to": the two ends of a range fill the gap
                true => match v.split_once(", ") {
                    Some((a, b)) => w.replace("from … to", &format!("from {a} to {b}")),
                    None => format!("{w}: {v}"),
                },
                false => format!("{w}: {v}"),
            })
            .collect(),
        other => vec![other.to_string()],
    };
    (lines, missing)
}
