//! The system of the paper's Figure 1, drawn by the library: a uniform cantilever clamped
//! at s = 0, its tip at s = 1 a gap d₀ from a point stop of stiffness k/4 (§2, eq (1)),
//! under the distributed forcing of eq (37). The deflected beam is the first free mode
//! φ₁(s) ([`crate::model::continuum::free_mode`]), scaled so that the tip just reaches
//! the stop.

use crate::model::continuum;
use crate::results::render::{drawing, RenderError};
use plotters::element::DashedPathElement;
use plotters::prelude::*;

/// Labels: large, as the drawing is shown at the text's width (and on a phone at a third).
const BIG: (&str, u32) = ("sans-serif", 30);

/// Canvas size in pixels.
const SIZE: (u32, u32) = (1000, 440);

/// The schematic as SVG text.
///
/// # Errors
/// [`RenderError`] when drawing fails.
pub fn svg() -> Result<String, RenderError> {
    let mut out = String::new();
    {
        let root = SVGBackend::with_string(&mut out, SIZE).into_drawing_area();
        root.fill(&WHITE).map_err(drawing)?;
        draw(&root)?;
        root.present().map_err(drawing)?;
    }
    Ok(out)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
) -> Result<(), RenderError> {
    let (x0, x1, y0) = (140.0, 800.0, 150.0);
    // the tip deflects down by the gap (px) and meets the stop's face
    let gap = 90.0;
    let mode = continuum::free_mode(1).map_err(|e| RenderError(e.to_string()))?;
    let tip = mode.value(1.0);
    let at = |s: f64| -> (i32, i32) {
        let w = gap * mode.value(s) / tip;
        ((x0 + s * (x1 - x0)) as i32, (y0 + w) as i32)
    };
    let text = |s: &str, x: f64, y: f64, font: (&str, u32)| -> Result<(), RenderError> {
        root.draw(&Text::new(
            s.to_string(),
            (x as i32, y as i32),
            font.into_font(),
        ))
        .map_err(drawing)
    };
    let thick = BLACK.stroke_width(5);
    let thin = BLACK.stroke_width(2);
    let grey = RGBColor(120, 120, 120).stroke_width(2);
    // the clamp: a hatched wall at s = 0
    root.draw(&Rectangle::new(
        [
            (x0 as i32 - 30, y0 as i32 - 70),
            (x0 as i32, y0 as i32 + 70),
        ],
        RGBColor(225, 225, 225).filled(),
    ))
    .map_err(drawing)?;
    // seven strokes, each inside the wall (the eighth would run below it)
    for i in 0..7 {
        let y = y0 - 70.0 + 20.0 * i as f64;
        root.draw(&PathElement::new(
            vec![(x0 as i32 - 30, (y + 18.0) as i32), (x0 as i32, y as i32)],
            grey,
        ))
        .map_err(drawing)?;
    }
    root.draw(&PathElement::new(
        vec![(x0 as i32, y0 as i32 - 70), (x0 as i32, y0 as i32 + 70)],
        thin,
    ))
    .map_err(drawing)?;
    // the undeflected beam (dashed) and the deflected one, w(s, t) = φ₁(s)
    root.draw(&DashedPathElement::new(
        vec![(x0 as i32, y0 as i32), (x1 as i32, y0 as i32)],
        8,
        6,
        grey,
    ))
    .map_err(drawing)?;
    let beam: Vec<(i32, i32)> = (0..=100).map(|i| at(i as f64 / 100.0)).collect();
    root.draw(&PathElement::new(beam, thick)).map_err(drawing)?;
    // the distributed forcing, eq (37): arrows along the beam
    for i in 1..=6 {
        let s = i as f64 / 7.0;
        let (x, y) = at(s);
        let top = y - 60;
        root.draw(&PathElement::new(
            vec![(x, top), (x, y - 8)],
            RGBColor(0, 114, 178).stroke_width(2),
        ))
        .map_err(drawing)?;
        root.draw(&Polygon::new(
            vec![(x - 6, y - 18), (x + 6, y - 18), (x, y - 6)],
            RGBColor(0, 114, 178).filled(),
        ))
        .map_err(drawing)?;
    }
    text("forcing f(s) cos ωt (eq 37)", 280.0, 30.0, BIG)?;
    // the stop: a spring of stiffness k/4 below the tip, its face at the gap d₀
    let (tx, ty) = at(1.0);
    let face = ty + 4;
    root.draw(&PathElement::new(
        vec![(tx - 35, face), (tx + 35, face)],
        thick,
    ))
    .map_err(drawing)?;
    let mut spring = vec![(tx, face), (tx, face + 15)];
    for i in 0..8 {
        let dx = if i % 2 == 0 { 18 } else { -18 };
        spring.push((tx + dx, face + 22 + 11 * i));
    }
    spring.extend([(tx, face + 22 + 11 * 8), (tx, face + 125)]);
    root.draw(&PathElement::new(spring, thin))
        .map_err(drawing)?;
    root.draw(&Rectangle::new(
        [(tx - 40, face + 125), (tx + 40, face + 140)],
        RGBColor(225, 225, 225).filled(),
    ))
    .map_err(drawing)?;
    text(
        "stop, stiffness k/4",
        (tx - 330) as f64,
        (face + 50) as f64,
        BIG,
    )?;
    text(
        "(k → ∞: a rigid stop)",
        (tx - 330) as f64,
        (face + 84) as f64,
        BIG,
    )?;
    // the gap d₀ between the undeflected tip and the stop's face
    let gx = tx + 60;
    root.draw(&PathElement::new(vec![(gx, y0 as i32), (gx, face)], thin))
        .map_err(drawing)?;
    for (y, d) in [(y0 as i32, 1), (face, -1)] {
        root.draw(&Polygon::new(
            vec![(gx - 6, y + 10 * d), (gx + 6, y + 10 * d), (gx, y)],
            BLACK.filled(),
        ))
        .map_err(drawing)?;
    }
    text("gap d₀", (gx + 12) as f64, y0 + 35.0, BIG)?;
    // coordinates
    text("s = 0, clamped", x0 - 100.0, y0 + 85.0, BIG)?;
    text("s = 1, tip", (tx + 30) as f64, (face + 40) as f64, BIG)?;
    let (mx, my) = at(0.5);
    text("w(s, t)", mx as f64 - 30.0, my as f64 + 22.0, BIG)?;
    text(
        "Euler–Bernoulli cantilever, damped (§2)",
        x0 - 100.0,
        SIZE.1 as f64 - 40.0,
        BIG,
    )?;
    Ok(())
}
