//! `cantilever continue`: a branch of periodic orbits of the compliant model continued in
//! k or ω, with its bifurcations ([`impacting_cantilever::analysis::continuation`]).

use crate::orbit;
use crate::simulate;
use impacting_cantilever::analysis::continuation::{self, Branch, Family, Parameter, Settings};
use impacting_cantilever::error::{Error, ParameterError};
use nalgebra::DVector;

/// The continuation parameter, as typed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ParameterArg {
    /// k/k₁ (--stop-stiffness).
    StopStiffness,
    /// ω/(β₁⁻)² (--omega).
    Omega,
    /// d₀ in units of the free tip amplitude at resonance (--gap; > 0).
    Gap,
}

/// The command's inputs: the start orbit of `orbit`, the parameter and where to go.
#[derive(Debug, Clone, clap::Args)]
pub struct ContinueArgs {
    #[command(flatten)]
    pub orbit: orbit::OrbitArgs,
    /// The parameter continued; the branch starts at its value in the model options.
    #[arg(long, value_enum)]
    pub parameter: ParameterArg,
    /// Where to continue to (a value of the parameter, > 0); the branch is traced from
    /// the start to this value and, unless --one-way, back past the start to
    /// start²/to (the same factor the other way).
    #[arg(long, allow_hyphen_values = true)]
    pub to: f64,
    /// Only towards --to, one branch: its period doublings are detected and reported but
    /// not followed (the doubled branches are traced without --one-way).
    #[arg(long)]
    pub one_way: bool,
    /// Largest step in ln p (also the spacing of the points), 1e-4 to 0.2. A branch
    /// stops after 4000 points.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.02)]
    pub max_step: f64,
    /// Follow period doublings up to this period (1 = no branch switching), 1 to 64.
    #[arg(long, default_value_t = 8)]
    pub doubling_up_to: u64,
}

/// The branches and what they started from.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    /// "k/k₁", "ω/(β₁⁻)²" or "d₀" (in units of the free tip amplitude at resonance).
    pub parameter: &'static str,
    /// The starting orbit's parameter value.
    pub start: f64,
    /// N, the number of modes.
    pub modes: usize,
    /// The branches (0: towards --to; then the other way; then period-doubled ones).
    pub branches: Vec<Branch>,
}

/// Traces the branch.
pub fn run(args: &ContinueArgs) -> Result<Report, Error> {
    let a = &args.orbit.model;
    let (parameter, p0) = match args.parameter {
        ParameterArg::StopStiffness => (Parameter::StopStiffness, a.stop_stiffness),
        ParameterArg::Omega => (Parameter::Frequency, a.omega),
        ParameterArg::Gap => (Parameter::Gap, a.gap),
    };
    // the branch is traced in ln p
    if p0.is_nan() || p0 <= 0.0 {
        let flag = match args.parameter {
            ParameterArg::StopStiffness => "--stop-stiffness",
            ParameterArg::Omega => "--omega",
            ParameterArg::Gap => "--gap",
        };
        return Err(ParameterError::new(
            flag,
            impacting_cantilever::error::number(p0),
            "a value > 0 to continue from (the branch is traced in the logarithm of the parameter)",
        )
        .into());
    }
    if !(args.to.is_finite() && args.to > 0.0 && args.to != p0) {
        return Err(ParameterError::new(
            "--to",
            impacting_cantilever::error::number(args.to),
            "a finite value > 0 other than the start value",
        )
        .into());
    }
    if !(1e-4..=0.2).contains(&args.max_step) {
        return Err(ParameterError::new("--max-step", args.max_step, "1e-4 to 0.2").into());
    }
    if !(1..=64).contains(&args.doubling_up_to) {
        return Err(ParameterError::new("--doubling-up-to", args.doubling_up_to, "1 to 64").into());
    }
    // --to must be a value the model accepts (k ≤ 1e12, say): refused here, not found
    // out as a corrector failure at the end of the branch
    let mut at_to = a.clone();
    match args.parameter {
        ParameterArg::StopStiffness => at_to.stop_stiffness = args.to,
        ParameterArg::Omega => at_to.omega = args.to,
        ParameterArg::Gap => at_to.gap = args.to,
    }
    if let Err(e) = simulate::model(&at_to) {
        return Err(ParameterError::new(
            "--to",
            impacting_cantilever::error::number(args.to),
            &format!("a value the model accepts ({e})"),
        )
        .into());
    }
    // the start orbit, found as `cantilever orbit` finds it (validates the model options)
    let start = orbit::run(&args.orbit)?;
    let base = a.clone();
    let family = Family::new(parameter, move |p| {
        let mut m = base.clone();
        match parameter {
            Parameter::StopStiffness => m.stop_stiffness = p,
            Parameter::Frequency => m.omega = p,
            Parameter::Gap => m.gap = p,
        }
        Ok(simulate::model(&m)?)
    });
    let other = if args.one_way { p0 } else { p0 * p0 / args.to };
    let settings = Settings {
        max_step: args.max_step,
        initial_step: args.max_step.min(0.01),
        max_period: args.doubling_up_to,
        ..Settings::new((args.to.min(other), args.to.max(other)))
    };
    let x = DVector::from_vec(start.orbit.state.clone());
    let m = start.orbit.period_m;
    let mut branches = if args.one_way {
        let dir = (args.to - p0).signum();
        vec![continuation::continue_branch(
            &family, &x, p0, m, dir, &settings,
        )?]
    } else {
        continuation::trace(&family, &x, p0, m, &settings)?
    };
    // branch 0 runs up; put the one towards --to first
    if !args.one_way && args.to < p0 && branches.len() > 1 {
        branches.swap(0, 1);
    }
    Ok(Report {
        parameter: parameter.symbol(),
        start: p0,
        modes: a.modes,
        branches,
    })
}

/// A parameter value for the text: six decimals for moderate sizes, e-notation beyond (a
/// k of 1e-300 would otherwise print as 300 zeros).
pub fn num(x: f64) -> String {
    if x == 0.0 || (1e-3..1e7).contains(&x.abs()) {
        format!("{x:.6}")
    } else {
        format!("{x:.6e}")
    }
}

/// Plain-text summary: each branch's extent and its bifurcations.
pub fn to_text(r: &Report) -> String {
    let mut s = format!(
        "N = {}, continuation in {} from {}\n",
        r.modes,
        r.parameter,
        num(r.start)
    );
    for (i, b) in r.branches.iter().enumerate() {
        let (first, last) = (&b.points[0], &b.points[b.points.len() - 1]);
        s.push_str(&format!(
            "branch {i}: period {}, {} points, {} = {} → {} ({}){}\n",
            b.period_m,
            b.points.len(),
            r.parameter,
            num(first.parameter),
            num(last.parameter),
            b.end,
            b.parent.map_or(String::new(), |p| format!(
                ", born at a period doubling of branch {p}"
            ))
        ));
        for f in &b.bifurcations {
            s.push_str(&format!(
                "  {:<16} at {} = {} (between {} and {}); contacts {} → {}, {} → {}\n",
                f.kind.to_string(),
                r.parameter,
                num(f.parameter),
                num(f.between.0),
                num(f.between.1),
                f.impacts.0,
                f.impacts.1,
                if f.stable.0 { "stable" } else { "unstable" },
                if f.stable.1 { "stable" } else { "unstable" },
            ));
        }
    }
    s
}
