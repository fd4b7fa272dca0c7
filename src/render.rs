//! Shared rendering helpers for the scenes' `render.rs`: SVG plots (plotters' SVG backend,
//! which writes text as SVG `<text>` and so needs no system fonts) and markdown tables.
//! No numerics here.

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
