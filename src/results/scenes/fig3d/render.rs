//! Figure 3(d): post-impact velocity profiles per N, for the stiffness-limit and the
//! collocation laws, with the pre-impact profile φ₁ dashed.

use crate::results::render::{
    dashed_key, draw_legend, drawing, markdown_table, palette, solid_key, styled_mesh,
    RenderError, CAPTION_FONT,
};
use crate::results::narrow::Layout;
use super::Fig3dData;
use plotters::prelude::*;

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &Fig3dData, layout: Layout) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, layout.grid_size(1, 2, 520)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let panels = layout.cells(&root, 1, 2);
        for (i, law) in ["stiffness-limit", "collocation"].iter().enumerate() {
            let profiles: Vec<_> = d.profiles.iter().filter(|p| p.law == *law).collect();
            let (lo, hi) = profiles
                .iter()
                .filter_map(|p| p.values.as_ref())
                .flatten()
                .chain(d.phi1.iter())
                .fold((0.0_f64, 0.0_f64), |(a, b), &v| (a.min(v), b.max(v)));
            let title = if i == 0 {
                "(d) stiffness limit, eq (29)"
            } else {
                "collocation, eq (12), equal spacing"
            };
            let mut chart = ChartBuilder::on(&panels[i])
                .caption(title, CAPTION_FONT)
                .margin(8)
                .margin_right(28)
                .x_label_area_size(44)
                .y_label_area_size(56)
                // headroom above the profiles for the legend
                .build_cartesian_2d(0.0..1.0, (lo - 0.2)..(hi + 1.4))
                .map_err(drawing)?;
            styled_mesh(&mut chart)
                .x_desc("s (along the beam)")
                .y_desc("post-impact velocity")
                .draw()
                .map_err(drawing)?;
            chart
                .draw_series(DashedLineSeries::new(
                    d.s.iter().cloned().zip(d.phi1.iter().cloned()),
                    5,
                    4,
                    BLACK.stroke_width(1),
                ))
                .map_err(drawing)?
                .label("pre-impact φ₁")
                .legend(dashed_key(BLACK.stroke_width(1)));
            for (j, p) in profiles.iter().enumerate() {
                let Some(values) = &p.values else { continue };
                let c = palette(j);
                chart
                    .draw_series(LineSeries::new(
                        d.s.iter().cloned().zip(values.iter().cloned()),
                        c.stroke_width(2),
                    ))
                    .map_err(drawing)?
                    .label(format!("N = {}", p.modes))
                    .legend(solid_key(c.stroke_width(2)));
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The markdown table: the distances (the verdict) first, then the profile at the probes.
pub fn table(d: &Fig3dData) -> String {
    let mut header = vec![
        "law".to_string(),
        "N".to_string(),
        "$L^2$ distance from $\\phi_1$".to_string(),
        "sup distance".to_string(),
        "$L^2$ norm".to_string(),
    ];
    header.extend(d.params.probes.iter().map(|s| format!("$w_t({s})$")));
    let rows: Vec<Vec<String>> = d
        .profiles
        .iter()
        .map(|p| {
            let law = match p.law.as_str() {
                "stiffness-limit" => "$[R]_N$".to_string(),
                "collocation" => "$[R]_C$".to_string(),
                other => other.to_string(),
            };
            let mut r = vec![law, p.modes.to_string()];
            match &p.error {
                Some(e) => {
                    r.push(format!("not built: {e}"));
                    r.extend(std::iter::repeat_n(
                        String::new(),
                        d.params.probes.len() + 2,
                    ));
                }
                None => {
                    r.extend([
                        format!("{:.5}", p.l2_distance),
                        format!("{:.4}", p.max_distance),
                        format!("{:.5}", p.l2_norm),
                    ]);
                    r.extend(p.at_probes.iter().map(|v| format!("{v:.4}")));
                }
            }
            r
        })
        .collect();
    let h: Vec<&str> = header.iter().map(|s| s.as_str()).collect();
    markdown_table(&h, &rows)
}
