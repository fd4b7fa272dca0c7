//! `cantilever orbit`: flags → the library's [`find_orbit`] (the one orbit path, the same
//! call the Python package makes) → JSON or text.

use crate::model_args::{ModelArgs, StartArgs};
use crate::progress::Bars;
use impacting_cantilever::analysis::find_orbit::{find_orbit_reporting, FoundOrbit, OrbitOptions};
use impacting_cantilever::analysis::shooting::PeriodicOrbit;
use impacting_cantilever::engine::built::BuiltModel;
use impacting_cantilever::error::Error;
use impacting_cantilever::model::spec::{ModelSpec, Named, Start, Stop, Structure};

/// The orbit options every front end starts from.
const DEFAULTS: OrbitOptions = OrbitOptions::DEFAULTS;

/// The command's inputs: the model and start of `simulate`, how the orbit is found, and
/// whether its r_E is wanted.
#[derive(Debug, Clone, clap::Args)]
pub struct OrbitArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub start: StartArgs,
    #[command(flatten)]
    pub search: SearchArgs,
    /// Also r_E (eq 39), the energetic coefficient of restitution over one period of the
    /// orbit (compliant model only).
    #[arg(long)]
    pub energetic_restitution: bool,
}

/// How the start orbit is found (`orbit` and `continue`).
#[derive(Debug, Clone, clap::Args)]
pub struct SearchArgs {
    /// Transient: forcing periods run from the start before the orbit is read (0 to 1e8). A
    /// transient that projects to take over 10 minutes says so after 2 s, with the time it
    /// projects.
    #[arg(long, value_parser = crate::model_args::whole, default_value_t = DEFAULTS.transient)]
    pub periods: u64,
    /// The window: periods whose stroboscopic samples give the period m (2 to 10 000; m is
    /// read up to min(64, record − 1)).
    #[arg(long, value_parser = crate::model_args::whole, default_value_t = DEFAULTS.window)]
    pub record: u64,
    /// The orbit's period m in forcing periods (1 to 64), if known; read from the window
    /// otherwise (the smallest m whose samples repeat to --period-tolerance).
    #[arg(long)]
    pub period: Option<u64>,
    /// How near the window's samples must repeat for m to be taken (relative, in (0, 1));
    /// Newton then converges the orbit to 1e-12.
    #[arg(long, allow_hyphen_values = true, default_value_t = DEFAULTS.period_tolerance)]
    pub period_tolerance: f64,
    /// Newton steps allowed (1 to 1000).
    #[arg(long, default_value_t = DEFAULTS.max_iterations)]
    pub max_iterations: usize,
}

impl SearchArgs {
    /// The library's options (with r_E or not).
    pub fn options(&self, restitution: bool) -> OrbitOptions {
        OrbitOptions {
            transient: self.periods,
            window: self.record,
            period: self.period,
            period_tolerance: self.period_tolerance,
            max_iterations: self.max_iterations,
            restitution,
        }
    }
}

/// The specification and start the flags give, and where the start came from.
pub fn spec_and_start(
    model: &ModelArgs,
    start: &StartArgs,
) -> Result<(ModelSpec, Start, Option<String>), Error> {
    let spec = model.spec()?;
    let (start, file) = start.start(spec.modes())?;
    Ok((spec, start, file))
}

/// The orbit and how it was found.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    /// The orbit.
    #[serde(flatten)]
    pub orbit: PeriodicOrbit,
    /// r_E (eq 39) over one period, when asked for (null if the balance has no real root).
    pub energetic_restitution: Option<f64>,
    /// [fewest, most] entries per orbit period over four periods run on from the orbit:
    /// apart when round-off decides an event (see `impacts_n_range` of `find_orbit`).
    pub impacts_n_range: [u64; 2],
    /// Where the Newton iteration started.
    pub start: String,
    /// The model: compliant or rigid.
    pub model: &'static str,
    /// The rigid model's law (null for the compliant model).
    pub law: Option<&'static str>,
    /// The rigid model's restitution coefficient (null for the compliant model).
    pub restitution: Option<f64>,
    /// N.
    pub modes: usize,
    /// k/k₁ (null for the rigid model).
    #[serde(rename = "stop_stiffness_over_k1")]
    pub k_over_k1: Option<f64>,
    /// ω/(β₁⁻)².
    #[serde(rename = "omega_over_beta1_squared")]
    pub omega_over_w1: f64,
    /// ζ₁.
    pub zeta1: f64,
    /// d₀ (in the unit of `gap_unit`).
    pub gap: f64,
    /// Wall time of the transient and the shooting, from the model's matrices (the flows'
    /// set-up included) to the orbit and its multipliers (s).
    pub wall_seconds: f64,
}

/// Finds the orbit.
pub fn run(args: &OrbitArgs) -> Result<Report, Error> {
    let (spec, start, file) = spec_and_start(&args.model, &args.start)?;
    let started = std::time::Instant::now();
    let model = BuiltModel::build(&spec)?;
    let (x0, from) = model.start(&start)?;
    let options = args.search.options(args.energetic_restitution);
    let found: FoundOrbit = find_orbit_reporting(&model, &x0, &options, &Bars::default())?;
    let wall_seconds = started.elapsed().as_secs_f64();
    let (law, restitution, k) = match spec.stop {
        Stop::Rigid { law, restitution } => (Some(law.name()), Some(restitution), None),
        Stop::Compliant { stop_stiffness } => (None, None, Some(stop_stiffness)),
    };
    let (omega, zeta1, gap) = match &spec.structure {
        Structure::Cantilever(c) => (c.omega, c.zeta1, c.gap),
        Structure::Oscillator(o) => (o.omega, 0.0, o.gap),
    };
    Ok(Report {
        orbit: found.orbit,
        energetic_restitution: found.energetic_restitution,
        impacts_n_range: [found.impacts_n_range.0, found.impacts_n_range.1],
        start: format!(
            "{} after {} transient periods",
            file.unwrap_or(from),
            args.search.periods
        ),
        model: spec.kind(),
        law,
        restitution,
        modes: spec.modes(),
        k_over_k1: k,
        omega_over_w1: omega,
        zeta1,
        gap,
        wall_seconds,
    })
}

/// Plain-text summary.
pub fn to_text(r: &Report) -> String {
    let o = &r.orbit;
    let model = match (r.law, r.restitution, r.k_over_k1) {
        (Some(law), Some(e), _) => format!("rigid-impact, {law} law, r = {e}"),
        // as typed: the shortest form, in e-notation beyond moderate sizes
        (_, _, Some(k)) if k != 0.0 && !(1e-3..1e7).contains(&k) => {
            format!("compliant, k = {k:e}k₁")
        }
        (_, _, k) => format!("compliant, k = {}k₁", k.unwrap_or(0.0)),
    };
    let [fewest, most] = r.impacts_n_range;
    let n = if fewest == most {
        o.impacts_n.to_string()
    } else {
        format!("{fewest}–{most}")
    };
    let mut s = format!(
        "({}, {n}) orbit, N = {}, {model}, ω = {}(β₁⁻)²: {} (spectral radius {:.6}), residual \
         {:.1e} after {} Newton steps\n",
        o.period_m,
        r.modes,
        r.omega_over_w1,
        if o.stable { "stable" } else { "unstable" },
        o.spectral_radius(),
        o.residual,
        o.iterations
    );
    if fewest != most {
        s.push_str(&format!(
            "entries per orbit period: {fewest} to {most} over {} periods of the orbit — \
             round-off decides at least one event (a flight or contact within round-off of \
             the stop), so the count is not exact\n",
            impacting_cantilever::analysis::find_orbit::COUNTED_REPEATS
        ));
    }
    if let Some(e) = r.energetic_restitution {
        s.push_str(&format!(
            "energetic coefficient of restitution r_E = {e:.10}\n"
        ));
    }
    let shown = o.multipliers.len().min(6);
    s.push_str(&if shown < o.multipliers.len() {
        format!(
            "multipliers (the {shown} largest of {}; all in --json):\n",
            o.multipliers.len()
        )
    } else {
        "multipliers (largest first):\n".to_string()
    });
    // a part that prints as zero prints as +0, not "-0.0000000000"
    let printed = |x: f64| if x.abs() < 5e-11 { 0.0 } else { x };
    for z in o.multipliers.iter().take(shown) {
        s.push_str(&format!(
            "  {:+.10} {:+.10}i  |μ| = {:.10}\n",
            printed(z[0]),
            printed(z[1]),
            z[0].hypot(z[1])
        ));
    }
    s
}
