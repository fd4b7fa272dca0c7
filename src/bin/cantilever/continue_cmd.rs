//! `cantilever continue`: flags → the library's [`continue_from`] (the start orbit by
//! `find_orbit`, then the branch; the same call the Python package makes) → JSON or text.

use crate::model_args::{ModelArgs, StartArgs};
use crate::orbit::{spec_and_start, SearchArgs};
use crate::progress::Bars;
use impacting_cantilever::analysis::continuation::{
    continue_from, Continuation, ContinueOptions, Parameter,
};
use impacting_cantilever::error::Error;

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
    pub model: ModelArgs,
    #[command(flatten)]
    pub start: StartArgs,
    #[command(flatten)]
    pub search: SearchArgs,
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

impl ParameterArg {
    /// The library's parameter.
    pub fn parameter(self) -> Parameter {
        match self {
            ParameterArg::StopStiffness => Parameter::StopStiffness,
            ParameterArg::Omega => Parameter::Frequency,
            ParameterArg::Gap => Parameter::Gap,
        }
    }
}

/// Traces the branch.
pub fn run(args: &ContinueArgs) -> Result<Continuation, Error> {
    let (spec, start, _) = spec_and_start(&args.model, &args.start)?;
    let options = ContinueOptions {
        parameter: args.parameter.parameter(),
        to: args.to,
        one_way: args.one_way,
        max_step: args.max_step,
        doubling_up_to: args.doubling_up_to,
    };
    continue_from(
        &spec,
        &start,
        &args.search.options(false),
        &options,
        &Bars::default(),
    )
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
pub fn to_text(r: &Continuation) -> String {
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
