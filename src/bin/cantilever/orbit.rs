//! `cantilever orbit`: one periodic orbit of the compliant model by Newton shooting, with
//! its Floquet multipliers ([`impacting_cantilever::analysis::shooting`]).

use crate::simulate::{self, ModelKind};
use impacting_cantilever::analysis::orbit::detect_period;
use impacting_cantilever::analysis::shooting::{self, PeriodicOrbit};
use impacting_cantilever::engine::sim::{Simulator, Strobe};
use impacting_cantilever::error::{Error, ParameterError};

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
    /// The parameters, as given.
    pub modes: usize,
    /// k/k₁.
    pub k_over_k1: f64,
    /// ω/(β₁⁻)².
    pub omega_over_w1: f64,
    /// ζ₁.
    pub zeta1: f64,
    /// d₀.
    pub gap: f64,
}

/// Finds the orbit.
pub fn run(args: &OrbitArgs) -> Result<Report, Error> {
    let a = &args.model;
    if a.model == ModelKind::Rigid {
        return Err(ParameterError::new(
            "--model",
            "rigid",
            "compliant (shooting uses the compliant model's exact monodromy)",
        )
        .into());
    }
    if let Some(m) = args.period {
        if !(1..=64).contains(&m) {
            return Err(ParameterError::new("--period", m, "an integer from 1 to 64").into());
        }
    }
    let setup = simulate::setup(a)?;
    let sim = Simulator::new(setup.model)?;
    let x = sim.run(&setup.x0, a.periods, &mut ())?.state;
    let (x, m) = match args.period {
        Some(m) => (x, m),
        None => {
            // read m from the window: the smallest period whose samples nearly repeat
            let mut strobe = Strobe::default();
            let start = sim.clock_at_cycle(a.periods as i64);
            let window = a.record.max(2);
            let end = sim.run_from(&x, start, window, &mut strobe)?.state;
            let (m, residual) = detect_period(&strobe.states(), 1e-3, 64.min(window as usize - 1));
            let m = m.ok_or_else(|| {
                Error::Unsupported(format!(
                    "no period m ≤ 64 in the recorded window (best relative residual {residual:.1e}): give --period, or more --periods of transient"
                ))
            })?;
            (end, m)
        }
    };
    let orbit = shooting::shoot(&sim, &x, m)?;
    Ok(Report {
        orbit,
        start: format!("{} after {} transient periods", setup.start, a.periods),
        modes: a.modes,
        k_over_k1: a.stop_stiffness,
        omega_over_w1: a.omega,
        zeta1: a.zeta1,
        gap: a.gap,
    })
}

/// Plain-text summary.
pub fn to_text(r: &Report) -> String {
    let o = &r.orbit;
    let mut s = format!(
        "({}, {}) orbit, N = {}, k = {}k₁, ω = {}(β₁⁻)²: {} (spectral radius {:.6}), residual {:.1e} after {} Newton steps\nmultipliers (largest first):\n",
        o.period_m,
        o.impacts_n,
        r.modes,
        r.k_over_k1,
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
