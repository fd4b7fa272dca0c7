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

pub use math::{convert_math, latex_to_mathml, MathPreprocessor};
pub use numbers::NumbersPreprocessor;

use crate::provenance::Provenance;
use crate::scene::{self, Entry, Progress, Resolution, SceneOutput};
use anyhow::{bail, Context, Result};
use mdbook_driver::MDBook;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

/// How long a build took, for the command line to report (the library prints nothing).
#[derive(Debug, Clone)]
pub struct BuildReport {
    /// Each scene's wall time (s), in the book's order.
    pub scene_seconds: Vec<(String, f64)>,
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
    if !root.join("book.toml").exists() {
        bail!(
            "no book.toml in '{}': run from the repository root or pass --book-dir",
            root.display()
        );
    }
    let started = Instant::now();
    let generated = root.join("src").join("generated");
    let scenes = crate::scenes::all();
    let task = progress.task("scenes", scenes.len() as u64);
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
    let mut runs: Vec<Option<Result<(SceneOutput, f64)>>> = scenes
        .par_iter()
        .map(|spec| (!spec.timed()).then(|| run_one(spec)))
        .collect();
    for (spec, run) in scenes.iter().zip(runs.iter_mut()) {
        if spec.timed() {
            *run = Some(run_one(spec));
        }
    }
    let runs: Vec<Result<(SceneOutput, f64)>> = runs.into_iter().flatten().collect();
    drop(task);
    let mut outputs = Vec::new();
    let mut scene_seconds = Vec::new();
    for (spec, run) in scenes.iter().zip(runs) {
        let (out, secs) = run?;
        scene_seconds.push((spec.name().to_string(), secs));
        outputs.push(out);
    }
    scene::write_atomically(
        &generated.join("summary.md"),
        &summary_table(scenes, &outputs, &|chapter| chapter_title(root, chapter)),
    )?;
    let provenance = outputs
        .first()
        .map(|o| o.provenance.clone())
        .unwrap_or_else(|| Provenance::now("book"));
    scene::write_atomically(&generated.join("citation.md"), &citation(&provenance))?;
    let t = Instant::now();
    let numbers = NumbersPreprocessor {
        numbers: scenes
            .iter()
            .zip(&outputs)
            .map(|(spec, out)| (spec.name().to_string(), out.key_numbers.clone()))
            .collect(),
        verdicts: scenes
            .iter()
            .zip(&outputs)
            .map(|(spec, out)| (spec.name().to_string(), out.verdict.clone()))
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
    book.with_preprocessor(numbers);
    book.with_preprocessor(MathPreprocessor);
    book.build().context("building the book")?;
    // The stylesheet refers to its fonts by relative path; mdBook copies only the CSS.
    copy_dir(
        &root.join("assets/math/font"),
        &root.join("build/assets/math/font"),
    )?;
    Ok(BuildReport {
        scene_seconds,
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
    outputs: &[SceneOutput],
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
    use crate::citation as c;
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
