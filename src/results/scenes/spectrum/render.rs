//! The continuum spectrum: (β_i^+)² across k with the small-k law (4) and the
//! clamped-pinned asymptotes; the remainder of (4) against k.

use crate::results::render::{
    axis_fraction, emptiest_corner,
    power_of_ten,
    cell, dashed_key, draw_legend, drawing, markdown_table, palette, solid_key, styled_mesh,
    RenderError, CAPTION_FONT, LABEL_FONT, WIDTH,
};
use crate::results::narrow::Layout;
use crate::base::report::format_sig;
use super::SpectrumData;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &SpectrumData, layout: Layout) -> Result<String, RenderError> {
    // the left panel 600 px wide, the right 400 (side by side) or stacked
    let (top, bottom) = (
        layout.panel_height(600, 520),
        layout.panel_height(WIDTH - 600, 520),
    );
    let size = match layout {
        Layout::Wide => (WIDTH, 520),
        Layout::Narrow => (layout.width(), top + bottom),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (left, right) = layout.beside(&root, 600, top);
        let (lo, hi) = d.params.k_over_k1_range;
        let ymax = d.frequency_pinned.last().copied().unwrap_or(10.0) * 1.3;
        let mut chart = ChartBuilder::on(&left)
            .caption("frequencies (βᵢ⁺)² / (β₁⁻)²", CAPTION_FONT)
            .margin(8)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(56)
            .build_cartesian_2d((lo..hi).log_scale(), (0.8..ymax).log_scale())
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("k / k₁")
            // narrow: fewer ticks, so that the powers of ten do not touch
            .x_labels(if layout == Layout::Wide { 10 } else { 5 })
            .x_label_formatter(&power_of_ten)
            .y_label_formatter(&|y| format!("{y:.0}"))
            .draw()
            .map_err(drawing)?;
        for (i, f) in d.frequency.iter().enumerate() {
            let c = palette(i);
            chart
                .draw_series(LineSeries::new(
                    d.k_over_k1.iter().cloned().zip(f.iter().cloned()),
                    c.stroke_width(2),
                ))
                .map_err(drawing)?;
            // each curve named at its right end, just above its clamped-pinned value
            if let Some(&last) = f.last() {
                chart
                    .draw_series(std::iter::once(Text::new(
                        format!("i = {}", i + 1),
                        (hi / 300.0, last * 1.04),
                        LABEL_FONT
                            .into_font()
                            .color(&c)
                            .pos(Pos::new(HPos::Left, VPos::Bottom)),
                    )))
                    .map_err(drawing)?;
            }
            let small: Vec<(f64, f64)> = d
                .k_over_k1
                .iter()
                .cloned()
                .zip(d.frequency_small_k[i].iter().cloned())
                .filter(|p| p.1 < ymax)
                .collect();
            let law = chart
                .draw_series(DashedLineSeries::new(small, 5, 4, c.stroke_width(1)))
                .map_err(drawing)?;
            if i == 0 {
                // short on a phone: the key then fits below mode 1's plateau
                law.label(match layout {
                    Layout::Wide => "small-k law, eq (4), same colour",
                    Layout::Narrow => "small-k law (4)",
                })
                    .legend(dashed_key(BLACK.stroke_width(1)));
            }
            let pinned = chart
                .draw_series(DashedLineSeries::new(
                    vec![(lo, d.frequency_pinned[i]), (hi, d.frequency_pinned[i])],
                    2,
                    4,
                    BLACK.mix(0.5).stroke_width(1),
                ))
                .map_err(drawing)?;
            if i == 0 {
                pinned
                    .label(match layout {
                        Layout::Wide => "clamped-pinned (k = ∞)",
                        Layout::Narrow => "pinned, k = ∞",
                    })
                    .legend(|(x, y)| {
                        DashedPathElement::new(
                            vec![(x, y), (x + 24, y)],
                            2,
                            4,
                            BLACK.mix(0.5).stroke_width(1),
                        )
                    });
            }
        }
        draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;

        let s = &d.small_k;
        let k1 = d.k1;
        let (kmin, kmax) = (s.k[0] / k1 / 1.5, s.k[s.k.len() - 1] / k1 * 1.5);
        let (xmin, xmax) = (s.k[0] / k1 / 2.0, s.k[s.k.len() - 1] / k1 * 2.0);
        // three decades of room above the data for the legend
        let rmax = s.remainder.iter().map(|r| r.abs()).fold(0.0, f64::max) * 1e3;
        let rmin = s.remainder.iter().map(|r| r.abs()).fold(f64::MAX, f64::min) / 10.0;
        let mut chart = ChartBuilder::on(&right)
            .caption("remainder of eq (4), mode 1", CAPTION_FONT)
            .margin(8)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d((xmin..xmax).log_scale(), (rmin..rmax).log_scale())
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("k / k₁")
            .y_desc("|(β₁⁺)⁴ − (β₁⁻)⁴ − k|")
            .x_label_formatter(&power_of_ten)
            .y_label_formatter(&power_of_ten)
            .draw()
            .map_err(drawing)?;
        chart
            .draw_series(
                s.k.iter()
                    .zip(&s.remainder)
                    .map(|(&k, &r)| Circle::new((k / k1, r.abs()), 4, palette(0).filled())),
            )
            .map_err(drawing)?
            .label("computed")
            .legend(|(x, y)| Circle::new((x + 10, y), 4, palette(0).filled()));
        let c = s.predicted_coefficient.abs();
        chart
            .draw_series(LineSeries::new(
                [kmin, kmax].map(|x| (x, c * (x * k1).powi(2))),
                palette(1).stroke_width(1),
            ))
            .map_err(drawing)?
            .label("second-order theory, c·k²")
            .legend(solid_key(palette(1).stroke_width(1)));
        let (xs, ys) = ((xmin, xmax), (rmin, rmax));
        let at = |x: f64, y: f64| (axis_fraction(x, xs, true), axis_fraction(y, ys, true));
        let mut curves: Vec<Vec<(f64, f64)>> =
            s.k.iter().zip(&s.remainder).map(|(&k, &r)| vec![at(k / k1, r.abs())]).collect();
        curves.push([kmin, kmax].map(|x| at(x, c * (x * k1).powi(2))).to_vec());
        // the legend is about as wide as this narrow panel
        draw_legend(&mut chart, emptiest_corner(&curves, (0.95, 0.2)).0)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// A relative difference: "0" when the two agree to the last bit.
fn rel_diff(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format_sig(x, 2)
    }
}

/// The markdown tables: golden comparisons, k₂/k₁ and the small-k law.
pub fn table(d: &SpectrumData) -> String {
    let mut rows = Vec::new();
    for (kind, checks) in [
        ("free (k = 0)", &d.free),
        ("clamped-pinned (k = ∞)", &d.clamped_pinned),
    ] {
        for c in checks.iter() {
            rows.push(vec![
                kind.to_string(),
                c.i.to_string(),
                cell(c.ours, 16),
                cell(c.golden, 16),
                rel_diff(c.rel_diff),
            ]);
        }
    }
    for (r, c) in &d.finite_k {
        rows.push(vec![
            // the stop stiffnesses are round numbers: 1, 100, 1e6 (10⁶ in the table)
            format!("k = {} k₁", {
                let c = cell(*r, 3);
                if c.contains('.') && !c.contains('e') {
                    c.trim_end_matches('0').trim_end_matches('.').to_string()
                } else {
                    c
                }
            }),
            c.i.to_string(),
            cell(c.ours, 16),
            cell(c.golden, 16),
            rel_diff(c.rel_diff),
        ]);
    }
    let mut s = markdown_table(
        &["stop", "i", "$\\beta_i$ (ours)", "$\\beta_i$ (golden)", "rel. diff."],
        &rows,
    );
    s.push_str(&format!("\nGolden source: {}.\n\n", d.golden_source));
    let sk = &d.small_k;
    s.push_str(&markdown_table(
        &["quantity", "value"],
        &[
            vec!["$k_1 = (\\beta_1^-)^4$".into(), cell(d.k1, 12)],
            vec!["$k_2/k_1$".into(), cell(d.k2_over_k1, 8)],
            vec![
                "fitted order of the remainder of eq (4)".into(),
                cell(sk.fitted_order, 4),
            ],
            vec![
                "remainder / $k^2$ at the smallest $k$".into(),
                format_sig(sk.fitted_coefficient, 5),
            ],
            vec![
                "second-order theory $-\\sum_{j\\ne1} 1/(k_j - k_1)$".into(),
                format_sig(sk.predicted_coefficient, 5),
            ],
        ],
    ));
    s
}
