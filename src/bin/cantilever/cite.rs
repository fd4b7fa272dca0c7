//! `cantilever cite SCENE [KEY]`: a key number (or all of a scene's) as a citation — the
//! value with its uncertainty and how it was obtained, its unit, the parameters, the
//! method, the build that computed it, and how to cite the software and the paper.

use impacting_cantilever::base::report::{unit_meaning, KeyNumbers, KeyValue};
use impacting_cantilever::error::ParameterError;
use impacting_cantilever::results::citation;
use impacting_cantilever::results::scene::{self, Entry, Resolution, SceneOutput};

/// What `cite` prints: the computed scene and the keys asked for.
pub struct Citation {
    spec: &'static dyn Entry,
    out: SceneOutput,
    keys: KeyNumbers,
}

/// Runs `name` at the book's resolution (the numbers the book publishes) and picks `key`,
/// or every key number when `key` is `None`. An unknown key is bad input, named with the
/// keys that contain its words.
pub fn run(
    name: &str,
    key: Option<&str>,
    progress: &dyn impacting_cantilever::results::scene::Progress,
) -> Result<Citation, super::Failure> {
    let spec = impacting_cantilever::results::scenes::find(name)?;
    let out = spec.run(Resolution::Book, progress)?;
    let keys = match key {
        None => out.key_numbers.clone(),
        Some(k) => match out.key_numbers.get(k) {
            Some(v) => KeyNumbers(vec![(k.to_string(), v.clone())]),
            None => return Err(unknown_key(spec.name(), k, &out.key_numbers).into()),
        },
    };
    Ok(Citation { spec, out, keys })
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

/// The citation as text.
pub fn to_text(c: &Citation) -> String {
    let p = &c.out.provenance;
    let mut s = String::new();
    let one = c.keys.0.len() == 1;
    for (k, v) in &c.keys.0 {
        s += &format!("{k} = {v}\n");
        match v {
            KeyValue::Float(x) if !one && x.uncertainty.value > 0.0 => {
                s += &format!("  ({})\n", x.uncertainty.basis);
            }
            _ => {}
        }
        if let (true, KeyValue::Float(x)) = (one, v) {
            s += &format!("  value        {} significant figures\n", x.digits);
            if x.uncertainty.value > 0.0 {
                s += &format!("  uncertainty  {}\n", x.uncertainty.basis);
            }
            match unit_meaning(&x.unit) {
                Some(m) => s += &format!("  unit         {}: {m}\n", x.unit),
                None if !x.unit.is_empty() => s += &format!("  unit         {}\n", x.unit),
                None => {}
            }
        }
    }
    let params = serde_json::to_string(&c.out.params).unwrap_or_default();
    s += &format!(
        "\nscene        {} ({}): {}\n",
        c.spec.name(),
        c.spec.paper(),
        c.spec.summary()
    );
    s += &format!("parameters   {params}\n");
    s += &format!("method       {}\n", c.spec.method());
    s += &format!(
        "verdict      {}: {}\n",
        c.out.verdict.outcome, c.out.verdict.evidence
    );
    s += &format!("computed by  {}\n", p.line());
    s += &format!(
        "reproduce    cargo run --release -- cite {} (at commit {})\n",
        c.spec.name(),
        p.commit
    );
    s += &format!(
        "\nCite the software:\n  {}\n\n{}\n\nand the paper:\n  {}\n\n{}\n",
        citation::software_plain(p),
        citation::software_bibtex(p),
        citation::PAPER_PLAIN,
        citation::PAPER_BIBTEX
    );
    s
}

/// The citation as JSON: the key-number document of the scene restricted to the keys
/// asked for, with the two citations.
pub fn to_json(c: &Citation) -> serde_json::Value {
    let mut doc = scene::key_numbers_document(c.spec, &c.out);
    doc["key_numbers"] = c.keys.to_json();
    doc["cite"] = serde_json::json!({
        "software": {
            "plain": citation::software_plain(&c.out.provenance),
            "bibtex": citation::software_bibtex(&c.out.provenance),
        },
        "paper": { "plain": citation::PAPER_PLAIN, "bibtex": citation::PAPER_BIBTEX },
    });
    doc
}
