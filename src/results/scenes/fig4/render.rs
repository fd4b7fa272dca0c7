//! Figure 4: one period of each orbit — tip displacement against time and the phase
//! portrait — free flight in blue, contact in red.

use crate::results::narrow::Layout;
use crate::results::render::{
    tick,clip_to_band, drawing, markdown_table, styled_mesh, RenderError, CAPTION_FONT};
use crate::analysis::orbit::OrbitKind;
use crate::base::report::format_sig;
use super::Fig4Data;
use plotters::prelude::*;

const FREE: RGBColor = RGBColor(0, 114, 178);
const CONTACT: RGBColor = RGBColor(213, 40, 0);

/// Consecutive samples joined, coloured by the region of the earlier one.
fn pieces(points: &[(f64, f64, bool)]) -> Vec<(Vec<(f64, f64)>, bool)> {
    let mut out: Vec<(Vec<(f64, f64)>, bool)> = Vec::new();
    for w in points.windows(2) {
        let (a, b) = (w[0], w[1]);
        match out.last_mut() {
            Some((line, c)) if *c == a.2 => line.push((b.0, b.1)),
            _ => out.push((vec![(a.0, a.1), (b.0, b.1)], a.2)),
        }
    }
    out
}

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &Fig4Data, layout: Layout) -> Result<String, RenderError> {
    // the contacts of the long-contact orbits, magnified, in a last row
    let zoomed: Vec<&super::Fig4Panel> = d
        .panels
        .iter()
        .filter(|p| p.dwell_depth.is_some() && !p.contacts.is_empty())
        .take(2)
        .collect();
    let rows = d.panels.len().max(1) + usize::from(!zoomed.is_empty());
    // every drawn cell: two per orbit, then the magnified contacts
    let drawn = 2 * d.panels.len() + zoomed.len();
    let size = match layout {
        Layout::Wide => layout.grid_size(rows, 2, 330 * rows as u32),
        Layout::Narrow => (
            layout.width(),
            layout.panel_height(500, 330) * u32::try_from(drawn.max(1)).unwrap_or(1),
        ),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let cells = match layout {
            Layout::Wide => root.split_evenly((rows, 2)),
            Layout::Narrow => root.split_evenly((drawn.max(1), 1)),
        };
        for (r, p) in d.panels.iter().enumerate() {
            let span = p.series.last().map_or(1.0, |s| s.0.max(1.0));
            let (dmin, dmax) = p
                .series
                .iter()
                .fold((0.0_f64, 0.0_f64), |(a, b), s| (a.min(s.1), b.max(s.1)));
            let (vmin, vmax) = p
                .series
                .iter()
                .fold((0.0_f64, 0.0_f64), |(a, b), s| (a.min(s.2), b.max(s.2)));
            let pad = |lo: f64, hi: f64| {
                let e = 0.08 * (hi - lo).max(1e-12);
                (lo - e, hi + e)
            };
            let (dlo, dhi) = pad(dmin, dmax);
            let (vlo, vhi) = pad(vmin, vmax);
            let title = format!("N = {}: {}; paper: {}", p.modes, p.kind, p.paper);
            let mut chart = ChartBuilder::on(&cells[2 * r])
                .caption(title, CAPTION_FONT)
                .margin(6)
                .margin_right(28)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d(0.0..span, dlo..dhi)
                .map_err(drawing)?;
            styled_mesh(&mut chart)
                .x_desc("t / T")
                .y_desc("tip d / free amplitude")
                .draw()
                .map_err(drawing)?;
            let td: Vec<(f64, f64, bool)> = p.series.iter().map(|s| (s.0, s.1, s.3)).collect();
            for (line, c) in pieces(&td) {
                let color = if c { CONTACT } else { FREE };
                chart
                    .draw_series(LineSeries::new(line, color.stroke_width(2)))
                    .map_err(drawing)?;
            }
            chart
                .draw_series(LineSeries::new(
                    vec![(0.0, 0.0), (span, 0.0)],
                    BLACK.mix(0.4),
                ))
                .map_err(drawing)?;
            let mut chart = ChartBuilder::on(&cells[2 * r + 1])
                .caption(format!("N = {}: phase portrait", p.modes), CAPTION_FONT)
                .margin(6)
                .margin_right(28)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d(dlo..dhi, vlo..vhi)
                .map_err(drawing)?;
            styled_mesh(&mut chart)
                .x_desc("tip d / free amplitude")
                .y_desc("ḋ / (ω · free amplitude)")
                .draw()
                .map_err(drawing)?;
            let dv: Vec<(f64, f64, bool)> = p.series.iter().map(|s| (s.1, s.2, s.3)).collect();
            for (line, c) in pieces(&dv) {
                let color = if c { CONTACT } else { FREE };
                chart
                    .draw_series(LineSeries::new(line, color.stroke_width(2)))
                    .map_err(drawing)?;
            }
        }
        for (z, p) in zoomed.iter().enumerate() {
            contact_magnified(&cells[2 * d.panels.len() + z], p)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// One contact of an orbit, magnified: the tip displacement from just before the entry to
/// just after the exit, with the stop's level, so that a shallow dwell shows.
fn contact_magnified<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    p: &super::Fig4Panel,
) -> Result<(), RenderError> {
    let (start, end) = p.contacts[0];
    let margin = 0.15 * (end - start);
    let (t0, t1) = (start - margin, end + margin);
    let inside: Vec<(f64, f64, bool)> = p
        .series
        .iter()
        .filter(|s| s.0 >= t0 && s.0 <= t1)
        .map(|s| (s.0, s.1, s.3))
        .collect();
    let top = inside.iter().fold(0.0_f64, |a, s| a.max(s.1));
    let (lo, hi) = (-0.6 * top, 1.15 * top);
    let mut chart = ChartBuilder::on(area)
        .caption(format!("N = {}: the contact, magnified", p.modes), CAPTION_FONT)
        .margin(6)
        .margin_right(28)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(t0..t1, lo..hi)
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("t / T")
        .y_desc("tip d / free amplitude")
        // two decimals, a minus sign, and 0 for a tick at ±round-off of 0
        .y_label_formatter(&|y| tick(&((y * 100.0).round() / 100.0)))
        .draw()
        .map_err(drawing)?;
    chart
        .draw_series(LineSeries::new(vec![(t0, 0.0), (t1, 0.0)], BLACK.mix(0.4)))
        .map_err(drawing)?;
    for (line, c) in pieces(&inside) {
        let color = if c { CONTACT } else { FREE };
        for part in clip_to_band(&line, (lo, hi)) {
            chart
                .draw_series(LineSeries::new(part, color.stroke_width(2)))
                .map_err(drawing)?;
        }
    }
    Ok(())
}

fn kinds(v: &[(OrbitKind, usize)]) -> String {
    v.iter()
        .map(|(k, c)| format!("{k}×{c}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The markdown table of what each orbit does in one period (the verdicts are in the
/// chapter, by name).
pub fn table(d: &Fig4Data) -> String {
    let rows: Vec<Vec<String>> = d
        .panels
        .iter()
        .map(|p| {
            vec![
                p.modes.to_string(),
                p.kind.to_string(),
                p.impact_velocities
                    .iter()
                    .map(|v| format!("{v:.4}"))
                    .collect::<Vec<_>>()
                    .join("<br>"),
                p.contacts
                    .iter()
                    .map(|(a, b)| format!("{a:.4}–{b:.4}"))
                    .collect::<Vec<_>>()
                    .join("<br>"),
                format!("{:.4}", p.max_tip),
                p.dwell_depth.map_or("—".into(), |d| format!("{d:.4}")),
            ]
        })
        .collect();
    markdown_table(
        &[
            "N",
            "orbit",
            "impact velocities / $(\\omega A_{\\rm free})$",
            "contact intervals, $t/T$",
            "max tip / $A_{\\rm free}$",
            "dwell depth / $A_{\\rm free}$",
        ],
        &rows,
    )
}

/// The robustness checks: one row per check, one column per N (narrow enough for a page).
pub fn robustness_table(d: &Fig4Data) -> String {
    let per_case = |f: &dyn Fn(&super::Fig4Panel) -> String| -> Vec<String> {
        d.panels.iter().map(f).collect()
    };
    let mut rows: Vec<Vec<String>> = Vec::new();
    let mut row = |label: String, cells: Vec<String>| {
        rows.push(std::iter::once(label).chain(cells).collect());
    };
    row(
        format!("orbit after {} periods", d.params.transient),
        per_case(&|p| p.kind.to_string()),
    );
    row(
        format!("after {} periods", d.params.long_transient),
        per_case(&|p| p.evidence.long_transient.to_string()),
    );
    row(
        format!("root tolerance {:e}", d.params.loose_root_tolerance),
        per_case(&|p| p.evidence.loose_tolerance.to_string()),
    );
    row(
        "DP5 reference: contacts per period".into(),
        per_case(&|p| match p.evidence.reference {
            None => "skipped".into(),
            Some((n, _)) => n.to_string(),
        }),
    );
    row(
        "DP5 reference: largest event-time difference".into(),
        per_case(&|p| match p.evidence.reference {
            Some((_, Some(dt))) => format!("≤ {}", format_sig(dt, 1)),
            Some((_, None)) => "event counts differ".into(),
            None => "—".into(),
        }),
    );
    row(
        format!("{} random starts reach", d.params.random_starts),
        per_case(&|p| kinds(&p.evidence.random_starts).replace(", ", "<br>")),
    );
    row(
        "damping read as ζ₁ ≈ 0.124 (literal caption)".into(),
        per_case(&|p| p.evidence.literal_caption.to_string()),
    );
    let header: Vec<String> = std::iter::once("check".to_string())
        .chain(d.panels.iter().map(|p| format!("N = {}", p.modes)))
        .collect();
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    markdown_table(&h, &rows)
}
