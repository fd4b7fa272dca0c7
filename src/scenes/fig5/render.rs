//! Figure 5: impact velocities on the impact section against k, one panel per N.

use crate::render::{
    cell, dashed_key, draw_legend, drawing, markdown_table, styled_mesh, RenderError,
    CAPTION_FONT, LABEL_FONT, WIDTH,
};
use super::Fig5Data;
use plotters::prelude::*;

/// The SVG plot: one panel per N, each with its own velocity range. Points repeating on a
/// periodic orbit are drawn once (to 1e-3 of the panel's range), which keeps the file small
/// without changing what is seen; the N = 1 panel states its rigid limit (k → ∞).
pub fn plot(d: &Fig5Data) -> Result<String, RenderError> {
    let rows = d.diagrams.len().max(1);
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (WIDTH, 300 * rows as u32)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let panels = root.split_evenly((rows, 1));
        let (lo, hi) = d.params.k_over_k1_range;
        let k2 = crate::continuum::modal_stiffness(2).unwrap_or(f64::NAN)
            / crate::galerkin::first_modal_stiffness();
        let letters = ["(a)", "(b)", "(c)", "(d)", "(e)", "(f)"];
        for (p, g) in d.diagrams.iter().enumerate() {
            let vmax = g
                .columns
                .iter()
                .flatten()
                .flat_map(|s| s.impact_velocities.iter())
                .fold(0.0_f64, |a, &v| a.max(v))
                * 1.08;
            let vmax = vmax.max(1e-9);
            let mut chart = ChartBuilder::on(&panels[p])
                .caption(
                    format!("{} N = {}", letters[p % 6], g.modes),
                    CAPTION_FONT,
                )
                .margin(8)
                .margin_right(28)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d((lo..hi).log_scale(), 0.0..vmax)
                .map_err(drawing)?;
            styled_mesh(&mut chart)
                .x_desc("k / k₁")
                .y_desc("impact velocity / (ω · free amplitude)")
                .x_label_formatter(&|x| format!("{x:.0e}"))
                .draw()
                .map_err(drawing)?;
            let quantum = 1e-3 * vmax;
            let mut points = Vec::new();
            for (col, &k) in g.columns.iter().zip(&d.k_over_k1) {
                let mut seen: Vec<i64> = col
                    .iter()
                    .flat_map(|s| s.impact_velocities.iter())
                    .map(|v| (v / quantum).round() as i64)
                    .collect();
                seen.sort_unstable();
                seen.dedup();
                points.extend(seen.into_iter().map(|q| (k, q as f64 * quantum)));
            }
            chart
                .draw_series(
                    points
                        .into_iter()
                        .map(|pt| Circle::new(pt, 2, RGBColor(0, 60, 140).mix(0.6).filled())),
                )
                .map_err(drawing)?;
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(k2, 0.0), (k2, vmax)],
                    6,
                    4,
                    RGBColor(213, 40, 0).stroke_width(2),
                ))
                .map_err(drawing)?
                .label("k₂")
                .legend(dashed_key(RGBColor(213, 40, 0).stroke_width(2)));
            if g.modes == 1 {
                if let Some(r) = &d.rigid_limit {
                    chart
                        .draw_series(std::iter::once(Text::new(
                            format!("rigid limit (k → ∞): {:.1} ↑", r.impact_velocity),
                            (hi / 12.0, vmax * 0.93),
                            LABEL_FONT.into_font().color(&RGBColor(0, 120, 60)),
                        )))
                        .map_err(drawing)?;
                }
            }
            draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// Where the set of orbits reached changes along k, for each N.
pub fn transitions_table(d: &Fig5Data) -> String {
    let mut rows = Vec::new();
    for (g, (n, ts)) in d.diagrams.iter().zip(&d.transitions) {
        let first = g
            .kinds(0)
            .iter()
            .map(|k| k.to_string())
            .collect::<Vec<_>>()
            .join(" ");
        rows.push(vec![
            n.to_string(),
            format!("start: {first}"),
            String::new(),
        ]);
        for t in ts {
            let set = |v: &[crate::orbit::OrbitKind]| {
                v.iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            rows.push(vec![
                n.to_string(),
                format!("{} → {}", set(&t.from), set(&t.to)),
                format!("{}–{}", cell(t.between.0, 3), cell(t.between.1, 3)),
            ]);
        }
    }
    markdown_table(&["N", "orbits reached (all starts)", "between k/k₁"], &rows)
}

/// The measured claims.
pub fn table(d: &Fig5Data) -> String {
    let c = &d.claims;
    let opt = |v: Option<f64>| v.map_or("never".to_string(), |k| cell(k, 3));
    markdown_table(
        &["claim", "measured"],
        &[
            vec![
                format!(
                    "every N and start gives (1,1) at k = {} k₁",
                    cell(d.k_over_k1[0], 2)
                ),
                c.all_one_one_at_smallest_k.to_string(),
            ],
            vec![
                "spread of the impact velocity across N there".into(),
                format!("{:.2}%", 100.0 * c.velocity_spread_at_smallest_k),
            ],
            vec![
                "first k/k₁ with different orbits, N = 10 vs N = 1".into(),
                opt(c.first_orbit_difference),
            ],
            vec![
                "first k/k₁ with impact velocities > 5% apart, N = 10 vs N = 1".into(),
                opt(c.first_velocity_difference),
            ],
            vec![
                "fraction of k with the same orbits, N = 3 vs N = 10".into(),
                format!("{:.0}%", 100.0 * c.n3_n10_agreement),
            ],
            vec![
                "fraction of k with the same orbits, N = 2 vs N = 10".into(),
                format!("{:.0}%", 100.0 * c.n2_n10_agreement),
            ],
            vec![
                "first k/k₁ where N = 3 from rest reaches the paper's (1,3)".into(),
                opt(c.n3_one_three_from),
            ],
            vec![
                "k/k₁ range where each N has the paper's Fig 4 orbit among its attractors".into(),
                match (
                    c.paper_figure4_set_reachable_at.first(),
                    c.paper_figure4_set_reachable_at.last(),
                ) {
                    (Some(a), Some(b)) => format!(
                        "{}–{} ({} of {} grid values)",
                        cell(*a, 3),
                        cell(*b, 3),
                        c.paper_figure4_set_reachable_at.len(),
                        d.k_over_k1.len()
                    ),
                    _ => "none".into(),
                },
            ],
            vec![
                "k/k₁ where all four Fig 4 orbits (from rest) match the paper".into(),
                if c.paper_figure4_set_at.is_empty() {
                    "none".into()
                } else {
                    c.paper_figure4_set_at
                        .iter()
                        .map(|k| cell(*k, 3))
                        .collect::<Vec<_>>()
                        .join(", ")
                },
            ],
        ],
    )
}
