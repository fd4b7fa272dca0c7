//! Key numbers read back: from the `key_numbers` object of a `key_numbers.json`
//! ([`KeyNumbers::from_json`]) and from the snapshot text the tests commit
//! ([`KeyNumbers::from_snapshot`]), in their order.

use super::{
    supported_digits, Cited, KeyNumbers, KeyValue, Uncertainty, NOT_RECORDED, SNAPSHOT_BASIS_INDENT,
};
use serde_json::Value;

impl KeyNumbers {
    /// Reads back the object [`KeyNumbers::to_json`] writes (the `key_numbers` member of a
    /// `key_numbers.json`), in its order. A series written before its `digits` were
    /// recorded gets the digits its uncertainties support.
    ///
    /// # Errors
    /// A message naming the key when `value` is not an object, an entry is neither a float with
    /// its uncertainty nor an integer or text, a series' lists differ in length, a value or
    /// uncertainty is not finite (or ± < 0), or `digits` is not 1 to 17.
    pub fn from_json(value: &Value) -> Result<Self, String> {
        let object = value
            .as_object()
            .ok_or("key numbers: expected an object of named numbers")?;
        let mut out = KeyNumbers::default();
        for (key, entry) in object {
            let bad = |what: &str| format!("key number \"{key}\": {what}");
            let text = |name: &str| entry.get(name).and_then(Value::as_str).unwrap_or("");
            let float = |v: &Value| v.as_f64().filter(|x| x.is_finite());
            // the method's own uncertainty, where the file records it
            let method = |good_to: Option<&Value>| match good_to.and_then(float) {
                Some(g) if g >= 0.0 => Uncertainty::new(g, text("good_to_basis")),
                _ => Uncertainty::new(0.0, NOT_RECORDED),
            };
            let value = if let Some(values) = entry.get("values") {
                let values = values
                    .as_array()
                    .ok_or_else(|| bad("values is not a list"))?;
                let us = entry
                    .get("uncertainties")
                    .and_then(Value::as_array)
                    .ok_or_else(|| bad("a series needs its uncertainties"))?;
                if us.len() != values.len() {
                    return Err(bad("as many uncertainties as values are needed"));
                }
                let digits = entry.get("digits").and_then(Value::as_array);
                let computed = entry.get("computed").and_then(Value::as_array);
                let mut cited = Vec::with_capacity(values.len());
                for (i, (v, u)) in values.iter().zip(us).enumerate() {
                    let (v, u) = match (float(v), float(u)) {
                        (Some(v), Some(u)) if u >= 0.0 => (v, u),
                        _ => return Err(bad("values and uncertainties must be finite, ± ≥ 0")),
                    };
                    let d = match digits.and_then(|d| d.get(i)) {
                        Some(d) => digits_of(d).ok_or_else(|| bad("digits from 1 to 17"))?,
                        None => supported_digits(v, u),
                    };
                    cited.push(Cited {
                        value: v,
                        computed: computed.and_then(|c| c.get(i)).and_then(float).unwrap_or(v),
                        digits: d,
                        uncertainty: Uncertainty::new(u, text("uncertainty_basis")),
                        unit: text("unit").to_string(),
                        method: method(entry.get("good_to").and_then(|g| g.get(i))),
                    });
                }
                KeyValue::Series(cited)
            } else if let Some(u) = entry.get("uncertainty") {
                let v = entry.get("value").and_then(float);
                match (v, float(u)) {
                    (Some(v), Some(u)) if u >= 0.0 => KeyValue::Float(Cited {
                        value: v,
                        computed: entry.get("computed").and_then(float).unwrap_or(v),
                        digits: match entry.get("digits") {
                            Some(d) => digits_of(d).ok_or_else(|| bad("digits from 1 to 17"))?,
                            None => supported_digits(v, u),
                        },
                        uncertainty: Uncertainty::new(u, text("uncertainty_basis")),
                        unit: text("unit").to_string(),
                        method: method(entry.get("good_to")),
                    }),
                    _ => return Err(bad("value and uncertainty must be finite, ± ≥ 0")),
                }
            } else {
                match entry.get("value") {
                    Some(Value::String(s)) => KeyValue::Text(s.clone()),
                    Some(v) if v.is_i64() => KeyValue::Integer(v.as_i64().unwrap_or_default()),
                    _ => {
                        return Err(bad(
                            "expected {\"value\": integer or text} or a float with its uncertainty",
                        ))
                    }
                }
            };
            out.0.push((key.clone(), value));
        }
        Ok(out)
    }

    /// Reads back the lines [`KeyNumbers::to_snapshot`] writes (the body of an insta
    /// snapshot; its `---` header is skipped). The snapshot keeps less than the JSON: each
    /// uncertainty to one figure (rounded up when printed, so read as it stands), its basis
    /// on the next line, and a label that reads as a number is
    /// taken for one. A key may itself contain " = " (`eps where k = k2`): the split is the
    /// first after which the rest reads as a number, else the first.
    ///
    /// # Errors
    /// A message naming the line when the `---` header is not closed, a line has no ` = `, or a
    /// basis line follows no number.
    pub fn from_snapshot(text: &str) -> Result<Self, String> {
        let mut lines: Vec<&str> = text.lines().collect();
        if lines.first() == Some(&"---") {
            let end = lines[1..]
                .iter()
                .position(|l| *l == "---")
                .ok_or("snapshot: its header is not closed by ---")?;
            lines.drain(..end + 2);
        }
        let mut out = KeyNumbers::default();
        for (n, line) in lines.iter().enumerate() {
            if line.trim().is_empty() {
                continue;
            }
            // the basis of the uncertainty of the number above
            if let Some(basis) = line
                .strip_prefix(SNAPSHOT_BASIS_INDENT)
                .and_then(|b| b.strip_prefix('('))
                .and_then(|b| b.strip_suffix(')'))
            {
                match out.0.last_mut() {
                    Some((_, KeyValue::Float(c))) => c.uncertainty.basis = basis.to_string(),
                    Some((_, KeyValue::Series(v))) => {
                        for c in v {
                            c.uncertainty.basis = basis.to_string();
                        }
                    }
                    _ => return Err(format!("snapshot line {}: a basis with no number", n + 1)),
                }
                continue;
            }
            let splits: Vec<usize> = line.match_indices(" = ").map(|(i, _)| i).collect();
            let Some(&first) = splits.first() else {
                return Err(format!("snapshot line {}: expected `key = value`", n + 1));
            };
            let parsed = splits.iter().find_map(|&i| {
                parse_snapshot_number(&line[i + 3..]).map(|v| (line[..i].to_string(), v))
            });
            out.0.push(parsed.unwrap_or_else(|| {
                (
                    line[..first].to_string(),
                    KeyValue::Text(line[first + 3..].to_string()),
                )
            }));
        }
        Ok(out)
    }
}

/// A digit count as JSON (1 to 17).
fn digits_of(v: &Value) -> Option<usize> {
    v.as_u64()
        .filter(|d| (1..=17).contains(d))
        .map(|d| d as usize)
}

/// `1.23e0 ± 3e-12 unit`, `1.23e0 (exact) unit`, an integer, or `[a ± u, …] unit`, as
/// printed by [`KeyValue`]'s `Display`; `None` for anything else (a label).
fn parse_snapshot_number(text: &str) -> Option<KeyValue> {
    if let Ok(i) = text.parse::<i64>() {
        return Some(KeyValue::Integer(i));
    }
    if let Some(body) = text.strip_prefix('[') {
        let (items, unit) = body.split_once(']')?;
        let unit = unit.strip_prefix(' ').unwrap_or(unit);
        let cited = items
            .split(", ")
            .map(|item| {
                let (v, u) = item.split_once(" ± ")?;
                cited_from_text(v, Some(u), unit)
            })
            .collect::<Option<Vec<_>>>()?;
        return Some(KeyValue::Series(cited));
    }
    let (mantissa, rest) = text.split_once(' ')?;
    if let Some(unit) = rest.strip_prefix("(exact)") {
        return cited_from_text(mantissa, None, unit.trim_start()).map(KeyValue::Float);
    }
    let rest = rest.strip_prefix("± ")?;
    let (u, unit) = rest.split_once(' ').unwrap_or((rest, ""));
    cited_from_text(mantissa, Some(u), unit).map(KeyValue::Float)
}

/// A float printed as `d.ddde±x` with its printed uncertainty (one figure), or exact.
fn cited_from_text(value: &str, uncertainty: Option<&str>, unit: &str) -> Option<Cited> {
    let (mantissa, _) = value.split_once('e')?;
    let x: f64 = value.parse().ok().filter(|x: &f64| x.is_finite())?;
    let digits = mantissa.chars().filter(char::is_ascii_digit).count().max(1);
    let (u, basis) = match uncertainty {
        None => (0.0, "exact"),
        Some(u) => {
            let u: f64 = u
                .parse()
                .ok()
                .filter(|u: &f64| u.is_finite() && *u >= 0.0)?;
            // printed rounded up to one figure, so the printed value is itself a bound
            (u, "as printed in a snapshot (one figure, rounded up)")
        }
    };
    Some(Cited {
        value: x,
        computed: x,
        digits,
        uncertainty: Uncertainty::new(u, basis),
        unit: unit.to_string(),
        method: Uncertainty::new(0.0, NOT_RECORDED),
    })
}
