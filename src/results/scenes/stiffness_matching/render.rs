//! Stiffness matching: errors against N and against the element count, N*(k) with the
//! criterion, and the post-contact velocity profiles at finite k and in the rigid limit.

use crate::results::narrow::Layout;
use super::MatchingData;
use crate::analysis::convergence::Needed;
use crate::results::render::{
    power_of_ten,
    cell, dashed_key, draw_legend, drawing, log_log_mesh, markdown_table, palette, solid_key,
    styled_mesh, RenderError, CAPTION_FONT, WIDTH,
};
use plotters::prelude::*;

/// The observable plotted against resolution.
const SHOWN: &str = "exit tip velocity";

/// The SVG plot: (a) Galerkin error against N, (b) element error against n, (c) N*(k),
/// (d)–(e) the velocity profiles.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &MatchingData, layout: Layout) -> Result<String, RenderError> {
    // four rows of 500 px: two half panels, the full-width N*(k), two, two
    let (half, full) = (layout.panel_height(500, 500), layout.panel_height(WIDTH, 500));
    let size = match layout {
        Layout::Wide => (WIDTH, 2000),
        Layout::Narrow => (layout.width(), 6 * half + full),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        // the seven panels in reading order
        let areas = match layout {
            Layout::Wide => {
                let rows = root.split_evenly((4, 1));
                let pair = |r: usize| rows[r].split_evenly((1, 2));
                let (top, third, bottom) = (pair(0), pair(2), pair(3));
                vec![
                    top[0].clone(),
                    top[1].clone(),
                    rows[1].clone(),
                    third[0].clone(),
                    third[1].clone(),
                    bottom[0].clone(),
                    bottom[1].clone(),
                ]
            }
            Layout::Narrow => {
                let heights = [half, half, full, half, half, half];
                let breaks: Vec<u32> = heights
                    .iter()
                    .scan(0, |y, h| {
                        *y += h;
                        Some(*y)
                    })
                    .collect();
                root.split_by_breakpoints([] as [u32; 0], breaks)
            }
        };
        errors(&areas[0], d, Ladder::Galerkin)?;
        errors(&areas[1], d, Ladder::Elements)?;
        needed(&areas[2], d)?;
        profiles(&areas[3], d, true)?;
        profiles(&areas[4], d, false)?;
        errors(&areas[5], d, Ladder::TwoBasis)?;
        super::render_two_basis::losses(&areas[6], d)?;
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// Which refinement ladder.
#[derive(Clone, Copy, PartialEq)]
enum Ladder {
    Galerkin,
    Elements,
    TwoBasis,
}

fn errors<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    d: &MatchingData,
    ladder: Ladder,
) -> Result<(), RenderError> {
    let series: Vec<(f64, Vec<(f64, f64)>)> = d
        .stiffness
        .iter()
        .filter_map(|a| {
            let c = a.observables.iter().find(|c| c.name == SHOWN)?;
            let study = match ladder {
                Ladder::Galerkin => &c.galerkin,
                Ladder::Elements => &c.elements,
                Ladder::TwoBasis => &c.two_basis,
            };
            let pts = study
                .sizes
                .iter()
                .zip(study.relative_errors())
                // the finest point is the extrapolation's anchor: its error is not measured
                .take(study.sizes.len() - 1)
                .filter(|(_, e)| *e > 0.0)
                .map(|(&n, e)| (n as f64, e))
                .collect();
            Some((a.k_over_k1, pts))
        })
        .collect();
    let xmax = series.iter().flat_map(|s| s.1.iter().map(|p| p.0)).fold(2.0, f64::max);
    let (title, xdesc) = match ladder {
        Ladder::Galerkin => ("(a) Galerkin model: error against N", "N (modes)"),
        Ladder::Elements => ("(b) finite elements: error against n", "n (elements)"),
        Ladder::TwoBasis => ("(f) two-basis truncation: error against N", "N (modes in each basis)"),
    };
    let mut chart = ChartBuilder::on(area)
        .caption(title, CAPTION_FONT)
        .margin(8)
        .margin_right(24)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((1.0..xmax * 1.2).log_scale(), (1e-10..10.0).log_scale())
        .map_err(drawing)?;
    // integer ticks on N: plotters' default log labels crowd on a short range
    styled_mesh(&mut chart)
        .x_desc(xdesc)
        .y_desc("relative error of the exit tip velocity")
        .x_labels(6)
        .x_label_formatter(&|x| format!("{x:.0}"))
        .y_label_formatter(&power_of_ten)
        .draw()
        .map_err(drawing)?;
    for (i, (k, pts)) in series.iter().enumerate() {
        let c = palette(i);
        chart
            .draw_series(LineSeries::new(pts.iter().map(|p| (p.0, p.1.max(1e-10))), c.stroke_width(2)))
            .map_err(drawing)?
            .label(format!("k = {}k₁", cell(*k, 2)))
            .legend(solid_key(c.stroke_width(2)));
        chart
            .draw_series(pts.iter().map(|p| Circle::new((p.0, p.1.max(1e-10)), 3, c.filled())))
            .map_err(drawing)?;
    }
    draw_legend(&mut chart, SeriesLabelPosition::LowerLeft)?;
    Ok(())
}

fn needed<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    d: &MatchingData,
) -> Result<(), RenderError> {
    let ks: Vec<f64> = d.stiffness.iter().map(|a| a.k_over_k1).collect();
    let (kmin, kmax) = (ks.iter().copied().fold(f64::INFINITY, f64::min), ks.iter().copied().fold(0.0, f64::max));
    let mut chart = ChartBuilder::on(area)
        .caption("(c) modes needed N* against the stop stiffness", CAPTION_FONT)
        .margin(8)
        .margin_right(24)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d((kmin / 2.0..kmax * 2.0).log_scale(), (1.0..3e4).log_scale())
        .map_err(drawing)?;
    log_log_mesh(&mut chart, "k / k₁", "N*")?;
    for (i, &tol) in d.params.tolerances.iter().enumerate() {
        let c = palette(i);
        let pts: Vec<(f64, f64, bool)> = d
            .stiffness
            .iter()
            .filter_map(|a| match a.needed.iter().find(|n| n.0 == tol)?.1 {
                Needed::Scanned(n) => Some((a.k_over_k1, n as f64, true)),
                Needed::Beyond { estimate } | Needed::Unconfirmed { estimate } => {
                    Some((a.k_over_k1, estimate, false))
                }
                Needed::Unresolved => None,
            })
            .collect();
        chart
            .draw_series(LineSeries::new(pts.iter().map(|p| (p.0, p.1)), c.stroke_width(2)))
            .map_err(drawing)?
            .label(format!("N* for relative error {}", power_of_ten(&tol)))
            .legend(solid_key(c.stroke_width(2)));
        chart
            .draw_series(pts.iter().map(|p| {
                let style = if p.2 { c.filled() } else { c.stroke_width(2) };
                Circle::new((p.0, p.1), 5, style)
            }))
            .map_err(drawing)?;
    }
    // the criterion (β_N)³ = c·k, drawn from the roots themselves
    let grid: Vec<f64> = (0..=40).map(|i| (kmin / 2.0) * (4.0 * kmax / kmin).powf(i as f64 / 40.0)).collect();
    let k1 = crate::model::galerkin::first_modal_stiffness();
    for (j, c) in [1.0, 100.0].into_iter().enumerate() {
        let line: Vec<(f64, f64)> = grid
            .iter()
            .filter_map(|&k| crate::analysis::convergence::criterion_modes(k * k1, c).ok().map(|n| (k, n as f64)))
            .collect();
        let style = BLACK.stroke_width(if j == 0 { 1 } else { 2 });
        chart
            .draw_series(DashedLineSeries::new(line, 6, 4, style))
            .map_err(drawing)?
            .label(if j == 0 { "criterion (β_N)³ = k" } else { "(β_N)³ = 100k" })
            .legend(dashed_key(style));
    }
    draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    Ok(())
}

fn profiles<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    d: &MatchingData,
    compliant: bool,
) -> Result<(), RenderError> {
    let all = d.profiles.iter().flat_map(|p| if compliant { p.compliant.iter() } else { p.rigid.iter() });
    let (lo, hi) = all.fold((0.0_f64, 0.0_f64), |(a, b), &v| (a.min(v), b.max(v)));
    let title = if compliant {
        format!("(d) after one contact, k = {}k₁", cell(d.params.profile_k, 2))
    } else {
        "(e) rigid limit [R]_N, r_e = 1 (Fig 3(d))".to_string()
    };
    let pad = 0.1 * (hi - lo).max(1e-3);
    let mut chart = ChartBuilder::on(area)
        .caption(title, CAPTION_FONT)
        .margin(8)
        .margin_right(24)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..1.0, (lo - pad)..(hi + 0.6 * (hi - lo) + pad))
        .map_err(drawing)?;
    styled_mesh(&mut chart)
        .x_desc("s (along the beam)")
        .y_desc("post-contact velocity w_t")
        .draw()
        .map_err(drawing)?;
    for (i, p) in d.profiles.iter().enumerate() {
        let c = palette(i);
        let v = if compliant { &p.compliant } else { &p.rigid };
        chart
            .draw_series(LineSeries::new(d.s.iter().copied().zip(v.iter().copied()), c.stroke_width(2)))
            .map_err(drawing)?
            .label(format!("N = {}", p.modes))
            .legend(solid_key(c.stroke_width(2)));
    }
    draw_legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
    Ok(())
}

/// The main table: per k and observable, both limits with their uncertainties and orders.
pub fn table(d: &MatchingData) -> String {
    let header = [
        "$k/k_1$ · observable",
        "Galerkin limit ± GCI",
        "order in $N$",
        "element limit ± GCI",
        "order in $n$",
        "agree",
    ];
    let order = |p: Option<f64>| p.map_or("—".to_string(), |p| format!("{p:.2}"));
    let rows: Vec<Vec<String>> = d
        .stiffness
        .iter()
        .flat_map(|a| {
            a.observables.iter().map(move |c| {
                vec![
                    format!("{} · {}", cell(a.k_over_k1, 2), c.name),
                    format!("{:.10} ± {:.1e}", c.galerkin.limit, c.galerkin.uncertainty),
                    order(c.galerkin.order),
                    format!("{:.10} ± {:.1e}", c.elements.limit, c.elements.uncertainty),
                    order(c.elements.order),
                    if c.agree { "yes" } else { "no" }.to_string(),
                ]
            })
        })
        .collect();
    markdown_table(&header, &rows)
}

/// N* per k and tolerance, with the observable that needs most and the criterion.
pub fn needed_table(d: &MatchingData) -> String {
    let mut header = vec!["$k/k_1$".to_string()];
    header.extend(d.params.tolerances.iter().map(|t| format!("$N^*$ for {t:.0e}")));
    header.push("hardest observable (1e-3)".to_string());
    header.push("$N$ with $(\\beta_N)^3 = k$".to_string());
    let header: Vec<&str> = header.iter().map(|s| s.as_str()).collect();
    let rows: Vec<Vec<String>> = d
        .stiffness
        .iter()
        .map(|a| {
            let mut r = vec![cell(a.k_over_k1, 2)];
            r.extend(a.needed.iter().map(|n| n.1.to_string()));
            r.push(a.needed.iter().find(|n| n.0 == 1e-3).map_or(String::new(), |n| n.2.clone()));
            r.push(a.criterion.to_string());
            r
        })
        .collect();
    markdown_table(&header, &rows)
}
