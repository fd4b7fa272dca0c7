//! A key number (or all of a scene's) as a citation: a sentence to paste, the value with its
//! uncertainty and how it was obtained, its unit, the parameters, the method, the build, and
//! how to cite the software and the paper. `cantilever cite` and the Python package print
//! this one text.
//!
//! The numbers are either the book's published ones — the committed snapshots
//! `tests/snapshots/published__book-*.snap` this build was made with, which the test suite
//! checks against a recomputation at every commit ([`Citation::published`], instant) — or a
//! scene's output computed afresh ([`Citation::of_output`]).

use crate::base::provenance::Provenance;
use crate::base::report::{pretty, round_up_one_figure, unit_meaning, Cited, KeyNumbers, KeyValue};
use crate::error::ParameterError;
use crate::results::citation;
use crate::results::diff;
use crate::results::names;
use crate::results::scene::{self, Entry, Group, Resolution, SceneOutput, Verdict};

/// What a citation says: the scene, where its numbers come from and the keys asked for.
pub struct Citation {
    spec: &'static dyn Entry,
    /// The parameters (readable: floats to 12 figures).
    params: serde_json::Value,
    provenance: Provenance,
    /// The verdict, when the scene was recomputed.
    verdict: Option<Verdict>,
    /// Whether the numbers were recomputed (else: the published ones).
    recomputed: bool,
    keys: KeyNumbers,
    key: Option<String>,
}

/// Why a citation cannot be made.
#[derive(Debug)]
pub enum CiteError {
    /// An unknown key: bad input, named with the keys that contain its words.
    Key(ParameterError),
    /// No published numbers of the scene in this build.
    Unpublished(String),
}

impl std::fmt::Display for CiteError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CiteError::Key(e) => e.fmt(f),
            CiteError::Unpublished(s) => f.write_str(s),
        }
    }
}

impl Citation {
    /// `key` (or every key number when `None`) of scene `spec` from the book's published
    /// numbers.
    ///
    /// # Errors
    /// [`CiteError::Unpublished`] when this build's published snapshots do not parse or hold no
    /// numbers of the scene; [`CiteError::Key`] for a key the scene does not have.
    pub fn published(spec: &'static dyn Entry, key: Option<&str>) -> Result<Self, CiteError> {
        let published = diff::published().map_err(CiteError::Unpublished)?;
        let all = published
            .into_iter()
            .find(|s| s.scene == spec.name())
            .ok_or_else(|| {
                CiteError::Unpublished(format!(
                    "no published numbers of {} in this build (try --recompute)",
                    spec.name()
                ))
            })?
            .numbers;
        let keys = pick(spec.name(), &all, key).map_err(CiteError::Key)?;
        Ok(Self {
            spec,
            params: readable(spec.params_json(Resolution::Book)),
            provenance: Provenance::of_published(spec.module()),
            verdict: None,
            recomputed: false,
            // the key found (a number asked for by its name is reproduced by its key)
            key: key.and_then(|_| keys.0.first()).map(|(k, _)| k.clone()),
            keys,
        })
    }

    /// `key` (or every key number when `None`) of a computed output of scene `spec`.
    ///
    /// # Errors
    /// [`ParameterError`] for a key that is not among the output's key numbers.
    pub fn of_output(
        spec: &'static dyn Entry,
        out: &SceneOutput,
        key: Option<&str>,
    ) -> Result<Self, ParameterError> {
        Ok(Self {
            spec,
            params: readable(out.params.clone()),
            provenance: out.provenance.clone(),
            verdict: Some(out.verdict.clone()),
            recomputed: true,
            key: None,
            keys: pick(spec.name(), &out.key_numbers, key)?,
        }
        .with_key_found(key.is_some()))
    }

    /// Records the key found when one was asked for (by key or by name).
    fn with_key_found(mut self, asked: bool) -> Self {
        self.key = asked
            .then(|| self.keys.0.first())
            .flatten()
            .map(|(k, _)| k.clone());
        self
    }

    /// The sentence to paste for one key number: the number and where it comes from. A
    /// number of one of the paper's results is the paper's, with its parameters; a number
    /// computed beyond the paper (a new question, the experiment's validation, a method's
    /// check) is this software's, for the paper's model.
    pub fn sentence(&self, key: &str, value: &KeyValue) -> String {
        let build = format!(
            "impacting-cantilever {}, commit {}",
            self.provenance.version,
            citation::commit(&self.provenance),
        );
        let of_the_paper =
            self.spec.group() == Group::Paper && !self.spec.paper().contains("beyond");
        let name = names::capitalised(&names::name(self.spec.name(), key));
        match of_the_paper {
            true => format!(
                "{name}: {} ({}, parameters of {}; {build})",
                decimal(value),
                citation::PAPER_SHORT,
                self.spec.paper(),
            ),
            false => format!(
                "{name}: {} (computed by {build}, for the model of {}; {})",
                decimal(value),
                citation::PAPER_SHORT,
                self.spec.summary(),
            ),
        }
    }

    /// The command that reproduces the citation by computing the number afresh.
    pub fn reproduce(&self) -> String {
        let key = self
            .key
            .as_deref()
            .map(|k| format!(" \"{k}\""))
            .unwrap_or_default();
        format!(
            "cargo run --release -- cite {}{key} --recompute   (at commit {})",
            self.spec.name(),
            self.provenance.commit
        )
    }
}

/// The keys asked for.
fn pick(scene: &str, all: &KeyNumbers, key: Option<&str>) -> Result<KeyNumbers, ParameterError> {
    match key {
        None => Ok(all.clone()),
        Some(k) => match all.get(k) {
            Some(v) => Ok(KeyNumbers(vec![(k.to_string(), v.clone())])),
            // a number may also be asked for by its name
            None => all
                .0
                .iter()
                .find(|(key, _)| names::name(scene, key).eq_ignore_ascii_case(k.trim()))
                .map(|(key, v)| KeyNumbers(vec![(key.clone(), v.clone())]))
                .ok_or_else(|| unknown_key(scene, k, all)),
        },
    }
}

/// Floats to 12 significant figures (0.09500000000000001 is 0.095): a parameter is what
/// was typed, not its last binary digit.
fn readable(v: serde_json::Value) -> serde_json::Value {
    use serde_json::Value;
    match v {
        Value::Number(n) if n.is_f64() => {
            let x = n.as_f64().unwrap_or_default();
            let short: f64 = format!("{x:.11e}").parse().unwrap_or(x);
            serde_json::Number::from_f64(short).map_or(Value::Null, Value::Number)
        }
        Value::Array(a) => Value::Array(a.into_iter().map(readable).collect()),
        Value::Object(o) => Value::Object(o.into_iter().map(|(k, v)| (k, readable(v))).collect()),
        other => other,
    }
}

/// One line: the key, and the scene's keys sharing most words with it (at most five).
pub fn unknown_key(scene: &str, key: &str, all: &KeyNumbers) -> ParameterError {
    let words = |s: &str| -> Vec<String> {
        s.split(|c: char| !c.is_alphanumeric())
            .filter(|w| !w.is_empty())
            .map(str::to_lowercase)
            .collect()
    };
    let asked = words(key);
    let mut near: Vec<(usize, &String)> = all
        .0
        .iter()
        .map(|(k, _)| {
            let have = words(k);
            let shared = asked.iter().filter(|w| have.contains(w)).count();
            // keys are "<case> <quantity>": the same case (e.g. "N=3") ranks first
            let same_case = key.split(' ').next() == k.split(' ').next();
            (2 * shared + usize::from(same_case), k)
        })
        .filter(|(shared, _)| *shared > 0)
        .collect();
    // most shared words first; the scene's order among equals
    near.sort_by_key(|(score, _)| std::cmp::Reverse(*score));
    let near: Vec<String> = near
        .iter()
        .take(5)
        .map(|(_, k)| format!("\"{k}\""))
        .collect();
    let hint = if near.is_empty() {
        format!("`cantilever cite {scene}` lists all {}", all.0.len())
    } else {
        format!("e.g. {}", near.join(", "))
    };
    ParameterError::new("KEY", key, &format!("a key number of {scene} ({hint})"))
}

/// How the values are rounded, said once at the head of a citation.
pub const ROUNDING_RULE: &str =
    "Each value is rounded to the nearest in its last digit shown. Where \
the computation is more precise than the digits kept, the ± is that rounding's bound, half a unit \
of the last digit, and the computed value's own accuracy is stated beside it; otherwise the ± is \
the computation's uncertainty, rounded up to one figure.";

/// The ± of a float: half a unit of its last digit when that bounds the rounding and the
/// method together (the value is as precise as its digits, whatever the luck of the
/// rounding: 0.25380 and 0.20479 both read ± 0.000005), else the stated uncertainty.
fn plus_minus(c: &Cited) -> f64 {
    let half_unit = if c.value == 0.0 {
        0.0
    } else {
        let exponent = c.value.abs().log10().floor() as i32 - c.digits as i32 + 1;
        0.5 * 10f64.powi(exponent)
    };
    let rounding = (c.value - c.computed).abs();
    let method = c.uncertainty.value - rounding;
    let rounded = c.uncertainty.basis.starts_with("the rounding to");
    if rounded && half_unit > 0.0 && rounding + method.max(0.0) <= half_unit {
        half_unit
    } else {
        round_up_one_figure(c.uncertainty.value)
    }
}

/// The value as a reader writes it: decimal between 10⁻³ and 10⁶ (× 10ⁿ beyond), ± its
/// uncertainty ([`plus_minus`]), and its unit.
fn decimal(v: &KeyValue) -> String {
    let unit = |u: &str| {
        if u.is_empty() {
            String::new()
        } else {
            format!(" {u}")
        }
    };
    match v {
        KeyValue::Float(c) if c.uncertainty.value > 0.0 => {
            let (value, u) = (pretty(c.value, c.digits), plus_minus(c));
            // a plain value takes its ± in the same notation, to its own last place or
            // coarser: 0.7173 ± 0.0001, not 0.7173 ± 10⁻⁴
            let u = match value.split_once('.') {
                Some(_) if !value.contains('×') && u >= 1e-8 => {
                    let places = (-u.log10().floor()).max(0.0) as usize;
                    format!("{u:.places$}")
                }
                None if !value.contains('×') && u >= 1.0 => format!("{u}"),
                _ => pretty(u, 1),
            };
            format!("{value} ± {u}{}", unit(&c.unit))
        }
        KeyValue::Float(c) => format!("{}{} (exact)", pretty(c.value, c.digits), unit(&c.unit)),
        other => other.prose(true),
    }
}

impl Citation {
    /// The citation as text.
    pub fn to_text(&self) -> String {
        let c = self;
        let p = &c.provenance;
        let mut s = String::new();
        let one = c.keys.0.len() == 1;
        if let [(k, v)] = c.keys.0.as_slice() {
            s += &format!("{}\n\n", c.sentence(k, v));
        }
        let scene = c.spec.name();
        for (k, v) in &c.keys.0 {
            // the name to read, the key to type
            s += &format!("{}: {}\n", names::name(scene, k), decimal(v));
            s += &format!("  key          {k}\n");
            let basis =
                |x: &Cited| (x.uncertainty.value > 0.0).then(|| x.uncertainty.basis.clone());
            match v {
                KeyValue::Float(x) if !one => {
                    if let Some(b) = basis(x) {
                        s += &format!("  uncertainty  {b}\n");
                    }
                }
                KeyValue::Float(x) => {
                    s += &format!("  value        {} significant figures\n", x.digits);
                    if let Some(b) = basis(x) {
                        s += &format!("  uncertainty  {b}\n");
                    }
                    match unit_meaning(&x.unit) {
                        Some(m) => s += &format!("  unit         {}: {m}\n", x.unit),
                        None if !x.unit.is_empty() => s += &format!("  unit         {}\n", x.unit),
                        None => {}
                    }
                }
                _ => {}
            }
        }
        let (params, _) = names::parameters::in_words(scene, &c.params);
        s += &format!(
            "\nscene        {} ({}): {}\n",
            c.spec.name(),
            c.spec.paper(),
            c.spec.summary()
        );
        s += &format!("parameters   {}\n", params.join("\n             "));
        s += &format!("method       {}\n", c.spec.method());
        s += &format!("rounding     {ROUNDING_RULE}\n");
        if let Some(v) = &c.verdict {
            s += &format!("verdict      {}: {}\n", v.outcome, v.evidence);
        }
        if c.recomputed {
            s += &format!("computed by  {}\n", p.line());
        } else {
            s += &format!(
                "source       the book's published numbers, as committed with this build ({}) and \
             checked against a recomputation by its test suite\n",
                p.line()
            );
        }
        s += &format!("reproduce    {}\n", c.reproduce());
        s += &format!(
            "\nCite the software:\n  {}\n\n{}\n\nand the paper:\n  {}\n\n{}\n",
            citation::software_plain(p),
            citation::software_bibtex(p),
            citation::PAPER_PLAIN,
            citation::PAPER_BIBTEX
        );
        s
    }

    /// The citation as JSON: the scene's key-number document restricted to the keys asked
    /// for, with the sentence(s) to paste and the two citations.
    pub fn to_json(&self) -> serde_json::Value {
        let c = self;
        let spec = c.spec;
        let sentences: Vec<String> = c.keys.0.iter().map(|(k, v)| c.sentence(k, v)).collect();
        let mut numbers = c.keys.to_json();
        names::annotate(spec.name(), &mut numbers);
        let (in_words, _) = names::parameters::in_words(spec.name(), &c.params);
        serde_json::json!({
            "schema_version": scene::SCHEMA_VERSION,
            "scene": spec.name(),
            "paper": spec.paper(),
            "claim": spec.claim(),
            "method": spec.method(),
            "parameters": c.params,
            "parameters_in_words": in_words,
            "provenance": c.provenance,
            "source": if c.recomputed { "recomputed" } else { "published" },
            "verdict": c.verdict,
            "key_numbers": numbers,
            "sentences": sentences,
            "rounding_rule": ROUNDING_RULE,
            "reproduce": c.reproduce(),
            "cite": {
                "software": {
                    "plain": citation::software_plain(&c.provenance),
                    "bibtex": citation::software_bibtex(&c.provenance),
                },
                "paper": { "plain": citation::PAPER_PLAIN, "bibtex": citation::PAPER_BIBTEX },
            },
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::report::Uncertainty;

    #[test]
    fn a_rounding_bound_reads_as_half_a_unit_of_the_last_digit() {
        // equal precision, different rounding luck: the same ±
        let lucky = Cited::new(0.253_800_2, 5, Uncertainty::new(2e-12, "round-off"), "");
        let unlucky = Cited::new(0.204_794_9, 5, Uncertainty::new(2e-12, "round-off"), "");
        assert_eq!(decimal(&KeyValue::Float(lucky)), "0.25380 ± 0.000005");
        assert_eq!(decimal(&KeyValue::Float(unlucky)), "0.20479 ± 0.000005");
        // a method's uncertainty larger than the rounding stays the ±, rounded up
        let wide = Cited::new(0.912_345, 4, Uncertainty::new(7.7e-5, "a step in N"), "");
        assert_eq!(decimal(&KeyValue::Float(wide)), "0.9123 ± 0.00008");
    }

    #[test]
    fn a_number_beyond_the_paper_is_credited_to_the_software() {
        let find = |n| crate::results::scenes::find(n).unwrap();
        let fig4 = Citation::published(find("fig4"), Some("N=3 impact_velocity_1")).unwrap();
        let (k, v) = &fig4.keys.0[0];
        let s = fig4.sentence(k, v);
        assert!(
            s.contains("Melcher, Champneys & Wagg 2013, parameters of Fig 4"),
            "{s}"
        );
        let atlas = Citation::published(find("atlas"), None).unwrap();
        let (k, v) = &atlas.keys.0[0];
        let s = atlas.sentence(k, v);
        assert!(
            s.contains("(computed by impacting-cantilever") && !s.contains("parameters of"),
            "{s}"
        );
    }
}
