//! Multi-panel plots for narrow screens: the same drawing with its panels stacked in one
//! column, so that a phone shows every panel at a readable size instead of a sideways
//! scroller with panels off screen. Each panel is a view of the one drawing (an SVG `<use>`
//! of it inside a viewport cut to the panel's rectangle), so nothing is drawn twice and the
//! two layouts cannot disagree.

/// A panel's rectangle in the plot's pixels: x, y, width, height.
pub type Panel = [u32; 4];

/// The rectangle of a drawing area (a panel of its plot).
#[cfg(feature = "plots")]
pub fn panel<DB: plotters::prelude::DrawingBackend>(
    area: &plotters::prelude::DrawingArea<DB, plotters::coord::Shift>,
) -> Panel {
    let (x, y) = area.get_pixel_range();
    let size = |r: &std::ops::Range<i32>| u32::try_from(r.end - r.start).unwrap_or(0);
    let start = |r: &std::ops::Range<i32>| u32::try_from(r.start).unwrap_or(0);
    [start(&x), start(&y), size(&x), size(&y)]
}

/// `svg` with `panels` stacked in one column as wide as the narrowest panel (a wider panel
/// is scaled to it), in their order; None for fewer than two panels or an SVG without its
/// root element.
pub fn stacked(svg: &str, panels: &[Panel]) -> Option<String> {
    if panels.len() < 2 || panels.iter().any(|p| p[2] == 0 || p[3] == 0) {
        return None;
    }
    let root = svg.find("<svg")?;
    let body_start = root + svg[root..].find('>')? + 1;
    let body = &svg[body_start..svg.rfind("</svg>")?];
    let width = panels.iter().map(|p| p[2]).min()?;
    let mut views = String::new();
    let mut y = 0.0;
    for &[px, py, pw, ph] in panels {
        let height = f64::from(ph) * f64::from(width) / f64::from(pw);
        views.push_str(&format!(
            "<svg x=\"0\" y=\"{y:.1}\" width=\"{width}\" height=\"{height:.1}\" \
             viewBox=\"{px} {py} {pw} {ph}\"><use href=\"#plot\"/></svg>\n"
        ));
        y += height;
    }
    Some(format!(
        "<svg width=\"{width}\" height=\"{y:.0}\" viewBox=\"0 0 {width} {y:.1}\" \
         xmlns=\"http://www.w3.org/2000/svg\">\n<defs><g id=\"plot\">{body}</g></defs>\n{views}</svg>\n"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn panels_are_views_of_one_drawing_stacked_at_the_narrowest_width() {
        let svg = "<svg width=\"1000\" height=\"400\" viewBox=\"0 0 1000 400\" \
                   xmlns=\"http://www.w3.org/2000/svg\"><rect x=\"1\"/></svg>";
        let narrow = stacked(
            svg,
            &[[0, 0, 500, 200], [500, 0, 500, 200], [0, 200, 1000, 200]],
        )
        .unwrap();
        assert!(
            narrow.starts_with("<svg width=\"500\" height=\"500\""),
            "{narrow}"
        );
        assert_eq!(narrow.matches("<rect x=\"1\"/>").count(), 1, "drawn once");
        assert!(
            narrow.contains("y=\"200.0\" width=\"500\" height=\"200.0\" viewBox=\"500 0 500 200\"")
        );
        // the full-width panel scaled to the column: half its height
        assert!(narrow
            .contains("y=\"400.0\" width=\"500\" height=\"100.0\" viewBox=\"0 200 1000 200\""));
        assert!(stacked(svg, &[[0, 0, 500, 200]]).is_none());
        assert!(stacked("no svg", &[[0, 0, 1, 1], [1, 0, 1, 1]]).is_none());
    }
}
