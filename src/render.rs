//! Shared rendering helpers for the scenes' `render.rs`: SVG plots (plotters' SVG backend,
//! which writes text as SVG `<text>` and so needs no system fonts) and markdown tables.
//! No numerics here.

use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::prelude::*;

/// Plot size in pixels (the book scales SVGs to the page width).
pub const WIDTH: u32 = 1000;

/// A rendering failure (plotters reports drawing errors as text).
#[derive(Debug, thiserror::Error)]
#[error("could not draw the plot: {0}")]
pub struct RenderError(pub String);

/// Maps any plotters error into [`RenderError`].
pub fn drawing<E: std::fmt::Debug>(e: E) -> RenderError {
    RenderError(format!("{e:?}"))
}

/// Tick labels (px as drawn; the 1000 px plots are shown at about 0.7 scale in the book,
/// so 16 px reads as about 11 px).
pub const LABEL_FONT: (&str, u32) = ("sans-serif", 16);
/// Axis descriptions.
pub const AXIS_FONT: (&str, u32) = ("sans-serif", 18);

/// Draws the mesh of `chart` with the book's label sizes and the given axis descriptions.
pub fn mesh<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    x_desc: &str,
    y_desc: &str,
) -> Result<(), RenderError>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(LABEL_FONT)
        .axis_desc_style(AXIS_FONT)
        .draw()
        .map_err(drawing)
}

/// Draws the series labels of `chart` in a framed, half-transparent box at `position`.
pub fn draw_legend<'a, DB, CT>(
    chart: &mut ChartContext<'a, DB, CT>,
    position: SeriesLabelPosition,
) -> Result<(), RenderError>
where
    DB: DrawingBackend + 'a,
    CT: plotters::coord::CoordTranslate,
{
    chart
        .configure_series_labels()
        .position(position)
        .label_font(LABEL_FONT)
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(drawing)
}

/// The colour of series `i` (a colour-blind-safe palette, Wong 2011).
pub fn palette(i: usize) -> RGBColor {
    const C: [RGBColor; 8] = [
        RGBColor(0, 114, 178),
        RGBColor(213, 94, 0),
        RGBColor(0, 158, 115),
        RGBColor(204, 121, 167),
        RGBColor(230, 159, 0),
        RGBColor(86, 180, 233),
        RGBColor(0, 0, 0),
        RGBColor(240, 228, 66),
    ];
    C[i % C.len()]
}

/// A markdown table from a header and rows of cells.
pub fn markdown_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!("| {} |\n|", header.join(" | "));
    for _ in header {
        s.push_str("---:|");
    }
    s.push('\n');
    for r in rows {
        s.push_str(&format!("| {} |\n", r.join(" | ")));
    }
    s
}

/// Formats a float for a table with `digits` significant figures, in plain notation when
/// that is short.
pub fn cell(x: f64, digits: usize) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..6).contains(&e) {
        let decimals = (digits as i32 - 1 - e).max(0) as usize;
        format!("{x:.decimals$}")
    } else {
        crate::report::format_sig(x, digits)
    }
}
