//! Figure 2: eigenfrequencies of K⁺ (solid) and of the continuum (dashed) against k, for
//! each N (panels a–c), and λ_N/(kN) (panel d).

use crate::results::render::{
    power_of_ten,
    cell, dashed_key, draw_legend, drawing, markdown_table, palette, solid_key, styled_mesh,
    RenderError, CAPTION_FONT,
};
use crate::results::narrow::Layout;
use super::Fig2Data;
use plotters::prelude::*;

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &Fig2Data, layout: Layout) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, layout.grid_size(2, 2, 900)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let panels = layout.cells(&root, 2, 2);
        let (lo, hi) = d.params.k_over_k1_range;
        let w1 = d.k1.sqrt();
        let letters = ["(a)", "(b)", "(c)", "(d)"];
        for (p, t) in d.truncations.iter().enumerate().take(3) {
            let n = t.modes;
            let ymax = t
                .lambda
                .last()
                .and_then(|l| l.iter().cloned().reduce(f64::max))
                .unwrap_or(1.0)
                .sqrt()
                / w1;
            let mut chart = ChartBuilder::on(&panels[p])
                .caption(
                    format!("{} N = {n}: frequency / (β₁⁻)²", letters[p]),
                    CAPTION_FONT,
                )
                .margin(8)
                .margin_right(28)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d((lo..hi).log_scale(), (0.5..ymax * 1.5).log_scale())
                .map_err(drawing)?;
            styled_mesh(&mut chart)
                .x_desc("k / k₁")
                .x_label_formatter(&power_of_ten)
                .y_label_formatter(&power_of_ten)
                .draw()
                .map_err(drawing)?;
            for (i, lam) in t.lambda.iter().enumerate() {
                let c = palette(i);
                let galerkin = chart
                    .draw_series(LineSeries::new(
                        d.k_over_k1
                            .iter()
                            .zip(lam)
                            .map(|(&k, &l)| (k, l.sqrt() / w1)),
                        c.stroke_width(2),
                    ))
                    .map_err(drawing)?;
                if i == 0 {
                    galerkin
                        .label(format!("N = {n} Galerkin (colour: mode i)"))
                        .legend(solid_key(c.stroke_width(2)));
                }
                let exact = chart
                    .draw_series(DashedLineSeries::new(
                        d.k_over_k1
                            .iter()
                            .zip(&d.exact[i])
                            .map(|(&k, &l)| (k, l.sqrt() / w1)),
                        6,
                        4,
                        BLACK.stroke_width(1),
                    ))
                    .map_err(drawing)?;
                if i == 0 {
                    exact
                        .label("continuum, eq (3)")
                        .legend(dashed_key(BLACK.stroke_width(1)));
                }
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        // λ_N/(kN) − 1 > 0 (the top eigenvalue exceeds kN by about the mean of the k_j), on
        // a log scale so that its approach to 0 shows
        let excess: Vec<Vec<f64>> = d
            .truncations
            .iter()
            .map(|t| t.scaled_highest.iter().map(|s| s - 1.0).collect())
            .collect();
        let positive = || excess.iter().flatten().cloned().filter(|e| *e > 0.0);
        let ymax = positive().fold(1e-300, f64::max) * 3.0;
        let ymin = positive().fold(f64::INFINITY, f64::min) / 3.0;
        let mut chart = ChartBuilder::on(&panels[3])
            .caption("(d) top eigenvalue: λ/(kN) − 1", CAPTION_FONT)
            .margin(8)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d((lo..hi).log_scale(), (ymin..ymax).log_scale())
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("k / k₁")
            .x_label_formatter(&power_of_ten)
            .y_label_formatter(&power_of_ten)
            .draw()
            .map_err(drawing)?;
        for (p, (t, e)) in d.truncations.iter().zip(&excess).enumerate() {
            let c = palette(p);
            chart
                .draw_series(LineSeries::new(
                    d.k_over_k1
                        .iter()
                        .cloned()
                        .zip(e.iter().cloned())
                        .filter(|(_, e)| *e > 0.0),
                    c.stroke_width(2),
                ))
                .map_err(drawing)?
                .label(format!("N = {}", t.modes))
                .legend(solid_key(c.stroke_width(2)));
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The markdown table at the table's k values.
pub fn table(d: &Fig2Data) -> String {
    let rows: Vec<Vec<String>> = d
        .table
        .iter()
        .map(|r| {
            vec![
                r.modes.to_string(),
                cell(r.k_over_k1, 4),
                r.i.to_string(),
                cell(r.lambda, 10),
                cell(r.exact, 10),
                cell(r.rel_error, 3),
                r.scaled_highest.map_or(String::new(), |s| cell(s, 6)),
            ]
        })
        .collect();
    markdown_table(
        &[
            "N",
            "k/k₁",
            "i",
            "$\\lambda_i$ of $K^+$",
            "$(\\beta_i^+)^4$ exact",
            "rel. error",
            "$\\lambda_N/(kN)$",
        ],
        &rows,
    )
}
