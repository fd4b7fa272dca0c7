//! Shared rendering helpers for the scenes' `render.rs`: SVG plots (plotters' SVG backend,
//! which writes text as SVG `<text>` and so needs no system fonts) and markdown tables.
//! No numerics here.

use crate::base::report::superscript;
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

/// The mesh of `chart` with the book's label sizes, tick labels without trailing zeros
/// and with a minus sign ([`tick`]), and a light grid of at most four minor lines per major
/// interval; add descriptions and other formatters, then `.draw()`.
pub fn styled_mesh<'a, 'b, DB, X, Y>(
    chart: &'b mut ChartContext<'a, DB, Cartesian2d<X, Y>>,
) -> MeshStyle<'a, 'b, X, Y, DB>
where
    DB: DrawingBackend + 'a,
    X: Ranged<ValueType = f64> + ValueFormatter<f64>,
    Y: Ranged<ValueType = f64> + ValueFormatter<f64>,
{
    let mut m = chart.configure_mesh();
    m.label_style(LABEL_FONT)
        .axis_desc_style(AXIS_FONT)
        .x_label_formatter(&tick)
        .y_label_formatter(&tick)
        .x_max_light_lines(4)
        .y_max_light_lines(4);
    m
}

/// A tick label on a linear axis: the value to ten significant figures without trailing
/// zeros (15, 0.35), with a minus sign for negative values; a value within round-off of
/// zero is 0.
pub fn tick(x: &f64) -> String {
    if x.abs() < 1e-12 || !x.is_finite() {
        return "0".into();
    }
    let digits = (9 - x.abs().log10().floor() as i32).max(0) as usize;
    let s = format!("{x:.digits$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    s.replace('-', "−")
}

/// Draws the mesh of a log–log `chart` with the book's label sizes, the given axis
/// descriptions and ticks as powers of ten.
///
/// # Errors
/// [`RenderError`] when the backend fails to draw the mesh.
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
        .x_label_formatter(&power_of_ten)
        .y_label_formatter(&power_of_ten)
        .draw()
        .map_err(drawing)
}

/// Draws the axes of a map over (ω, log₁₀ k): ω/(β₁⁻)² horizontally with `x_labels`
/// ticks, k/k₁ vertically with a tick per decade of [l0, l1], no grid.
///
/// # Errors
/// [`RenderError`] when the backend fails to draw the mesh.
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
        .y_label_formatter(&|l| power_of_ten(&10f64.powf(l.round())))
        .y_labels(((l1 - l0) as usize + 1).max(2))
        .x_labels(x_labels)
        .draw()
        .map_err(drawing)
}

/// The number in e-notation that starts at `chars[i]` (`1.778e3`, `1e-12`), as the book
/// prints numbers elsewhere (`1.778 × 10³`, `10⁻¹²`), and how many chars it spans; `None`
/// where `chars[i]` does not start one. A number starts after a character that is not
/// alphanumeric, `.` or `_`, has at most three exponent digits and is not followed by a
/// letter, a digit or a decimal point — except the unit k₁, written without a space.
fn e_notation_at(chars: &[char], i: usize) -> Option<(String, usize)> {
    if i > 0 && (chars[i - 1].is_alphanumeric() || matches!(chars[i - 1], '.' | '_')) {
        return None;
    }
    let digits = |from: usize| {
        chars[from..]
            .iter()
            .take_while(|c| c.is_ascii_digit())
            .count()
    };
    let mut j = i + digits(i);
    if j == i {
        return None;
    }
    if chars.get(j) == Some(&'.') && digits(j + 1) > 0 {
        j += 1 + digits(j + 1);
    }
    let mantissa: String = chars[i..j].iter().collect();
    if !matches!(chars.get(j), Some('e' | 'E')) {
        return None;
    }
    j += 1;
    let negative = matches!(chars.get(j), Some('-' | '−'));
    if matches!(chars.get(j), Some('-' | '−' | '+')) {
        j += 1;
    }
    let n = digits(j);
    let after = chars.get(j + n);
    let unit_k1 = after == Some(&'k') && chars.get(j + n + 1) == Some(&'₁');
    // a full stop ends a sentence; a point followed by a digit continues a number
    let continues = after.is_some_and(|c| c.is_alphanumeric())
        || (after == Some(&'.') && chars.get(j + n + 1).is_some_and(|c| c.is_ascii_digit()));
    if n == 0 || n > 3 || (continues && !unit_k1) {
        return None;
    }
    let exponent: String = chars[j..j + n].iter().collect();
    let e = exponent.parse::<i32>().unwrap_or(0) * if negative { -1 } else { 1 };
    // the mantissa's figures without trailing zeros: 1.000e1 is the integer 10
    let mantissa = if mantissa.contains('.') {
        mantissa
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    } else {
        mantissa
    };
    let unit = if unit_k1 { " " } else { "" };
    let span = j + n - i;
    // moderate sizes plainly, as the book prints them elsewhere (1.778e3 is 1778)
    if (-3..=5).contains(&e) {
        let value: f64 = format!("{mantissa}e{e}").parse().ok()?;
        let figures = mantissa.chars().filter(|c| c.is_ascii_digit()).count() as i32;
        let decimals = (figures - 1 - e).max(0) as usize;
        return Some((format!("{value:.decimals$}{unit}"), span));
    }
    // the rest as a power of ten, never broken across lines at its ×
    let sup = superscript(e);
    Some(if mantissa == "1" {
        (format!("10{sup}{unit}"), span)
    } else {
        (format!("{mantissa}\u{a0}×\u{a0}10{sup}{unit}"), span)
    })
}

/// Numbers in text as the book prints them: e-notation as powers of ten
/// (`e_notation_at`) and a minus sign (−, not a hyphen) before a negative number. Code
/// (`…`) and TeX (`$…$`) are left alone.
pub fn readable_numbers(text: &str) -> String {
    rewrite(text, false)
}

/// Text for a page or a table: numbers as [`readable_numbers`] writes them, and the
/// paper's subscripts as HTML — `r_E`, `A_free`, `β_N`, `[R]_N` and `ωA_free` would show
/// their underscores. A subscript is a single-letter symbol (or `]`) followed by `_` and
/// letters or digits; identifiers such as `impact_velocity_1` and anything inside
/// backticks are left alone.
pub fn readable_text(text: &str) -> String {
    rewrite(text, true)
}

/// The one pass of [`readable_numbers`] and (with `subscripts`) [`readable_text`].
fn rewrite(text: &str, subscripts: bool) -> String {
    let chars: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len() + 16);
    let mut in_code = false;
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        // code and TeX (`$…$`, converted later to MathML) stay as written
        if c == '`' || c == '$' {
            in_code = !in_code;
        }
        if in_code {
            out.push(c);
            i += 1;
            continue;
        }
        if let Some((power, span)) = e_notation_at(&chars, i) {
            out.push_str(&power);
            i += span;
            continue;
        }
        // a hyphen that starts a number (after a space, a bracket or a sign of relation)
        let starts =
            i == 0 || matches!(chars[i - 1], ' ' | '(' | '[' | '=' | ',' | '/' | '≈' | '~');
        if c == '-' && starts && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()) {
            out.push('−');
            i += 1;
            continue;
        }
        // the symbol stands alone: nothing alphanumeric before it, except ω in ωA_free
        let symbol = c.is_alphabetic() || c == ']';
        let alone = c == ']' || i == 0 || !chars[i - 1].is_alphanumeric() || chars[i - 1] == 'ω';
        let run = chars[(i + 2).min(chars.len())..]
            .iter()
            .take_while(|ch| ch.is_ascii_alphanumeric())
            .count();
        if subscripts && symbol && alone && chars.get(i + 1) == Some(&'_') && run > 0 {
            let sub: String = chars[i + 2..i + 2 + run].iter().collect();
            out.push(c);
            out.push_str(&format!("<sub>{sub}</sub>"));
            i += 2 + run;
            continue;
        }
        out.push(c);
        i += 1;
    }
    // a power of ten is not broken across lines at its ×
    out.replace(" × 10", "\u{a0}×\u{a0}10")
}

/// A tick label on a logarithmic axis: a power of ten as 10ⁿ (1 and 10 as themselves),
/// another value as m×10ⁿ to one figure.
pub fn power_of_ten(x: &f64) -> String {
    if !(x.is_finite() && *x > 0.0) {
        return format!("{x}");
    }
    let e = x.log10().round() as i32;
    let m = x / 10f64.powi(e);
    match e {
        _ if (m - 1.0).abs() > 1e-6 => {
            let e = x.log10().floor() as i32;
            format!(
                "{:.0}×10{}",
                x / 10f64.powi(e),
                crate::base::report::superscript(e)
            )
        }
        0 => "1".into(),
        1 => "10".into(),
        _ => format!("10{}", crate::base::report::superscript(e)),
    }
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
///
/// # Errors
/// [`RenderError`] when the backend fails to draw the legend.
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

/// The parts of a polyline inside the band lo ≤ y ≤ hi, cut where it leaves and re-enters
/// the band (plotters would instead press the points outside onto the plot's edge, which
/// draws a flat line that is not in the data).
pub fn clip_to_band(line: &[(f64, f64)], (lo, hi): (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let inside = |p: &(f64, f64)| p.1 >= lo && p.1 <= hi;
    // the point where the segment a → b meets the level y
    let cut = |a: (f64, f64), b: (f64, f64), y: f64| {
        let t = (y - a.1) / (b.1 - a.1);
        (a.0 + t * (b.0 - a.0), y)
    };
    let mut parts: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    for (i, &p) in line.iter().enumerate() {
        let prev = i.checked_sub(1).map(|j| line[j]);
        match (prev, inside(&p)) {
            (_, true) if !current.is_empty() => current.push(p),
            (Some(a), true) => {
                // entering the band from beyond one of its edges
                current.push(cut(a, p, if a.1 < lo { lo } else { hi }));
                current.push(p);
            }
            (None, true) => current.push(p),
            (Some(a), false) if inside(&a) => {
                current.push(cut(a, p, if p.1 < lo { lo } else { hi }));
                parts.push(std::mem::take(&mut current));
            }
            (Some(a), false) if (a.1 < lo) != (p.1 < lo) => {
                // crossing the whole band between two points
                let (y0, y1) = if a.1 < lo { (lo, hi) } else { (hi, lo) };
                parts.push(vec![cut(a, p, y0), cut(a, p, y1)]);
            }
            _ => {}
        }
    }
    if !current.is_empty() {
        parts.push(current);
    }
    parts
}

/// A value's position along an axis from `lo` to `hi` as a fraction (0 at `lo`, 1 at
/// `hi`), on a logarithmic axis if `log`.
pub fn axis_fraction(v: f64, (lo, hi): (f64, f64), log: bool) -> f64 {
    if log {
        (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
    } else {
        (v - lo) / (hi - lo)
    }
}

/// The corner of a plot where a legend box of `size` (width, height as fractions of the
/// plot) covers least of the data: `curves` in plot fractions ([`axis_fraction`]), each in
/// drawing order, so that a line crossing the box between two of its points counts too.
/// Ties go to the first of upper right, upper left, lower right, lower left. Returns the
/// corner and how many segments (or lone points) its box still covers.
pub fn emptiest_corner(
    curves: &[Vec<(f64, f64)>],
    (w, h): (f64, f64),
) -> (SeriesLabelPosition, usize) {
    use SeriesLabelPosition::*;
    let corners = [
        (UpperRight, (1.0 - w, 1.0), (1.0 - h, 1.0)),
        (UpperLeft, (0.0, w), (1.0 - h, 1.0)),
        (LowerRight, (1.0 - w, 1.0), (0.0, h)),
        (LowerLeft, (0.0, w), (0.0, h)),
    ];
    let covered = |(x0, x1): (f64, f64), (y0, y1): (f64, f64)| {
        let inside = |(x, y): (f64, f64)| x >= x0 && x <= x1 && y >= y0 && y <= y1;
        curves
            .iter()
            .map(|c| {
                let single = c.len() == 1 && inside(c[0]);
                let along = c.windows(2).filter(|p| {
                    // sampled finely enough that a segment cannot cross the box unseen
                    (0..=32).any(|k| {
                        let t = k as f64 / 32.0;
                        inside((
                            p[0].0 + t * (p[1].0 - p[0].0),
                            p[0].1 + t * (p[1].1 - p[0].1),
                        ))
                    })
                });
                along.count() + usize::from(single)
            })
            .sum::<usize>()
    };
    let mut best = (UpperRight, usize::MAX);
    for (corner, xs, ys) in corners {
        let n = covered(xs, ys);
        if n < best.1 {
            best = (corner, n);
        }
    }
    best
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
    table(header, rows, "---:|")
}

/// A markdown table whose cells are sentences: every column left-aligned (a sentence set
/// flush right is hard to read).
pub fn markdown_text_table(header: &[&str], rows: &[Vec<String>]) -> String {
    table(header, rows, ":---|")
}

fn table(header: &[&str], rows: &[Vec<String>], others: &str) -> String {
    let mut s = format!("| {} |\n|", readable_text(&header.join(" | ")));
    // the first column names the row (left); the others hold numbers (right) or text
    for i in 0..header.len() {
        s.push_str(if i == 0 { ":---|" } else { others });
    }
    s.push('\n');
    for r in rows {
        s.push_str(&format!("| {} |\n", readable_text(&r.join(" | "))));
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn e_notation_becomes_powers_of_ten_and_identifiers_stay() {
        assert_eq!(readable_numbers("below 1e-12."), "below 10⁻¹².");
        assert_eq!(readable_numbers("k = 1.778e3k₁)"), "k = 1778 k₁)");
        assert_eq!(readable_numbers("k = 1.000e1k₁)"), "k = 10 k₁)");
        assert_eq!(readable_numbers("to 3.6e-16;"), "to 3.6\u{a0}×\u{a0}10⁻¹⁶;");
        assert_eq!(readable_numbers("(1e2 times"), "(100 times");
        assert_eq!(
            readable_numbers("is 1.2e-5 at"),
            "is 1.2\u{a0}×\u{a0}10⁻⁵ at"
        );
        assert_eq!(readable_numbers("is 2.5e-3 at"), "is 0.0025 at");
        assert_eq!(readable_numbers("ε = 1e0"), "ε = 1");
        assert_eq!(readable_numbers("rtol 1e+06"), "rtol 10⁶");
        assert_eq!(readable_numbers("k = 1.00e6 k₁"), "k = 10⁶ k₁");
        assert_eq!(readable_numbers("2.424e0, 3.635e-1"), "2.424, 0.3635");
        // not numbers in e-notation: identifiers, hashes, code, versions, ranges
        assert_eq!(readable_numbers("commit 5e31a2c"), "commit 5e31a2c");
        assert_eq!(readable_numbers("x1e3 a1e-3"), "x1e3 a1e-3");
        assert_eq!(readable_numbers("`1e-3` $1e3$"), "`1e-3` $1e3$");
        assert_eq!(readable_numbers("v1.2e3"), "v1.2e3");
        assert_eq!(readable_numbers("3e4f 2e12345"), "3e4f 2e12345");
        assert_eq!(readable_numbers("1e"), "1e");
        // a minus sign for negative numbers, not for hyphens, ranges or flags
        assert_eq!(
            readable_numbers("slope -0.51 (-2) x=-3"),
            "slope −0.51 (−2) x=−3"
        );
        assert_eq!(
            readable_numbers("2026-11-25, N=1-3, --out, a-1"),
            "2026-11-25, N=1-3, --out, a-1"
        );
    }

    #[test]
    fn ticks_read_as_written_by_hand() {
        assert_eq!(tick(&15.0), "15");
        assert_eq!(tick(&0.35), "0.35");
        assert_eq!(tick(&(0.1 + 0.2)), "0.3");
        assert_eq!(tick(&-4.0), "−4");
        assert_eq!(tick(&-1e-17), "0");
        assert_eq!(tick(&250.0), "250");
        assert_eq!(tick(&1.5e-5), "0.000015");
    }

    #[test]
    fn powers_of_ten_read_as_powers() {
        assert_eq!(power_of_ten(&1e-3), "10⁻³");
        assert_eq!(power_of_ten(&1.0), "1");
        assert_eq!(power_of_ten(&10.0), "10");
        assert_eq!(power_of_ten(&1e12), "10¹²");
        assert_eq!(power_of_ten(&2e-3), "2×10⁻³");
        assert_eq!(power_of_ten(&0.0), "0");
    }

    #[test]
    fn a_line_is_cut_where_it_leaves_the_band() {
        let line = [(0.0, -2.0), (1.0, 0.0), (2.0, 0.5), (3.0, 2.0), (4.0, -2.0)];
        let parts = clip_to_band(&line, (-1.0, 1.0));
        assert_eq!(
            parts,
            vec![
                vec![(0.5, -1.0), (1.0, 0.0), (2.0, 0.5), (2.0 + 1.0 / 3.0, 1.0)],
                vec![(3.25, 1.0), (3.75, -1.0)],
            ]
        );
        assert!(clip_to_band(&[(0.0, 5.0), (1.0, 6.0)], (-1.0, 1.0)).is_empty());
    }

    #[test]
    fn the_legend_goes_where_the_data_are_not() {
        // a rising line from lower left to upper right: the upper-left corner is empty
        let rising = vec![(0.0, 0.0), (1.0, 1.0)];
        assert_eq!(
            emptiest_corner(&[rising], (0.4, 0.25)),
            (SeriesLabelPosition::UpperLeft, 0)
        );
        // a line crossing the upper right box between two distant points counts there
        let across = vec![(0.5, 0.9), (1.0, 0.9)];
        let falling = vec![(0.0, 1.0), (1.0, 0.0)];
        assert_eq!(
            emptiest_corner(&[across, falling], (0.4, 0.25)),
            (SeriesLabelPosition::LowerLeft, 0)
        );
        // every corner taken: the least covered
        let border = vec![
            (0.0, 0.05),
            (1.0, 0.05),
            (1.0, 0.95),
            (0.0, 0.95),
            (0.0, 0.5),
        ];
        assert_eq!(
            emptiest_corner(&[border], (0.4, 0.25)),
            (SeriesLabelPosition::LowerLeft, 1)
        );
        // a single point is data too
        assert_eq!(
            emptiest_corner(&[vec![(0.9, 0.9)]], (0.4, 0.25)),
            (SeriesLabelPosition::UpperLeft, 0)
        );
    }
}
