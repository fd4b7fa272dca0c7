//! Figure 3(a)–(c): simulated return velocities against the impact laws, and the gap's
//! convergence for every N.

use crate::results::render::{
    axis_fraction, emptiest_corner,
    power_of_ten,
    cell,
    dashed_key, draw_legend, drawing, markdown_table, palette, solid_key, styled_mesh,
    RenderError, CAPTION_FONT,
};
use crate::results::narrow::Layout;
use super::Fig3abcData;
use plotters::prelude::*;

fn panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    eps: &[f64],
    simulated: &[f64],
    predicted: &[f64],
    labels: (&str, &str),
) -> Result<(), RenderError> {
    let (lo, hi) = simulated
        .iter()
        .chain(predicted)
        .fold((f64::MAX, f64::MIN), |(a, b), &v| (a.min(v), b.max(v)));
    let pad = 0.05 * (hi - lo).max(1e-6);
    // the legend (two rows, about 0.7 of the width and 0.2 of the height, with its margin) in a corner
    // free of data, with room made below the data if no corner is free
    let xs = (eps[0], eps[eps.len() - 1]);
    let mut placed = (SeriesLabelPosition::LowerLeft, (lo - pad, hi + pad));
    for room in [0.0, 0.2, 0.4] {
        let ys = (lo - pad - room * (hi - lo), hi + pad);
        let curve = |v: &[f64]| -> Vec<(f64, f64)> {
            eps.iter()
                .zip(v)
                .map(|(&e, &y)| (axis_fraction(e, xs, true), axis_fraction(y, ys, false)))
                .collect()
        };
        let (corner, covered) = emptiest_corner(&[curve(simulated), curve(predicted)], (0.75, 0.24));
        placed = (corner, ys);
        if covered == 0 {
            break;
        }
    }
    let (corner, ys) = placed;
    let mut chart = ChartBuilder::on(area)
        .caption(title, CAPTION_FONT)
        .margin(8)
        .margin_right(28)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((xs.0..xs.1).log_scale(), ys.0..ys.1)
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("ε")
        .x_label_formatter(&power_of_ten)
        .draw()
        .map_err(drawing)?;
    let c = palette(0);
    chart
        .draw_series(LineSeries::new(
            eps.iter().cloned().zip(simulated.iter().cloned()),
            c.stroke_width(2),
        ))
        .map_err(drawing)?
        .label(labels.0)
        .legend(solid_key(c.stroke_width(2)));
    chart
        .draw_series(DashedLineSeries::new(
            eps.iter().cloned().zip(predicted.iter().cloned()),
            5,
            4,
            BLACK.stroke_width(1),
        ))
        .map_err(drawing)?
        .label(labels.1)
        .legend(dashed_key(BLACK.stroke_width(1)));
    draw_legend(&mut chart, corner)?;
    Ok(())
}

/// The SVG plot: (a) N = 1, (b), (c) N = 2 modes 1 and 2, and the gap for every N.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &Fig3abcData, layout: Layout) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, layout.grid_size(2, 2, 860)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let cells = layout.cells(&root, 2, 2);
        let eps = &d.params.eps;
        if let Some(one) = d.series.iter().find_map(|s| s.one_mode.as_ref()) {
            panel(
                &cells[0],
                "(a) N = 1: (v⁻/v⁺)²",
                eps,
                &one.simulated,
                &one.asymptotic,
                ("simulated", "rₑ², eq (19)"),
            )?;
        }
        if let Some(two) = d.series.iter().find(|s| s.modes == 2) {
            let col = |j: usize, v: &[Vec<f64>]| v.iter().map(|x| x[j]).collect::<Vec<_>>();
            panel(
                &cells[1],
                "(b) N = 2, mode 1: −v₁⁻/v₁⁺",
                eps,
                &col(0, &two.simulated),
                &col(0, &two.predicted),
                ("simulated", "[R]₁₁ = (1 − rₑ)/2"),
            )?;
            panel(
                &cells[2],
                "(c) N = 2, mode 2: −v₂⁻/v₁⁺",
                eps,
                &col(1, &two.simulated),
                &col(1, &two.predicted),
                ("simulated", "[R]₂₁ = (3rₑ − 1)/2"),
            )?;
        }
        let gmin = d
            .series
            .iter()
            .flat_map(|s| s.gap.iter())
            .cloned()
            .fold(f64::MAX, f64::min)
            .max(1e-16);
        let gmax = d
            .series
            .iter()
            .flat_map(|s| s.gap.iter())
            .cloned()
            .fold(0.0, f64::max);
        let mut chart = ChartBuilder::on(&cells[3])
            .caption("(d) gap to the impact law, every N", CAPTION_FONT)
            .margin(8)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(
                (eps[0]..eps[eps.len() - 1]).log_scale(),
                (gmin / 2.0..gmax * 2.0).log_scale(),
            )
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("ε")
            .x_label_formatter(&power_of_ten)
            .y_label_formatter(&power_of_ten)
            .draw()
            .map_err(drawing)?;
        for (i, s) in d.series.iter().enumerate() {
            let c = palette(i);
            chart
                .draw_series(LineSeries::new(
                    eps.iter().cloned().zip(s.gap.iter().cloned()),
                    c.stroke_width(2),
                ))
                .map_err(drawing)?
                .label(format!("N = {} (order {:.2})", s.modes, s.observed_order))
                .legend(solid_key(c.stroke_width(2)));
        }
        draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The observed orders of the gap, one row per N.
pub fn table(d: &Fig3abcData) -> String {
    markdown_table(
        &[
            "N",
            "$\\kappa = kN\\varepsilon^2$",
            "observed order of the gap, $\\varepsilon \\in [10^{-4}, 10^{-3}]$",
            "observed order, $\\varepsilon \\in [10^{-4}, 10^{-2}]$",
            "contact time over eq (18) at $\\varepsilon = 10^{-4}$",
        ],
        &d.series
            .iter()
            .map(|s| {
                vec![
                    s.modes.to_string(),
                    format!("{}", s.kappa),
                    format!("{:.3}", s.observed_order),
                    format!("{:.3}", s.observed_order_wide),
                    format!("{:.7}", s.passage_ratio[0]),
                ]
            })
            .collect::<Vec<_>>(),
    )
}

/// The return ratios at the decades of ε and around $\varepsilon = k_2^{-1/2}$, where the
/// gap jumps (every ε is in `data.json`).
pub fn ratios_table(d: &Fig3abcData) -> String {
    // powers of ten, and the refined points around k = k₂
    let shown = |e: f64| (e.log10() - e.log10().round()).abs() < 1e-9 || (0.03..0.07).contains(&e);
    let mut rows = Vec::new();
    for s in &d.series {
        for (i, e) in d.params.eps.iter().enumerate() {
            if !shown(*e) {
                continue;
            }
            let show = |v: &[f64]| {
                v.iter()
                    .take(2)
                    .map(|x| format!("{x:.6}"))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            rows.push(vec![
                s.modes.to_string(),
                cell(*e, 3),
                show(&s.simulated[i]),
                show(&s.predicted[i]),
                cell(s.gap[i], 2),
            ]);
        }
    }
    markdown_table(
        &[
            "N",
            "$\\varepsilon$",
            "simulated $-\\dot\\eta_j^-\\varepsilon$, $j = 1, 2$",
            "$[R]_N e_1$, modes 1, 2",
            "gap (all modes)",
        ],
        &rows,
    )
}
