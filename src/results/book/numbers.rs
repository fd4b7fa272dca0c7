//! Generated numbers in the prose (`{{n SCENE/KEY}}` and friends) and the provenance footer
//! of every page.

use super::{capitalised, for_html, human_size};
use crate::base::provenance::Provenance;
use crate::base::report::{pretty, KeyNumbers, KeyValue};
use anyhow::Result;
use mdbook_preprocessor::book::{Book, BookItem};
use mdbook_preprocessor::{Preprocessor, PreprocessorContext};
use std::collections::HashMap;

/// Puts generated numbers into the prose, and a provenance footer under every page.
///
/// In a chapter, `{{n SCENE/KEY}}` becomes the key number's value (to its significant
/// figures), `{{pm SCENE/KEY}}` the value ± its uncertainty with its unit, and
/// `{{u SCENE/KEY}}` the uncertainty alone, `{{verdict SCENE}}` the result's verdict
/// ("**Partly reproduced.**"), `{{evidence SCENE}}` its evidence in one line and
/// `{{time SCENE}}` how long it took to compute in the build that computed it. An unknown scene or key fails the build.
pub struct NumbersPreprocessor {
    /// Key numbers by scene.
    pub numbers: HashMap<String, KeyNumbers>,
    /// Verdicts by scene.
    pub verdicts: HashMap<String, crate::results::scene::Verdict>,
    /// The size of each scene's `data.json` in bytes (for the links under its chapter).
    pub data_sizes: HashMap<String, u64>,
    /// Scene by chapter file.
    pub chapters: HashMap<String, Vec<String>>,
    /// Where each scene's numbers come from (they may come from different builds when
    /// `cantilever book --only` reused current outputs).
    pub provenances: HashMap<String, Provenance>,
    /// Where the numbers of pages without a scene come from.
    pub provenance: Provenance,
    /// How long each scene took in the build that computed it (s).
    pub seconds: HashMap<String, f64>,
    /// The scenes whose plot has a narrow layout (`plot-narrow.svg`), shown instead on
    /// narrow screens.
    pub narrow: std::collections::HashSet<String>,
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
    ///
    /// # Errors
    /// For an unclosed reference, a reference not written `SCENE/KEY`, or an unknown scene, key
    /// or scene time.
    pub fn expand(&self, text: &str) -> Result<String> {
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(start) = rest.find("{{") {
            let tail = &rest[start + 2..];
            let Some((kind, after)) = ["n ", "pm ", "u ", "verdict ", "evidence ", "time "]
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
            if kind == "time" {
                let scene = after[..end].trim();
                let secs = self
                    .seconds
                    .get(scene)
                    .ok_or_else(|| anyhow::anyhow!("no time known for scene `{scene}`"))?;
                // whole seconds, or one figure below ten (a fast scene is not "0 s")
                out.push_str(&if *secs >= 9.5 {
                    format!("{secs:.0} s")
                } else {
                    format!("{} s", crate::base::report::pretty(secs.max(1e-3), 1))
                });
                rest = &after[end + 2..];
                continue;
            }
            if kind == "verdict" || kind == "evidence" {
                let scene = after[..end].trim();
                let verdict = self
                    .verdicts
                    .get(scene)
                    .ok_or_else(|| anyhow::anyhow!("unknown scene `{scene}` in a {kind}"))?;
                out.push_str(&if kind == "verdict" {
                    format!("**{}.**", capitalised(&verdict.outcome.to_string()))
                } else {
                    // it follows the verdict's full stop: a new sentence
                    capitalised(&for_html(&verdict.evidence))
                });
                rest = &after[end + 2..];
                continue;
            }
            let value = self.lookup(&after[..end])?;
            out.push_str(&match (kind, value) {
                ("u", KeyValue::Float(c)) => pretty(
                    crate::base::report::round_up_one_figure(c.uncertainty.value),
                    1,
                ),
                ("pm", v) => for_html(&v.prose(true)),
                (_, v) => for_html(&v.prose(false)),
            });
            rest = &after[end + 2..];
        }
        out.push_str(rest);
        Ok(out)
    }

    /// `text` with each plot of a scene in [`Self::narrow`], `[![alt](generated/S/plot.svg)]
    /// (generated/S/plot.svg)`, as a picture whose source on screens up to 620 px wide is
    /// the plot's narrow layout (its panels in one column, each readable on a phone); the
    /// link still opens the full plot.
    pub fn narrow_plots(&self, text: &str) -> String {
        let mut out = text.to_string();
        for scene in &self.narrow {
            let plot = format!("generated/{scene}/plot.svg");
            let tail = format!("]({plot})]({plot})");
            while let Some(end) = out.find(&tail) {
                let Some(start) = out[..end].rfind("[![") else {
                    break;
                };
                let alt = out[start + 3..end]
                    .replace('&', "&amp;")
                    .replace('"', "&quot;")
                    .replace('<', "&lt;");
                let narrow = format!("generated/{scene}/{}", crate::results::scene::NARROW_PLOT);
                let html = format!(
                    "<a href=\"{plot}\"><picture><source media=\"(max-width: 620px)\" \
                     srcset=\"{narrow}\"><img src=\"{plot}\" alt=\"{alt}\"></picture></a>"
                );
                out.replace_range(start..end + tail.len(), &html);
            }
        }
        out
    }

    /// The footer of a page: provenance, and the data of its scene if it has one.
    pub fn footer(&self, chapter: &str) -> String {
        // the chapter's own result's build (a reused result may come from an earlier one)
        let own = self
            .chapters
            .get(chapter)
            .and_then(|scenes| scenes.first())
            .and_then(|scene| self.provenances.get(scene))
            .unwrap_or(&self.provenance);
        let mut s = format!(
            "\n\n---\n\n<div class=\"provenance\">\n\nNumbers on this page were generated by {}.",
            own.line()
        );
        for scene in self.chapters.get(chapter).into_iter().flatten() {
            let size = self
                .data_sizes
                .get(scene)
                .map(|b| format!(" ({})", human_size(*b)))
                .unwrap_or_default();
            s.push_str(&format!(
                " Data of `{scene}`: [data.json](generated/{scene}/data.json){size} · [its numbers \
                 with their uncertainties](generated/{scene}/key_numbers.json) · \
                 `cantilever cite {scene}`."
            ));
        }
        // the page's own source, numbers as placeholders (see `copy_sources`)
        s.push_str(&format!(
            " The source of this page: [`book/src/{chapter}`]({}/{}.txt).",
            super::SOURCES,
            chapter.trim_end_matches(".md")
        ));
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
                    Ok(c) => ch.content = self.narrow_plots(&c) + &self.footer(&file),
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
            crate::base::report::Uncertainty::new(3e-4, "t"),
            "T",
        );
        k.integer("n", 7);
        let p = NumbersPreprocessor {
            numbers: [("s".to_string(), k)].into_iter().collect(),
            verdicts: [(
                "s".to_string(),
                crate::results::scene::Verdict {
                    outcome: crate::results::scene::Outcome::Partly,
                    evidence: "e".into(),
                },
            )]
            .into_iter()
            .collect(),
            data_sizes: HashMap::new(),
            chapters: HashMap::new(),
            provenances: HashMap::new(),
            provenance: Provenance::now("test"),
            seconds: [("s".to_string(), 12.3)].into_iter().collect(),
            narrow: ["s".to_string()].into_iter().collect(),
        };
        assert_eq!(
            p.narrow_plots("a\n[![The \"plot\"](generated/s/plot.svg)](generated/s/plot.svg)\nb"),
            "a\n<a href=\"generated/s/plot.svg\"><picture><source media=\"(max-width: 620px)\" \
             srcset=\"generated/s/plot-narrow.svg\"><img src=\"generated/s/plot.svg\" \
             alt=\"The &quot;plot&quot;\"></picture></a>\nb"
        );
        let other = "[![x](generated/t/plot.svg)](generated/t/plot.svg)";
        assert_eq!(p.narrow_plots(other), other);
        assert_eq!(p.expand("{{time s}}").unwrap(), "12 s");
        assert_eq!(p.expand("a {{n s/x}} b").unwrap(), "a 1.235 b");
        // (1.23456 to 4 figures: the rounding, 4.4e-4, is larger than 3e-4 and is added)
        // (the power of ten is not broken at its ×)
        assert_eq!(
            p.expand("{{pm s/x}}").unwrap(),
            "1.235 ± 8\u{a0}×\u{a0}10⁻⁴ T"
        );
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
}
