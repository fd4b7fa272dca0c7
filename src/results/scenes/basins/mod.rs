//! Scene `basins`: beyond the paper — which start reaches which of the stable orbits that
//! coexist in one cell of the atlas ([`crate::analysis::atlas::basins`]): the beam released
//! in its first mode with a tip displacement and velocity from a grid, each start run with
//! the atlas's own search, and the orbit it settles on recognised.

pub mod render;

use crate::analysis::atlas::basins::{self, BasinData, BasinParams};
use crate::analysis::atlas::Attractor;
use crate::base::report::{pretty, KeyNumbers};
use crate::error::Error;
use crate::results::scene::{Group, Outcome, Progress, Rendered, Resolution, Scene, Verdict};

/// The scene.
pub struct Basins;

/// An orbit's label.
pub fn label(a: &Attractor) -> String {
    format!("({},{})", a.period_m, a.impacts_n)
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
            Resolution::Book => BasinParams::book(),
            Resolution::Test => BasinParams::test(),
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
                // not ending in "= <number>": the snapshot's reader would split the key there
                "k/k₁ = {}, ω/(β₁⁻)² = {:.3}, {} modes",
                pretty(d.k_over_k1, 3),
                d.omega_over_w1,
                d.params.modes
            ),
        );
        k.integer("starts", (d.params.points * d.params.points) as i64);
        k.integer("orbits reached", d.orbits.len() as i64);
        let (per, none) = d.counts();
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
        k.text("orbit from rest", d.from_rest().map_or("none".into(), label));
        k
    }

    fn verdict(d: &BasinData) -> Verdict {
        let (per, none) = d.counts();
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
            extra_tables: vec![],
            ..Rendered::drawn(|layout| render::plot(d, layout), render::table(d))?
        })
    }
}
