//! `cantilever motion`: flags → the library's [`classify`] with the book's options
//! ([`MotionOptions::for_model`], the atlas's) → JSON or text: what a motion is (periodic,
//! chaotic, quasi-periodic, undecided) and its evidence.

use crate::model_args::{ModelArgs, StartArgs};
use crate::orbit::spec_and_start;
use crate::progress::Bars;
use impacting_cantilever::analysis::motion::{classify, Motion, MotionOptions, MotionOverrides};
use impacting_cantilever::engine::built::BuiltModel;
use impacting_cantilever::error::Error;

/// The command's inputs: the model and start of `simulate`, and the classification's
/// record (each default the book's, as the atlas classifies its cells).
#[derive(Debug, Clone, clap::Args)]
pub struct MotionArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub start: StartArgs,
    /// Forcing periods run from the start before anything is measured (0 to 1e8; default
    /// 300, the atlas's).
    #[arg(long, value_parser = crate::model_args::whole, default_value_t = 300)]
    pub transient: u64,
    /// Segments of the Lyapunov record, whose spread gives the exponents' 95 % intervals
    /// (2 to 30; default 20).
    #[arg(long)]
    pub segments: Option<usize>,
    /// Forcing periods per segment (1 to 1e8; default 50).
    #[arg(long, value_parser = crate::model_args::whole)]
    pub segment_periods: Option<u64>,
    /// Iterates of the stroboscopic map recorded after the exponents, for the period and the
    /// rotation number (4 to 1e6, at least twice --longest-period; default 256).
    #[arg(long)]
    pub iterates: Option<usize>,
    /// The longest period m searched among the iterates (default 64).
    #[arg(long)]
    pub longest_period: Option<u64>,
    /// ε, the smallest rate per unit time the record is asked to resolve (λ₁ is zero when
    /// its interval lies inside ±ε, positive above ε; default a quarter of mode 1's free
    /// decay rate, ζ₁ω₁/4).
    #[arg(long, allow_hyphen_values = true)]
    pub resolution: Option<f64>,
}

/// The classification and what it was of.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Report {
    /// The class and its evidence.
    #[serde(flatten)]
    pub motion: Motion,
    /// The options used.
    pub options: MotionOptions,
    /// Where the run started.
    pub start: String,
    /// The model: compliant or rigid.
    pub model: &'static str,
    /// N.
    pub modes: usize,
}

/// Classifies the motion.
pub fn run(args: &MotionArgs) -> Result<Report, Error> {
    let (spec, start, file) = spec_and_start(&args.model, &args.start)?;
    let model = BuiltModel::build(&spec)?;
    let (x0, from) = model.start(&start)?;
    let changed = MotionOverrides {
        segments: args.segments,
        periods: args.segment_periods,
        iterates: args.iterates,
        longest_period: args.longest_period,
        resolution: args.resolution,
    };
    let options = MotionOptions::for_model_with(model.galerkin(), args.transient, &changed);
    let motion = classify(&model, &x0, &options, &Bars::default())?;
    Ok(Report {
        motion,
        options,
        start: file.unwrap_or(from),
        model: spec.kind(),
        modes: spec.modes(),
    })
}

/// Plain-text summary.
pub fn to_text(r: &Report) -> String {
    let m = &r.motion;
    let o = &r.options;
    let mut s = format!(
        "{}: λ₁ = {:.4e} ± {:.1e}, λ₂ = {:.4e} ± {:.1e} per unit time (95 %, {} segments of {} \
         periods after {}), resolution ε = {:.3e}\n",
        m.class.words(),
        m.exponents[0],
        m.half_widths[0],
        m.exponents[1],
        m.half_widths[1],
        o.segments,
        o.periods,
        o.transient,
        o.resolution
    );
    match m.period_m {
        Some(p) => s.push_str(&format!("period m = {p} (P^m(x) = x to 1e-8)\n")),
        None => s.push_str(&format!(
            "no period up to {} over {} iterates\n",
            o.longest_period, o.iterates
        )),
    }
    s.push_str(&format!(
        "rotation number ρ = {:.4} (its two halves differ by {:.1e})\n",
        m.rotation.turns, m.rotation.halves_differ
    ));
    s.push_str(&format!(
        "{} model, N = {}, from {}\n",
        r.model, r.modes, r.start
    ));
    s
}
