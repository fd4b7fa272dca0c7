//! `cantilever continue2`: flags → the library's [`curve_from`] (the start orbit by
//! `find_orbit`, the curve's point at the start's second parameter, then the curve) → text,
//! JSON or CSV.

use crate::continue_cmd::{num, ParameterArg};
use crate::model_args::{ModelArgs, StartArgs};
use crate::orbit::{spec_and_start, SearchArgs};
use crate::progress::Bars;
use impacting_cantilever::analysis::continuation::request::keyword;
use impacting_cantilever::analysis::curves::request::{curve_from, CurveOptions, CurveReport};
use impacting_cantilever::analysis::curves::CurveKind;
use impacting_cantilever::error::{Error, ParameterError};

/// What the curve follows, as typed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum KindArg {
    /// A multiplier at +1.
    Fold,
    /// A multiplier at −1.
    PeriodDoubling,
    /// The tip's extremum nearest the stop touches it.
    Grazing,
    /// A complex pair of multipliers on the unit circle.
    NeimarkSacker,
}

/// The command's inputs.
#[derive(Debug, Clone, clap::Args)]
pub struct Continue2Args {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub start: StartArgs,
    #[command(flatten)]
    pub search: SearchArgs,
    /// What the curve follows.
    #[arg(long, value_enum)]
    pub kind: KindArg,
    /// The first parameter p: solved for at the start, from its value in the model options.
    #[arg(long, value_enum)]
    pub parameter: ParameterArg,
    /// The second parameter q: held at its value in the model options while the curve's
    /// first point is found.
    #[arg(long, value_enum)]
    pub second: ParameterArg,
    /// The interval of p the curve is traced in (two numbers, 0 < FROM < TO, containing the
    /// start value).
    #[arg(long, num_args = 2, value_names = ["FROM", "TO"], allow_hyphen_values = true, required = true)]
    pub range: Vec<f64>,
    /// The interval of q (two numbers, 0 < FROM < TO, containing the start value).
    #[arg(long, num_args = 2, value_names = ["FROM", "TO"], allow_hyphen_values = true, required = true)]
    pub second_range: Vec<f64>,
    /// Largest arclength step (in ln p, ln q and the state scaled by the free response),
    /// 1e-4 to 0.2.
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.05)]
    pub max_step: f64,
    /// Points each way from the start at most, 2 to 20 000.
    #[arg(long, default_value_t = 400)]
    pub max_points: u64,
}

/// Traces the curve.
pub fn run(args: &Continue2Args) -> Result<CurveReport, Error> {
    // a repeated flag appends its two values: refused, not silently cut to the first pair
    for (name, v) in [("range", &args.range), ("second-range", &args.second_range)] {
        if v.len() != 2 {
            return Err(ParameterError::new(
                name,
                format!("{} numbers", v.len()),
                "two numbers FROM TO, given once",
            )
            .into());
        }
    }
    let (spec, start, _) = spec_and_start(&args.model, &args.start)?;
    let options = CurveOptions {
        kind: match args.kind {
            KindArg::Fold => CurveKind::Fold,
            KindArg::PeriodDoubling => CurveKind::PeriodDoubling,
            KindArg::Grazing => CurveKind::Grazing,
            KindArg::NeimarkSacker => CurveKind::NeimarkSacker,
        },
        parameter: args.parameter.parameter(),
        second: args.second.parameter(),
        range: (args.range[0], args.range[1]),
        second_range: (args.second_range[0], args.second_range[1]),
        max_step: args.max_step,
        max_points: args.max_points,
    };
    curve_from(
        &spec,
        &start,
        &args.search.options(false),
        &options,
        &Bars::default(),
    )
}

/// Plain-text summary: the curve's extent, its ends and its codimension-two points.
pub fn to_text(r: &CurveReport) -> String {
    let c = &r.curve;
    let (p, q) = c.parameters;
    let worst = |f: fn(&impacting_cantilever::analysis::curves::CurvePoint) -> f64| {
        c.points.iter().map(f).fold(0.0, f64::max)
    };
    let mut s = format!(
        "N = {}, {} curve of period-{} orbits in ({p}, {q}), started at ({}, {})\n\
         {} points; residuals at most {:.1e} (orbit) and {:.1e} (test)\n\
         first point ends: {}\nlast point ends: {}\n",
        r.modes,
        c.kind,
        c.period_m,
        num(r.start.0),
        num(r.start.1),
        c.points.len(),
        worst(|p| p.orbit_residual),
        worst(|p| p.test_residual),
        c.ends.0,
        c.ends.1,
    );
    for x in &c.codim_two {
        s.push_str(&format!(
            "  meets {:?} at ({p}, {q}) = ({}, {}) (between points {} and {})\n",
            x.meets,
            num(x.p),
            num(x.q),
            x.index,
            x.index + 1
        ));
    }
    s
}

/// The points as CSV: p, q, contacts, residuals and the largest multiplier modulus.
pub fn to_csv(r: &CurveReport, args: &Continue2Args) -> String {
    let mut s = format!(
        "{},{},contacts,orbit_residual,test_residual,spectral_radius\n",
        keyword(args.parameter.parameter()),
        keyword(args.second.parameter())
    );
    for p in &r.curve.points {
        let radius = p.multipliers.first().map_or(0.0, |z| z[0].hypot(z[1]));
        s.push_str(&format!(
            "{:.17e},{:.17e},{},{:.3e},{:.3e},{:.17e}\n",
            p.p, p.q, p.impacts_n, p.orbit_residual, p.test_residual, radius
        ));
    }
    s
}
