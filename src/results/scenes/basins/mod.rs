//! Scene `basins`: beyond the paper — which start reaches which of the stable orbits that
//! coexist in one cell of the atlas ([`crate::analysis::atlas::basins`]): the beam released
//! in its first mode with a tip displacement and velocity from a grid, each start run with
//! the atlas's own search, and the orbit it settles on recognised.

pub mod render;

use crate::analysis::atlas::basins::{self, BasinData, BasinParams};
use crate::analysis::atlas::{AtlasParams, Attractor};
use crate::base::report::{pretty, KeyNumbers};
use crate::error::Error;
use crate::results::scene::{Group, Outcome, Progress, Rendered, Resolution, Scene, Verdict};

/// The scene.
pub struct Basins;

/// The book's cell: row 49 and column 106 of the book's atlas, k = 34.9k₁ and
/// ω = 2.587(β₁⁻)², where rest and one random start reach a (1,1) orbit and the other a
/// (2,2) orbit; its row uses N = 10.
pub fn book() -> BasinParams {
    BasinParams {
        atlas: AtlasParams::book(),
        cell: (49, 106),
        modes: 10,
        points: 81,
        extent: 4.0,
    }
}

/// The tests' resolution: the same cell, 11 × 11 starts.
pub fn test() -> BasinParams {
    BasinParams {
        points: 11,
        ..book()
    }
}

/// An orbit's label.
pub fn label(a: &Attractor) -> String {
    format!("({},{})", a.period_m, a.impacts_n)
}

/// Starts that reached each orbit, and those that reached none.
pub fn counts(d: &BasinData) -> (Vec<usize>, usize) {
    let mut per = vec![0; d.orbits.len()];
    let mut none = 0;
    for r in d.reached.iter().flatten() {
        match r {
            Some(i) => per[*i] += 1,
            None => none += 1,
        }
    }
    (per, none)
}

/// The orbit rest reaches (the centre start).
pub fn from_rest(d: &BasinData) -> Option<&Attractor> {
    let c = d.params.points / 2;
    d.reached[c][c].map(|i| &d.orbits[i])
}

impl Scene for Basins {
    const NAME: &'static str = "basins";
    const PAPER: &'static str = "beyond §5.3";
    const TITLE: &'static str = "Basins of attraction in one atlas cell";
    const GIST: &'static str = "— (coexistence not mapped)";
    const GROUP: Group = Group::Beyond;
    const SUMMARY: &'static str =
        "which start reaches which coexisting stable orbit, over a grid of tip displacements and velocities";
    const CLAIM: &'static str = "None: the paper finds coexisting orbits at single points (Figure 5's (1,1) and (3,3)), not which starts reach which.";
    const CHAPTER: &'static str = "basins.md";
    const METHOD: &'static str = "the beam released in its first mode shape with tip displacement d and velocity v on a square grid centred on rest (the other modes at rest); each start runs the atlas's search (300-period transient read in thirds, the period from the strobe, Newton shooting to 1e-12, kept if stable) and its orbit is recognised among those met (within 1e-6, up to a shift along the orbit)";
    const HEADLINE: &'static [(&'static str, &'static str)] = &[
        ("stable orbits reached", "orbits reached"),
        ("starts reaching each", "starts per orbit"),
    ];
    type Params = BasinParams;
    type Data = BasinData;

    fn params(resolution: Resolution) -> BasinParams {
        match resolution {
            Resolution::Book => book(),
            Resolution::Test => test(),
        }
    }

    fn compute(p: &BasinParams, progress: &dyn Progress) -> Result<BasinData, Error> {
        basins::basins(p, progress)
    }

    fn key_numbers(d: &BasinData) -> KeyNumbers {
        // counts of starts: exact integers of the computed grid
        let mut k = KeyNumbers::default();
        k.text(
            "cell",
            format!(
                "k/k₁ = {}, ω/(β₁⁻)² = {:.3}, N = {}",
                pretty(d.k_over_k1, 3),
                d.omega_over_w1,
                d.params.modes
            ),
        );
        k.integer("starts", (d.params.points * d.params.points) as i64);
        k.integer("orbits reached", d.orbits.len() as i64);
        let (per, none) = counts(d);
        let total = (d.params.points * d.params.points).max(1) as f64;
        k.text(
            "starts per orbit",
            d.orbits
                .iter()
                .zip(&per)
                .map(|(a, n)| format!("{} {n} ({:.0} %)", label(a), 100.0 * *n as f64 / total))
                .collect::<Vec<_>>()
                .join(", "),
        );
        k.integer("starts reaching no orbit", none as i64);
        k.text("orbit from rest", from_rest(d).map_or("none".into(), label));
        k
    }

    fn verdict(d: &BasinData) -> Verdict {
        let (per, none) = counts(d);
        let total = d.params.points * d.params.points;
        Verdict {
            outcome: Outcome::Extension,
            evidence: format!(
                "of {total} starts at k/k₁ = {}, ω/(β₁⁻)² = {:.3}, {}; {none} reach no stable orbit of period ≤ {} within the transient",
                pretty(d.k_over_k1, 3),
                d.omega_over_w1,
                d.orbits
                    .iter()
                    .zip(&per)
                    .map(|(a, n)| format!("{n} reach the {} orbit", label(a)))
                    .collect::<Vec<_>>()
                    .join(", "),
                d.params.atlas.max_period
            ),
        }
    }

    fn render(d: &BasinData) -> Result<Rendered, crate::results::render::RenderError> {
        Ok(Rendered {
            svg: render::plot(d)?,
            table: render::table(d),
            extra_tables: vec![],
        })
    }
}
