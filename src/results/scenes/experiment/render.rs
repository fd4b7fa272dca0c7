//! The experiment's plot — the Figure 9 velocity in milliseconds with the contact cluster
//! magnified and the periods of modes 2–4 as scale bars, and the spectrum in hertz with the
//! free frequencies — and its table of beam theory.

use super::ExperimentData;
use crate::results::render::{
    axis_fraction, emptiest_corner,
    power_of_ten,
    draw_legend, drawing, markdown_table, solid_key, styled_mesh, RenderError, CAPTION_FONT,
    LABEL_FONT, WIDTH,
};
use crate::results::narrow::Layout;

/// A mode number as subscript digits (T₂).
fn subscript(n: usize) -> String {
    const DIGITS: [char; 10] = ['₀', '₁', '₂', '₃', '₄', '₅', '₆', '₇', '₈', '₉'];
    n.to_string()
        .chars()
        .filter_map(|c| c.to_digit(10).map(|d| DIGITS[d as usize]))
        .collect()
}
use plotters::prelude::*;

const FREE: RGBColor = RGBColor(0, 114, 178);
const CONTACT: RGBColor = RGBColor(213, 40, 0);

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &ExperimentData, layout: Layout) -> Result<String, RenderError> {
    // (a) 1000 × 420 px above (b) 1000 × 400 px
    let (a, b) = (layout.panel_height(WIDTH, 420), layout.panel_height(WIDTH, 400));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (layout.width(), a + b)).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (top, bottom) = root.split_vertically(a);
        // (a) the contact cluster, with a margin of a tenth of the period either side
        let margin = 0.1 * d.forcing.1 * 1e3;
        let (c0, c1) = match (d.contacts_ms.first(), d.contacts_ms.last()) {
            (Some(a), Some(b)) => (a.0 - margin, b.1 + margin),
            _ => (0.0, d.forcing.1 * 1e3),
        };
        let inside: Vec<&(f64, f64, bool)> =
            d.samples.iter().filter(|s| s.0 >= c0 && s.0 <= c1).collect();
        let (lo, hi) = inside
            .iter()
            .fold((0.0_f64, 0.0_f64), |(a, b), s| (a.min(s.1), b.max(s.1)));
        let pad = 0.1 * (hi - lo).max(1e-9);
        let mut chart = ChartBuilder::on(&top)
            .caption("(a) the contacts of one period, in milliseconds", CAPTION_FONT)
            .margin(8)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(c0..c1, (lo - pad)..(hi + 4.0 * pad))
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("t (ms) from the start of the forcing period")
            .y_desc("v / (ω · free amplitude)")
            .draw()
            .map_err(drawing)?;
        let mut first = [true, true];
        for w in inside.windows(2) {
            let c = if w[0].2 { CONTACT } else { FREE };
            let s = chart
                .draw_series(LineSeries::new(vec![(w[0].0, w[0].1), (w[1].0, w[1].1)], c.stroke_width(2)))
                .map_err(drawing)?;
            let i = usize::from(w[0].2);
            if first[i] {
                s.label(if w[0].2 { "in contact" } else { "free flight" })
                    .legend(solid_key(c.stroke_width(2)));
                first[i] = false;
            }
        }
        // scale bars: the periods of modes 2, 3, 4
        for (j, t) in d.mode_periods_ms.iter().enumerate().take(4).skip(1) {
            let y = hi + pad * (1.0 + 0.9 * (j - 1) as f64);
            let x = c0 + 0.02 * (c1 - c0);
            chart
                .draw_series(LineSeries::new(vec![(x, y), (x + t, y)], BLACK.stroke_width(3)))
                .map_err(drawing)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    match layout {
                        Layout::Wide => format!("mode {} period, {t:.1} ms", j + 1),
                        // (the mode as a subscript: the long bar leaves little room)
                        Layout::Narrow => format!("T{} {t:.1} ms", subscript(j + 1)),
                    },
                    (x + t + 0.01 * (c1 - c0), y + 0.3 * pad),
                    LABEL_FONT,
                )))
                .map_err(drawing)?;
        }
        // the legend where neither the curve nor the scale bars with their labels are
        let (xs, ys) = ((c0, c1), (lo - pad, hi + 4.0 * pad));
        let at = |x: f64, y: f64| (axis_fraction(x, xs, false), axis_fraction(y, ys, false));
        let mut curves = vec![inside.iter().map(|s| at(s.0, s.1)).collect::<Vec<_>>()];
        for (j, t) in d.mode_periods_ms.iter().enumerate().take(4).skip(1) {
            let y = hi + pad * (1.0 + 0.9 * (j - 1) as f64);
            let x = c0 + 0.02 * (c1 - c0);
            // the label runs about a quarter of the width past the bar
            curves.push(vec![at(x, y), at(x + t + 0.27 * (c1 - c0), y)]);
        }
        // two rows with their frame and margin: about a fifth of the width, a third of
        // this short panel's height
        draw_legend(&mut chart, emptiest_corner(&curves, (0.22, 0.32)).0)?;
        // (b) the spectrum in hertz
        let top_v = d.spectrum.iter().map(|s| s.0).fold(0.0, f64::max);
        let least = d.spectrum.iter().map(|s| s.0).fold(f64::INFINITY, f64::min);
        let floor = (least / 3.0).max(top_v * 1e-12).max(1e-300);
        let fmax = d.spectrum.last().map_or(1.0, |s| s.1) * 1.04;
        let mut chart = ChartBuilder::on(&bottom)
            .caption("(b) the spectrum in hertz, free frequencies dashed", CAPTION_FONT)
            .margin(8)
            .margin_right(28)
            .x_label_area_size(44)
            .y_label_area_size(64)
            .build_cartesian_2d(0.0..fmax, (floor..top_v * 3.0).log_scale())
            .map_err(drawing)?;
        styled_mesh(&mut chart)
            .x_desc("frequency (Hz)")
            .y_desc("Vₙ / (ω · free amplitude)")
            .y_label_formatter(&power_of_ten)
            .draw()
            .map_err(drawing)?;
        let width = 0.3 * d.forcing.0;
        chart
            .draw_series(d.spectrum.iter().map(|&(v, f)| {
                Rectangle::new([(f - width, floor), (f + width, v.max(floor))], FREE.filled())
            }))
            .map_err(drawing)?;
        for (i, f) in d.mode_frequencies.iter().enumerate() {
            if *f > fmax {
                continue;
            }
            chart
                .draw_series(DashedLineSeries::new(
                    vec![(*f, floor), (*f, top_v * 3.0)],
                    4,
                    4,
                    BLACK.mix(0.5).stroke_width(1),
                ))
                .map_err(drawing)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    match layout {
                        Layout::Wide => format!("mode {}: {f:.0} Hz", i + 1),
                        // (the caption says the dashed lines are the free frequencies)
                        Layout::Narrow => format!("{f:.0} Hz"),
                    },
                    // narrow: every other label lower, so that neighbours do not overlap
                    (
                        *f + 2.0,
                        top_v * if layout == Layout::Narrow && i % 2 == 1 { 0.3 } else { 1.6 },
                    ),
                    LABEL_FONT,
                )))
                .map_err(drawing)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// Beam theory over the rig's tolerances: each quantity nominal, lowest and highest.
pub fn table(d: &ExperimentData) -> String {
    use crate::base::report::{Cited, KeyValue, Uncertainty};
    let m = &d.mapping;
    // the text quotes each range as its middle ± half its width, to the figures of the
    // chapter's key numbers (`digits`)
    let row = |name: &str, r: &super::Ranged, scale: f64, decimals: usize, digits: usize| {
        let (lo, hi) = (r.range.0 * scale, r.range.1 * scale);
        let quoted = Cited::new(0.5 * (lo + hi), digits, Uncertainty::new(0.5 * (hi - lo), ""), "");
        vec![
            name.to_string(),
            format!("{:.*}", decimals, r.nominal * scale),
            format!("{:.*}", decimals, lo),
            format!("{:.*}", decimals, hi),
            KeyValue::Float(quoted).prose(true),
        ]
    };
    let rows = vec![
        row("$f_1$ of the strip (Hz)", &m.f1_theory, 1.0, 2, 4),
        row("free length for 5.92 Hz (mm)", &m.length_for_measured, 1e3, 0, 4),
        row("tip mass for 5.92 Hz (× strip's mass)", &m.tip_mass_fraction, 1.0, 2, 3),
        row("pin stiffness $K$ (kN/m)", &m.pin_stiffness, 1e-3, 1, 4),
        row("$k/k_1$", &m.k_ratio, 1.0, 0, 4),
        row("$k/k_1$ at the free length for 5.92 Hz", &m.k_ratio_effective_length, 1.0, 0, 4),
        row("the pin's first resonance (Hz)", &m.pin_resonance, 1.0, 0, 4),
        row("the pin's modal tip mass / the strip's", &m.pin_mass_ratio, 1.0, 1, 3),
    ];
    markdown_table(
        &["quantity", "nominal rig", "lowest", "highest", "quoted in the text: middle ± half the range"],
        &rows,
    )
}

/// The Figure 9 orbit under eq (37) and in the two sensitivity runs.
pub fn variants_table(d: &ExperimentData) -> String {
    let mut rows = vec![vec![
        "eq (37): mode 1 forced, material damping (the paper's model)".to_string(),
        d.kind.to_string(),
        d.contacts_ms.len().to_string(),
        format!("{:.1}", d.cluster_ms),
    ]];
    for v in &d.variants {
        // a motion that does not settle: its range over the periods summarised, and no
        // cluster (its contacts straddle the period's ends)
        let (intervals, cluster) = match v.spread {
            Some(spread) => (spread.to_string(), "—".to_string()),
            None => (v.contacts_ms.len().to_string(), format!("{:.1}", v.cluster_ms)),
        };
        rows.push(vec![v.name.clone(), v.kind.to_string(), intervals, cluster]);
    }
    markdown_table(
        &["model", "orbit", "contact intervals per period", "contact cluster (ms)"],
        &rows,
    )
}
