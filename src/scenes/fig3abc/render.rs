//! Figure 3(a)–(c): simulated return velocities against the impact laws, and the gap's
//! convergence for every N.

use crate::render::{draw_legend, drawing, markdown_table, palette, RenderError, WIDTH};
use crate::report::format_sig;
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
    let mut chart = ChartBuilder::on(area)
        .caption(title, ("sans-serif", 16))
        .margin(8)
        .x_label_area_size(32)
        .y_label_area_size(52)
        .build_cartesian_2d(
            (eps[0]..eps[eps.len() - 1]).log_scale(),
            (lo - pad)..(hi + pad),
        )
        .map_err(drawing)?;
    chart
        .configure_mesh()
        .x_desc("ε")
        .x_label_formatter(&|x| format!("{x:.0e}"))
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
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
    chart
        .draw_series(DashedLineSeries::new(
            eps.iter().cloned().zip(predicted.iter().cloned()),
            5,
            4,
            BLACK.stroke_width(1),
        ))
        .map_err(drawing)?
        .label(labels.1)
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
    draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
    Ok(())
}

/// The SVG plot: (a) N = 1, (b), (c) N = 2 modes 1 and 2, and the gap for every N.
pub fn plot(d: &Fig3abcData) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, 760)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let cells = root.split_evenly((2, 2));
        let eps = &d.params.eps;
        if let Some(one) = d.series.iter().find_map(|s| s.one_mode.as_ref()) {
            panel(
                &cells[0],
                "(a) N = 1: (v⁻/v⁺)²",
                eps,
                &one.simulated,
                &one.asymptotic,
                ("simulated", "r_e², eq (19)"),
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
                ("simulated", "[R]₁₁ = (1 − r_e)/2"),
            )?;
            panel(
                &cells[2],
                "(c) N = 2, mode 2: −v₂⁻/v₁⁺",
                eps,
                &col(1, &two.simulated),
                &col(1, &two.predicted),
                ("simulated", "[R]₂₁ = (3r_e − 1)/2"),
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
            .caption("gap to the impact law [R]_N, every N", ("sans-serif", 16))
            .margin(8)
            .x_label_area_size(32)
            .y_label_area_size(52)
            .build_cartesian_2d(
                (eps[0]..eps[eps.len() - 1]).log_scale(),
                (gmin / 2.0..gmax * 2.0).log_scale(),
            )
            .map_err(drawing)?;
        chart
            .configure_mesh()
            .x_desc("ε")
            .x_label_formatter(&|x| format!("{x:.0e}"))
            .y_label_formatter(&|y| format!("{y:.0e}"))
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
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The markdown table at each ε.
pub fn table(d: &Fig3abcData) -> String {
    let mut rows = Vec::new();
    for s in &d.series {
        for (i, e) in d.params.eps.iter().enumerate() {
            if i % 2 != 0 {
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
                format_sig(*e, 2),
                show(&s.simulated[i]),
                show(&s.predicted[i]),
                format_sig(s.gap[i], 2),
                format!("{:.4}", s.passage_ratio[i]),
            ]);
        }
    }
    let mut t = markdown_table(
        &[
            "N",
            "ε",
            "simulated −η̇⁻/ε⁻¹ (modes 1, 2)",
            "[R]_N e₁ (modes 1, 2)",
            "gap (all modes)",
            "contact time / πκ^{−1/2}ε",
        ],
        &rows,
    );
    t.push('\n');
    t.push_str(&markdown_table(
        &[
            "N",
            "κ = kNε²",
            "observed order of the gap (ε ∈ [1e-4, 1e-2])",
        ],
        &d.series
            .iter()
            .map(|s| {
                vec![
                    s.modes.to_string(),
                    format!("{}", s.kappa),
                    format!("{:.3}", s.observed_order),
                ]
            })
            .collect::<Vec<_>>(),
    ));
    t
}
