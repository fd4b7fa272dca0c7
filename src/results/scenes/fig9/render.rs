//! Figure 9's plot — (a) the tip velocity over one period, (b) its harmonic amplitudes with
//! the free modes marked, and the contact count along each scan — and its tables.

use super::{Fig9Data, ScanPoint};
use crate::results::render::{
    tick,
    power_of_ten,
    cell, draw_legend, drawing, markdown_table, palette, solid_key, styled_mesh, RenderError,
    CAPTION_FONT, LABEL_FONT, WIDTH,
};
use crate::results::narrow::Layout;
use plotters::prelude::*;

const FREE: RGBColor = RGBColor(0, 114, 178);
const CONTACT: RGBColor = RGBColor(213, 40, 0);
const ENTRY: RGBColor = RGBColor(0, 158, 115);

fn velocity_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    d: &Fig9Data,
    layout: Layout,
) -> Result<(), RenderError> {
    let span = d.samples.last().map_or(1.0, |s| s.0.max(1.0));
    let (lo, hi) = d
        .samples
        .iter()
        .fold((0.0_f64, 0.0_f64), |(a, b), s| (a.min(s.1), b.max(s.1)));
    let pad = 0.08 * (hi - lo).max(1e-9);
    // on a phone the key is as wide as half the panel: room for it below the curve
    let below = match layout {
        Layout::Wide => pad,
        Layout::Narrow => pad + 0.65 * (hi - lo),
    };
    let mut chart = ChartBuilder::on(area)
        .caption(format!("(a) tip velocity over one period: {}", d.count.kind), CAPTION_FONT)
        .margin(8)
        .margin_right(28)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..span, (lo - below)..(hi + pad))
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("t / T")
        .y_desc("v / (ω · free amplitude)")
        .draw()
        .map_err(drawing)?;
    let mut first = [true, true];
    for w in d.samples.windows(2) {
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
    // contact entries, as the experiment's Figure 8 marks them
    let entries: Vec<(f64, f64)> = d
        .contacts
        .iter()
        .zip(&d.entry_velocities)
        .map(|(c, v)| (c.0, *v))
        .collect();
    chart
        .draw_series(entries.iter().map(|&p| Circle::new(p, 5, ENTRY.filled())))
        .map_err(drawing)?
        .label("contact entries")
        .legend(|(x, y)| Circle::new((x + 12, y), 5, ENTRY.filled()));
    draw_legend(&mut chart, SeriesLabelPosition::LowerRight)?;
    Ok(())
}

fn spectrum_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    d: &Fig9Data,
    layout: Layout,
) -> Result<(), RenderError> {
    let n = d.harmonic_amplitudes.len();
    let top = d.harmonic_amplitudes.iter().cloned().fold(0.0, f64::max);
    let least = d.harmonic_amplitudes.iter().cloned().fold(f64::INFINITY, f64::min);
    let floor = (least / 3.0).max(top * 1e-12).max(1e-300);
    let mut chart = ChartBuilder::on(area)
        .caption("(b) amplitudes of the first 25 harmonics (exact)", CAPTION_FONT)
        .margin(8)
        .margin_right(28)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..(n as f64 + 1.0), (floor..top * 3.0).log_scale())
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("harmonic n (frequency / ω)")
        .y_desc("Vₙ / (ω · free amplitude)")
        // n is an integer: ticks every 5
        .x_labels(n / 5 + 2)
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&power_of_ten)
        .draw()
        .map_err(drawing)?;
    for (i, &h) in d.mode_harmonics.iter().enumerate() {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(h, floor), (h, top * 3.0)],
                4,
                4,
                BLACK.mix(0.5).stroke_width(1),
            ))
            .map_err(drawing)?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("mode {}", i + 1),
                // narrow: every other label lower, so that neighbours do not run together
                (h + 0.15, top * if layout == Layout::Narrow && i % 2 == 1 { 0.25 } else { 1.6 }),
                LABEL_FONT,
            )))
            .map_err(drawing)?;
    }
    chart
        .draw_series(d.harmonic_amplitudes.iter().enumerate().map(|(k, &v)| {
            let x = (k + 1) as f64;
            Rectangle::new([(x - 0.3, floor), (x + 0.3, v.max(floor))], FREE.filled())
        }))
        .map_err(drawing)?;
    Ok(())
}

fn scan_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    title: &str,
    axis: &str,
    points: &[ScanPoint],
    log: bool,
) -> Result<(), RenderError> {
    let xs: Vec<f64> = points.iter().map(|s| s.value).collect();
    let (x0, x1) = (
        xs.iter().cloned().fold(f64::INFINITY, f64::min),
        xs.iter().cloned().fold(f64::NEG_INFINITY, f64::max),
    );
    let top = points
        .iter()
        .flat_map(|s| [s.count.maxima, s.count.intervals])
        .flatten()
        .fold(5.0_f64, f64::max)
        + 1.0;
    let pad = 0.06 * (x1 - x0).max(1e-9);
    let map = |x: f64| if log { x.log10() } else { x };
    let mut chart = ChartBuilder::on(area)
        .caption(title, CAPTION_FONT)
        .margin(6)
        .margin_right(16)
        .x_label_area_size(44)
        .y_label_area_size(44)
        .build_cartesian_2d((map(x0) - map(pad).min(0.05))..(map(x1) + 0.05), 0.0..top)
        .map_err(drawing)?;
    // counts, and a scan over N, are integers: their ticks are printed as such
    let integer_scan = xs.iter().all(|x| x.fract() == 0.0);
    styled_mesh(&mut chart)
        .x_desc(axis)
        .x_labels(4)
        .x_label_formatter(&|x| {
            if log {
                format!("{:.0}", 10f64.powf(*x))
            } else if integer_scan && x.fract().abs() < 1e-9 {
                format!("{x:.0}")
            } else {
                tick(&((x * 10.0).round() / 10.0))
            }
        })
        .y_labels((top as usize / 2 + 1).min(11))
        .y_label_formatter(&|y| {
            if y.fract().abs() < 1e-9 {
                format!("{y:.0}")
            } else {
                format!("{y:.1}")
            }
        })
        .draw()
        .map_err(drawing)?;
    // the paper's five
    chart
        .draw_series(DashedLineSeries::new(
            vec![(map(x0) - 1.0, 5.0), (map(x1) + 1.0, 5.0)],
            4,
            4,
            CONTACT.mix(0.6).stroke_width(1),
        ))
        .map_err(drawing)?;
    chart
        .draw_series(points.iter().filter_map(|s| {
            s.count
                .intervals
                .map(|i| Circle::new((map(s.value), i), 5, palette(0).filled()))
        }))
        .map_err(drawing)?;
    chart
        .draw_series(points.iter().filter_map(|s| {
            s.count
                .maxima
                .map(|m| Circle::new((map(s.value), m), 7, palette(1).stroke_width(2)))
        }))
        .map_err(drawing)?;
    Ok(())
}

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &Fig9Data, layout: Layout) -> Result<String, RenderError> {
    // (a) and (b) 1000 × 380 px each; the scans' title, in lines; four scans side by side
    // (250 × 330 px) or stacked (300 px each)
    let top = layout.panel_height(WIDTH, 380);
    let lines: &[&str] = match layout {
        Layout::Wide => &[
            "contacts per period: intervals (filled), penetration maxima (rings); dashed: five",
        ],
        Layout::Narrow => &[
            "contacts per period: intervals (filled),",
            "penetration maxima (rings); dashed: five",
        ],
    };
    let title_height = 12 + 28 * u32::try_from(lines.len()).unwrap_or(1);
    let scans_height = match layout {
        Layout::Wide => 330,
        Layout::Narrow => 4 * 300,
    };
    let size = (layout.width(), 2 * top + title_height + scans_height);
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let (a, rest) = root.split_vertically(top);
        let (b, scans) = rest.split_vertically(top);
        velocity_panel(&a, d, layout)?;
        spectrum_panel(&b, d, layout)?;
        let (title, cells) = scans.split_vertically(title_height);
        for (i, line) in lines.iter().enumerate() {
            title
                .draw(&Text::new(*line, (20, 10 + 28 * i as i32), LABEL_FONT))
                .map_err(drawing)?;
        }
        let cells = layout.cells(&cells, 1, 4);
        scan_panel(&cells[0], "d₀ / free amplitude", "d₀ / A_free", &d.scan_gap, false)?;
        scan_panel(&cells[1], "stop stiffness", "k / k₁", &d.scan_k, true)?;
        scan_panel(&cells[2], "forcing frequency", "ω / (β₁⁻)²", &d.scan_omega, false)?;
        scan_panel(&cells[3], "truncation", "N", &d.scan_modes, false)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// The main table: the spectrum with the nearest mode of each peak.
pub fn table(d: &Fig9Data) -> String {
    let rows: Vec<Vec<String>> = d
        .harmonic_amplitudes
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let n = k + 1;
            let peak = d.peaks.iter().find(|p| p.harmonic == n);
            vec![
                n.to_string(),
                crate::base::report::format_sig(*v, 4),
                peak.map_or(String::new(), |p| {
                    format!("peak: mode {} at n = {:.2}", p.mode, p.mode_harmonic)
                }),
            ]
        })
        .collect();
    markdown_table(&["n", "$V_n/(\\omega A_{\\rm free})$", "nearest free mode"], &rows)
}

/// The scans: contacts per period along each parameter.
pub fn scans_table(d: &Fig9Data) -> String {
    let mut rows = Vec::new();
    for (name, scan) in [
        ("$d_0/A_{\\rm free}$", &d.scan_gap),
        ("$k/k_1$", &d.scan_k),
        ("$\\omega/(\\beta_1^-)^2$", &d.scan_omega),
        ("$N$", &d.scan_modes),
    ] {
        for s in scan {
            rows.push(vec![
                name.to_string(),
                // N is a count
                if name == "$N$" { format!("{:.0}", s.value) } else { cell(s.value, 3) },
                s.count.kind.to_string(),
                s.count.intervals.map_or("—".into(), super::per_period),
                s.count.maxima.map_or("—".into(), super::per_period),
                s.count.transient.to_string(),
            ]);
        }
    }
    markdown_table(
        &[
            "scanned",
            "value",
            "orbit",
            "contact intervals per forcing period (mean over the orbit)",
            "penetration maxima per forcing period (mean over the orbit)",
            "periods discarded",
        ],
        &rows,
    )
}
