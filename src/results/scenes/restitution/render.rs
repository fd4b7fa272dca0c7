//! The restitution scene's plot — the gap to the rigid limit against k (left) and the r_e
//! error against ε (right) — and its table.

use super::RestitutionData;
use crate::results::render::{
    tick,
    cell, draw_legend, drawing, log_log_mesh, markdown_table, palette, solid_key, RenderError,
    CAPTION_FONT, WIDTH,
};
use crate::results::narrow::Layout;
use plotters::prelude::*;

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &RestitutionData, layout: Layout) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, layout.grid_size(1, 2, 500)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (left, right) = layout.beside(&root, WIDTH / 2, layout.panel_height(WIDTH / 2, 500));
        let ks = &d.params.nordmark_k;
        let gaps = d.nordmark.iter().flat_map(|n| n.gap.iter().cloned());
        let (lo, hi) = gaps.fold((f64::INFINITY, 0.0f64), |(a, b), g| (a.min(g), b.max(g)));
        let mut chart = ChartBuilder::on(&left)
            .caption("N = 1: compliant against rigid impact", CAPTION_FONT)
            .margin(10)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (ks[0] * 0.7..ks[ks.len() - 1] * 1.4).log_scale(),
                (lo * 0.5..hi * 2.0).log_scale(),
            )
            .map_err(drawing)?;
        log_log_mesh(&mut chart, "k / k₁", "velocity gap / (ω · free amplitude)")?;
        for (i, n) in d.nordmark.iter().enumerate() {
            let c = palette(i);
            chart
                .draw_series(LineSeries::new(
                    ks.iter().cloned().zip(n.gap.iter().cloned()),
                    c.stroke_width(2),
                ))
                .map_err(drawing)?
                .label(format!("ω = {}(β₁⁻)², slope {}", n.omega_over_w1, tick(&((n.rate.0 * 100.0).round() / 100.0))))
                .legend(solid_key(c.stroke_width(2)));
            chart
                .draw_series(ks.iter().zip(&n.gap).map(|(&k, &g)| Circle::new((k, g), 4, c.filled())))
                .map_err(drawing)?;
        }
        draw_legend(&mut chart, SeriesLabelPosition::MiddleRight)?;
        let eps = &d.params.eps;
        let (elo, ehi) = d
            .re_error
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), g| (a.min(*g), b.max(*g)));
        let mut chart = ChartBuilder::on(&right)
            .caption("rₑ (eq 19) against the exact ratio", CAPTION_FONT)
            .margin(10)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(70)
            .build_cartesian_2d(
                (eps[0] * 0.7..eps[eps.len() - 1] * 1.4).log_scale(),
                (elo * 0.5..ehi * 2.0).log_scale(),
            )
            .map_err(drawing)?;
        log_log_mesh(&mut chart, "ε", "|rₑ − exact|")?;
        chart
            .draw_series(LineSeries::new(
                eps.iter().cloned().zip(d.re_error.iter().cloned()),
                palette(0).stroke_width(2),
            ))
            .map_err(drawing)?;
        chart
            .draw_series(
                eps.iter()
                    .zip(&d.re_error)
                    .map(|(&e, &r)| Circle::new((e, r), 4, palette(0).filled())),
            )
            .map_err(drawing)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The Nordmark table.
pub fn table(d: &RestitutionData) -> String {
    let mut rows = Vec::new();
    for n in &d.nordmark {
        for ((k, (kind, v)), g) in d.params.nordmark_k.iter().zip(&n.compliant).zip(&n.gap) {
            rows.push(vec![
                format!("{}", n.omega_over_w1),
                cell(*k, 3),
                kind.to_string(),
                cell(*v, 6),
                cell(n.rigid_velocity, 6),
                cell(*g, 2),
            ]);
        }
    }
    markdown_table(
        &[
            "$\\omega/(\\beta_1^-)^2$",
            "$k/k_1$",
            "compliant orbit",
            "impact velocity / $(\\omega A_{\\rm free})$",
            "rigid limit / $(\\omega A_{\\rm free})$",
            "gap",
        ],
        &rows,
    )
}
