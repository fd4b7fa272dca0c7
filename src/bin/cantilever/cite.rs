//! `cantilever cite SCENE [KEY]`: a key number (or all of a scene's) as a citation — a
//! sentence to paste, then the value with its uncertainty and how it was obtained, its
//! unit, the parameters, the method, the build, and how to cite the software and the
//! paper.
//!
//! By default the numbers are the book's published ones, read from the snapshots this build
//! was made with (`tests/snapshots/published__book-*.snap`, which the test suite checks
//! against a recomputation at every commit): instant. `--recompute` computes the scene at
//! the book's resolution instead (seconds to a minute), so the number is the one of the code
//! as it stands, uncommitted changes included.

use impacting_cantilever::base::provenance::Provenance;
use impacting_cantilever::base::report::{
    pretty, round_up_one_figure, unit_meaning, KeyNumbers, KeyValue,
};
use impacting_cantilever::error::ParameterError;
use impacting_cantilever::results::citation;
use impacting_cantilever::results::diff;
use impacting_cantilever::results::scene::{self, Entry, Resolution, Verdict};

/// What `cite` prints: the scene, where its numbers come from and the keys asked for.
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

/// Picks `key` (or every key number when `None`) of scene `name`: from the published
/// numbers, or computed afresh at the book's resolution when `recompute`. An unknown key is
/// bad input, named with the keys that contain its words.
pub fn run(
    name: &str,
    key: Option<&str>,
    recompute: bool,
    progress: &dyn impacting_cantilever::results::scene::Progress,
) -> Result<Citation, super::Failure> {
    let spec = impacting_cantilever::results::scenes::find(name)?;
    let (all, provenance, verdict) = if recompute {
        let out = spec.run(Resolution::Book, progress)?;
        (out.key_numbers, out.provenance, Some(out.verdict))
    } else {
        let published = diff::published().map_err(super::Failure::Other)?;
        let keys = published
            .into_iter()
            .find(|s| s.scene == spec.name())
            .ok_or_else(|| {
                super::Failure::Other(format!(
                    "no published numbers of {} in this build (try --recompute)",
                    spec.name()
                ))
            })?;
        (
            keys.numbers,
            Provenance::of_scene(spec.module(), "book"),
            None,
        )
    };
    let keys = match key {
        None => all.clone(),
        Some(k) => match all.get(k) {
            Some(v) => KeyNumbers(vec![(k.to_string(), v.clone())]),
            None => return Err(unknown_key(spec.name(), k, &all).into()),
        },
    };
    Ok(Citation {
        spec,
        params: readable(spec.params_json(Resolution::Book)),
        provenance,
        verdict,
        recomputed: recompute,
        keys,
        key: key.map(str::to_string),
    })
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
fn unknown_key(scene: &str, key: &str, all: &KeyNumbers) -> ParameterError {
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

/// The value as a reader writes it: decimal between 10⁻³ and 10⁶ (× 10ⁿ beyond), ± its
/// uncertainty to one figure rounded up, and its unit.
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
            let (value, u) = (
                pretty(c.value, c.digits),
                round_up_one_figure(c.uncertainty.value),
            );
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

/// The sentence to paste: the number and where it comes from.
pub fn sentence(c: &Citation, key: &str, value: &KeyValue) -> String {
    format!(
        "{key} = {} ({}, parameters of {}; impacting-cantilever {}, commit {})",
        decimal(value),
        citation::PAPER_SHORT,
        c.spec.paper(),
        c.provenance.version,
        citation::commit(&c.provenance),
    )
}

/// The command that reproduces the citation by computing the number afresh.
fn reproduce(c: &Citation) -> String {
    let key = c
        .key
        .as_deref()
        .map(|k| format!(" \"{k}\""))
        .unwrap_or_default();
    format!(
        "cargo run --release -- cite {}{key} --recompute   (at commit {})",
        c.spec.name(),
        c.provenance.commit
    )
}

/// The citation as text.
pub fn to_text(c: &Citation) -> String {
    let p = &c.provenance;
    let mut s = String::new();
    let one = c.keys.0.len() == 1;
    if let [(k, v)] = c.keys.0.as_slice() {
        s += &format!("{}\n\n", sentence(c, k, v));
    }
    for (k, v) in &c.keys.0 {
        s += &format!("{k} = {}\n", decimal(v));
        let basis = |x: &impacting_cantilever::base::report::Cited| {
            (x.uncertainty.value > 0.0).then(|| x.uncertainty.basis.clone())
        };
        match v {
            KeyValue::Float(x) if !one => {
                if let Some(b) = basis(x) {
                    s += &format!("  ({b})\n");
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
    let params = serde_json::to_string(&c.params).unwrap_or_default();
    s += &format!(
        "\nscene        {} ({}): {}\n",
        c.spec.name(),
        c.spec.paper(),
        c.spec.summary()
    );
    s += &format!("parameters   {params}\n");
    s += &format!("method       {}\n", c.spec.method());
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
    s += &format!("reproduce    {}\n", reproduce(c));
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
pub fn to_json(c: &Citation) -> serde_json::Value {
    let spec = c.spec;
    let sentences: Vec<String> = c.keys.0.iter().map(|(k, v)| sentence(c, k, v)).collect();
    serde_json::json!({
        "schema_version": scene::SCHEMA_VERSION,
        "scene": spec.name(),
        "paper": spec.paper(),
        "claim": spec.claim(),
        "method": spec.method(),
        "parameters": c.params,
        "provenance": c.provenance,
        "source": if c.recomputed { "recomputed" } else { "published" },
        "verdict": c.verdict,
        "key_numbers": c.keys.to_json(),
        "sentences": sentences,
        "reproduce": reproduce(c),
        "cite": {
            "software": {
                "plain": citation::software_plain(&c.provenance),
                "bibtex": citation::software_bibtex(&c.provenance),
            },
            "paper": { "plain": citation::PAPER_PLAIN, "bibtex": citation::PAPER_BIBTEX },
        },
    })
}
