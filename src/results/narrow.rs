//! Plots for narrow screens. Every scene's plot is drawn twice by the same renderer: in the
//! book's wide layout ([`Layout::Wide`], panels side by side, 1000 px) and in one column
//! for phones ([`Layout::Narrow`], panels stacked, 430 px). The narrow drawing keeps the
//! font sizes of the wide one in a drawing less than half as wide, so on a 390 px phone
//! (a column of about 335 px) its smallest text is drawn at 14.5 × 335/430 ≈ 11.3 px, where
//! the wide plot scaled to the column would be 4.9 px and, in a sideways scroller at
//! 680 px, would leave its right-hand panels off screen. `book/check/phones.sh` measures
//! both in a built book.

use crate::results::render::WIDTH;

/// The narrow layout's width in pixels: the fonts' 14.5 px drawn at ≥ 11 px in a 335 px
/// column.
pub const NARROW_WIDTH: u32 = 430;

/// The layout a plot is drawn in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Layout {
    /// The book's: [`WIDTH`] wide, panels side by side.
    Wide,
    /// For narrow screens: [`NARROW_WIDTH`] wide, one panel per row.
    Narrow,
}

impl Layout {
    /// The drawing's width.
    pub fn width(self) -> u32 {
        match self {
            Layout::Wide => WIDTH,
            Layout::Narrow => NARROW_WIDTH,
        }
    }

    /// The height of a panel that is `w × h` px in the wide layout: the same when wide;
    /// when narrow, as tall as its aspect asks at the narrow width, but not flatter than
    /// `min(h, ¾ of the narrow width)` (a wide strip keeps a readable height).
    pub fn panel_height(self, w: u32, h: u32) -> u32 {
        match self {
            Layout::Wide => h,
            Layout::Narrow if w == 0 => h,
            Layout::Narrow => {
                let scaled = u64::from(h) * u64::from(NARROW_WIDTH) / u64::from(w.max(1));
                let scaled = u32::try_from(scaled).unwrap_or(h);
                scaled.max(h.min(NARROW_WIDTH * 3 / 4))
            }
        }
    }

    /// The size of a drawing that is a grid of `rows × columns` equal panels on a wide
    /// canvas `WIDTH × height`: that canvas when wide; when narrow, the panels in one
    /// column.
    pub fn grid_size(self, rows: usize, columns: usize, height: u32) -> (u32, u32) {
        match self {
            Layout::Wide => (WIDTH, height),
            Layout::Narrow => {
                let (r, c) = (count(rows), count(columns));
                let panel = self.panel_height(WIDTH / c, height / r);
                (NARROW_WIDTH, panel * r * c)
            }
        }
    }

    /// The cells of a `rows × columns` grid on `area`, in reading order (row by row): side
    /// by side when wide, one per row when narrow.
    #[cfg(feature = "plots")]
    pub fn cells<DB: plotters::prelude::DrawingBackend>(
        self,
        area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
        rows: usize,
        columns: usize,
    ) -> Vec<plotters::prelude::DrawingArea<DB, plotters::coord::Shift>> {
        match self {
            Layout::Wide => area.split_evenly((rows, columns)),
            Layout::Narrow => area.split_evenly((rows * columns, 1)),
        }
    }

    /// Two panels that sit side by side when wide (the first `at` px of the width) and one
    /// above the other when narrow (the first `first` px of the height).
    #[cfg(feature = "plots")]
    pub fn beside<DB: plotters::prelude::DrawingBackend>(
        self,
        area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
        at: u32,
        first: u32,
    ) -> (
        plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
        plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
    ) {
        match self {
            Layout::Wide => area.split_horizontally(at),
            Layout::Narrow => area.split_vertically(first),
        }
    }
}

/// A count of rows or columns as pixels' factor (at least 1).
fn count(n: usize) -> u32 {
    u32::try_from(n.max(1)).unwrap_or(u32::MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_narrow_grid_stacks_its_panels_at_their_aspect() {
        assert_eq!(Layout::Wide.grid_size(2, 2, 900), (1000, 900));
        // 500 × 450 panels: 430 × 387 each, four in a column
        assert_eq!(Layout::Narrow.grid_size(2, 2, 900), (430, 4 * 387));
        // a full-width strip 1000 × 300 keeps 300 px (its aspect would give 129)
        assert_eq!(Layout::Narrow.panel_height(1000, 300), 300);
        // a tall strip keeps its aspect
        assert_eq!(Layout::Narrow.panel_height(500, 1000), 860);
        assert_eq!(Layout::Narrow.panel_height(0, 100), 100);
    }

    #[test]
    fn text_of_the_narrow_layout_reads_at_11_px_on_a_phone() {
        // the smallest font as drawn (LABEL_FONT 18 in plotters' SVG: 14.516 px) in the
        // column of a 390 px screen (335 px, measured by book/check/phones.sh)
        let smallest = 18.0 * 0.806_451_6 * 335.0 / f64::from(NARROW_WIDTH);
        assert!(smallest >= 11.0, "{smallest}");
    }
}
