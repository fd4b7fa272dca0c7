//! Figure 3(d): post-impact velocity profiles per N, for the stiffness-limit and the
//! collocation laws, with the pre-impact profile φ₁ dashed.

use crate::render::{draw_legend, drawing, markdown_table, palette, RenderError, WIDTH};
use super::Fig3dData;
use plotters::prelude::*;

/// The SVG plot.
pub fn plot(d: &Fig3dData) -> Result<String, RenderError> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, 440)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let panels = root.split_evenly((1, 2));
        for (i, law) in ["stiffness-limit", "collocation"].iter().enumerate() {
            let profiles: Vec<_> = d.profiles.iter().filter(|p| p.law == *law).collect();
            let (lo, hi) = profiles
                .iter()
                .filter_map(|p| p.values.as_ref())
                .flatten()
                .chain(d.phi1.iter())
                .fold((0.0_f64, 0.0_f64), |(a, b), &v| (a.min(v), b.max(v)));
            let title = if i == 0 {
                "(d) [R]_N, eq (29)"
            } else {
                "[R]_C, eq (12), equally spaced points"
            };
            let mut chart = ChartBuilder::on(&panels[i])
                .caption(format!("{title}: post-impact w_t(s)"), ("sans-serif", 16))
                .margin(8)
                .x_label_area_size(32)
                .y_label_area_size(44)
                .build_cartesian_2d(0.0..1.0, (lo - 0.2)..(hi + 0.2))
                .map_err(drawing)?;
            chart.configure_mesh().x_desc("s").draw().map_err(drawing)?;
            chart
                .draw_series(DashedLineSeries::new(
                    d.s.iter().cloned().zip(d.phi1.iter().cloned()),
                    5,
                    4,
                    BLACK.stroke_width(1),
                ))
                .map_err(drawing)?
                .label("pre-impact φ₁")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], BLACK));
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
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
            }
            draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The markdown table.
pub fn table(d: &Fig3dData) -> String {
    let mut header = vec!["law".to_string(), "N".to_string()];
    header.extend(d.params.probes.iter().map(|s| format!("w_t({s})")));
    header.extend([
        "L² norm".to_string(),
        "L² distance from φ₁".to_string(),
        "max over s of the distance from φ₁".to_string(),
    ]);
    let rows: Vec<Vec<String>> = d
        .profiles
        .iter()
        .map(|p| {
            let mut r = vec![p.law.clone(), p.modes.to_string()];
            match &p.error {
                Some(e) => {
                    r.push(format!("not built: {e}"));
                    r.extend(std::iter::repeat_n(
                        String::new(),
                        d.params.probes.len() + 2,
                    ));
                }
                None => {
                    r.extend(p.at_probes.iter().map(|v| format!("{v:.5}")));
                    r.extend([
                        format!("{:.5}", p.l2_norm),
                        format!("{:.5}", p.l2_distance),
                        format!("{:.4}", p.max_distance),
                    ]);
                }
            }
            r
        })
        .collect();
    let h: Vec<&str> = header.iter().map(|s| s.as_str()).collect();
    markdown_table(&h, &rows)
}
