//! The atlas plot: four maps over (ω, k) — contacts per forcing period, period, stable
//! orbits found, spectral radius — each with its key below; and two tables.

use crate::results::narrow::Layout;
use super::{cells, label, rest_labels};
use crate::analysis::atlas::{AtlasData, Cell};
use crate::analysis::motion::MotionClass;
use crate::results::render::{
    cell, drawing, markdown_table, omega_log_k_mesh, viridis, RenderError, LABEL_FONT,
};
use plotters::prelude::*;

/// No stable orbit of period ≤ max_m (from rest, or at all).
const NONE: RGBColor = RGBColor(190, 190, 190);

/// Height of a panel's key strip (its lines wrap at the panel's width).
fn key_height(layout: Layout) -> u32 {
    match layout {
        Layout::Wide => 160,
        Layout::Narrow => 250,
    }
}

/// One map: a caption, the colour of a cell, the key, and whether the boundary curves are
/// drawn over it.
struct Panel {
    caption: &'static str,
    color: fn(&Cell) -> RGBColor,
    key: Vec<(RGBColor, String)>,
    curves: bool,
}

/// How a boundary curve of each kind is drawn: colour and whether dashed.
fn curve_style(kind: &str) -> (RGBColor, bool) {
    match kind {
        "grazing" => (BLACK, false),
        "period doubling" => (RGBColor(200, 0, 0), false),
        "fold" => (BLACK, true),
        _ => (RGBColor(200, 0, 0), true),
    }
}

/// Contacts per forcing period n/m, in six classes (a sequential scale, ColorBrewer
/// YlGnBu).
fn taps_color(c: &Cell) -> RGBColor {
    const C: [RGBColor; 6] = [
        RGBColor(255, 255, 204),
        RGBColor(199, 233, 180),
        RGBColor(127, 205, 187),
        RGBColor(65, 182, 196),
        RGBColor(44, 127, 184),
        RGBColor(37, 52, 148),
    ];
    let Some(a) = c.rest() else { return NONE };
    let (n, m) = (a.impacts_n, a.period_m as usize);
    C[if n < m {
        0
    } else if n == m {
        1
    } else if n < 2 * m {
        2
    } else if n < 3 * m {
        3
    } else if n < 5 * m {
        4
    } else {
        5
    }]
}

/// Where rest reaches no stable orbit of period ≤ max_m: the motion's class (periodic after
/// all: sky blue, the Wong palette's; quasi-periodic: grey; chaotic: near-black;
/// undecided: Wong's yellow).
fn motion_color(c: &Cell) -> RGBColor {
    match c.motion.as_ref().map(|m| m.class) {
        Some(MotionClass::Periodic) => RGBColor(86, 180, 233),
        Some(MotionClass::QuasiPeriodic) | None => NONE,
        Some(MotionClass::Chaotic) => RGBColor(40, 40, 40),
        Some(MotionClass::Undecided) => RGBColor(240, 228, 66),
    }
}

/// The period m (Wong's colour-blind-safe palette), or the class of the motion.
fn period_color(c: &Cell) -> RGBColor {
    match c.rest().map(|a| a.period_m) {
        None => motion_color(c),
        Some(1) => RGBColor(0, 114, 178),
        Some(2) => RGBColor(230, 159, 0),
        Some(3) => RGBColor(0, 158, 115),
        Some(4) => RGBColor(204, 121, 167),
        Some(_) => RGBColor(213, 94, 0),
    }
}

/// The number of distinct stable orbits found (ColorBrewer Blues).
fn count_color(c: &Cell) -> RGBColor {
    match c.attractors.len() {
        0 => NONE,
        1 => RGBColor(222, 235, 247),
        2 => RGBColor(107, 174, 214),
        3 => RGBColor(33, 113, 181),
        _ => RGBColor(8, 48, 107),
    }
}

/// The spectral radius of the orbit from rest, in five classes of width 0.2 (so that runs
/// of cells merge into one rectangle and the plot stays small).
fn radius_color(c: &Cell) -> RGBColor {
    match c.rest() {
        None => NONE,
        Some(a) => viridis(((a.spectral_radius * 5.0).floor().min(4.0) + 0.5) / 5.0),
    }
}

fn panels() -> [Panel; 4] {
    let s = |t: &str| t.to_string();
    [
        Panel {
            caption: "(a) contacts per forcing period n/m, from rest",
            color: taps_color,
            key: vec![
                (RGBColor(255, 255, 204), s("< 1")),
                (RGBColor(199, 233, 180), s("1")),
                (RGBColor(127, 205, 187), s("(1, 2)")),
                (RGBColor(65, 182, 196), s("[2, 3)")),
                (RGBColor(44, 127, 184), s("[3, 5)")),
                (RGBColor(37, 52, 148), s("≥ 5")),
                (NONE, s("no orbit of period ≤ 8")),
            ],
            curves: true,
        },
        Panel {
            caption: "(b) period m (forcing periods), or the motion, from rest",
            color: period_color,
            key: vec![
                (RGBColor(0, 114, 178), s("1")),
                (RGBColor(230, 159, 0), s("2")),
                (RGBColor(0, 158, 115), s("3")),
                (RGBColor(204, 121, 167), s("4")),
                (RGBColor(213, 94, 0), s("5–8")),
                (RGBColor(86, 180, 233), s("periodic, found later")),
                (NONE, s("quasi-periodic")),
                (RGBColor(40, 40, 40), s("chaotic")),
                (RGBColor(240, 228, 66), s("undecided")),
            ],
            curves: true,
        },
        Panel {
            caption: "(c) coexisting stable orbits found",
            color: count_color,
            key: vec![
                (RGBColor(222, 235, 247), s("1")),
                (RGBColor(107, 174, 214), s("2")),
                (RGBColor(33, 113, 181), s("3")),
                (RGBColor(8, 48, 107), s("≥ 4")),
                (NONE, s("none of period ≤ 8")),
            ],
            curves: false,
        },
        Panel {
            caption: "(d) largest |Floquet multiplier|, from rest",
            color: radius_color,
            key: (0..5)
                .map(|i| {
                    let r = 0.2 * i as f64;
                    (viridis(r + 0.1), format!("[{r:.1}, {:.1})", r + 0.2))
                })
                .chain(std::iter::once((NONE, s("none"))))
                .collect(),
            curves: false,
        },
    ]
}

/// The SVG plot.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn plot(d: &AtlasData, layout: Layout) -> Result<String, RenderError> {
    let p = &d.params;
    let key_height = key_height(layout);
    // four maps of 500 × 430 px, each with its key below
    let size = match layout {
        Layout::Wide => layout.grid_size(2, 2, 2 * (430 + key_height)),
        Layout::Narrow => (
            layout.width(),
            4 * (layout.panel_height(500, 430) + key_height),
        ),
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        let areas = layout.cells(&root, 2, 2);
        let ks: Vec<f64> = d.rows.iter().map(|r| r.k_over_k1.log10()).collect();
        let half = |v: &[f64]| {
            if v.len() < 2 {
                0.5
            } else {
                0.5 * (v[v.len() - 1] - v[0]) / (v.len() - 1) as f64
            }
        };
        let (dw, dl) = (half(&d.omega_over_w1), half(&ks));
        let (w0, w1) = (p.omega_range.0 - dw, p.omega_range.1 + dw);
        let (l0, l1) = (ks[0] - dl, ks[ks.len() - 1] + dl);
        for (area, panel) in areas.iter().zip(panels()) {
            let (map, key) = area.split_vertically(area.dim_in_pixel().1 - key_height);
            let mut chart = ChartBuilder::on(&map)
                .caption(panel.caption, ("sans-serif", 20))
                .margin(6)
                .margin_right(16)
                .x_label_area_size(44)
                .y_label_area_size(64)
                .build_cartesian_2d(w0..w1, l0..l1)
                .map_err(drawing)?;
            omega_log_k_mesh(&mut chart, (l0, l1), 6)?;
            // runs of equal colour along a row are one rectangle each
            for (row, &l) in d.rows.iter().zip(&ks) {
                let mut j = 0;
                while j < row.cells.len() {
                    let color = (panel.color)(&row.cells[j]);
                    let mut end = j + 1;
                    while end < row.cells.len() && (panel.color)(&row.cells[end]) == color {
                        end += 1;
                    }
                    // overlapping the next run and row a little, so that anti-aliasing
                    // leaves no hairline seams between them
                    let corners = [
                        (d.omega_over_w1[j] - dw, l - dl),
                        (
                            (d.omega_over_w1[end - 1] + 1.8 * dw).min(w1),
                            (l + 1.8 * dl).min(l1),
                        ),
                    ];
                    chart
                        .draw_series(std::iter::once(Rectangle::new(corners, color.filled())))
                        .map_err(drawing)?;
                    j = end;
                }
            }
            // where N = 10 stops meeting the stiffness-matching criterion: a dashed line
            // between the last row that needs at most 10 modes and the next
            if let Some(i) = d.rows.iter().rposition(|r| r.modes <= 10) {
                if i + 1 < d.rows.len() {
                    let y = 0.5 * (ks[i] + ks[i + 1]);
                    chart
                        .draw_series(DashedLineSeries::new(
                            vec![(w0, y), (w1, y)],
                            6,
                            4,
                            BLACK.stroke_width(2),
                        ))
                        .map_err(drawing)?;
                    // no label on the map (it would cover cells): the caption names the line
                }
            }
            let mut lines: Vec<(RGBColor, bool, String)> = Vec::new();
            if let Some(c) = d.curves.as_ref().filter(|_| panel.curves) {
                for cv in &c.curves {
                    let (color, dashed) = curve_style(&cv.kind);
                    let pts: Vec<(f64, f64)> =
                        cv.points.iter().map(|&(w, k)| (w, k.log10())).collect();
                    let style = color.stroke_width(2);
                    if dashed {
                        chart
                            .draw_series(DashedLineSeries::new(pts, 5, 4, style))
                            .map_err(drawing)?;
                    } else {
                        chart.draw_series(LineSeries::new(pts, style)).map_err(drawing)?;
                    }
                    if !lines.iter().any(|l| l.2 == cv.kind) {
                        lines.push((color, dashed, cv.kind.clone()));
                    }
                }
            }
            draw_key(&key, &panel.key, &lines)?;
        }
        root.present().map_err(drawing)?;
    }
    Ok(svg)
}

/// A key of coloured boxes and labels, then line samples and labels, wrapped into lines.
fn draw_key<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    items: &[(RGBColor, String)],
    lines: &[(RGBColor, bool, String)],
) -> Result<(), RenderError> {
    let width = area.dim_in_pixel().0 as i32;
    let (mut x, mut y) = (70, 8);
    for (color, dashed, text) in lines.iter().map(|l| (l.0, l.1, format!("{} curve", l.2))) {
        let w = 36 + 9 * text.chars().count() as i32 + 14;
        if x + w > width {
            x = 70;
            y += 30;
        }
        let style = color.stroke_width(3);
        let segments: Vec<(i32, i32)> = if dashed {
            vec![(x, x + 8), (x + 14, x + 22), (x + 28, x + 30)]
        } else {
            vec![(x, x + 30)]
        };
        for (a, b) in segments {
            area.draw(&PathElement::new(vec![(a, y + 10), (b, y + 10)], style))
                .map_err(drawing)?;
        }
        area.draw(&Text::new(text.clone(), (x + 36, y + 2), LABEL_FONT))
            .map_err(drawing)?;
        x += w;
    }
    if !lines.is_empty() {
        x = 70;
        y += 30;
    }
    for (color, text) in items {
        // 18 px sans-serif: about 9 px per character
        let w = 28 + 9 * text.chars().count() as i32 + 14;
        if x + w > width {
            x = 70;
            y += 30;
        }
        area.draw(&Rectangle::new([(x, y), (x + 20, y + 20)], color.filled()))
            .map_err(drawing)?;
        area.draw(&Rectangle::new([(x, y), (x + 20, y + 20)], BLACK.mix(0.5)))
            .map_err(drawing)?;
        area.draw(&Text::new(text.clone(), (x + 28, y + 2), LABEL_FONT))
            .map_err(drawing)?;
        x += w;
    }
    Ok(())
}

/// The orbits from rest by (m, n): how many cells, and where.
pub fn labels_table(d: &AtlasData) -> String {
    let all = cells(d).count().max(1);
    let labels = rest_labels(d);
    let shown = 14;
    let mut rows: Vec<Vec<String>> = labels
        .iter()
        .take(shown)
        .map(|&(l, n)| {
            let at: Vec<(f64, f64)> = d
                .rows
                .iter()
                .flat_map(|r| {
                    r.cells.iter().zip(&d.omega_over_w1).filter_map(move |(c, &w)| {
                        (c.rest().map(|a| (a.period_m, a.impacts_n)) == l)
                            .then_some((r.k_over_k1, w))
                    })
                })
                .collect();
            let (k0, k1) = at.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
            let (w0, w1) = at.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
            vec![
                label(l),
                n.to_string(),
                format!("{:.1}%", 100.0 * n as f64 / all as f64),
                format!("{}–{}", cell(k0, 2), cell(k1, 2)),
                format!("{w0:.2}–{w1:.2}"),
            ]
        })
        .collect();
    if labels.len() > shown {
        let rest: usize = labels[shown..].iter().map(|l| l.1).sum();
        rows.push(vec![
            format!("{} others", labels.len() - shown),
            rest.to_string(),
            format!("{:.1}%", 100.0 * rest as f64 / all as f64),
            String::new(),
            String::new(),
        ]);
    }
    markdown_table(
        &["orbit (m,n) from rest", "cells", "share", "$k/k_1$ from–to", "$\\omega/(\\beta_1^-)^2$ from–to"],
        &rows,
    )
}

/// Per decade of k: the share of cells that tap more than once per period, drum-roll
/// (n/m ≥ 2), with coexisting orbits, and with no stable orbit from rest.
pub fn decades_table(d: &AtlasData) -> String {
    let (lo, hi) = d.params.k_over_k1_range;
    let decades = (hi / lo).log10().ceil().max(1.0) as usize;
    let rows: Vec<Vec<String>> = (0..decades)
        .map(|i| {
            let (a, b) = (lo * 10f64.powi(i as i32), lo * 10f64.powi(i as i32 + 1));
            let last = i + 1 == decades;
            let cs: Vec<&Cell> = d
                .rows
                .iter()
                .filter(|r| r.k_over_k1 >= a * (1.0 - 1e-12) && (r.k_over_k1 < b * (1.0 - 1e-12) || last))
                .flat_map(|r| r.cells.iter())
                .collect();
            let share = |f: &dyn Fn(&Cell) -> bool| {
                let n = cs.iter().filter(|c| f(c)).count();
                format!("{:.0}%", 100.0 * n as f64 / cs.len().max(1) as f64)
            };
            vec![
                format!("{}–{}{}", cell(a, 2), cell(b, 2), if last { "" } else { " (excl.)" }),
                cs.len().to_string(),
                share(&|c| c.rest().is_some_and(|x| x.impacts_n > x.period_m as usize)),
                share(&|c| c.rest().is_some_and(|x| x.impacts_n >= 2 * x.period_m as usize)),
                share(&|c| c.attractors.len() > 1),
                share(&|c| c.from_rest.is_none()),
            ]
        })
        .collect();
    markdown_table(
        &["$k/k_1$", "cells", "n/m > 1", "n/m ≥ 2", "≥ 2 stable orbits", "none from rest"],
        &rows,
    )
}

/// The motions from rest of the cells that reach no stable orbit of period ≤ max_m, by class,
/// with the evidence of each class.
pub fn motions_table(d: &AtlasData) -> String {
    let counts = super::motion_counts(d);
    let all: usize = counts.iter().map(|c| c.1).sum();
    let rows: Vec<Vec<String>> = counts
        .iter()
        .map(|&(class, n)| {
            let [lambda, widths, extra] = super::motion_evidence_parts(d, class)
                .unwrap_or_else(|| ["—".into(), "—".into(), String::new()]);
            vec![
                class.words().to_string(),
                n.to_string(),
                format!("{:.0}%", 100.0 * n as f64 / all.max(1) as f64),
                lambda,
                widths,
                if extra.is_empty() { "—".into() } else { extra },
            ]
        })
        .collect();
    markdown_table(
        &[
            "motion from rest",
            "cells",
            "share",
            "λ₁ per unit time",
            "its 95 % half-widths",
            "further evidence",
        ],
        &rows,
    )
}
