//! Work-precision diagrams (error against CPU time, one panel per problem) and the tables of
//! the side-by-side comparison. No numerics.

use super::{best_error, OrbitData, ProblemData, Series, SideBySideData};
use crate::results::peers::OWN;
use crate::base::report::format_sig;
use crate::results::render::{
    power_of_ten,
    drawing, markdown_table, markdown_text_table, palette, styled_mesh, RenderError, CAPTION_FONT, LABEL_FONT,
};
use crate::results::narrow::Layout;
use plotters::prelude::*;

/// Errors below this are drawn at it (round-off).
const FLOOR: f64 = 1e-16;

/// The methods in the legend's order: (label, colour), matched by the start of the
/// method's name (the first match wins). The compiled tools first: CVODE in dark red and
/// purple, this project's own Dormand–Prince in grey.
const STYLES: [(&str, &str, Colour); 9] = [
    ("BDF", "CVODE BDF (C, exact Jacobian)", Colour::Rgb(165, 30, 45)),
    ("Adams", "CVODE Adams (C)", Colour::Rgb(110, 60, 170)),
    ("Dormand", "this project's Dormand–Prince 5(4)", Colour::Rgb(120, 120, 120)),
    ("DOP853, largest step", "scipy DOP853, step ≤ T/100", Colour::Palette(5)),
    ("DOP853", "scipy DOP853", Colour::Palette(0)),
    ("Radau", "scipy Radau (exact Jacobian)", Colour::Palette(1)),
    ("LSODA", "scipy LSODA", Colour::Palette(2)),
    ("event-driven", "Siconos event-driven (LSODAR)", Colour::Palette(3)),
    ("Moreau", "Siconos Moreau–Jean", Colour::Palette(4)),
];

/// A series' colour: one of the book's palette, or its own.
#[derive(Clone, Copy)]
enum Colour {
    Palette(usize),
    Rgb(u8, u8, u8),
}

impl Colour {
    fn rgb(self) -> RGBColor {
        match self {
            Colour::Palette(i) => palette(i),
            Colour::Rgb(r, g, b) => RGBColor(r, g, b),
        }
    }
}

fn style_of(method: &str) -> Option<(&'static str, RGBColor)> {
    STYLES
        .iter()
        .find(|(prefix, _, _)| method.starts_with(prefix))
        .map(|(_, label, c)| (*label, c.rgb()))
}

/// A short title for a panel.
fn short(p: &ProblemData) -> String {
    match p.name.as_str() {
        "oscillator" => "1-DOF impact oscillator".into(),
        "chatter" => "1-DOF with chatter and sticking".into(),
        "rigid-n2" => "rigid impacts, N = 2".into(),
        "fig4-n3" => "Figure 4 model, N = 3".into(),
        "fig4-n10" => "Figure 4 model, N = 10".into(),
        _ => p.title.clone(),
    }
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<
        plotters::coord::combinators::LogCoord<f64>,
        plotters::coord::combinators::LogCoord<f64>,
    >,
>;

fn panel<'a, 'b>(
    area: &DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    title: &str,
    x: (f64, f64),
    y_desc: &str,
) -> Result<Chart<'a, 'b>, RenderError>
where
    'b: 'a,
{
    let mut chart = ChartBuilder::on(area)
        .caption(title, CAPTION_FONT)
        .margin(8)
        .margin_right(20)
        .x_label_area_size(46)
        .y_label_area_size(70)
        .build_cartesian_2d((x.0..x.1).log_scale(), (FLOOR / 2.0..100.0).log_scale())
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("CPU time (s)")
        .y_desc(y_desc)
        .x_label_formatter(&power_of_ten)
        .y_label_formatter(&power_of_ten)
        .draw()
        .map_err(drawing)?;
    Ok(chart)
}

/// Where a run that stopped before the end is drawn (it has no error).
const STOPPED: f64 = 20.0;

/// One peer's ladder: its runs that found this project's impacts joined by a line (in a
/// problem with sticking, where impacts accumulate and cannot be counted alike, every run
/// that reached the end), the others as open circles, the runs that stopped early as
/// crosses at the top.
fn draw_series(chart: &mut Chart, s: &Series, sticking: bool) -> Result<(), RenderError> {
    let Some((_, colour)) = style_of(&s.method) else {
        return Ok(());
    };
    let joined = |p: &super::Point| super::counts(p, sticking);
    let clean: Vec<(f64, f64)> = s
        .points
        .iter()
        .filter(|p| joined(p))
        .filter_map(|p| Some((p.seconds?, p.error?.max(FLOOR))))
        .collect();
    let missed: Vec<(f64, f64)> = s
        .points
        .iter()
        .filter(|p| !joined(p))
        .filter_map(|p| Some((p.seconds?, p.error?.clamp(FLOOR, 50.0))))
        .collect();
    let stopped: Vec<(f64, f64)> = s
        .points
        .iter()
        .filter(|p| p.error.is_none())
        .filter_map(|p| Some((p.seconds?, STOPPED)))
        .collect();
    chart
        .draw_series(stopped.iter().map(|&p| Cross::new(p, 6, colour.stroke_width(2))))
        .map_err(drawing)?;
    chart
        .draw_series(LineSeries::new(clean.clone(), colour.stroke_width(2)))
        .map_err(drawing)?;
    chart
        .draw_series(clean.iter().map(|&p| Circle::new(p, 4, colour.filled())))
        .map_err(drawing)?;
    chart
        .draw_series(missed.iter().map(|&p| Circle::new(p, 5, colour.stroke_width(2))))
        .map_err(drawing)?;
    Ok(())
}

fn draw_ours(chart: &mut Chart, at: (f64, f64)) -> Result<(), RenderError> {
    let at = (at.0, at.1.max(FLOOR));
    chart
        .draw_series(std::iter::once(TriangleMarker::new(at, 9, BLACK.filled())))
        .map_err(drawing)?;
    Ok(())
}

/// Height of the legend strip: ten entries in three columns, and the markers' row; or
/// one entry per row when narrow.
fn legend_height(layout: Layout) -> u32 {
    match layout {
        Layout::Wide => 18 + 5 * 28,
        Layout::Narrow => 18 + 13 * 28,
    }
}

fn legend(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    layout: Layout,
) -> Result<(), RenderError> {
    let font = LABEL_FONT.into_font().color(&BLACK);
    let mut entries: Vec<(String, Option<RGBColor>)> = STYLES
        .iter()
        .map(|(_, label, c)| (label.to_string(), Some(c.rgb())))
        .collect();
    entries.insert(0, ("this project".into(), None));
    let per_row = if layout == Layout::Wide { 3 } else { 1 };
    for (i, (label, colour)) in entries.iter().enumerate() {
        let (x, y) = (20 + (i % per_row) as i32 * 330, 18 + (i / per_row) as i32 * 28);
        match colour {
            Some(c) => {
                area.draw(&PathElement::new(vec![(x, y), (x + 26, y)], c.stroke_width(2)))
                    .map_err(drawing)?;
                area.draw(&Circle::new((x + 13, y), 4, c.filled())).map_err(drawing)?;
            }
            None => area
                .draw(&TriangleMarker::new((x + 13, y), 9, BLACK.filled()))
                .map_err(drawing)?,
        }
        area.draw(&Text::new(label.clone(), (x + 34, y - 9), font.clone()))
            .map_err(drawing)?;
    }
    // the markers: in a row under the entries, or one per row
    let rows = entries.len().div_ceil(per_row) as i32;
    let at = |i: i32| match layout {
        Layout::Wide => (33 + 330 * i, 18 + rows * 28),
        Layout::Narrow => (33, 18 + (rows + i) * 28),
    };
    let grey = RGBColor(90, 90, 90);
    let (x, y) = at(0);
    area.draw(&Circle::new((x, y), 4, grey.filled())).map_err(drawing)?;
    area.draw(&Text::new("every event found", (x + 21, y - 9), font.clone()))
        .map_err(drawing)?;
    let (x, y) = at(1);
    area.draw(&Circle::new((x, y), 5, grey.stroke_width(2))).map_err(drawing)?;
    area.draw(&Text::new("events missed or added", (x + 21, y - 9), font.clone()))
        .map_err(drawing)?;
    let (x, y) = at(2);
    area.draw(&Cross::new((x, y), 6, grey.stroke_width(2))).map_err(drawing)?;
    area.draw(&Text::new("stopped early (drawn at the top)", (x + 21, y - 9), font))
        .map_err(drawing)?;
    Ok(())
}

/// The SVG: one work-precision panel per problem and one for the N = 10 orbit.
///
/// # Errors
/// [`RenderError`] when drawing fails.
///
/// # Panics
/// Never: every method it looks up ("DOP853", "Radau", "LSODA") is in the style table.
pub fn plot(d: &SideBySideData, layout: Layout) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        let strip = legend_height(layout);
        let (width, body_height) = layout.grid_size(3, 2, 1400);
        let root = SVGBackend::with_string(&mut svg, (width, strip + body_height))
            .into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (top, body) = root.split_vertically(strip);
        legend(&top, layout)?;
        let panels = layout.cells(&body, 3, 2);
        let times = d
            .problems
            .iter()
            .flat_map(|p| {
                p.series
                    .iter()
                    .flat_map(|s| s.points.iter().filter_map(|q| q.seconds))
                    .chain([p.ours_seconds])
            })
            .chain(d.orbits.iter().flat_map(|o| {
                o.peers.iter().filter_map(|q| q.seconds).chain([o.ours_seconds])
            }));
        let (lo, hi) = times.fold((f64::MAX, 0.0_f64), |(a, b), t| (a.min(t), b.max(t)));
        let x = (lo / 2.0, hi * 2.0);
        for (p, area) in d.problems.iter().zip(panels.iter()) {
            let mut chart = panel(area, &short(p), x, "error against the reference")?;
            for s in &p.series {
                draw_series(&mut chart, s, p.first_sticking.is_some())?;
            }
            draw_ours(&mut chart, (p.ours_seconds, p.ours_error))?;
        }
        // the N = 10 orbit from the earliest start (Newton has work to do there): each peer's
        // orbit against this project's, whose own error is bounded by its residual under
        // the independent 40-digit period map
        if let (Some(o), Some(area)) = (d.orbits.iter().find(|o| o.modes == 10), panels.get(5)) {
            let title = format!("periodic orbit, N = 10, from {} periods", o.start_periods);
            let mut chart = panel(area, &title, x, "error of the orbit's state")?;
            for method in ["DOP853", "Radau", "LSODA"] {
                let (_, colour) = style_of(method).expect("a listed method");
                let pts: Vec<(f64, f64)> = o
                    .peers
                    .iter()
                    .filter(|q| q.method.starts_with(method))
                    .filter_map(|q| Some((q.seconds?, q.state_error?.max(FLOOR))))
                    .collect();
                chart
                    .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
                    .map_err(drawing)?;
                chart
                    .draw_series(pts.iter().map(|&q| Circle::new(q, 4, colour.filled())))
                    .map_err(drawing)?;
            }
            draw_ours(&mut chart, (o.ours_seconds, o.reference_residual))?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// A series as the tables name it: its tool and method ("this project's" for its own
/// Dormand–Prince).
fn named(s: &Series) -> String {
    let tool = if s.tool == OWN { "this project's" } else { &s.tool };
    format!("{tool} {}", s.method)
}

/// A setting as written: an rtol to one figure, a step count in full.
fn setting(s: &Series, x: Option<f64>) -> String {
    match x {
        Some(v) if s.setting_name == "rtol" => sig(Some(v), 1),
        Some(v) => format!("{v:.0}"),
        None => "—".into(),
    }
}

fn sig(x: Option<f64>, digits: usize) -> String {
    match x {
        Some(0.0) => "0".into(),
        Some(v) if v.is_finite() => format_sig(v, digits),
        _ => "—".into(),
    }
}

/// Seconds in a readable unit.
fn time(s: f64) -> String {
    if s < 1e-3 {
        format!("{:.0} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.1} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

/// The fastest clean run with an error at or below `target` of the tools `which` accepts:
/// (label, s).
fn fastest(p: &ProblemData, target: f64, which: impl Fn(&str) -> bool) -> Option<(String, f64)> {
    let (s, q) = super::fastest_of(p, target, which)?;
    Some((style_of(&s.method)?.0.to_string(), q.seconds?))
}

/// A time over this project's: two figures below 10, whole numbers above.
fn times(ratio: f64) -> String {
    if ratio < 10.0 {
        format!("{}×", format_sig(ratio, 2))
    } else {
        format!("{ratio:.0}×")
    }
}

/// The headline table: per problem, this project beside the fastest compiled peer (CVODE),
/// the fastest scipy run, the fastest run of any peer, and this project's own
/// Dormand–Prince.
pub fn headline(d: &SideBySideData) -> String {
    let at = |p: &ProblemData, target: f64, which: &dyn Fn(&str) -> bool, label: bool| {
        match fastest(p, target, which) {
            Some((name, s)) if label => {
                format!("{name}: {} ({})", time(s), times(s / p.ours_seconds))
            }
            Some((_, s)) => format!("{} ({})", time(s), times(s / p.ours_seconds)),
            None if which(OWN) && !p.series.iter().any(|s| s.tool == OWN) => "—".into(),
            None => "none".into(),
        }
    };
    let rows: Vec<Vec<String>> = d
        .problems
        .iter()
        .map(|p| {
            let sticking = p.first_sticking.is_some();
            let best = p
                .series
                .iter()
                .filter_map(|s| best_error(s, sticking))
                .min_by(f64::total_cmp);
            vec![
                short(p),
                format!("{} ({})", time(p.ours_seconds), sig(Some(p.ours_error), 1)),
                at(p, 1e-9, &|t| t == "CVODE", true),
                at(p, 1e-9, &|t| t == "scipy", true),
                at(p, 1e-6, &|t| t != OWN, true),
                at(p, 1e-9, &|t| t == OWN, false),
                sig(best, 1),
            ]
        })
        .collect();
    markdown_table(
        &[
            "problem",
            "this project: CPU time (error)",
            "CVODE to error ≤ 10⁻⁹ (× our time)",
            "scipy to error ≤ 10⁻⁹ (× our time)",
            "any peer to error ≤ 10⁻⁶ (× our time)",
            "this project's Dormand–Prince to ≤ 10⁻⁹ (× our time)",
            "smallest peer error",
        ],
        &rows,
    )
}

/// What each tool's time includes.
pub fn includes(d: &SideBySideData) -> String {
    let rows: Vec<Vec<String>> = d
        .includes
        .iter()
        .map(|(tool, what)| vec![tool.clone(), what.clone()])
        .collect();
    markdown_text_table(&["tool", "its time is"], &rows)
}

/// A run's outcome as a reader should see it: Siconos reports a failure of its
/// event-driven integrator only as a bare C++ exception.
fn in_words(outcome: &str) -> String {
    outcome.replace("Exception: std::exception", "a C++ exception without a message")
}

/// The machine, the date and the versions.
pub fn setup(d: &SideBySideData) -> String {
    let mut rows = vec![
        vec!["machine".to_string(), d.machine.clone()],
        vec![
            "1-minute load average at the start of the runs".into(),
            format!("{:.1} to {:.1}", d.load.0, d.load.1),
        ],
        vec!["measured".into(), format!("{} to {}", d.dates.0, d.dates.1)],
        vec![
            "timing".into(),
            format!(
                "CPU time of the solve alone, set-up apart, one thread: the best of {} runs \
                 alternated between the tools (a compiled tool's run: the best of up to {} \
                 solves, until 1 s of CPU); a ladder stops after a run over {} s",
                d.repeats, d.inner_repeats, d.budget_seconds
            ),
        ],
    ];
    for (k, v) in &d.versions {
        // the result files' keys, in words
        let name = match k.as_str() {
            "cantilever" => "this project's command line",
            "commit" => "this project's commit for these runs",
            "siconos_numpy" => "NumPy used by Siconos",
            "siconos_python" => "Python used by Siconos",
            "python" => "Python",
            "numpy" => "NumPy",
            "scipy" => "SciPy",
            "siconos" => "Siconos",
            "rustc" => "Rust compiler",
            "sundials" => "SUNDIALS (CVODE)",
            "cc" => "C compiler (CVODE's right-hand side)",
            other => other,
        };
        rows.push(vec![name.to_string(), v.clone()]);
    }
    markdown_text_table(&["setting", "value"], &rows)
}

/// The problems and their references.
pub fn problems(d: &SideBySideData) -> String {
    let rows: Vec<Vec<String>> = d
        .problems
        .iter()
        .map(|p| {
            vec![
                p.title.replace("]_IR", "]<sub>IR</sub>"),
                p.periods.to_string(),
                format!("{} ({})", p.ours_events, p.reference_events),
                p.reference.clone(),
                sig(Some(p.sensitivity), 1),
                sig(Some(p.ours_error), 1),
            ]
        })
        .collect();
    markdown_table(
        &[
            "problem",
            "periods",
            "events: ours (reference)",
            "reference",
            "change for 10⁻¹⁶ at the start",
            "this project's error",
        ],
        &rows,
    )
}

/// What each tool could not do: every run that stopped early or did not find this
/// project's impacts, grouped by peer; the outcome of the loosest such run.
pub fn outcomes(d: &SideBySideData) -> String {
    let mut rows = Vec::new();
    for p in &d.problems {
        for s in &p.series {
            let ran = s.points.iter().filter(|q| q.seconds.is_some()).count();
            let bad: Vec<_> = s
                .points
                .iter()
                .filter(|q| q.seconds.is_some() && !q.clean)
                .collect();
            if bad.is_empty() {
                continue;
            }
            let settings: Vec<String> = bad.iter().map(|q| setting(s, q.setting)).collect();
            let first = bad[0];
            let what = if first.outcome == "completed" {
                format!(
                    "completed with {} {} (this project {}, the reference {}); error {}",
                    first.events.unwrap_or(0),
                    if p.model == "rigid" { "impacts" } else { "switches" },
                    p.ours_events,
                    p.reference_events,
                    sig(first.error, 1)
                )
            } else {
                in_words(&first.outcome)
            };
            rows.push(vec![
                short(p),
                named(s),
                format!("{} of {} ({})", bad.len(), ran, settings.join(", ")),
                what,
            ]);
        }
    }
    markdown_table(
        &["problem", "peer", "runs affected (settings)", "outcome (loosest affected run)"],
        &rows,
    )
}

fn orbit_rows(o: &OrbitData) -> Vec<Vec<String>> {
    let case = format!("N = {}, from {} periods", o.modes, o.start_periods);
    let mut rows = vec![vec![
        case.clone(),
        "this project (exact monodromy)".into(),
        "—".into(),
        o.ours_iterations.to_string(),
        "—".into(),
        time(o.ours_seconds),
        format!("{} (residual under the reference map)", sig(Some(o.reference_residual), 1)),
        "—".into(),
    ]];
    for q in &o.peers {
        rows.push(vec![
            case.clone(),
            q.method.clone(),
            sig(Some(q.rtol), 1),
            q.newton_steps.map_or("—".into(), |n| n.to_string()),
            q.periods.map_or("—".into(), |n| n.to_string()),
            q.seconds.map_or(in_words(&q.outcome), |s| {
                format!("{} ({:.0}×)", time(s), s / o.ours_seconds)
            }),
            sig(q.state_error, 1),
            sig(q.multiplier_error, 1),
        ]);
    }
    rows
}

/// The orbit comparison.
pub fn orbits(d: &SideBySideData) -> String {
    let rows: Vec<Vec<String>> = d.orbits.iter().flat_map(orbit_rows).collect();
    markdown_table(
        &[
            "case",
            "method",
            "rtol",
            "Newton steps",
            "periods integrated",
            "CPU time (× ours)",
            "state error",
            "multiplier error",
        ],
        &rows,
    )
}

/// Every run of every problem.
pub fn runs(d: &SideBySideData) -> String {
    let mut rows = Vec::new();
    for p in &d.problems {
        rows.push(vec![
            short(p),
            "this project".into(),
            "—".into(),
            format!("{} (set-up {})", time(p.ours_seconds), time(p.ours_setup_seconds)),
            format!("{}", p.ours_events),
            sig(Some(p.ours_error), 2),
            "completed".into(),
        ]);
        for s in &p.series {
            for q in &s.points {
                rows.push(vec![
                    short(p),
                    named(s),
                    setting(s, q.setting),
                    q.seconds.map_or("—".into(), time),
                    q.events.map_or("—".into(), |n| n.to_string()),
                    sig(q.error, 2),
                    in_words(&q.outcome),
                ]);
            }
        }
    }
    markdown_table(
        &[
            "problem",
            "method",
            "rtol or steps per period",
            "CPU time, best (this project: its set-up apart)",
            "events",
            "error against the reference",
            "outcome",
        ],
        &rows,
    )
}
