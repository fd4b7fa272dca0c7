//! Figure 6's plot — each case over one period of its orbit: the 20-mode tip (solid), its
//! mode-1 part (dashed), blue in free flight and red in contact, and the one-mode impact
//! oscillator (green); then r_E and the impact velocity along the scan of panel (a) — and
//! its tables.

use crate::results::narrow::Layout;
use super::{Case, Fig6Data, Probe};
use crate::analysis::energetic::Coefficient;
use crate::analysis::orbit::OrbitKind;
use crate::results::render::{
    cell, dashed_key, draw_legend, drawing, markdown_table, palette, solid_key, styled_mesh,
    RenderError, CAPTION_FONT, WIDTH,
};
use plotters::prelude::*;
use crate::results::marker::{Marker, Shape};

const FREE: RGBColor = RGBColor(0, 114, 178);
const CONTACT: RGBColor = RGBColor(213, 40, 0);
const ONE_MODE: RGBColor = RGBColor(0, 158, 115);

/// r_E as text.
pub fn r_text(c: &Option<Coefficient>) -> String {
    match c {
        None => "— (not periodic)".into(),
        Some(Coefficient::Value(r)) => format!("{r:.4}"),
        Some(Coefficient::NoRealValue(r2)) => format!("no real value (r² = {r2:.3})"),
        Some(Coefficient::NoContact) => "— (no contact)".into(),
    }
}

fn title(c: &Case) -> String {
    let which = if c.panel == "b" {
        "Fig 6(b)".to_string()
    } else {
        format!("Fig 6(a), d₀/A_free = {:.3}", c.gap_over_free_amplitude)
    };
    let r = c
        .coefficient
        .and_then(|r| r.value())
        .map_or(String::new(), |r| format!(", r_E = {r:.3}"));
    format!("{which}: {}{r}", c.kind)
}

fn case_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    c: &Case,
    modes: usize,
) -> Result<(), RenderError> {
    let span = c.samples.last().map_or(1.0, |s| s.0.max(1.0));
    let one = c.one_mode.as_ref();
    let values = c
        .samples
        .iter()
        .flat_map(|s| [s.1, s.2])
        .chain(one.into_iter().flat_map(|o| o.samples.iter().map(|s| s.1)))
        .chain([c.gap_over_free_amplitude]);
    let (lo, hi) = values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| (a.min(v), b.max(v)));
    let pad = 0.08 * (hi - lo).max(1e-9);
    let mut chart = ChartBuilder::on(area)
        .caption(title(c), CAPTION_FONT)
        .margin(6)
        .margin_right(28)
        .x_label_area_size(44)
        .y_label_area_size(64)
        // headroom above the curves for the legend
        .build_cartesian_2d(0.0..span, (lo - pad)..(hi + 0.55 * (hi - lo)))
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("t / T")
        .y_desc("tip d / free amplitude")
        .draw()
        .map_err(drawing)?;
    // the stop
    chart
        .draw_series(DashedLineSeries::new(
            vec![(0.0, c.gap_over_free_amplitude), (span, c.gap_over_free_amplitude)],
            3,
            3,
            BLACK.mix(0.5).stroke_width(1),
        ))
        .map_err(drawing)?;
    // the 20-mode tip and its mode-1 part, coloured by region
    let mut first = [true, true];
    for w in c.samples.windows(2) {
        let color = if w[0].3 { CONTACT } else { FREE };
        let tip = chart
            .draw_series(LineSeries::new(
                vec![(w[0].0, w[0].1), (w[1].0, w[1].1)],
                color.stroke_width(2),
            ))
            .map_err(drawing)?;
        if first[0] && !w[0].3 {
            tip.label(format!("{modes} modes: tip"))
                .legend(solid_key(FREE.stroke_width(2)));
            first[0] = false;
        }
        let part = chart
            .draw_series(DashedLineSeries::new(
                vec![(w[0].0, w[0].2), (w[1].0, w[1].2)],
                4,
                3,
                color.stroke_width(1),
            ))
            .map_err(drawing)?;
        if first[1] && !w[0].3 {
            part.label("its mode-1 part")
                .legend(dashed_key(FREE.stroke_width(1)));
            first[1] = false;
        }
    }
    if let Some(o) = one {
        chart
            .draw_series(LineSeries::new(o.samples.iter().cloned(), ONE_MODE.stroke_width(2)))
            .map_err(drawing)?
            .label(format!("one mode, r = r_E = {:.3}", o.restitution))
            .legend(solid_key(ONE_MODE.stroke_width(2)));
    }
    draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
    Ok(())
}

fn scan_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    d: &Fig6Data,
    velocity: bool,
) -> Result<(), RenderError> {
    let xs: Vec<f64> = d.scan.iter().map(|s| s.gap_over_free_amplitude).collect();
    let (x0, x1) = (xs.first().copied().unwrap_or(0.0), xs.last().copied().unwrap_or(1.0));
    let value = |s: &super::ScanPoint| {
        if velocity {
            s.entry_velocity
        } else {
            s.rest.value()
        }
    };
    // headroom above the points for the legend, and room for the whole continued branch
    // (its r_E reaches 1 where its contact vanishes)
    let branch_top = d.gap_branch.as_ref().map_or(0.0, |b| {
        b.points
            .iter()
            .filter_map(|q| if velocity { q.smallest_entry_velocity } else { q.r_e })
            .filter(|v| v.is_finite())
            .fold(0.0_f64, f64::max)
    });
    let top = (d.scan.iter().filter_map(value).fold(0.0_f64, f64::max).max(0.05) * 2.4)
        .max(branch_top * 1.08);
    let mut chart = ChartBuilder::on(area)
        .caption(
            if velocity {
                "Fig 6(a) scan: impact velocity against d₀"
            } else {
                "Fig 6(a) scan: energetic restitution against d₀"
            },
            CAPTION_FONT,
        )
        .margin(6)
        .margin_right(28)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((x0 - 0.03)..(x1 + 0.03), 0.0..top)
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("d₀ / free amplitude")
        .y_desc(if velocity { "largest v / (ω · free amplitude)" } else { "energetic r_E, eq (39)" })
        .draw()
        .map_err(drawing)?;
    // colour by contacts per period n
    for n in 1..=4u64 {
        let pts: Vec<(f64, f64)> = d
            .scan
            .iter()
            .filter(|s| matches!(s.rest.kind, OrbitKind::Periodic { n: k, .. } if k == n))
            .filter_map(|s| value(s).map(|v| (s.gap_over_free_amplitude, v)))
            .collect();
        if pts.is_empty() {
            continue;
        }
        let c = palette(n as usize - 1);
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
            .map_err(drawing)?
            .label(format!("{n} contact{}", if n > 1 { "s" } else { "" }))
            .legend(move |(x, y)| Circle::new((x + 12, y), 4, c.filled()));
    }
    // the (1,1) branch continued in d₀: solid where stable, dotted where not
    if let Some(b) = &d.gap_branch {
        let on = |q: &super::branch::GapPoint| {
            let v = if velocity { q.smallest_entry_velocity } else { q.r_e };
            v.filter(|v| *v <= top).map(|v| (q.gap_over_free_amplitude, v))
        };
        let (stable, unstable): (Vec<_>, Vec<_>) = b.points.iter().partition(|q| q.stable);
        let c = BLACK;
        chart
            .draw_series(stable.iter().filter_map(|q| on(q)).map(|p| Circle::new(p, 2, c.filled())))
            .map_err(drawing)?
            .label("(1,1) branch, stable")
            .legend(move |(x, y)| Circle::new((x + 12, y), 2, c.filled()));
        chart
            .draw_series(unstable.iter().filter_map(|q| on(q)).map(|p| Circle::new(p, 2, c.stroke_width(1))))
            .map_err(drawing)?
            .label("(1,1) branch, unstable")
            .legend(move |(x, y)| Circle::new((x + 12, y), 2, c.stroke_width(1)));
        let folds: Vec<f64> = b
            .bifurcations
            .iter()
            .filter(|f| f.kind == "fold")
            .map(|f| f.gap_over_free_amplitude)
            .collect();
        if !folds.is_empty() {
            chart
                .draw_series(folds.iter().map(|&x| Marker::new((x, 0.0), Shape::Triangle, 8, RED.filled())))
                .map_err(drawing)?
                .label("its folds")
                .legend(|(x, y)| Marker::new((x + 12, y), Shape::Triangle, 8, RED.filled()));
        }
    }
    if !velocity {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(x0 - 0.03, 0.036), (x1 + 0.03, 0.036)],
                6,
                4,
                CONTACT.stroke_width(2),
            ))
            .map_err(drawing)?
            .label("the paper's 0.036")
            .legend(dashed_key(CONTACT.stroke_width(2)));
    }
    for c in d.cases.iter().filter(|c| c.panel == "a") {
        let x = c.gap_over_free_amplitude;
        if x <= x1 + 0.03 {
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(x, 0.0), (x, top)],
                    2,
                    4,
                    BLACK.mix(0.5).stroke_width(1),
                ))
                .map_err(drawing)?;
        }
    }
    draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    Ok(())
}

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &Fig6Data, layout: Layout) -> Result<String, RenderError> {
    // the cases two per row (500 × 360 px each), then the two scans (500 × 560 px each)
    let rows = d.cases.len().div_ceil(2);
    let (case, scan) = (layout.panel_height(500, 360), layout.panel_height(500, 560));
    let (cases_height, height) = match layout {
        Layout::Wide => (case * rows as u32, case * rows as u32 + scan),
        Layout::Narrow => {
            let n = u32::try_from(d.cases.len()).unwrap_or(0);
            (case * n, case * n + 2 * scan)
        }
    };
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (layout.width(), height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (top, bottom) = root.split_vertically(cases_height);
        let cells = match layout {
            Layout::Wide => top.split_evenly((rows, 2)),
            Layout::Narrow => top.split_evenly((d.cases.len().max(1), 1)),
        };
        for (cell, c) in cells.iter().zip(&d.cases) {
            case_panel(cell, c, d.params.modes)?;
        }
        let (left, right) = layout.beside(&bottom, WIDTH / 2, scan);
        scan_panel(&left, d, false)?;
        scan_panel(&right, d, true)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

fn which(c: &Case) -> String {
    if c.panel == "b" {
        "(b)".into()
    } else {
        format!("(a) {}", c.reading.short())
    }
}

fn r_with_uncertainty(c: &Case) -> String {
    match (c.coefficient.and_then(|r| r.value()), c.uncertainty) {
        (Some(r), Some(u)) => {
            // the key number's value and uncertainty, its rounding included (one story)
            use crate::base::report::{format_sig, pretty, round_up_one_figure, Cited, Uncertainty};
            let c = Cited::new(r, 4, Uncertainty::new(u.max(1e-12), ""), "");
            format!("{} ± {}", pretty(c.value, c.digits), format_sig(round_up_one_figure(c.uncertainty.value), 1))
        }
        (Some(r), None) => format!("{r:.4} (orbit not robust)"),
        _ => r_text(&c.coefficient),
    }
}

/// The main table: each case's orbit and r_E against the paper.
pub fn table(d: &Fig6Data) -> String {
    let rows: Vec<Vec<String>> = d
        .cases
        .iter()
        .map(|c| {
            vec![
                which(c),
                cell(c.gap_over_free_amplitude, 3),
                c.kind.to_string(),
                r_with_uncertainty(c),
                format!("{}", c.paper_r_e),
                c.contact_coefficients
                    .iter()
                    .map(|r| r.map_or("—".into(), |r| format!("{r:.4}")))
                    .collect::<Vec<_>>()
                    .join("<br>"),
                c.contacts
                    .iter()
                    .map(|(a, b)| format!("{a:.4}–{b:.4}"))
                    .collect::<Vec<_>>()
                    .join("<br>"),
            ]
        })
        .collect();
    markdown_table(
        &[
            "panel",
            "$d_0/A_{\\rm free}$",
            "orbit",
            "$r_E$ (eq 39)",
            "paper",
            "per contact (eq 38)",
            "contacts, $t/T$",
        ],
        &rows,
    )
}

fn probe_text(p: &Probe) -> String {
    format!("{}: {}", p.kind, r_text(&p.coefficient))
}

/// The diagnostics of every case.
pub fn diagnostics_table(d: &Fig6Data) -> String {
    let mut rows = Vec::new();
    for c in &d.cases {
        let g = &c.diagnostics;
        let mut row = vec![which(c)];
        row.push(
            g.by_modes
                .iter()
                .map(|(n, p)| format!("N = {n} — {}", probe_text(p)))
                .collect::<Vec<_>>()
                .join("<br>"),
        );
        row.push(probe_text(&g.long_transient));
        row.push(probe_text(&g.loose_tolerance));
        row.push(
            g.random_starts
                .iter()
                .map(probe_text)
                .collect::<Vec<_>>()
                .join("<br>"),
        );
        rows.push(row);
    }
    let p = &d.params;
    markdown_table(
        &[
            "panel",
            "truncation",
            &format!("{} periods", p.long_transient),
            &format!("root tolerance {:e}", p.loose_root_tolerance),
            &format!("{} random starts", p.random_starts),
        ],
        &rows,
    )
}

/// The 20-mode orbit against the one-mode impact oscillator with r = r_E: one column per
/// case that has an r_E, each cell "20 modes / one mode".
pub fn comparison_table(d: &Fig6Data) -> String {
    let list = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let cases: Vec<(&Case, &super::OneMode)> = d
        .cases
        .iter()
        .filter_map(|c| c.one_mode.as_ref().map(|o| (c, o)))
        .collect();
    let row = |label: &str, f: &dyn Fn(&Case, &super::OneMode) -> String| -> Vec<String> {
        std::iter::once(label.to_string())
            .chain(cases.iter().map(|(c, o)| f(c, o)))
            .collect()
    };
    let rows = vec![
        row("orbit", &|c, o| format!("{} / {}", c.kind, o.kind)),
        row("entries, $t/T$", &|c, o| {
            let entries: Vec<f64> = c.contacts.iter().map(|x| x.0).collect();
            format!("{}<br>/ {}", list(&entries), list(&o.impact_phases))
        }),
        row("impact velocity / $(\\omega A_{\\rm free})$", &|c, o| {
            format!("{}<br>/ {}", list(&c.entry_velocities), list(&o.impact_velocities))
        }),
        row("largest $d/A_{\\rm free}$", &|c, o| {
            format!("{:.3} / {:.3}", c.extremes.0, o.extremes.0)
        }),
        row("smallest $d/A_{\\rm free}$", &|c, o| {
            format!("{:.3} / {:.3}", c.extremes.1, o.extremes.1)
        }),
        row("chatters of the one-mode model", &|_, o| o.chatters.to_string()),
    ];
    let header: Vec<String> = std::iter::once(String::new())
        .chain(cases.iter().map(|(c, _)| which(c)))
        .collect();
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    markdown_table(&h, &rows)
}
