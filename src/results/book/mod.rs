//! `cantilever book`: regenerate every scene into `book/src/generated/NAME/`, write the
//! verdict summary of the landing page (`generated/summary.md`), and build the HTML book
//! with mdBook, in-process (feature `book`).
//!
//! Math is written in the chapters as `$…$` and `$$…$$` and converted here to MathML
//! (pulldown-latex), which browsers render natively; the vendored stylesheet and Latin
//! Modern Math font in `book/assets/math/` make it look right offline. No page loads
//! anything from a CDN.

mod math;
mod numbers;
pub mod reuse;
mod worked;

pub use math::{convert_math, latex_to_mathml, MathPreprocessor};
pub use numbers::NumbersPreprocessor;
pub use reuse::SceneNumbers;

use crate::base::provenance::Provenance;
use crate::results::scene::{self, Entry, Progress, Resolution, SceneOutput};
use anyhow::{bail, Context, Result};
use mdbook_driver::MDBook;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

/// The examples of `examples/`, shown by the library chapter.
const EXAMPLES: [(&str, &str); 3] = [
    (
        "find_orbit.rs",
        include_str!("../../../examples/find_orbit.rs"),
    ),
    (
        "custom_model.rs",
        include_str!("../../../examples/custom_model.rs"),
    ),
    (
        "rigid_impact.rs",
        include_str!("../../../examples/rigid_impact.rs"),
    ),
];

/// How long a build took and what it reused, for the command line to report (the library
/// prints nothing).
#[derive(Debug, Clone)]
pub struct BuildReport {
    /// Each computed scene's wall time (s), in the book's order.
    pub scene_seconds: Vec<(String, f64)>,
    /// Scenes whose previous output was current and reused, with the date it was computed.
    pub reused: Vec<(String, String)>,
    /// Scenes not asked for but recomputed, with the reason their previous output was not
    /// current.
    pub refreshed: Vec<(String, String)>,
    /// mdBook's own time (s).
    pub book_seconds: f64,
    /// The whole build (s).
    pub total_seconds: f64,
    /// The book's entry page.
    pub index: std::path::PathBuf,
}

/// Regenerates every scene (in parallel) at `resolution` and builds the book at `root`.
/// The book uses [`Resolution::Book`]; the test suite builds it at [`Resolution::Test`]
/// to check the pipeline without the full sweeps.
pub fn build(root: &Path, resolution: Resolution, progress: &dyn Progress) -> Result<BuildReport> {
    build_only(root, resolution, None, progress)
}

/// [`build`], recomputing only the scenes named in `only` (all when `None`): every other
/// scene's previous output in `generated/` is reused when it is current (same fingerprint
/// and resolution, see [`reuse`]) and recomputed otherwise, so the book never mixes numbers
/// of code that has since changed. Unknown names are an error.
pub fn build_only(
    root: &Path,
    resolution: Resolution,
    only: Option<&[String]>,
    progress: &dyn Progress,
) -> Result<BuildReport> {
    if !root.join("book.toml").exists() {
        bail!(
            "no book.toml in '{}': run from the repository root or pass --book-dir",
            root.display()
        );
    }
    let started = Instant::now();
    let generated = root.join("src").join("generated");
    let scenes = crate::results::scenes::all();
    if let Some(names) = only {
        for name in names {
            crate::results::scenes::find(name)?;
        }
    }
    // what each scene's page will use: a current previous output, or a fresh run
    let mut reused = Vec::new();
    let mut refreshed = Vec::new();
    let plan: Vec<Option<SceneNumbers>> = scenes
        .iter()
        .map(|spec| {
            let asked = only.is_none_or(|n| n.iter().any(|x| x == spec.name()));
            if asked {
                return None;
            }
            match reuse::previous(*spec, &generated.join(spec.name()), resolution) {
                Ok(prev) => {
                    reused.push((spec.name().to_string(), prev.provenance.date.clone()));
                    Some(prev)
                }
                Err(why) => {
                    refreshed.push((spec.name().to_string(), why));
                    None
                }
            }
        })
        .collect();
    let fresh = scenes
        .iter()
        .zip(&plan)
        .filter(|(_, p)| p.is_none())
        .count();
    let task = progress.task("scenes", fresh as u64);
    let run_one = |spec: &&dyn Entry| -> Result<(SceneOutput, f64)> {
        let t = Instant::now();
        let out = spec
            .run(resolution, progress)
            .with_context(|| format!("scene {}", spec.name()))?;
        scene::write(*spec, &out, &generated.join(spec.name()))?;
        task.advance(1);
        Ok((out, t.elapsed().as_secs_f64()))
    };
    // scenes that time themselves run alone, after the others (both cores otherwise)
    let todo = |spec: &&dyn Entry, p: &Option<SceneNumbers>| p.is_none() && !spec.timed();
    let mut runs: Vec<Option<Result<(SceneOutput, f64)>>> = scenes
        .par_iter()
        .zip(&plan)
        .map(|(spec, p)| todo(spec, p).then(|| run_one(spec)))
        .collect();
    for ((spec, run), p) in scenes.iter().zip(runs.iter_mut()).zip(&plan) {
        if p.is_none() && spec.timed() {
            *run = Some(run_one(spec));
        }
    }
    drop(task);
    let mut numbers = Vec::new();
    let mut scene_seconds = Vec::new();
    let mut fig4 = None;
    for ((spec, run), p) in scenes.iter().zip(runs).zip(plan) {
        match (run, p) {
            (Some(run), _) => {
                let (out, secs) = run?;
                scene_seconds.push((spec.name().to_string(), secs));
                numbers.push(SceneNumbers::from(&out));
            }
            (None, Some(prev)) => numbers.push(prev),
            (None, None) => bail!("scene {} was neither run nor reused", spec.name()),
        }
        if spec.name() == "fig4" {
            fig4 = numbers.last().cloned();
        }
    }
    let fig4 = fig4.context("the registry has no fig4 scene")?;
    // the library chapter shows the examples as compiled with this build (the tests run
    // them, tests/api.rs)
    let examples = generated.join("examples");
    std::fs::create_dir_all(&examples)
        .with_context(|| format!("creating {}", examples.display()))?;
    for (name, source) in EXAMPLES {
        scene::write_atomically(&examples.join(name), source)?;
    }
    worked::write(
        &generated.join(worked::DIR),
        &fig4,
        &scene_seconds,
        resolution,
        progress,
    )?;
    scene::write_atomically(
        &generated.join("summary.md"),
        &summary_table(scenes, &numbers, &|chapter| chapter_title(root, chapter)),
    )?;
    let provenance = numbers
        .first()
        .map(|o| o.provenance.clone())
        .unwrap_or_else(|| Provenance::now("book"));
    scene::write_atomically(&generated.join("citation.md"), &citation(&provenance))?;
    let t = Instant::now();
    let numbers_pre = NumbersPreprocessor {
        numbers: scenes
            .iter()
            .zip(&numbers)
            .map(|(spec, n)| (spec.name().to_string(), n.key_numbers.clone()))
            .collect(),
        verdicts: scenes
            .iter()
            .zip(&numbers)
            .map(|(spec, n)| (spec.name().to_string(), n.verdict.clone()))
            .collect(),
        provenances: scenes
            .iter()
            .zip(&numbers)
            .map(|(spec, n)| (spec.name().to_string(), n.provenance.clone()))
            .collect(),
        data_sizes: scenes
            .iter()
            .filter_map(|spec| {
                let path = generated.join(spec.name()).join("data.json");
                let bytes = std::fs::metadata(path).ok()?.len();
                Some((spec.name().to_string(), bytes))
            })
            .collect(),
        chapters: scenes.iter().fold(HashMap::new(), |mut m, spec| {
            m.entry(spec.chapter().to_string())
                .or_insert_with(Vec::new)
                .push(spec.name().to_string());
            m
        }),
        provenance,
    };
    let mut book = MDBook::load(root).context("loading the book")?;
    book.with_preprocessor(numbers_pre);
    book.with_preprocessor(MathPreprocessor);
    book.build().context("building the book")?;
    // The stylesheet refers to its fonts by relative path; mdBook copies only the CSS.
    copy_dir(
        &root.join("assets/math/font"),
        &root.join("build/assets/math/font"),
    )?;
    Ok(BuildReport {
        scene_seconds,
        reused,
        refreshed,
        book_seconds: t.elapsed().as_secs_f64(),
        total_seconds: started.elapsed().as_secs_f64(),
        index: root.join("build").join("index.html"),
    })
}

/// The landing page's summary: for each result, its verdict, the paper's claim, our
/// headline numbers with their uncertainties, the evidence, and links to the chapter and the
/// data. One block per result (a table this wide would hide columns).
pub fn summary_table(
    scenes: &[&dyn Entry],
    outputs: &[SceneNumbers],
    title: &dyn Fn(&str) -> Option<String>,
) -> String {
    let mut s = String::new();
    for (spec, out) in scenes.iter().zip(outputs) {
        let numbers: Vec<String> = spec
            .headline()
            .iter()
            .filter_map(|(label, key)| {
                out.key_numbers
                    .get(key)
                    .map(|v| format!("{label}: {}", for_html(&v.prose(true))))
            })
            .collect();
        let name = spec.name();
        s.push_str(&format!(
            "<div class=\"result\">\n\n**[{}]({})** — **{}**\n\n\
             *The paper:* {}\n\n*Our numbers:* {}.\n\n*Evidence:* {}.\n\n\
             Data: [data.json](generated/{name}/data.json) · \
             [key numbers](generated/{name}/key_numbers.json)\n\n</div>\n\n",
            title(spec.chapter()).unwrap_or_else(|| spec.paper().to_string()),
            spec.chapter(),
            capitalised(&out.verdict.outcome.to_string()),
            spec.claim(),
            numbers.join("; "),
            out.verdict.evidence
        ));
    }
    s
}

/// The first heading of chapter file `chapter` under `root/src`.
fn chapter_title(root: &Path, chapter: &str) -> Option<String> {
    let text = std::fs::read_to_string(root.join("src").join(chapter)).ok()?;
    text.lines()
        .find_map(|l| l.strip_prefix("# "))
        .map(|t| t.trim().to_string())
}

/// "partly reproduced" → "Partly reproduced".
fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// A file size for a link: "640 kB", "15.5 MB".
fn human_size(bytes: u64) -> String {
    if bytes < 1_000_000 {
        format!("{} kB", bytes.div_ceil(1000))
    } else {
        format!("{:.1} MB", bytes as f64 / 1e6)
    }
}

/// A key number's prose for a page: the unit's subscript as HTML (`A_free` would show its
/// underscore).
fn for_html(prose: &str) -> String {
    prose.replace("A_free", "A<sub>free</sub>")
}

/// How to cite the software that built this book, and the paper (plain text and BibTeX).
pub fn citation(provenance: &Provenance) -> String {
    use crate::results::citation as c;
    format!(
        "**The software** (this build):\n\n> {}\n\n```bibtex\n{}\n```\n\n\
         **The paper:**\n\n> {}\n\n```bibtex\n{}\n```\n",
        c::software_plain(provenance),
        c::software_bibtex(provenance),
        c::PAPER_PLAIN.replace(
            "doi:10.1098/rsta.2012.0434",
            "[doi:10.1098/rsta.2012.0434](https://doi.org/10.1098/rsta.2012.0434)"
        ),
        c::PAPER_BIBTEX
    )
}

fn copy_dir(from: &Path, to: &Path) -> Result<()> {
    std::fs::create_dir_all(to).with_context(|| format!("creating {}", to.display()))?;
    for entry in std::fs::read_dir(from).with_context(|| format!("reading {}", from.display()))? {
        let entry = entry?;
        std::fs::copy(entry.path(), to.join(entry.file_name()))
            .with_context(|| format!("copying {}", entry.path().display()))?;
    }
    Ok(())
}
