//! The basins plot: each start's cell coloured by the orbit it reaches, rest marked; and the
//! table of the orbits.

use super::label;
use crate::analysis::atlas::basins::BasinData;
use crate::results::render::{
    drawing, markdown_table, palette, styled_mesh, RenderError, CAPTION_FONT, LABEL_FONT,
};
use crate::results::narrow::Layout;
use plotters::prelude::*;

/// No stable orbit of period ≤ max_m within the transient.
const NONE: RGBColor = RGBColor(190, 190, 190);

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &BasinData, layout: Layout) -> Result<String, RenderError> {
    let (per, none) = d.counts();
    let mut items: Vec<(RGBColor, String)> = d
        .orbits
        .iter()
        .zip(&per)
        .enumerate()
        .map(|(i, (a, n))| (palette(i), format!("{} ({n} starts)", label(a))))
        .collect();
    if none > 0 {
        items.push((NONE, format!("none ({none} starts)")));
    }
    items.push((BLACK, "× rest".to_string()));
    // the map (760 × 660 px) and its key: one line, or one item per line when narrow
    let (w, map_height, key_height) = match layout {
        Layout::Wide => (760, 660, 60),
        Layout::Narrow => (
            layout.width(),
            layout.panel_height(760, 660),
            20 + 30 * u32::try_from(items.len()).unwrap_or(0),
        ),
    };
    let mut svg = String::new();
    {
        let root =
            SVGBackend::with_string(&mut svg, (w, map_height + key_height)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (plot, key) = root.split_vertically(map_height);
        let e = d.params.extent;
        let step = if d.params.points > 1 {
            2.0 * e / (d.params.points - 1) as f64
        } else {
            e
        };
        let half = 0.5 * step;
        let mut chart = ChartBuilder::on(&plot)
            .caption("the orbit each start reaches", CAPTION_FONT)
            .margin(10)
            .margin_right(24)
            .x_label_area_size(52)
            .y_label_area_size(70)
            .build_cartesian_2d(-e - half..e + half, -e - half..e + half)
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("tip displacement d / A_free")
            .y_desc("tip velocity v / (ω A_free)")
            .draw()
            .map_err(drawing)?;
        for (row, &v) in d.reached.iter().zip(&d.velocity) {
            for (r, &x) in row.iter().zip(&d.displacement) {
                let colour = r.map_or(NONE, palette);
                // a little overlap, so that anti-aliasing leaves no seams
                let corners = [(x - half, v - half), (x + 1.05 * half, v + 1.05 * half)];
                chart
                    .draw_series(std::iter::once(Rectangle::new(corners, colour.filled())))
                    .map_err(drawing)?;
            }
        }
        // rest: the atlas's start
        chart
            .draw_series(std::iter::once(Cross::new((0.0, 0.0), 8, BLACK.stroke_width(3))))
            .map_err(drawing)?;
        let (mut x, mut y) = (if layout == Layout::Wide { 70 } else { 20 }, 16);
        for (colour, text) in items {
            if text.starts_with('×') {
                key.draw(&Text::new(text.clone(), (x, y + 2), LABEL_FONT))
                    .map_err(drawing)?;
                continue;
            }
            key.draw(&Rectangle::new([(x, y), (x + 20, y + 20)], colour.filled()))
                .map_err(drawing)?;
            key.draw(&Text::new(text.clone(), (x + 28, y + 2), LABEL_FONT))
                .map_err(drawing)?;
            match layout {
                Layout::Wide => x += 28 + 9 * text.chars().count() as i32 + 24,
                Layout::Narrow => (x, y) = (20, y + 30),
            }
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The orbits reached: (m, n), starts, share, largest Floquet multiplier modulus, entry
/// velocities.
pub fn table(d: &BasinData) -> String {
    let (per, none) = d.counts();
    let total = (d.params.points * d.params.points).max(1) as f64;
    let mut rows: Vec<Vec<String>> = d
        .orbits
        .iter()
        .zip(&per)
        .map(|(a, n)| {
            vec![
                label(a),
                n.to_string(),
                format!("{:.0}%", 100.0 * *n as f64 / total),
                format!("{:.3}", a.spectral_radius),
                a.impact_velocities
                    .iter()
                    .map(|v| format!("{v:.3}"))
                    .collect::<Vec<_>>()
                    .join(", "),
            ]
        })
        .collect();
    rows.push(vec![
        "none".into(),
        none.to_string(),
        format!("{:.0}%", 100.0 * none as f64 / total),
        String::new(),
        String::new(),
    ]);
    markdown_table(
        &[
            "orbit (m,n)",
            "starts",
            "share",
            "largest Floquet multiplier modulus",
            "entry velocities / (ω A_free)",
        ],
        &rows,
    )
}
