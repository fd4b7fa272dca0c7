//! Which published number moved, and by how much against its uncertainty: two sets of key
//! numbers compared key by key (`cantilever diff`, and the book's chapter on changing the
//! model).
//!
//! Two values of a float are taken to agree when they differ by no more than the sum of
//! their stated uncertainties and of their rounding (half a unit of the last printed digit
//! of each). The sum, not a root-sum-square: the uncertainties here are bounds and
//! convergence estimates, not standard deviations, and two values each within its bound of
//! the exact number differ by at most the sum. A float moved *within* its uncertainty is a
//! change the method cannot resolve (a different transient, round-off); a float moved
//! *beyond* it is a different result. Integers and labels agree only when equal; a changed
//! unit or kind is a change beyond uncertainty, since the two values are not comparable.

use crate::base::report::{Cited, KeyNumbers, KeyValue};
use serde::Serialize;

include!(concat!(env!("OUT_DIR"), "/published.rs"));

/// The published key numbers this build was made with: the committed snapshots
/// `tests/snapshots/published__book-*.snap`, read at compile time (book resolution).
///
/// # Errors
/// A message naming the scene when a committed snapshot does not parse
/// ([`KeyNumbers::from_snapshot`]).
pub fn published() -> Result<Vec<SceneKeys>, String> {
    PUBLISHED_SNAPSHOTS
        .iter()
        .map(|(scene, text, record)| {
            let mut numbers = KeyNumbers::from_snapshot(text)
                .map_err(|e| format!("published snapshot of {scene}: {e}"))?;
            if !record.is_empty() {
                let record: serde_json::Value = serde_json::from_str(record)
                    .map_err(|e| format!("published record of {scene}: {e}"))?;
                with_record(&mut numbers, &record);
            }
            Ok(SceneKeys {
                scene: scene.to_string(),
                resolution: Some("book".into()),
                numbers,
            })
        })
        .collect()
}

/// The printed numbers of a snapshot with their full-precision values and the method's
/// own uncertainties from the scene's record (results::record).
fn with_record(numbers: &mut KeyNumbers, record: &serde_json::Value) {
    let entries = &record["numbers"];
    let fill = |c: &mut Cited, e: &serde_json::Value| {
        if let Some((computed, method)) = crate::results::record::read_entry(e) {
            c.computed = computed;
            c.method = method;
        }
    };
    for (key, v) in &mut numbers.0 {
        match v {
            KeyValue::Float(c) => fill(c, &entries[key.as_str()]),
            KeyValue::Series(s) => {
                for (i, c) in s.iter_mut().enumerate() {
                    fill(c, &entries[key.as_str()][i]);
                }
            }
            _ => {}
        }
    }
}

/// A scene's key numbers from its `key_numbers.json` document (what `cantilever scene`
/// and the book write).
///
/// # Errors
/// A message when `doc` has no `scene` name or no `key_numbers`, or the errors of
/// [`KeyNumbers::from_json`].
pub fn from_document(doc: &serde_json::Value) -> Result<SceneKeys, String> {
    let scene = doc
        .get("scene")
        .and_then(serde_json::Value::as_str)
        .ok_or("no \"scene\" name: not a key_numbers.json document")?;
    let numbers = doc
        .get("key_numbers")
        .ok_or("no \"key_numbers\": not a key_numbers.json document")?;
    Ok(SceneKeys {
        scene: scene.to_string(),
        resolution: doc
            .pointer("/provenance/resolution")
            .and_then(serde_json::Value::as_str)
            .map(str::to_string),
        numbers: KeyNumbers::from_json(numbers)?,
    })
}

/// The key numbers of one scene, as read from an output or a snapshot.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneKeys {
    /// The scene's name.
    pub scene: String,
    /// `"book"` or `"test"`, when known.
    pub resolution: Option<String>,
    /// The numbers.
    pub numbers: KeyNumbers,
}

/// How one key number changed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "change", rename_all = "snake_case")]
pub enum Change {
    /// The same value (to its printed digits).
    Unchanged,
    /// Moved by `moved`, no more than `allowed`, the combined uncertainty.
    Within {
        /// |new − old| (for a list: of its element that moved most against its allowance).
        moved: f64,
        /// The two uncertainties and roundings summed.
        allowed: f64,
    },
    /// Moved by `moved`, more than `allowed`.
    Beyond {
        /// |new − old| (for a list: of its element that moved most against its allowance).
        moved: f64,
        /// The two uncertainties and roundings summed.
        allowed: f64,
    },
    /// An integer or label that differs.
    Changed,
    /// The unit differs: the values are not comparable.
    UnitChanged,
    /// A number became a label, a list changed length…: not comparable.
    KindChanged,
    /// Only in the new set.
    Added,
    /// Only in the old set.
    Removed,
}

impl Change {
    /// Whether this change is a different result (what makes `cantilever diff` exit 1): a
    /// number moved beyond its uncertainty, an integer or label changed, a unit or kind
    /// changed, or a number that OLD has and NEW has lost.
    pub fn is_beyond(&self) -> bool {
        matches!(
            self,
            Change::Beyond { .. }
                | Change::Changed
                | Change::UnitChanged
                | Change::KindChanged
                | Change::Removed
        )
    }
}

/// One key's comparison.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    /// The scene.
    pub scene: String,
    /// The key.
    pub key: String,
    /// The key number's name in words ([`crate::results::names`]).
    pub name: String,
    /// The old value as printed (none if added).
    pub old: Option<String>,
    /// The new value as printed (none if removed).
    pub new: Option<String>,
    /// What changed.
    #[serde(flatten)]
    pub change: Change,
    /// The old value itself (for renderings other than the printed one).
    #[serde(skip)]
    pub old_value: Option<KeyValue>,
    /// The new value itself.
    #[serde(skip)]
    pub new_value: Option<KeyValue>,
}

/// The comparison of two sets.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Diff {
    /// Every key of either side, scene by scene (in the new set's order, then removed ones).
    pub rows: Vec<Row>,
    /// Scenes only in the new set.
    pub scenes_added: Vec<String>,
    /// Scenes only in the old set.
    pub scenes_removed: Vec<String>,
    /// Whether numbers and scenes only in OLD are expected (`--allow-removed`): they are
    /// then listed but not a change.
    #[serde(skip)]
    pub allow_removed: bool,
    /// The one scene compared when one side holds only it and the other holds it among
    /// others (a scene's output folder against `published`): the other side's other
    /// scenes are then not "removed" or "added".
    pub only_scene: Option<String>,
}

impl Diff {
    /// Whether any number moved beyond its uncertainty, changed unit, kind or value (an
    /// integer or a label), or went missing — a key or a whole scene of OLD that NEW does
    /// not have (unless removals are allowed): a run whose key numbers all vanished is not
    /// "unchanged".
    pub fn any_beyond(&self) -> bool {
        let lost = |r: &Row| r.change == Change::Removed && self.allow_removed;
        self.rows.iter().any(|r| r.change.is_beyond() && !lost(r))
            || (!self.allow_removed && !self.scenes_removed.is_empty())
    }

    /// The rows of one kind of change.
    pub fn rows_where(&self, keep: impl Fn(&Change) -> bool) -> Vec<&Row> {
        self.rows.iter().filter(|r| keep(&r.change)).collect()
    }
}

/// Compares `old` with `new` scene by scene. Fails when a scene is on both sides at
/// different resolutions (its numbers would differ by resolution, not by a change), saying
/// which.
///
/// # Errors
/// A message naming the scene when it is on both sides at different resolutions.
pub fn compare(old: &[SceneKeys], new: &[SceneKeys]) -> Result<Diff, String> {
    let mut diff = Diff::default();
    // one scene against a collection that has it: compare that scene alone
    let single = |one: &[SceneKeys], many: &[SceneKeys]| {
        (one.len() == 1 && many.len() > 1 && many.iter().any(|m| m.scene == one[0].scene))
            .then(|| one[0].scene.clone())
    };
    let only = single(new, old).or_else(|| single(old, new));
    let keep = |s: &&SceneKeys| only.as_ref().is_none_or(|o| &s.scene == o);
    let old: Vec<&SceneKeys> = old.iter().filter(keep).collect();
    let new: Vec<&SceneKeys> = new.iter().filter(keep).collect();
    diff.only_scene = only;
    for n in &new {
        match old.iter().find(|o| o.scene == n.scene) {
            None => diff.scenes_added.push(n.scene.clone()),
            Some(o) => {
                if let (Some(a), Some(b)) = (&o.resolution, &n.resolution) {
                    if a != b {
                        return Err(format!(
                            "scene {} at {a} resolution in OLD, {b} in NEW",
                            n.scene
                        ));
                    }
                }
                diff.rows
                    .extend(compare_numbers(&n.scene, &o.numbers, &n.numbers));
            }
        }
    }
    for o in &old {
        if !new.iter().any(|n| n.scene == o.scene) {
            diff.scenes_removed.push(o.scene.clone());
        }
    }
    Ok(diff)
}

/// Compares one scene's numbers key by key: the new set's keys in order, then those only
/// in the old set.
pub fn compare_numbers(scene: &str, old: &KeyNumbers, new: &KeyNumbers) -> Vec<Row> {
    // keys looked up by name in a map: linear in the number of keys (a search per key
    // took 70 s at 80 000)
    let old_by_key: std::collections::HashMap<&str, &KeyValue> =
        old.0.iter().map(|(k, v)| (k.as_str(), v)).collect();
    let new_keys: std::collections::HashSet<&str> = new.0.iter().map(|(k, _)| k.as_str()).collect();
    let row = |key: &str, o: Option<&KeyValue>, n: Option<&KeyValue>, change| Row {
        scene: scene.to_string(),
        key: key.to_string(),
        name: crate::results::names::name(scene, key),
        old: o.map(ToString::to_string),
        new: n.map(ToString::to_string),
        change,
        old_value: o.cloned(),
        new_value: n.cloned(),
    };
    let mut rows: Vec<Row> = new
        .0
        .iter()
        .map(|(key, n)| match old_by_key.get(key.as_str()) {
            None => row(key, None, Some(n), Change::Added),
            Some(o) => row(key, Some(o), Some(n), compare_values(o, n)),
        })
        .collect();
    for (key, o) in &old.0 {
        if !new_keys.contains(key.as_str()) {
            rows.push(row(key, Some(o), None, Change::Removed));
        }
    }
    rows
}

/// Half a unit in the last printed digit of a cited value: how far its rounding may have
/// moved it.
pub fn rounding(c: &Cited) -> f64 {
    if c.value == 0.0 || !c.value.is_finite() {
        return 0.0;
    }
    0.5 * 10f64.powf(c.value.abs().log10().floor() - c.digits as f64 + 1.0)
}

/// |new − old| and what the two values' uncertainties and roundings allow (plus a few
/// units of f64 round-off, since printed decimals are not exact binary numbers: a change of
/// one unit in the last digit of an exact number must read as within its rounding).
fn moved_allowed(o: &Cited, n: &Cited) -> (f64, f64) {
    let moved = (n.value - o.value).abs();
    let representation = 4.0 * f64::EPSILON * o.value.abs().max(n.value.abs());
    let allowed =
        o.uncertainty.value + n.uncertainty.value + rounding(o) + rounding(n) + representation;
    (moved, allowed)
}

/// The change from `o` to `n`.
pub fn compare_values(o: &KeyValue, n: &KeyValue) -> Change {
    let floats = |o: &Cited, n: &Cited| -> Change {
        if o.unit != n.unit {
            return Change::UnitChanged;
        }
        let (printed_move, allowed) = moved_allowed(o, n);
        // At full precision (both sides record the computed value and the method's own
        // uncertainty): unchanged means reproduced within the reproducibility tolerance
        // (results::record), whatever the printing; otherwise, as printed.
        let recorded = |c: &Cited| c.method.basis != crate::base::report::NOT_RECORDED;
        let (moved, unchanged) = if recorded(o) && recorded(n) {
            let moved = (n.computed - o.computed).abs();
            let tolerance =
                crate::results::record::tolerance(o).max(crate::results::record::tolerance(n));
            (moved, moved <= tolerance)
        } else {
            (printed_move, printed_move == 0.0)
        };
        if unchanged {
            Change::Unchanged
        } else if moved <= allowed {
            Change::Within { moved, allowed }
        } else {
            Change::Beyond { moved, allowed }
        }
    };
    match (o, n) {
        // a label and an integer that read the same are the same value (a scene writes the
        // label "4", its snapshot reads back the integer 4)
        (KeyValue::Integer(a), KeyValue::Text(b)) | (KeyValue::Text(b), KeyValue::Integer(a))
            if a.to_string() == *b =>
        {
            Change::Unchanged
        }
        (KeyValue::Integer(a), KeyValue::Integer(b)) if a == b => Change::Unchanged,
        (KeyValue::Integer(_), KeyValue::Integer(_)) => Change::Changed,
        (KeyValue::Text(a), KeyValue::Text(b)) if a == b => Change::Unchanged,
        (KeyValue::Text(_), KeyValue::Text(_)) => Change::Changed,
        (KeyValue::Float(a), KeyValue::Float(b)) => floats(a, b),
        (KeyValue::Series(a), KeyValue::Series(b)) if a.len() == b.len() => {
            // the element that moved most against its allowance speaks for the list
            let mut worst = Change::Unchanged;
            let mut worst_ratio = 0.0;
            for (x, y) in a.iter().zip(b) {
                let c = floats(x, y);
                let ratio = match c {
                    Change::UnitChanged => return c,
                    Change::Unchanged => 0.0,
                    Change::Within { moved, allowed } | Change::Beyond { moved, allowed } => {
                        if allowed > 0.0 {
                            moved / allowed
                        } else {
                            f64::INFINITY
                        }
                    }
                    _ => 0.0,
                };
                if ratio > worst_ratio || (worst == Change::Unchanged && c != worst) {
                    worst = c;
                    worst_ratio = ratio;
                }
            }
            worst
        }
        _ => Change::KindChanged,
    }
}

/// `moved / allowed` as a factor for a reader ("0.3×", "2 × 10⁶×").
pub fn factor(moved: f64, allowed: f64) -> String {
    if allowed <= 0.0 {
        return "—".into();
    }
    format!("{}×", crate::base::report::pretty(moved / allowed, 2))
}

/// The comparison for a terminal: what moved beyond its uncertainty first, then what moved
/// within it, then what changed kind, was added or removed, and a count of the rest.
pub fn to_text(d: &Diff) -> String {
    let mut s = String::new();
    let section =
        |s: &mut String, title: &str, rows: Vec<&Row>, detail: &dyn Fn(&Row) -> String| {
            if rows.is_empty() {
                return;
            }
            s.push_str(&format!("{title} ({}):\n", rows.len()));
            for r in rows {
                // the name to read, and the key to type when it differs
                let key = match r.name == r.key {
                    true => String::new(),
                    false => format!(" (key \"{}\")", r.key),
                };
                s.push_str(&format!("  {} / {}{key}: {}\n", r.scene, r.name, detail(r)));
            }
        };
    let arrow = |r: &Row| {
        format!(
            "{} → {}",
            r.old.as_deref().unwrap_or("—"),
            r.new.as_deref().unwrap_or("—")
        )
    };
    let moved = |r: &Row| match r.change {
        Change::Within { moved, allowed } | Change::Beyond { moved, allowed } => format!(
            "{}  (moved {:.1e}, allowed {:.1e}: {})",
            arrow(r),
            moved,
            allowed,
            factor(moved, allowed)
        ),
        _ => arrow(r),
    };
    section(
        &mut s,
        "moved beyond its uncertainty",
        d.rows_where(|c| matches!(c, Change::Beyond { .. })),
        &moved,
    );
    section(
        &mut s,
        "changed (integers and labels)",
        d.rows_where(|c| *c == Change::Changed),
        &arrow,
    );
    section(
        &mut s,
        "not comparable (unit or kind changed)",
        d.rows_where(|c| matches!(c, Change::UnitChanged | Change::KindChanged)),
        &arrow,
    );
    section(
        &mut s,
        "moved within its uncertainty",
        d.rows_where(|c| matches!(c, Change::Within { .. })),
        &moved,
    );
    section(
        &mut s,
        "added",
        d.rows_where(|c| *c == Change::Added),
        &|r: &Row| r.new.clone().unwrap_or_default(),
    );
    section(
        &mut s,
        if d.allow_removed {
            "removed (allowed)"
        } else {
            "removed (only in OLD: a change)"
        },
        d.rows_where(|c| *c == Change::Removed),
        &|r: &Row| r.old.clone().unwrap_or_default(),
    );
    for (title, scenes) in [
        ("scenes only in NEW", &d.scenes_added),
        ("scenes only in OLD", &d.scenes_removed),
    ] {
        if !scenes.is_empty() {
            s.push_str(&format!("{title}: {}\n", scenes.join(", ")));
        }
    }
    if let Some(scene) = &d.only_scene {
        s.push_str(&format!(
            "compared scene {scene} alone (one side holds only it)\n"
        ));
    }
    let unchanged = d.rows_where(|c| *c == Change::Unchanged).len();
    let beyond = d
        .rows
        .iter()
        .filter(|r| r.change.is_beyond() && !(d.allow_removed && r.change == Change::Removed))
        .count();
    s.push_str(&format!(
        "{} numbers compared: {beyond} beyond uncertainty or changed, {} within, {unchanged} unchanged\n",
        d.rows.len(),
        d.rows_where(|c| matches!(c, Change::Within { .. })).len(),
    ));
    s
}

/// The comparison as JSON: every row (scene, key, name, old, new, change, moved, allowed), the
/// scenes on one side only, and the verdict `beyond_uncertainty`.
pub fn to_json(d: &Diff) -> serde_json::Value {
    serde_json::json!({
        "beyond_uncertainty": d.any_beyond(),
        "rows": d.rows,
        "scenes_added": d.scenes_added,
        "scenes_removed": d.scenes_removed,
        "only_scene": d.only_scene,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::base::report::Uncertainty;

    fn float(x: f64, u: f64, unit: &str) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        k.cited("x", x, 6, Uncertainty::new(u, "test"), unit);
        k
    }

    #[test]
    fn a_move_is_judged_against_both_uncertainties_and_roundings() {
        // kept to 4 figures (± 1e-3 supports no more): 1.000 against 1.002 moved 2e-3, within
        // 1e-3 + 1e-3 + 2 × 5e-4 of rounding; 1.000 against 1.006 is beyond
        let c = compare_numbers("s", &float(1.0, 1e-3, "T"), &float(1.002, 1e-3, "T"));
        assert!(matches!(c[0].change, Change::Within { .. }), "{c:?}");
        let c = compare_numbers("s", &float(1.0, 1e-3, "T"), &float(1.006, 1e-3, "T"));
        assert!(matches!(c[0].change, Change::Beyond { .. }), "{c:?}");
        let c = compare_numbers("s", &float(1.0, 1e-3, "T"), &float(1.0, 1e-3, "A"));
        assert_eq!(c[0].change, Change::UnitChanged);
    }

    #[test]
    fn an_exact_number_may_move_by_its_rounding_only() {
        // printed to 6 figures, 1.23457 and 1.23458: one unit of the last digit is the
        // two roundings of 5e-6; two units are beyond
        let c = compare_values(
            &float(1.234567, 0.0, "").0[0].1,
            &float(1.234584, 0.0, "").0[0].1,
        );
        assert!(matches!(c, Change::Within { .. }), "{c:?}");
        let c = compare_values(
            &float(1.234567, 0.0, "").0[0].1,
            &float(1.234599, 0.0, "").0[0].1,
        );
        assert!(c.is_beyond(), "{c:?}");
    }
}
