//! `cantilever book`: regenerate every scene into `book/src/generated/NAME/`, write the
//! verdict summary of the landing page (`generated/summary.md`), and build the HTML book
//! with mdBook, in-process (feature `book`).
//!
//! Math is written in the chapters as `$…$` and `$$…$$` and converted here to MathML
//! (pulldown-latex), which browsers render natively; the vendored stylesheet and Latin
//! Modern Math font in `book/assets/math/` make it look right offline. No page loads
//! anything from a CDN.

mod build_dir;
mod math;
mod numbers;
pub mod python;
pub mod reuse;
mod worked;

pub use math::{convert_math, latex_to_mathml, MathPreprocessor};
pub use numbers::NumbersPreprocessor;
pub use reuse::SceneNumbers;

use crate::base::provenance::Provenance;
use crate::results::scene::{self, Entry, Outcome, Progress, Resolution, SceneOutput};
use anyhow::{bail, Context, Result};
use mdbook_driver::MDBook;
use rayon::prelude::*;
use std::collections::HashMap;
use std::path::Path;
use std::time::Instant;

/// The examples of `examples/`, shown by the library chapter.
const EXAMPLES: [(&str, &str); 4] = [
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
    (
        "use_cases.rs",
        include_str!("../../../examples/use_cases.rs"),
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
    /// Where the chapter *From Python* took its outputs from.
    pub python: python::Source,
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
///
/// # Errors
/// As [`build_only`].
pub fn build(root: &Path, resolution: Resolution, progress: &dyn Progress) -> Result<BuildReport> {
    build_only(root, resolution, None, progress)
}

/// [`build`], recomputing only the scenes named in `only` (all when `None`): every other
/// scene's previous output in `generated/` is reused when it is current (same fingerprint
/// and resolution, see [`reuse`]) and recomputed otherwise, so the book never mixes numbers
/// of code that has since changed. Unknown names are an error.
///
/// # Errors
/// No `book.toml` in `root`, an unknown scene in `only`, a scene that fails to compute or be
/// written, a generated file that cannot be written, or mdBook failing to load or build.
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
    // the old pages may be replaced only if they are the program's (checked before the work)
    build_dir::recover(root);
    build_dir::check(&root.join("build"))?;
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
    // a scene's folder must hold only the program's own files of its set's names (an older
    // build's folder, without a manifest, is refused before the work, with the way out)
    for (spec, p) in scenes.iter().zip(&plan) {
        if p.is_none() {
            let dir = generated.join(spec.name());
            crate::results::output_set::check_set(
                "the book's generated folder",
                &dir,
                &crate::results::output_set::SCENE_FILES,
            )
            .with_context(|| {
                format!(
                    "{} was not written by this version (delete it, or all of {}, and build \
                     again)",
                    dir.display(),
                    generated.display()
                )
            })?;
        }
    }
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
    let seconds = worked::write(
        &generated.join(worked::DIR),
        &fig4,
        &scene_seconds,
        resolution,
        progress,
    )?;
    scene::write_atomically(
        &generated.join("summary.md"),
        &summary_table(scenes, &numbers),
    )?;
    scene::write_atomically(
        &generated.join("glance.md"),
        &glance_table(scenes, &numbers),
    )?;
    let provenance = numbers
        .first()
        .map(|o| o.provenance.clone())
        .unwrap_or_else(|| Provenance::now("book"));
    // run alone, after the scenes: its table measures times
    let python = python::write(root, &generated, &Provenance::now("book"), progress)?;
    scene::write_atomically(&generated.join("citation.md"), &citation(&provenance))?;
    scene::write_atomically(&generated.join("cite-example.md"), &cite_example())?;
    let schematic = crate::results::schematic::svg().map_err(|e| anyhow::anyhow!("{e}"))?;
    scene::write_atomically(&generated.join("schematic.svg"), &schematic)?;
    let t = Instant::now();
    let numbers_pre = NumbersPreprocessor {
        seconds: seconds.into_iter().collect(),
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
        narrow: scenes
            .iter()
            .filter(|spec| {
                let path = generated.join(spec.name()).join(scene::NARROW_PLOT);
                path.is_file()
            })
            .map(|spec| spec.name().to_string())
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
    // mdBook empties its build folder first: built beside it and swapped in whole, so an
    // interrupted build leaves the previous book, not a few pages of the new one
    let pid = std::process::id();
    // absolute: mdBook takes a relative build folder relative to the book's root, where a
    // relative `root` ("book", the main job's) would put the pages in book/book/… and swap
    // in a folder holding only the fonts
    let root = &std::fs::canonicalize(root)
        .with_context(|| format!("finding the book at {}", root.display()))?;
    let fresh = root.join(format!(".build.cantilever-{pid}.tmp"));
    let old = root.join(format!(".build.cantilever-{pid}.old"));
    let _ = std::fs::remove_dir_all(&fresh);
    crate::results::files::register(&fresh);
    book.config.build.build_dir = fresh.clone();
    let built = book.build().context("building the book").and_then(|()| {
        // the stylesheet refers to its fonts by relative path; mdBook copies only the CSS
        copy_dir(
            &root.join("assets/math/font"),
            &fresh.join("assets/math/font"),
        )?;
        copy_sources(&root.join("src"), &fresh.join(SOURCES))?;
        build_dir::write_manifest(&fresh)
    });
    if let Err(e) = built {
        let _ = std::fs::remove_dir_all(&fresh);
        crate::results::files::unregister(&fresh);
        return Err(e);
    }
    let target = root.join("build");
    {
        let _writing = crate::results::files::writing();
        // a user's files in the old pages go on in the new ones
        if let Err(e) = build_dir::carry_over(&target, &fresh) {
            let _ = std::fs::remove_dir_all(&fresh);
            crate::results::files::unregister(&fresh);
            return Err(e);
        }
        if target.exists() {
            std::fs::rename(&target, &old).context("moving the previous book aside")?;
            crate::results::files::register_aside(&old, Some(&target));
        }
        std::fs::rename(&fresh, &target).context("putting the new book in place")?;
        crate::results::files::unregister(&fresh);
        let _ = std::fs::remove_dir_all(&old);
        crate::results::files::unregister(&old);
    }
    Ok(BuildReport {
        scene_seconds,
        reused,
        refreshed,
        python,
        book_seconds: t.elapsed().as_secs_f64(),
        total_seconds: started.elapsed().as_secs_f64(),
        index: root.join("build").join("index.html"),
    })
}

/// The landing page's table, one screen: per group (the paper's results, beyond the paper,
/// validation, methods), each result's title linked to its chapter, the paper's claim in a
/// few words, the verdict as a coloured badge and the first headline number with its
/// uncertainty.
pub fn glance_table(scenes: &[&dyn Entry], outputs: &[SceneNumbers]) -> String {
    let mut rows: Vec<(&&dyn Entry, &SceneNumbers)> = scenes.iter().zip(outputs).collect();
    rows.sort_by_key(|(spec, _)| spec.group());
    let mut s = String::from(
        "<table class=\"glance\">\n<thead><tr><th>Result</th><th>The paper says</th>\
         <th>Verdict</th><th>Our number</th></tr></thead>\n<tbody>\n",
    );
    let mut group = None;
    for (spec, out) in rows {
        if group != Some(spec.group()) {
            group = Some(spec.group());
            s.push_str(&format!(
                "<tr class=\"group\"><th colspan=\"4\">{}</th></tr>\n",
                spec.group()
            ));
        }
        let headline = spec
            .headline()
            .iter()
            .find_map(|(label, key)| {
                let v = out.key_numbers.get(key)?;
                Some(for_html(&format!("{label}: {}", v.prose(true))))
            })
            .unwrap_or_else(|| "—".into());
        let outcome = out.verdict.outcome;
        s.push_str(&format!(
            "<tr><td><a href=\"{}\">{}</a></td><td>{}</td><td><span class=\"badge {}\">{}</span></td><td>{}</td></tr>\n",
            spec.chapter().replace(".md", ".html"),
            for_html(spec.title()),
            for_html(spec.gist()),
            badge_class(outcome),
            badge_text(outcome),
            headline
        ));
    }
    s.push_str("</tbody>\n</table>\n");
    s
}

/// The badge's colour class.
fn badge_class(o: Outcome) -> &'static str {
    match o {
        Outcome::Reproduced => "yes",
        Outcome::Partly | Outcome::PartlyConsistent => "partly",
        Outcome::NotReproduced | Outcome::Inconsistent => "no",
        Outcome::NoClaim | Outcome::Extension => "none",
    }
}

/// The badge's words (short: the table must fit one screen).
fn badge_text(o: Outcome) -> &'static str {
    match o {
        Outcome::Reproduced => "reproduced",
        Outcome::Partly => "partly",
        Outcome::NotReproduced => "not reproduced",
        Outcome::NoClaim => "method check",
        Outcome::Extension => "beyond",
        Outcome::PartlyConsistent => "partly consistent",
        Outcome::Inconsistent => "inconsistent",
    }
}

/// The landing page's detail: for each result, its verdict, the paper's claim, our
/// headline numbers with their uncertainties, the evidence, and links to the chapter and the
/// data. One block per result (a table this wide would hide columns).
pub fn summary_table(scenes: &[&dyn Entry], outputs: &[SceneNumbers]) -> String {
    let mut s = String::new();
    for (spec, out) in scenes.iter().zip(outputs) {
        let numbers: Vec<String> = spec
            .headline()
            .iter()
            .filter_map(|(label, key)| {
                out.key_numbers
                    .get(key)
                    .map(|v| for_html(&format!("{label}: {}", v.prose(true))))
            })
            .collect();
        let name = spec.name();
        s.push_str(&format!(
            "<div class=\"result\">\n\n**[{}]({})** — **{}**\n\n\
             *The paper:* {}\n\n*Our numbers:* {}.\n\n*Evidence:* {}.\n\n\
             Data: [data.json](generated/{name}/data.json) · \
             [numbers with uncertainties](generated/{name}/key_numbers.json)\n\n</div>\n\n",
            for_html(spec.title()),
            spec.chapter(),
            capitalised(&out.verdict.outcome.to_string()),
            for_html(spec.claim()),
            numbers.join("; "),
            capitalised(&for_html(&out.verdict.evidence))
        ));
    }
    s
}

pub(crate) use crate::results::names::capitalised;

/// A file size for a link: "640 kB", "15.5 MB".
fn human_size(bytes: u64) -> String {
    if bytes < 1_000_000 {
        format!("{} kB", bytes.div_ceil(1000))
    } else {
        format!("{:.1} MB", bytes as f64 / 1e6)
    }
}

pub use crate::results::render::readable_text as for_html;

/// What `cantilever cite fig4 "N=3 impact_velocity_1"` prints first: the sentence to
/// paste, from the numbers published with this build (empty if they do not parse).
fn cite_example() -> String {
    let Ok(spec) = crate::results::scenes::find("fig4") else {
        return String::new();
    };
    let key = "N=3 impact_velocity_1";
    match crate::results::cite::Citation::published(spec, Some(key)) {
        Ok(c) => {
            let text = c.to_text();
            let sentence = text.lines().next().unwrap_or_default();
            format!("```text\n{sentence}\n```\n")
        }
        Err(_) => String::new(),
    }
}

/// How to cite the software that built this book, and the paper (plain text and BibTeX).
pub fn citation(provenance: &Provenance) -> String {
    use crate::results::citation as c;
    format!(
        "**The software** (this build):\n\n> {}\n\n```bibtex\n{}\n```\n\n{}\n\n\
         **The paper:**\n\n> {}\n\n```bibtex\n{}\n```\n",
        c::software_plain(provenance),
        c::software_bibtex(provenance),
        c::archive_statement(),
        c::PAPER_PLAIN.replace(
            "doi:10.1098/rsta.2012.0434",
            "[doi:10.1098/rsta.2012.0434](https://doi.org/10.1098/rsta.2012.0434)"
        ),
        c::PAPER_BIBTEX
    )
}

/// The folder of the built book that holds each chapter's source, linked from its footer.
pub const SOURCES: &str = "source";

/// Each chapter's Markdown source (`src/NAME.md`, with its number placeholders) as
/// `NAME.txt`, which every browser shows as text (not `NAME.md.txt`: mdBook would rewrite
/// a link to it as one to `NAME.html`): the "view the source of this page" link (there is
/// no public repository to link to yet).
fn copy_sources(src: &Path, to: &Path) -> Result<()> {
    std::fs::create_dir_all(to).with_context(|| format!("creating {}", to.display()))?;
    for entry in std::fs::read_dir(src).with_context(|| format!("reading {}", src.display()))? {
        let path = entry?.path();
        let name = path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        if path.is_file() && name.ends_with(".md") && name != "SUMMARY.md" {
            let text = format!("{}.txt", name.trim_end_matches(".md"));
            std::fs::copy(&path, to.join(text))
                .with_context(|| format!("copying {}", path.display()))?;
        }
    }
    Ok(())
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

#[cfg(test)]
mod html_tests {
    use super::for_html;

    #[test]
    fn sentences_are_capitalised_and_symbols_are_not() {
        use super::capitalised;
        assert_eq!(capitalised("partly reproduced"), "Partly reproduced");
        assert_eq!(capitalised("a (1,1) orbit"), "A (1,1) orbit");
        assert_eq!(capitalised("r<sub>E</sub> ranges"), "r<sub>E</sub> ranges");
        assert_eq!(capitalised("k/k₁ = 1459–1931"), "k/k₁ = 1459–1931");
        assert_eq!(capitalised("ω = 2"), "ω = 2");
        assert_eq!(capitalised("d₀ = 0"), "d₀ = 0");
        assert_eq!(capitalised(""), "");
    }

    #[test]
    fn subscripts_become_html_and_identifiers_stay() {
        assert_eq!(for_html("r_E = 0.72"), "r<sub>E</sub> = 0.72");
        assert_eq!(for_html("2 ωA_free"), "2 ωA<sub>free</sub>");
        assert_eq!(for_html("(β_N⁺)³ ≫ k"), "(β<sub>N</sub>⁺)³ ≫ k");
        assert_eq!(for_html("[R]_N"), "[R]<sub>N</sub>");
        assert_eq!(for_html("impact_velocity_1"), "impact_velocity_1");
        assert_eq!(for_html("`r_E` r_E"), "`r_E` r<sub>E</sub>");
        assert_eq!(for_html("$k_2/k_1$ r_E"), "$k_2/k_1$ r<sub>E</sub>");
        assert_eq!(for_html("a_"), "a_");
    }
}
