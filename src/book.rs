//! `cantilever book`: regenerate every scene into `book/src/generated/NAME/`, write the
//! verdict summary of the landing page (`generated/summary.md`), and build the HTML book
//! with mdBook, in-process (feature `book`).
//!
//! Math is written in the chapters as `$…$` and `$$…$$` and converted here to MathML
//! (pulldown-latex), which browsers render natively; the vendored stylesheet and Latin
//! Modern Math font in `book/assets/math/` make it look right offline. No page loads
//! anything from a CDN.

use crate::provenance::Provenance;
use crate::report::{pretty, KeyNumbers, KeyValue};
use crate::scene::{self, Entry, Progress, Resolution, SceneOutput};
use anyhow::{bail, Context, Result};
use mdbook_driver::MDBook;
use mdbook_preprocessor::book::{Book, BookItem};
use mdbook_preprocessor::{Preprocessor, PreprocessorContext};
use pulldown_latex::config::DisplayMode;
use pulldown_latex::{push_mathml, Parser, RenderConfig, Storage};
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

/// Puts generated numbers into the prose, and a provenance footer under every page.
///
/// In a chapter, `{{n SCENE/KEY}}` becomes the key number's value (to its significant
/// figures), `{{pm SCENE/KEY}}` the value ± its uncertainty with its unit, and
/// `{{u SCENE/KEY}}` the uncertainty alone, `{{verdict SCENE}}` the result's verdict
/// ("**Partly reproduced.**") and `{{evidence SCENE}}` its evidence in one line. An unknown scene or key fails the build.
pub struct NumbersPreprocessor {
    /// Key numbers by scene.
    pub numbers: HashMap<String, KeyNumbers>,
    /// Verdicts by scene.
    pub verdicts: HashMap<String, crate::scene::Verdict>,
    /// The size of each scene's `data.json` in bytes (for the links under its chapter).
    pub data_sizes: HashMap<String, u64>,
    /// Scene by chapter file.
    pub chapters: HashMap<String, Vec<String>>,
    /// Where the numbers come from.
    pub provenance: Provenance,
}

impl NumbersPreprocessor {
    fn lookup(&self, reference: &str) -> Result<&KeyValue> {
        let (scene, key) = reference
            .split_once('/')
            .ok_or_else(|| anyhow::anyhow!("`{reference}`: write SCENE/KEY"))?;
        let numbers = self
            .numbers
            .get(scene.trim())
            .ok_or_else(|| anyhow::anyhow!("unknown scene `{scene}` in `{reference}`"))?;
        numbers
            .get(key.trim())
            .ok_or_else(|| anyhow::anyhow!("unknown key `{key}` of scene `{scene}`"))
    }

    /// Replaces every reference in `text`.
    pub fn expand(&self, text: &str) -> Result<String> {
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(start) = rest.find("{{") {
            let tail = &rest[start + 2..];
            let Some((kind, after)) = ["n ", "pm ", "u ", "verdict ", "evidence "]
                .iter()
                .find_map(|k| tail.strip_prefix(k).map(|a| (k.trim(), a)))
            else {
                out.push_str(&rest[..start + 2]);
                rest = tail;
                continue;
            };
            let end = after
                .find("}}")
                .ok_or_else(|| anyhow::anyhow!("unclosed {{{{{kind} …"))?;
            out.push_str(&rest[..start]);
            if kind == "verdict" || kind == "evidence" {
                let scene = after[..end].trim();
                let verdict = self
                    .verdicts
                    .get(scene)
                    .ok_or_else(|| anyhow::anyhow!("unknown scene `{scene}` in a {kind}"))?;
                out.push_str(&if kind == "verdict" {
                    format!("**{}.**", capitalised(&verdict.outcome.to_string()))
                } else {
                    verdict.evidence.clone()
                });
                rest = &after[end + 2..];
                continue;
            }
            let value = self.lookup(&after[..end])?;
            out.push_str(&match (kind, value) {
                ("u", KeyValue::Float(c)) => pretty(c.uncertainty.value, 1),
                ("pm", v) => for_html(&v.prose(true)),
                (_, v) => v.prose(false),
            });
            rest = &after[end + 2..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// The footer of a page: provenance, and the data of its scene if it has one.
    pub fn footer(&self, chapter: &str) -> String {
        let mut s = format!(
            "\n\n---\n\n<div class=\"provenance\">\n\nNumbers on this page were generated by {}.",
            self.provenance.line()
        );
        for scene in self.chapters.get(chapter).into_iter().flatten() {
            let size = self
                .data_sizes
                .get(scene)
                .map(|b| format!(" ({})", human_size(*b)))
                .unwrap_or_default();
            s.push_str(&format!(
                " Data of `{scene}`: [data.json](generated/{scene}/data.json){size} · [key numbers \
                 with their uncertainties](generated/{scene}/key_numbers.json) · \
                 `cantilever cite {scene}`."
            ));
        }
        s.push_str("\n\n</div>\n");
        s
    }
}

impl Preprocessor for NumbersPreprocessor {
    fn name(&self) -> &str {
        "numbers"
    }

    fn run(
        &self,
        _: &PreprocessorContext,
        mut book: Book,
    ) -> mdbook_preprocessor::errors::Result<Book> {
        let mut failure = None;
        book.for_each_mut(|item| {
            if let BookItem::Chapter(ch) = item {
                let file = ch
                    .path
                    .as_ref()
                    .and_then(|p| p.file_name())
                    .map(|f| f.to_string_lossy().into_owned())
                    .unwrap_or_default();
                match self.expand(&ch.content) {
                    Ok(c) => ch.content = c + &self.footer(&file),
                    Err(e) => {
                        failure.get_or_insert(anyhow::anyhow!("chapter '{}': {e}", ch.name));
                    }
                }
            }
        });
        match failure {
            Some(e) => Err(e),
            None => Ok(book),
        }
    }
}

/// Converts `$…$` (inline) and `$$…$$` (display) to MathML, outside code.
pub struct MathPreprocessor;

impl Preprocessor for MathPreprocessor {
    fn name(&self) -> &str {
        "mathml"
    }

    fn run(
        &self,
        _: &PreprocessorContext,
        mut book: Book,
    ) -> mdbook_preprocessor::errors::Result<Book> {
        let mut failure = None;
        book.for_each_mut(|item| {
            if let BookItem::Chapter(ch) = item {
                match convert_math(&ch.content) {
                    Ok(c) => ch.content = c,
                    Err(e) => {
                        failure.get_or_insert(anyhow::anyhow!("chapter '{}': {e}", ch.name));
                    }
                }
            }
        });
        match failure {
            Some(e) => Err(e),
            None => Ok(book),
        }
    }
}

/// One LaTeX fragment to MathML; parse errors are errors (the book must not ship them).
pub fn latex_to_mathml(tex: &str, display: bool) -> Result<String> {
    let storage = Storage::new();
    let events: Vec<_> = Parser::new(tex, &storage).collect();
    if let Some(Err(e)) = events.iter().find(|e| e.is_err()) {
        bail!("cannot parse LaTeX `{tex}`: {e}");
    }
    let config = RenderConfig {
        display_mode: if display {
            DisplayMode::Block
        } else {
            DisplayMode::Inline
        },
        ..Default::default()
    };
    let mut out = String::new();
    push_mathml(&mut out, events.into_iter(), config)?;
    // The MathML sits inside markdown: hide characters markdown would act on, and repair
    // pulldown-latex 0.8's `stretchy="true"minsize=…` (no space between attributes after
    // \bigl and friends), which markdown would not recognise as a tag.
    let mut safe = String::with_capacity(out.len());
    let chars: Vec<char> = out.chars().collect();
    for (i, &c) in chars.iter().enumerate() {
        let closing_quote = c == '"' && i > 0 && chars[i - 1] != '=';
        if closing_quote && chars.get(i + 1).is_some_and(|n| n.is_ascii_alphabetic()) {
            safe.push_str("\" ");
            continue;
        }
        match c {
            '*' | '_' | '\\' | '`' | '[' | ']' | '$' | '~' | '|' | '\n' => {
                if c != '\n' {
                    safe.push_str(&format!("&#{};", c as u32));
                }
            }
            c => safe.push(c),
        }
    }
    Ok(safe)
}

/// Replaces math delimiters in markdown, leaving fenced code and inline code alone.
/// `\$` is a literal dollar sign. Math may continue across line breaks (prose is wrapped),
/// but not across a blank line.
pub fn convert_math(markdown: &str) -> Result<String> {
    let mut out = String::with_capacity(markdown.len());
    let mut in_fence = false;
    // open math: its text so far, and whether it is display math
    let mut open: Option<(String, bool)> = None;
    for line in markdown.split_inclusive('\n') {
        if open.is_none() && line.trim_start().starts_with("```") {
            in_fence = !in_fence;
            out.push_str(line);
            continue;
        }
        if in_fence {
            out.push_str(line);
            continue;
        }
        if let Some((buf, _)) = &open {
            if line.trim().is_empty() {
                bail!("math left open at a blank line: ${}", buf.trim());
            }
        }
        let mut rest = line;
        while !rest.is_empty() {
            if let Some((buf, display)) = open.as_mut() {
                let delimiter = if *display { "$$" } else { "$" };
                match rest.find(delimiter) {
                    Some(end) => {
                        buf.push_str(&rest[..end]);
                        let tex = buf.split_whitespace().collect::<Vec<_>>().join(" ");
                        out.push_str(&latex_to_mathml(&tex, *display)?);
                        rest = &rest[end + delimiter.len()..];
                        open = None;
                    }
                    None => {
                        buf.push_str(rest);
                        rest = "";
                    }
                }
                continue;
            }
            let Some(pos) = rest.find(['$', '`', '\\']) else {
                out.push_str(rest);
                break;
            };
            out.push_str(&rest[..pos]);
            let tail = &rest[pos..];
            if let Some(after) = tail.strip_prefix("\\$") {
                out.push('$');
                rest = after;
            } else if let Some(after) = tail.strip_prefix('\\') {
                out.push('\\');
                rest = after;
            } else if let Some(code) = tail.strip_prefix('`') {
                let end = code.find('`').map_or(tail.len(), |e| e + 2);
                out.push_str(&tail[..end]);
                rest = &tail[end..];
            } else if let Some(after) = tail.strip_prefix("$$") {
                open = Some((String::new(), true));
                rest = after;
            } else {
                open = Some((String::new(), false));
                rest = &tail[1..];
            }
        }
    }
    if let Some((buf, _)) = open {
        bail!("unclosed math at the end of the chapter: ${}", buf.trim());
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_expanded_by_name_and_unknown_names_fail() {
        let mut k = KeyNumbers::default();
        k.cited(
            "x",
            1.23456,
            4,
            crate::report::Uncertainty::new(3e-4, "t"),
            "T",
        );
        k.integer("n", 7);
        let p = NumbersPreprocessor {
            numbers: [("s".to_string(), k)].into_iter().collect(),
            verdicts: [(
                "s".to_string(),
                crate::scene::Verdict {
                    outcome: crate::scene::Outcome::Partly,
                    evidence: "e".into(),
                },
            )]
            .into_iter()
            .collect(),
            data_sizes: HashMap::new(),
            chapters: HashMap::new(),
            provenance: Provenance::now("test"),
        };
        assert_eq!(p.expand("a {{n s/x}} b").unwrap(), "a 1.235 b");
        assert_eq!(p.expand("{{pm s/x}}").unwrap(), "1.235 ± 3 × 10⁻⁴ T");
        assert_eq!(
            p.expand("{{n s/n}} {{#include x}}").unwrap(),
            "7 {{#include x}}"
        );
        assert_eq!(p.expand("{{verdict s}}").unwrap(), "**Partly reproduced.**");
        assert!(p.expand("{{verdict t}}").is_err());
        assert!(p.expand("{{n s/y}}").is_err());
        assert!(p.expand("{{n t/x}}").is_err());
        assert_eq!(pretty(3.6e-16, 2), "3.6 × 10⁻¹⁶");
        assert_eq!(pretty(1e-9, 1), "10⁻⁹");
    }

    #[test]
    fn math_becomes_mathml_and_code_is_left_alone() {
        let md = "Let $k_j = (\\beta_j^-)^4$ and `$x$`.\n```\n$y$\n```\n$$\nK^+ = K^- + k\\mathbf{1}\\mathbf{1}^T\n$$\nCost \\$5.\n";
        let html = convert_math(md).unwrap();
        assert!(html.contains("<math"));
        assert!(html.contains("display=\"block\""));
        assert!(html.contains("`$x$`"));
        assert!(html.contains("\n$y$\n"));
        assert!(html.contains("Cost $5."));
        assert!(!html.contains("k_j"));
    }

    #[test]
    fn delimiter_sizes_give_well_formed_attributes() {
        let html = latex_to_mathml("\\bigl(x\\bigr)", false).unwrap();
        assert!(
            !html.contains("\"minsize") && !html.contains("\"maxsize"),
            "{html}"
        );
    }

    #[test]
    fn bad_latex_is_an_error() {
        assert!(convert_math("$\\frac{1}$").is_err());
        assert!(convert_math("$x").is_err());
        assert!(convert_math("$x\n\ny$").is_err(), "not across paragraphs");
    }

    #[test]
    fn inline_math_may_wrap_across_lines() {
        let html = convert_math("a sum $g(s) = x +\n y$ here\n").unwrap();
        assert!(html.contains("<math") && html.contains(" here"));
    }
}
