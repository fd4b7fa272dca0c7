//! The published record at the precision of the computation: every float of a scene's key
//! numbers as computed (all 17 digits), with its *reproducibility tolerance* — how far a
//! recomputation of the same code may move it — beside the printed, rounded form the
//! snapshots show.
//!
//! **The tolerance** is the part of the number's error that a recomputation can change,
//! plus an allowance for other platforms and thread counts:
//!
//! - the method's own round-off and solver-tolerance part, when its uncertainty is of that
//!   kind (a round-off bound, a certified or polished event time, an orbit's stroboscopic
//!   or shooting residual, a closed form, a root to a tolerance): what "the computed value
//!   is good to 3e-12" states;
//! - an estimate from a long run's own statistics (the two halves of many iterates of a map):
//!   a platform whose round-off differs follows another trajectory, so its stated
//!   uncertainty;
//! - nothing for a truncation, a grid interval, a model-form range or a fit's standard
//!   error: a recomputation of the same code at the same resolution does not move those;
//! - plus [`PLATFORM_ALLOWANCE`] of the value, for the order of floating-point sums on other
//!   platforms and thread counts (the sweeps are deterministic whatever the thread count, so
//!   on one machine a recomputation is bit for bit the same).
//!
//! Not the truncation or model-form part of the uncertainty, and not the printing: a change
//! of the model or the engine that moves a number by 1e-9 of itself fails the check of
//! every number computed to better than that.

use crate::base::report::{Cited, KeyNumbers, KeyValue, Uncertainty};
use serde_json::{json, Map, Value};

/// The relative allowance for the order of floating-point operations on other platforms and
/// thread counts (the round-off of a sum of ~10⁴ terms, amplified by a moderate condition).
pub const PLATFORM_ALLOWANCE: f64 = 1e-10;

/// The record's format.
pub const FORMAT: &str = "impacting-cantilever published record v1";

/// A float's full-precision value and the method's own uncertainty, from its record entry
/// (`None` when the entry is not a float's).
pub fn read_entry(e: &Value) -> Option<(f64, Uncertainty)> {
    let computed = e["computed"].as_f64()?;
    let good_to = e["good_to"].as_f64()?;
    let basis = e["good_to_basis"].as_str()?;
    Some((computed, Uncertainty::new(good_to, basis)))
}

/// Which part of a number's stated uncertainty a recomputation can change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// Round-off and solver tolerance: the stated uncertainty.
    RoundOff,
    /// A long run's own statistics: the stated uncertainty.
    Trajectory,
    /// Truncation, grid, model form, a fit: none of it.
    Fixed,
}

impl Part {
    /// The part, in words (as the record states it).
    pub fn as_str(self) -> &'static str {
        match self {
            Part::RoundOff => "round-off and solver tolerance",
            Part::Trajectory => "a long run's statistics",
            Part::Fixed => "none (truncation, grid, model form or fit)",
        }
    }
}

/// The part of an uncertainty with this basis that a recomputation can change.
pub fn part(basis: &str) -> Part {
    const ROUND_OFF: [&str; 12] = [
        "round-off",
        "certified",
        "residual",
        "settled to",
        "closed form",
        "closed-form",
        "exact simulation",
        "Brent",
        "secular",
        "monodromy",
        "polished",
        "the two values compared",
    ];
    if basis.contains("iterates of") {
        Part::Trajectory
    } else if ROUND_OFF.iter().any(|w| basis.contains(w)) {
        Part::RoundOff
    } else {
        Part::Fixed
    }
}

/// The reproducibility tolerance of a computed float (see the module doc).
pub fn tolerance(c: &Cited) -> f64 {
    let stated = match part(&c.method.basis) {
        Part::RoundOff | Part::Trajectory => c.method.value,
        Part::Fixed => 0.0,
    };
    stated + PLATFORM_ALLOWANCE * c.computed.abs()
}

fn entry(c: &Cited) -> Value {
    json!({
        "computed": c.computed,
        "tolerance": tolerance(c),
        "part": part(&c.method.basis).as_str(),
        "good_to": c.method.value,
        "good_to_basis": c.method.basis,
    })
}

/// The record of a scene's key numbers: each float as computed with its tolerance, each
/// integer and label as it is.
pub fn record(scene: &str, numbers: &KeyNumbers) -> Value {
    let mut m = Map::new();
    for (key, v) in &numbers.0 {
        let e = match v {
            KeyValue::Float(c) => entry(c),
            KeyValue::Series(s) => Value::Array(s.iter().map(entry).collect()),
            KeyValue::Integer(i) => json!({ "exact": i }),
            KeyValue::Text(t) => json!({ "exact": t }),
        };
        m.insert(key.clone(), e);
    }
    json!({
        "format": FORMAT,
        "scene": scene,
        "platform_allowance": PLATFORM_ALLOWANCE,
        "numbers": m,
    })
}

/// One float against its recorded value: the tolerance is the larger of the record's and
/// the fresh number's own (each states what its run can resolve).
fn check_float(key: &str, old: &Value, new: &Cited, out: &mut Vec<String>) {
    let (Some(x), Some(t)) = (old["computed"].as_f64(), old["tolerance"].as_f64()) else {
        out.push(format!("{key}: the record's entry is not a computed value"));
        return;
    };
    let allowed = t.max(tolerance(new));
    let moved = (new.computed - x).abs();
    // a NaN on either side is a move too
    if moved.is_nan() || moved > allowed {
        out.push(format!(
            "{key}: {x:e} → {:e} (moved {moved:.1e}, its reproducibility tolerance {allowed:.1e}: {:.3}×)",
            new.computed,
            moved / allowed
        ));
    }
}

/// Every difference between a fresh scene's key numbers and its committed record: a float
/// moved beyond its reproducibility tolerance, an integer or label changed, a key gained or
/// lost. Empty: the recomputation reproduces the record.
pub fn check(record: &Value, fresh: &KeyNumbers) -> Vec<String> {
    let mut out = Vec::new();
    if record["format"] != FORMAT {
        return vec![format!("not a record of this format ({FORMAT})")];
    }
    let Some(old) = record["numbers"].as_object() else {
        return vec!["the record has no numbers".into()];
    };
    for (key, v) in &fresh.0 {
        let Some(o) = old.get(key) else {
            out.push(format!("{key}: not in the record (a new key)"));
            continue;
        };
        match v {
            KeyValue::Float(c) => check_float(key, o, c, &mut out),
            KeyValue::Series(s) => match o.as_array() {
                Some(a) if a.len() == s.len() => {
                    for (i, (o, c)) in a.iter().zip(s).enumerate() {
                        check_float(&format!("{key}[{i}]"), o, c, &mut out);
                    }
                }
                _ => out.push(format!("{key}: the record's series has another length")),
            },
            KeyValue::Integer(i) => {
                if o["exact"] != json!(i) {
                    out.push(format!("{key}: {} → {i}", o["exact"]));
                }
            }
            KeyValue::Text(t) => {
                if o["exact"] != json!(t) {
                    out.push(format!("{key}: {} → {t}", o["exact"]));
                }
            }
        }
    }
    for key in old.keys() {
        if fresh.get(key).is_none() {
            out.push(format!("{key}: in the record, not computed (a lost key)"));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbers(x: f64, good_to: f64, basis: &str) -> KeyNumbers {
        let mut k = KeyNumbers::default();
        k.push("v", Cited::new(x, 6, Uncertainty::new(good_to, basis), "T"));
        k.integer("n", 3);
        k
    }

    /// The check can fail: a 1e-9 relative move of a number good to 3e-12 fails, though it
    /// is far inside the printed ± (5e-6, the rounding to six figures); a move within the
    /// round-off part passes; a truncation estimate gives no tolerance beyond the
    /// platform allowance.
    #[test]
    fn a_move_beyond_the_computations_precision_fails_inside_the_printed_one() {
        let x = 3.412_231_234_567;
        let basis = "distance to the periodic orbit (stroboscopic residual) and round-off";
        let rec = record("s", &numbers(x, 3e-12, basis));
        assert!(check(&rec, &numbers(x, 3e-12, basis)).is_empty());
        assert!(check(&rec, &numbers(x + 2e-12, 3e-12, basis)).is_empty());
        let moved = check(&rec, &numbers(x * (1.0 + 1e-9), 3e-12, basis));
        assert_eq!(moved.len(), 1, "{moved:?}");
        let trunc = "change from the order observed one refinement coarser";
        let rec = record("s", &numbers(x, 1e-4, trunc));
        assert!(!check(&rec, &numbers(x * (1.0 + 1e-9), 1e-4, trunc)).is_empty());
        assert!(check(&rec, &numbers(x * (1.0 + 1e-11), 1e-4, trunc)).is_empty());
        // an integer that changes, a key lost
        let mut other = numbers(x, 3e-12, basis);
        other.0[1].1 = KeyValue::Integer(4);
        assert_eq!(
            check(&record("s", &numbers(x, 3e-12, basis)), &other).len(),
            1
        );
        other.0.pop();
        assert_eq!(
            check(&record("s", &numbers(x, 3e-12, basis)), &other).len(),
            1
        );
    }
}
