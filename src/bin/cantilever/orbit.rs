//! `cantilever orbit`: one periodic orbit of the compliant model, or of the rigid-impact
//! model with its law, by Newton shooting, with its Floquet multipliers
//! ([`impacting_cantilever::analysis::shooting`]).

use crate::simulate::{self, Law, ModelKind};
use impacting_cantilever::analysis::orbit::detect_period_by;
use impacting_cantilever::analysis::shooting::{self, PeriodicOrbit};
use impacting_cantilever::engine::map::PeriodMap;
use impacting_cantilever::engine::rigid::RigidImpact;
use impacting_cantilever::engine::sim::Simulator;
use impacting_cantilever::error::{Error, ParameterError};
use nalgebra::DVector;

/// The command's inputs: the model and start of `simulate`, and the orbit's period.
#[derive(Debug, Clone, clap::Args)]
pub struct OrbitArgs {
    #[command(flatten)]
    pub model: simulate::SimulateArgs,
    /// The orbit's period m in forcing periods (1 to 64). Without it, m is read from the
    /// stroboscopic samples of the recorded window (the smallest m whose samples repeat to
    /// 1e-3), so the start needs enough transient to come near the orbit.
    #[arg(long)]
    pub period: Option<u64>,
}

/// The orbit and how it was found.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    /// The orbit.
    #[serde(flatten)]
    pub orbit: PeriodicOrbit,
    /// Where the Newton iteration started.
    pub start: String,
    /// The model: compliant or rigid.
    pub model: ModelKind,
    /// The rigid model's law (null for the compliant model).
    pub law: Option<Law>,
    /// The rigid model's restitution coefficient (null for the compliant model).
    pub restitution: Option<f64>,
    /// The parameters, as given.
    pub modes: usize,
    /// k/k₁.
    #[serde(rename = "stop_stiffness_over_k1")]
    pub k_over_k1: f64,
    /// ω/(β₁⁻)².
    #[serde(rename = "omega_over_beta1_squared")]
    pub omega_over_w1: f64,
    /// ζ₁.
    pub zeta1: f64,
    /// d₀.
    pub gap: f64,
    /// Wall time of the transient and the shooting, from the model's matrices (the flows' set-up
    /// included) to the orbit and its multipliers (s).
    pub wall_seconds: f64,
}

/// Finds the orbit, of the compliant model or of the rigid-impact model with its law.
pub fn run(args: &OrbitArgs) -> Result<Report, Error> {
    let a = &args.model;
    if let Some(m) = args.period {
        if !(1..=64).contains(&m) {
            return Err(ParameterError::new("--period", m, "an integer from 1 to 64").into());
        }
    }
    let setup = simulate::setup(a)?;
    let started = std::time::Instant::now();
    let sim = Simulator::new(setup.model)?;
    let orbit = match (a.model, setup.law) {
        (ModelKind::Rigid, Some(law)) => find(&RigidImpact::new(sim, law)?, &setup.x0, args)?,
        _ => find(&sim, &setup.x0, args)?,
    };
    let wall_seconds = started.elapsed().as_secs_f64();
    Ok(Report {
        orbit,
        start: format!("{} after {} transient periods", setup.start, a.periods),
        model: a.model,
        law: (a.model == ModelKind::Rigid).then_some(a.law),
        restitution: (a.model == ModelKind::Rigid).then_some(a.restitution),
        modes: a.modes,
        k_over_k1: a.stop_stiffness,
        omega_over_w1: a.omega,
        zeta1: a.zeta1,
        gap: a.gap,
        wall_seconds,
    })
}

/// The transient, the period (given, or read from the window: the smallest whose strobe
/// samples nearly repeat) and the orbit by shooting, for any model with a Jacobian.
fn find<M: PeriodMap>(
    model: &M,
    x0: &DVector<f64>,
    args: &OrbitArgs,
) -> Result<PeriodicOrbit, Error> {
    let a = &args.model;
    let x = model.advance(x0, 0, a.periods, false)?.state;
    let (x, m) = match args.period {
        Some(m) => (x, m),
        None => {
            let window = a.record.max(2);
            let w = model.advance(&x, a.periods as i64, window, true)?;
            let (m, residual) =
                detect_period_by(&w.strobe, 1e-3, 64.min(window as usize - 1), &|p, q| {
                    model.residual(p, q)
                });
            let m = m.ok_or_else(|| {
                Error::Unsupported(format!(
                    "no period m ≤ 64 in the recorded window (best relative residual {residual:.1e}): give --period, or more --periods of transient"
                ))
            })?;
            (w.state, m)
        }
    };
    shooting::shoot(model, &x, m)
}

/// Plain-text summary.
pub fn to_text(r: &Report) -> String {
    let o = &r.orbit;
    let model = match (r.law, r.restitution) {
        (Some(law), Some(e)) => {
            use clap::ValueEnum;
            let name = law
                .to_possible_value()
                .map(|v| v.get_name().to_string())
                .unwrap_or_default();
            format!("rigid-impact, {name} law, r = {e}")
        }
        // as typed: the shortest form, in e-notation beyond moderate sizes
        _ if r.k_over_k1 != 0.0 && !(1e-3..1e7).contains(&r.k_over_k1) => {
            format!("compliant, k = {:e}k₁", r.k_over_k1)
        }
        _ => format!("compliant, k = {}k₁", r.k_over_k1),
    };
    let mut s = format!(
        "({}, {}) orbit, N = {}, {model}, ω = {}(β₁⁻)²: {} (spectral radius {:.6}), residual {:.1e} after {} Newton steps\nmultipliers (largest first):\n",
        o.period_m,
        o.impacts_n,
        r.modes,
        r.omega_over_w1,
        if o.stable { "stable" } else { "unstable" },
        o.spectral_radius(),
        o.residual,
        o.iterations
    );
    for z in o.multipliers.iter().take(6) {
        s.push_str(&format!(
            "  {:+.10} {:+.10}i  |μ| = {:.10}\n",
            z[0],
            z[1],
            z[0].hypot(z[1])
        ));
    }
    s
}
