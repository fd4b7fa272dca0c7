//! Error against run time: event-time error and end-state error against wall time, one
//! series per method.

use crate::results::render::{
    power_of_ten,
    draw_legend, drawing, markdown_table, palette, solid_key, styled_mesh, RenderError,
    CAPTION_FONT,
};
use crate::base::report::format_sig;
use super::WorkPrecisionData;
use crate::results::narrow::Layout;
use plotters::prelude::*;

/// Errors below this are drawn at this floor (they are round-off).
const FLOOR: f64 = 1e-16;

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &WorkPrecisionData, layout: Layout) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        // two rows of two panels: (a), (b) above (c), (d)
        let (width, height) = layout.grid_size(2, 2, 1000);
        let root = SVGBackend::with_string(&mut svg, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (top, bottom) = root.split_vertically(height / 2);
        scaling_panels(&bottom, d, layout)?;
        let panels = layout.cells(&top, 1, 2);
        let (tmin, tmax) = d.points.iter().fold((f64::MAX, 0.0_f64), |(a, b), p| {
            (a.min(p.seconds), b.max(p.seconds))
        });
        let titles = ["(a) max event-time error", "(b) relative end-state error"];
        for (i, panel) in panels.iter().enumerate() {
            let value = |p: &super::WorkPoint| {
                let e = if i == 0 { p.event_error } else { p.state_error };
                e.max(FLOOR)
            };
            let finite: Vec<f64> = d
                .points
                .iter()
                .map(value)
                .filter(|e| e.is_finite())
                .collect();
            let emax = finite.iter().cloned().fold(FLOOR, f64::max) * 10.0;
            let mut chart = ChartBuilder::on(panel)
                .caption(titles[i], CAPTION_FONT)
                .margin(10)
                .margin_right(28)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d(
                    (tmin / 2.0..tmax * 2.0).log_scale(),
                    (FLOOR / 2.0..emax).log_scale(),
                )
                .map_err(drawing)?;
            styled_mesh(&mut chart)
                .x_desc("wall time (s)")
                .x_label_formatter(&power_of_ten)
                .y_label_formatter(&power_of_ten)
                .draw()
                .map_err(drawing)?;
            for (s, method) in ["exact", "DP5"].iter().enumerate() {
                let c = palette(s);
                let pts: Vec<(f64, f64)> = d
                    .points
                    .iter()
                    .filter(|p| p.method == *method && value(p).is_finite())
                    .map(|p| (p.seconds, value(p)))
                    .collect();
                chart
                    .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                    .map_err(drawing)?
                    .label(*method)
                    .legend(solid_key(c.stroke_width(2)));
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
                    .map_err(drawing)?;
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperMiddle)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The markdown table.
pub fn table(d: &WorkPrecisionData) -> String {
    let rows: Vec<Vec<String>> = d
        .points
        .iter()
        .map(|p| {
            vec![
                p.method.clone(),
                format_sig(p.tolerance, 1),
                if !p.event_error.is_finite() {
                    "—".into()
                } else if p.event_error == 0.0 {
                    "0".into()
                } else {
                    format_sig(p.event_error, 2)
                },
                if p.state_error == 0.0 {
                    "0".into()
                } else {
                    format_sig(p.state_error, 2)
                },
                format!("{:.2}", p.seconds * 1e3),
                p.evaluations.to_string(),
                if p.same_sequence {
                    format!("{}, same", p.events)
                } else {
                    format!("**{}, differ**", p.events)
                },
            ]
        })
        .collect();
    markdown_table(
        &[
            "method",
            "tolerance",
            "event-time error",
            "end-state error",
            "wall time (ms)",
            "evaluations",
            "switches (vs reference)",
        ],
        &rows,
    )
}

/// The exact simulator's work counters on the speed-target runs.
pub fn costs_table(d: &WorkPrecisionData) -> String {
    let rows: Vec<Vec<String>> = d
        .costs
        .iter()
        .map(|c| {
            let s = &c.stats;
            let per_period = |x: u64| format!("{:.1}", x as f64 / c.periods as f64);
            vec![
                format!(
                    "{}, N = {}, k = {}k₁",
                    c.label, c.modes, c.stop_stiffness_over_k1
                ),
                c.events.to_string(),
                per_period(s.segments),
                format!("{} ({})", per_period(s.steps), per_period(s.contact_steps)),
                per_period(s.evaluations),
                format!(
                    "{:.1}",
                    s.polish_evaluations as f64 / c.events.max(1) as f64
                ),
                format!("{:.1}", c.seconds * 1e3),
            ]
        })
        .collect();
    markdown_table(
        &[
            "model",
            "switches",
            "segments per period",
            "steps per period (contact)",
            "g evaluations per period",
            "polish per switch",
            "ms",
        ],
        &rows,
    )
}

/// A generated record of the wall times, with the machine that measured them.
pub fn timing_summary(d: &WorkPrecisionData) -> String {
    let exact = d
        .points
        .iter()
        .find(|p| p.method == "exact" && p.tolerance <= 1e-6 + 1e-18 && p.tolerance >= 1e-6 - 1e-18);
    let dp5 = d
        .points
        .iter()
        .filter(|p| p.method != "exact" && p.event_error < 1e-10)
        .min_by(|a, b| a.seconds.total_cmp(&b.seconds));
    let mut s = format!(
        "Wall times measured on {} when this book was built (best of {}, one thread). ",
        d.machine, d.params.repeats
    );
    if let (Some(e), Some(r)) = (exact, dp5) {
        s.push_str(&format!(
            "For {} periods the exact method at root tolerance 10⁻⁶ took {} ms; the fastest \
             DP5 run with event times within 10⁻¹⁰ (rtol {}) took {} ms — about {} times longer.",
            d.params.periods,
            crate::base::report::pretty(e.seconds * 1e3, 3),
            crate::results::render::power_of_ten(&r.tolerance),
            crate::base::report::pretty(r.seconds * 1e3, 3),
            crate::base::report::pretty(r.seconds / e.seconds, 2)
        ));
    }
    s.push('\n');
    s
}

/// (c) cost against N at k = 100k₁ and (d) against k at N = 10: wall time per period and
/// per orbit with its multipliers, log–log.
fn scaling_panels(
    area: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    d: &WorkPrecisionData,
    layout: Layout,
) -> Result<(), RenderError> {
    let panels = layout.cells(area, 1, 2);
    let lines = [
        ("(c) cost against N, k = 100k₁", "N (modes)", &d.scaling.along_modes, true),
        ("(d) cost against k, N = 10", "k / k₁", &d.scaling.along_stiffness, false),
    ];
    for (panel, (title, xdesc, pts, by_modes)) in panels.iter().zip(lines) {
        let x = |q: &super::scaling::ScalingPoint| if by_modes { q.modes as f64 } else { q.k_over_k1 };
        let series: [(&str, Vec<(f64, f64)>); 2] = [
            ("per period", pts.iter().map(|q| (x(q), q.seconds_per_period)).collect()),
            (
                "per orbit with multipliers",
                pts.iter().filter_map(|q| Some((x(q), q.seconds_per_orbit?))).collect(),
            ),
        ];
        let all = series.iter().flat_map(|s| s.1.iter());
        let (xmin, xmax, ymin, ymax) = all.fold((f64::MAX, 0.0f64, f64::MAX, 0.0f64), |a, p| {
            (a.0.min(p.0), a.1.max(p.0), a.2.min(p.1), a.3.max(p.1))
        });
        if xmax <= 0.0 {
            continue;
        }
        // ticks exactly at the N (or k) computed: N is an integer
        let mut ticks: Vec<f64> = pts.iter().map(x).collect();
        ticks.dedup();
        let mut chart = ChartBuilder::on(panel)
            .caption(title, CAPTION_FONT)
            .margin(10)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(
                (xmin / 1.3..xmax * 1.3).log_scale().with_key_points(ticks),
                (ymin / 3.0..ymax * 3.0).log_scale(),
            )
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc(xdesc)
            .y_desc("wall time (s)")
            .x_label_formatter(&|v| {
                if by_modes {
                    format!("{}", v.round())
                } else {
                    power_of_ten(v)
                }
            })
            .y_label_formatter(&power_of_ten)
            .draw()
            .map_err(drawing)?;
        for (s, (label, p)) in series.iter().enumerate() {
            let c = palette(s);
            chart
                .draw_series(LineSeries::new(p.clone(), c.stroke_width(2)))
                .map_err(drawing)?
                .label(*label)
                .legend(solid_key(c.stroke_width(2)));
            chart
                .draw_series(p.iter().map(|&q| Circle::new(q, 4, c.filled())))
                .map_err(drawing)?;
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    }
    Ok(())
}

/// The scaling runs: per (N, k) the wall times and the work counters per period, then the
/// fitted exponents.
pub fn scaling_table(d: &WorkPrecisionData) -> String {
    let sc = &d.scaling;
    let table = {
    let rows: Vec<Vec<String>> = sc
        .along_modes
        .iter()
        .chain(&sc.along_stiffness)
        .map(|q| {
            vec![
                q.modes.to_string(),
                format_sig(q.k_over_k1, 2),
                format!("{:.2}", q.seconds_per_period * 1e6),
                q.seconds_per_orbit.map_or("—".into(), |t| format!("{:.3}", t * 1e3)),
                format!("{:.1}", q.per_period(q.stats.segments)),
                format!("{:.1}", q.per_period(q.stats.evaluations)),
                format!("{:.1}", q.per_period(q.stats.steps)),
            ]
        })
        .collect();
    markdown_table(
        &[
            "N",
            "k/k₁",
            "µs per period",
            "ms per orbit",
            "segments per period",
            "evaluations per period",
            "certified steps per period",
        ],
        &rows,
    )
    };
    // the times' exponents: this machine's, so stated here and not among the key numbers
    let fit = |pts: &[super::scaling::ScalingPoint], x: &dyn Fn(&super::scaling::ScalingPoint) -> f64, per_orbit: bool, from: usize| {
        let xy: Vec<(f64, f64)> = pts
            .iter()
            .filter_map(|q| Some((x(q), if per_orbit { q.seconds_per_orbit? } else { q.seconds_per_period })))
            .collect();
        super::scaling::exponent(&xy, from).map_or("—".to_string(), |(e, u)| {
            if u.is_finite() {
                format!("{e:.2} ± {:.2}", u.max(0.005))
            } else {
                format!("{e:.2}")
            }
        })
    };
    let modes: Vec<usize> = sc.along_modes.iter().map(|q| q.modes).collect();
    let from = super::scaling::fit_from(&modes);
    let n = |q: &super::scaling::ScalingPoint| q.modes as f64;
    let k = |q: &super::scaling::ScalingPoint| q.k_over_k1;
    let sentence = format!(
        "The wall time's exponents on this machine (least-squares slopes on log–log \
         axes, ± their standard error; along N from N = {} on): per period {} in N, per orbit \
         {} in N; per period {} in k, per orbit {} in k.\n",
        modes.get(from).copied().unwrap_or(0),
        fit(&sc.along_modes, &n, false, from),
        fit(&sc.along_modes, &n, true, from),
        fit(&sc.along_stiffness, &k, false, 0),
        fit(&sc.along_stiffness, &k, true, 0),
    );
    format!("{table}\n{}", crate::results::render::readable_text(&sentence))
}
