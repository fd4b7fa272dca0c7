//! Figure 5: impact velocities on the impact section against k, one panel per N.

use crate::results::render::{
    power_of_ten,
    cell, dashed_key, draw_legend, drawing, markdown_table, styled_mesh, RenderError,
    CAPTION_FONT, LABEL_FONT,
};
use crate::results::marker::{Marker, Shape};
use super::Fig5Data;
use crate::results::narrow::Layout;
use plotters::prelude::*;

/// The SVG plot: one panel per N, each with its own velocity range. Points repeating on a
/// periodic orbit are drawn once (to 1e-3 of the panel's range), which keeps the file small
/// without changing what is seen; the N = 1 panel states its rigid limit (k → ∞).
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &Fig5Data, layout: Layout) -> Result<String, RenderError> {
    let rows = d.diagrams.len().max(1);
    // one diagram per row, 1000 × 300 px each, and the legend's strip
    let (_, height) = layout.grid_size(rows, 1, 300 * rows as u32);
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (layout.width(), height + legend_height(layout)))
                .into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (top, strip) = root.split_vertically(height);
        let panels = top.split_evenly((rows, 1));
        if !d.branches.is_empty() {
            branch_legend(&strip, d, layout)?;
        }
        let (lo, hi) = d.params.k_over_k1_range;
        let k2 = crate::model::continuum::modal_stiffness(2).unwrap_or(f64::NAN)
            / crate::model::galerkin::first_modal_stiffness();
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
                .y_desc("v / (ω A_free)")
                .x_label_formatter(&power_of_ten)
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
            if let Some(set) = d.branches.iter().find(|b| b.modes == g.modes) {
                draw_branches(&mut chart, set, (lo, hi), vmax)?;
            }
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
                            match layout {
                                Layout::Wide => {
                                    format!("rigid limit (k → ∞): {:.1} ↑", r.impact_velocity)
                                }
                                Layout::Narrow => format!("k → ∞: {:.1} ↑", r.impact_velocity),
                            },
                            // narrow: further left, so that the label ends inside the panel
                            match layout {
                                Layout::Wide => (hi / 12.0, vmax * 0.93),
                                Layout::Narrow => (lo * (hi / lo).powf(0.5), vmax * 0.93),
                            },
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

use crate::analysis::continuation::BifurcationKind as K;

const STABLE: ShapeStyle = ShapeStyle {
    color: RGBAColor(0, 0, 0, 1.0),
    filled: false,
    stroke_width: 2,
};
const UNSTABLE: ShapeStyle = ShapeStyle {
    color: RGBAColor(200, 30, 30, 1.0),
    filled: false,
    stroke_width: 2,
};
const MARKERS: [(K, &str, RGBColor, Shape); 5] = [
    (K::PeriodDoubling, "period doubling", RGBColor(230, 120, 0), Shape::Square),
    (K::Fold, "fold", RGBColor(120, 0, 160), Shape::Triangle),
    (K::NeimarkSacker, "Neimark–Sacker", RGBColor(200, 0, 120), Shape::Diamond),
    (K::Grazing, "grazing", RGBColor(0, 140, 60), Shape::Circle),
    (K::BranchPoint, "branch point", RGBColor(0, 0, 0), Shape::Cross),
];

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::combinators::LogCoord<f64>, plotters::coord::types::RangedCoordf64>,
>;

/// The continued branches over the brute-force points: stable solid, unstable dashed, one
/// line per impact of the period (largest first); bifurcations marked.
fn draw_branches(
    chart: &mut Chart,
    set: &super::branches::BranchSet,
    (lo, hi): (f64, f64),
    vmax: f64,
) -> Result<(), RenderError> {
    let inside = |k: f64| k >= lo && k <= hi;
    let (mut stable_runs, mut unstable_runs) = (Vec::new(), Vec::new());
    for b in &set.branches {
        let pts: Vec<_> = b.points.iter().filter(|q| inside(q.k_over_k1)).collect();
        for w in pts.windows(2) {
            let (a, c) = (w[0], w[1]);
            if a.impacts_n != c.impacts_n || a.stable != c.stable {
                continue;
            }
            for j in 0..a.impacts_n {
                let seg = vec![
                    (a.k_over_k1, a.impact_velocities[j].min(vmax)),
                    (c.k_over_k1, c.impact_velocities[j].min(vmax)),
                ];
                if a.stable {
                    stable_runs.push(seg);
                } else {
                    unstable_runs.push(seg);
                }
            }
        }
    }
    for seg in stable_runs {
        chart
            .draw_series(LineSeries::new(seg, STABLE))
            .map_err(drawing)?;
    }
    for seg in unstable_runs {
        chart
            .draw_series(DashedLineSeries::new(seg, 4, 3, UNSTABLE))
            .map_err(drawing)?;
    }
    let marks: Vec<(K, f64, f64)> = set
        .branches
        .iter()
        .flat_map(|b| {
            b.bifurcations.iter().filter(|f| inside(f.parameter)).map(|f| {
                let v = b.points[f.index]
                    .impact_velocities
                    .first()
                    .copied()
                    .unwrap_or(0.0);
                (f.kind, f.parameter, v.min(vmax))
            })
        })
        .collect();
    for (kind, _, color, shape) in MARKERS {
        let style = color.stroke_width(2);
        chart
            .draw_series(
                marks
                    .iter()
                    .filter(|m| m.0 == kind)
                    .map(|m| Marker::new((m.1, m.2), shape, 7, style)),
            )
            .map_err(drawing)?;
    }
    Ok(())
}

/// Height of the strip under the panels that holds the branches' legend.
fn legend_height(layout: Layout) -> u32 {
    match layout {
        Layout::Wide => 64,
        Layout::Narrow => 150,
    }
}

/// The legend of the branches, in a strip under the panels (inside a panel it would hide
/// points): line styles and every bifurcation kind found in any panel.
fn branch_legend(
    strip: &DrawingArea<SVGBackend, plotters::coord::Shift>,
    d: &Fig5Data,
    layout: Layout,
) -> Result<(), RenderError> {
    let font = LABEL_FONT.into_font();
    let width = i32::try_from(layout.width()).unwrap_or(i32::MAX);
    let (mut x, mut y) = (20i32, 24i32);
    // an entry's label; when narrow, the next entry goes on a new line if it would not fit
    // (180 px)
    let entry = |x: &mut i32, y: &mut i32, label: &str| -> Result<(), RenderError> {
        strip
            .draw(&Text::new(label.to_string(), (*x + 34, *y - 8), font.clone()))
            .map_err(drawing)?;
        *x += 44 + 8 * label.chars().count() as i32;
        if layout == Layout::Narrow && *x + 180 > width {
            (*x, *y) = (20, *y + 30);
        }
        Ok(())
    };
    // the points of the diagram itself: the runs from rest and the random starts
    strip
        .draw(&Circle::new((x + 13, y), 3, RGBColor(0, 60, 140).mix(0.6).filled()))
        .map_err(drawing)?;
    entry(&mut x, &mut y, "simulated")?;
    strip
        .draw(&PathElement::new(vec![(x, y), (x + 26, y)], STABLE))
        .map_err(drawing)?;
    entry(&mut x, &mut y, "branch, stable")?;
    for i in 0..3 {
        let x0 = x + 9 * i;
        strip
            .draw(&PathElement::new(vec![(x0, y), (x0 + 5, y)], UNSTABLE))
            .map_err(drawing)?;
    }
    entry(&mut x, &mut y, "unstable")?;
    for (kind, name, color, shape) in MARKERS {
        let found = d
            .branches
            .iter()
            .flat_map(|s| &s.branches)
            .any(|b| b.bifurcations.iter().any(|f| f.kind == kind));
        if found {
            strip
                .draw(&Marker::new((x + 13, y), shape, 7, color.stroke_width(2)))
                .map_err(drawing)?;
            entry(&mut x, &mut y, name)?;
        }
    }
    Ok(())
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
            let set = |v: &[crate::analysis::orbit::OrbitKind]| {
                v.iter()
                    .map(|k| k.to_string())
                    .collect::<Vec<_>>()
                    .join(" ")
            };
            rows.push(vec![
                n.to_string(),
                format!("{} → {}", set(&t.from), set(&t.to)),
                super::claims::threshold_text(&d.k_over_k1, Some(t.between.1), true),
            ]);
        }
    }
    markdown_table(&["N", "orbits reached (all starts)", "at k/k₁ (between two grid values)"], &rows)
}

/// The measured claims.
pub fn table(d: &Fig5Data) -> String {
    let c = &d.claims;
    let threshold = |v: Option<f64>| super::claims::threshold_text(&d.k_over_k1, v, true);
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
                threshold(c.first_orbit_difference),
            ],
            vec![
                "first k/k₁ with impact velocities > 5% apart, N = 10 vs N = 1".into(),
                threshold(c.first_velocity_difference),
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
                threshold(c.n3_one_three_from),
            ],
            vec![
                "k/k₁ range where each N has the paper's Fig 4 orbit among its attractors".into(),
                match (
                    c.paper_figure4_set_reachable_at.first(),
                    c.paper_figure4_set_reachable_at.last(),
                ) {
                    (Some(a), Some(b)) => format!(
                        "from {} to {} ({} of {} grid values)",
                        super::claims::threshold_text(&d.k_over_k1, Some(*a), true),
                        super::claims::threshold_text(&d.k_over_k1, Some(*b), false),
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

/// The "not periodic" bands between each N's Neimark–Sacker pair, with their rotation
/// numbers (see [`super::rotation`]).
pub fn bands_table(d: &Fig5Data) -> String {
    let rows: Vec<Vec<String>> = d
        .bands
        .iter()
        .map(|b| {
            let range = |f: fn(f64, f64) -> f64| {
                b.points.iter().map(|q| q.rotation).fold(f64::NAN, f)
            };
            let worst = b.points.iter().map(|q| q.halves_differ).fold(0.0, f64::max);
            vec![
                b.modes.to_string(),
                format!("{} and {}", cell(b.neimark_sacker.0, 3), cell(b.neimark_sacker.1, 3)),
                format!("{} and {}", cell(b.onset_rotation.0, 3), cell(b.onset_rotation.1, 3)),
                format!(
                    "{} to {} ({} grid values)",
                    cell(range(f64::max), 3),
                    cell(range(f64::min), 3),
                    b.points.len()
                ),
                format!("{worst:.0e}"),
            ]
        })
        .collect();
    markdown_table(
        &[
            "N",
            "Neimark–Sacker pair, k/k₁",
            "∣arg μ∣/2π there",
            "ρ measured inside, from rest",
            "largest change between halves",
        ],
        &rows,
    )
}
