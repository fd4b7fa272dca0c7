//! Plot markers told apart by shape as well as colour (a reader of a grey print, or one who
//! does not tell red from green, still tells a fold from a period doubling).

use plotters::element::{Drawable, PointCollection};
use plotters::style::ShapeStyle;
use plotters_backend::{BackendCoord, DrawingBackend, DrawingErrorKind};

/// The shapes, each one bifurcation kind in every plot of the book.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shape {
    /// Fold (saddle-node).
    Triangle,
    /// Period doubling.
    Square,
    /// Neimark–Sacker.
    Diamond,
    /// Grazing.
    Circle,
    /// Branch point.
    Cross,
}

/// A marker of `shape`, `size` pixels from its centre to its corners, drawn at `at`.
pub struct Marker<C> {
    at: C,
    shape: Shape,
    size: i32,
    style: ShapeStyle,
}

impl<C> Marker<C> {
    /// The marker; `style` sets its outline (or its fill, if filled).
    pub fn new(at: C, shape: Shape, size: i32, style: ShapeStyle) -> Self {
        Self {
            at,
            shape,
            size,
            style,
        }
    }
}

/// The outline of `shape` around the origin, in pixels, as a closed path.
fn outline(shape: Shape, s: i32) -> Vec<(i32, i32)> {
    match shape {
        Shape::Triangle => vec![(0, -s), (s, s * 4 / 5), (-s, s * 4 / 5), (0, -s)],
        Shape::Square => {
            let h = s * 4 / 5;
            vec![(-h, -h), (h, -h), (h, h), (-h, h), (-h, -h)]
        }
        Shape::Diamond => vec![(0, -s), (s, 0), (0, s), (-s, 0), (0, -s)],
        Shape::Circle => (0..=16)
            .map(|i| {
                let a = std::f64::consts::TAU * f64::from(i) / 16.0;
                let r = f64::from(s) * 0.85;
                ((r * a.cos()).round() as i32, (r * a.sin()).round() as i32)
            })
            .collect(),
        // both strokes of an ×, the path retracing through the centre
        Shape::Cross => vec![(-s, -s), (s, s), (0, 0), (s, -s), (-s, s)],
    }
}

impl<'a, C> PointCollection<'a, C> for &'a Marker<C> {
    type Point = &'a C;
    type IntoIter = std::iter::Once<&'a C>;
    fn point_iter(self) -> Self::IntoIter {
        std::iter::once(&self.at)
    }
}

impl<C, DB: DrawingBackend> Drawable<DB> for Marker<C> {
    fn draw<I: Iterator<Item = BackendCoord>>(
        &self,
        mut pos: I,
        backend: &mut DB,
        _: (u32, u32),
    ) -> Result<(), DrawingErrorKind<DB::ErrorType>> {
        let Some((x, y)) = pos.next() else {
            return Ok(());
        };
        let path = outline(self.shape, self.size)
            .into_iter()
            .map(|(dx, dy)| (x + dx, y + dy));
        if self.style.filled && self.shape != Shape::Cross {
            backend.fill_polygon(path, &self.style)
        } else {
            backend.draw_path(path, &self.style)
        }
    }
}
