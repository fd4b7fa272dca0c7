//! The r_E map: a coloured cell per (ω, k) with a colour bar, special cells in grey
//! shades and marks; and a table of the points that are not plain values.

use super::{Cell, MapData};
use crate::results::render::{omega_log_k_mesh, viridis, drawing, markdown_table, styled_mesh, RenderError, CAPTION_FONT, LABEL_FONT, WIDTH};
use crate::results::narrow::Layout;
use plotters::prelude::*;

fn special(c: &Cell) -> Option<(RGBColor, &'static str)> {
    match c {
        Cell::Value(_) => None,
        Cell::Unconverged => Some((RGBColor(120, 120, 120), "unconverged in N")),
        Cell::NotPeriodic => Some((RGBColor(200, 200, 200), "not periodic")),
        Cell::Coexisting => Some((RGBColor(213, 94, 0), "coexisting orbits")),
        Cell::NoRealValue => Some((RGBColor(60, 60, 60), "no real r_E")),
        Cell::NoContact => Some((WHITE, "no contact")),
    }
}

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &MapData, layout: Layout) -> Result<String, RenderError> {
    let p = &d.params;
    // the map, and beside it (or under it) the colour bar and the key of special cells
    let map_height = layout.panel_height(WIDTH - 230, 620);
    let size = match layout {
        Layout::Wide => (WIDTH, 620),
        Layout::Narrow => (layout.width(), map_height + 240),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (map, side) = layout.beside(&root, WIDTH - 230, map_height);
        let half = |v: &[f64], log: bool| -> f64 {
            if v.len() < 2 {
                return if log { 0.25 } else { 0.05 };
            }
            0.5 * if log { (v[1] / v[0]).log10() } else { v[1] - v[0] }
        };
        let (dw, dk) = (half(&p.omega_over_w1, false), half(&p.k_over_k1, true));
        let w0 = p.omega_over_w1.first().copied().unwrap_or(0.8) - dw;
        let w1 = p.omega_over_w1.last().copied().unwrap_or(3.0) + dw;
        let l0 = p.k_over_k1.first().map_or(1.0, |k| k.log10()) - dk;
        let l1 = p.k_over_k1.last().map_or(4.0, |k| k.log10()) + dk;
        let mut chart = ChartBuilder::on(&map)
            .caption(
                match layout {
                    Layout::Wide => "energetic restitution r_E over ω and k (d₀ = 0, ζ₁ = 0.01)",
                    Layout::Narrow => "r_E over ω and k (d₀ = 0, ζ₁ = 0.01)",
                },
                CAPTION_FONT,
            )
            .margin(8)
            .margin_right(20)
            .x_label_area_size(48)
            .y_label_area_size(70)
            .build_cartesian_2d(w0..w1, l0..l1)
            .map_err(drawing)?;
        // plotters' default of 10 ω ticks
        omega_log_k_mesh(&mut chart, (l0, l1), 10)?;
        for pt in &d.points {
            let (w, l) = (pt.omega_over_w1, pt.k_over_k1.log10());
            let corners = [(w - dw, l - dk), (w + dw, l + dk)];
            // the fill overlaps the next cell a little, so that anti-aliasing leaves no
            // hairline seams between cells (the outline keeps the cell's own size)
            let fill = [(w - dw, l - dk), ((w + 1.8 * dw).min(w1), (l + 1.8 * dk).min(l1))];
            let color = match special(&pt.cell) {
                Some((c, _)) => c,
                None => match pt.cell {
                    Cell::Value(r) => viridis(r),
                    _ => WHITE,
                },
            };
            chart
                .draw_series(std::iter::once(Rectangle::new(fill, color.filled())))
                .map_err(drawing)?;
            if pt.cell == Cell::NoContact {
                chart
                    .draw_series(std::iter::once(Rectangle::new(corners, BLACK.mix(0.3))))
                    .map_err(drawing)?;
            }
        }
        // colour bar and the key of the special cells
        let (bar_area, key_area) = match layout {
            Layout::Wide => side.margin(40, 60, 20, 20).split_vertically(300),
            Layout::Narrow => side.margin(20, 20, 20, 20).split_horizontally(150),
        };
        let mut bar_chart = ChartBuilder::on(&bar_area)
            .caption("r_E", LABEL_FONT)
            .x_label_area_size(0)
            .y_label_area_size(44)
            .build_cartesian_2d(0.0..1.0, 0.0..1.0)
            .map_err(drawing)?;
        styled_mesh(&mut bar_chart)
            .disable_mesh()
            .disable_x_axis()
            .y_labels(6)
            .draw()
            .map_err(drawing)?;
        for i in 0..100 {
            let r = i as f64 / 100.0;
            bar_chart
                .draw_series(std::iter::once(Rectangle::new(
                    // overlapping the next band: no hairline seams
                    [(0.0, r), (1.0, (r + 0.015).min(1.0))],
                    viridis(r + 0.005).filled(),
                )))
                .map_err(drawing)?;
        }
        let cells = [
            Cell::Unconverged,
            Cell::NotPeriodic,
            Cell::Coexisting,
            Cell::NoRealValue,
            Cell::NoContact,
        ];
        for (i, c) in cells.iter().enumerate() {
            let Some((color, label)) = special(c) else { continue };
            let y = 20 + 30 * i as i32;
            key_area
                .draw(&Rectangle::new([(0, y), (22, y + 18)], color.filled()))
                .map_err(drawing)?;
            key_area
                .draw(&Rectangle::new([(0, y), (22, y + 18)], BLACK.mix(0.4)))
                .map_err(drawing)?;
            key_area
                .draw(&Text::new(label, (30, y + 2), LABEL_FONT))
                .map_err(drawing)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The table: r_E along k at three frequencies, each cell its value or what it is.
pub fn table(d: &MapData) -> String {
    let p = &d.params;
    let chosen: Vec<f64> = p
        .omega_over_w1
        .iter()
        .copied()
        .filter(|w| [0.8, 1.5, 2.0, 3.0].iter().any(|x| (w - x).abs() < 1e-9))
        .collect();
    let rows: Vec<Vec<String>> = p
        .k_over_k1
        .iter()
        .map(|&k| {
            let mut row = vec![crate::results::render::cell(k, 3)];
            let n = d.points.iter().find(|q| q.k_over_k1 == k).map_or(0, |q| q.modes);
            row.push(n.to_string());
            for &w in &chosen {
                let q = d.points.iter().find(|q| q.k_over_k1 == k && q.omega_over_w1 == w);
                row.push(q.map_or(String::new(), |q| match q.cell {
                    Cell::Value(r) => format!("{r:.3} {}", q.kind),
                    Cell::NotPeriodic => "not periodic".to_string(),
                    c => format!("{} {}", special(&c).map_or("", |s| s.1), q.kind),
                }));
            }
            row
        })
        .collect();
    let header: Vec<String> = ["$k/k_1$".to_string(), "N".to_string()]
        .into_iter()
        .chain(chosen.iter().map(|w| format!("$\\omega = {w}(\\beta_1^-)^2$")))
        .collect();
    let h: Vec<&str> = header.iter().map(String::as_str).collect();
    markdown_table(&h, &rows)
}
