//! The boundaries in N: the period-doubling (solid) and grazing (dashed) curves of the
//! (1,1) orbit in (k, ω), one colour per N; the table of their ω at the tabulated k.

use super::{converged_from, relative_to_finest, Boundary, BoundariesData};
use crate::results::render::{
    dashed_key, draw_legend, drawing, markdown_table, palette, power_of_ten, solid_key,
    styled_mesh, RenderError, CAPTION_FONT,
};
use crate::results::narrow::Layout;
use plotters::prelude::*;

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &BoundariesData, layout: Layout) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        // on a phone the key needs its own room above the curves: a taller panel
        let size = match layout {
            Layout::Wide => layout.grid_size(1, 1, 560),
            Layout::Narrow => (layout.width(), 480),
        };
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (k0, k1) = d.params.k_range;
        // the ω the curves span, with a margin (the traced rectangle is wider)
        let (lo, hi) = [&d.period_doubling, &d.grazing]
            .iter()
            .flat_map(|c| c.iter())
            .flat_map(|b| b.points.iter())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.0), b.max(p.0)));
        let (w0, w1) = if lo < hi {
            (lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo))
        } else {
            d.params.omega_range
        };
        let w1 = match layout {
            Layout::Wide => w1,
            Layout::Narrow => w1 + 0.7 * (w1 - w0),
        };
        let mut chart = ChartBuilder::on(&root)
            .caption(
                match layout {
                    Layout::Wide => {
                        "period doubling (solid) and grazing into two contacts (dashed) of the \
                         (1,1) orbit"
                    }
                    Layout::Narrow => "(1,1): period doubling (solid), grazing (dashed)",
                },
                CAPTION_FONT,
            )
            .margin(10)
            .margin_right(24)
            .x_label_area_size(48)
            .y_label_area_size(64)
            .build_cartesian_2d((k0..k1).log_scale(), w0..w1)
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("k / k₁")
            .y_desc("ω / (β₁⁻)²")
            .x_label_formatter(&power_of_ten)
            .y_label_formatter(&|y| format!("{y:.1}"))
            .draw()
            .map_err(drawing)?;
        for (i, n) in d.modes.iter().enumerate() {
            let colour = palette(i);
            let style = colour.stroke_width(2);
            let find = |curves: &[Boundary]| curves.iter().find(|b| b.modes == *n).cloned();
            let mut labelled = false;
            if let Some(b) = find(&d.period_doubling).filter(|b| !b.points.is_empty()) {
                let s = chart
                    .draw_series(LineSeries::new(b.points.iter().map(|&(w, k)| (k, w)), style))
                    .map_err(drawing)?;
                s.label(format!("N = {n}")).legend(solid_key(style));
                labelled = true;
            }
            if let Some(b) = find(&d.grazing).filter(|b| !b.points.is_empty()) {
                let s = chart
                    .draw_series(DashedLineSeries::new(
                        b.points.iter().map(|&(w, k)| (k, w)),
                        6,
                        4,
                        style,
                    ))
                    .map_err(drawing)?;
                if !labelled {
                    s.label(format!("N = {n}")).legend(dashed_key(style));
                }
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    }
    Ok(svg)
}

/// One curve's ω at each tabulated k per N, with the relative distance from the largest N.
fn curve_table(d: &BoundariesData, curves: &[Boundary]) -> String {
    let mut header = vec!["N".to_string()];
    for k in &d.params.table_k {
        header.push(format!("k/k₁ = {}", super::k_label(*k)));
    }
    let rel: Vec<Vec<Option<f64>>> = (0..d.params.table_k.len())
        .map(|j| relative_to_finest(curves, j))
        .collect();
    let mut rows = Vec::new();
    for (i, b) in curves.iter().enumerate() {
        let last = i + 1 == curves.len();
        let matched: Vec<String> = d
            .params
            .table_k
            .iter()
            .zip(&d.matched)
            .filter(|(_, m)| **m == b.modes)
            .map(|(k, _)| super::k_label(*k))
            .collect();
        let mut row = vec![if matched.is_empty() {
            b.modes.to_string()
        } else if matched.len() == d.params.table_k.len() {
            format!("{} (matched)", b.modes)
        } else {
            format!("{} (matched at k/k₁ = {})", b.modes, matched.join(", "))
        }];
        for (j, r) in rel.iter().enumerate() {
            row.push(match (b.at_k[j], r[i]) {
                (Some(w), Some(r)) if !last => format!("{w:.6} ({:.2} %)", 100.0 * r),
                (Some(w), _) => format!("{w:.6}"),
                _ => "—".to_string(),
            });
        }
        rows.push(row);
    }
    let mut conv = vec!["converged (1 %) from N".to_string()];
    for j in 0..d.params.table_k.len() {
        conv.push(converged_from(d, curves, j).map_or("—".into(), |n| n.to_string()));
    }
    rows.push(conv);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    markdown_table(&header, &rows)
}

/// The period doubling's table.
pub fn table(d: &BoundariesData) -> String {
    curve_table(d, &d.period_doubling)
}

/// The grazing's table.
pub fn grazing_table(d: &BoundariesData) -> String {
    curve_table(d, &d.grazing)
}
