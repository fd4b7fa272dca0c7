//! Shared rendering helpers for the scenes' `render.rs`: SVG plots (plotters' SVG backend,
//! which writes text as SVG `<text>` and so needs no system fonts) and markdown tables.
//! No numerics here.

use plotters::chart::MeshStyle;
use plotters::coord::ranged1d::{Ranged, ValueFormatter};
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// Plot size in pixels (the book scales SVGs to the page width).
pub const WIDTH: u32 = 1000;

pub use crate::error::RenderError;

/// Maps any plotters error into [`RenderError`].
pub fn drawing<E: std::fmt::Debug>(e: E) -> RenderError {
    RenderError(format!("{e:?}"))
}

/// Tick labels (px as drawn; the 1000 px plots are shown at about 0.7 scale in the book,
/// so 18 px reads as about 12.5 px).
pub const LABEL_FONT: (&str, u32) = ("sans-serif", 18);
/// Axis descriptions.
pub const AXIS_FONT: (&str, u32) = ("sans-serif", 20);
/// Panel titles.
pub const CAPTION_FONT: (&str, u32) = ("sans-serif", 22);

/// The mesh of `chart` with the book's label sizes; add descriptions and formatters, then
/// `.draw()`.
pub fn styled_mesh<'a, 'b, DB, X, Y, XT, YT>(
    chart: &'b mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
) -> MeshStyle<'a, 'b, X, Y, DB>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = XT> + ValueFormatter<XT>,
    Y: Ranged<ValueType = YT> + ValueFormatter<YT>,
{
    let mut m = chart.configure_mesh();
    m.label_style(LABEL_FONT).axis_desc_style(AXIS_FONT);
    m
}

/// Draws the mesh of a log–log `chart` with the book's label sizes, the given axis
/// descriptions and ticks as powers of ten.
pub fn log_log_mesh<'a, DB, X, Y>(
    chart: &mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
    x_desc: &str,
    y_desc: &str,
) -> Result<(), RenderError>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    styled_mesh(chart)
        .x_desc(x_desc)
        .y_desc(y_desc)
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .y_label_formatter(&|y| format!("{y:.0e}"))
        .draw()
        .map_err(drawing)
}

/// Draws the axes of a map over (ω, log₁₀ k): ω/(β₁⁻)² horizontally with `x_labels`
/// ticks, k/k₁ vertically with a tick per decade of [l0, l1], no grid.
pub fn omega_log_k_mesh<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<
        'a,
        DB,
        Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
    >,
    (l0, l1): (f64, f64),
    x_labels: usize,
) -> Result<(), RenderError> {
    styled_mesh(chart)
        .disable_mesh()
        .x_desc("ω / (β₁⁻)²")
        .y_desc("k / k₁")
        .y_label_formatter(&|l| format!("1e{l:.0}"))
        .y_labels(((l1 - l0) as usize + 1).max(2))
        .x_labels(x_labels)
        .draw()
        .map_err(drawing)
}

/// A legend entry for a solid line of `style`.
pub fn solid_key(style: ShapeStyle) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], style)
}

/// A legend entry for a dashed line of `style` (as the series is drawn).
pub fn dashed_key(
    style: ShapeStyle,
) -> impl Fn((i32, i32)) -> DashedPathElement<std::vec::IntoIter<(i32, i32)>, i32> {
    move |(x, y)| DashedPathElement::new(vec![(x, y), (x + 24, y)], 5, 3, style)
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

/// Viridis (van der Walt & Smith) at r ∈ [0, 1], linear between five of its stops: a
/// perceptually ordered colour scale for maps.
pub fn viridis(r: f64) -> RGBColor {
    let stops = [
        (0.0, (68, 1, 84)),
        (0.25, (59, 82, 139)),
        (0.5, (33, 145, 140)),
        (0.75, (94, 201, 98)),
        (1.0, (253, 231, 37)),
    ];
    let r = r.clamp(0.0, 1.0);
    for w in stops.windows(2) {
        let ((a, ca), (b, cb)) = (w[0], w[1]);
        if r <= b {
            let t = (r - a) / (b - a);
            let mix = |x: u8, y: u8| (x as f64 + t * (y as f64 - x as f64)).round() as u8;
            return RGBColor(mix(ca.0, cb.0), mix(ca.1, cb.1), mix(ca.2, cb.2));
        }
    }
    RGBColor(253, 231, 37)
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

/// A markdown table from a header and rows of cells: the first column left-aligned, the
/// rest right-aligned.
pub fn markdown_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!("| {} |\n|", header.join(" | "));
    // the first column names the row (left); the others hold numbers (right)
    for i in 0..header.len() {
        s.push_str(if i == 0 { ":---|" } else { "---:|" });
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
        crate::base::report::format_sig(x, digits)
    }
}
