//! Key numbers of a scene: named values rounded to the significant figures the method
//! resolves, for `--json`, for the book's tables and for insta snapshots.

use serde::Serialize;
use serde_json::{Map, Value};

/// One key number.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum KeyValue {
    /// An exact integer (mode counts, orbit periods, impact counts).
    Integer(i64),
    /// A float rounded to `digits` significant figures.
    Float {
        /// The rounded value.
        value: f64,
        /// Significant figures kept.
        #[serde(skip)]
        digits: usize,
    },
    /// A label.
    Text(String),
}

/// Rounds `x` to `digits` significant figures (the printed digits are exactly these).
pub fn round_sig(x: f64, digits: usize) -> f64 {
    format_sig(x, digits).parse().unwrap_or(x)
}

/// Formats `x` with `digits` significant figures in scientific notation, `1.234e5`.
pub fn format_sig(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    format!("{:.*e}", digits.max(1) - 1, x)
}

impl std::fmt::Display for KeyValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            KeyValue::Integer(i) => write!(f, "{i}"),
            KeyValue::Float { value, digits } => write!(f, "{}", format_sig(*value, *digits)),
            KeyValue::Text(s) => write!(f, "{s}"),
        }
    }
}

/// An ordered list of named key numbers.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct KeyNumbers(pub Vec<(String, KeyValue)>);

impl KeyNumbers {
    /// Adds a float kept to `digits` significant figures.
    pub fn float(&mut self, name: impl Into<String>, value: f64, digits: usize) {
        let value = round_sig(value, digits);
        self.0
            .push((name.into(), KeyValue::Float { value, digits }));
    }

    /// Adds an integer.
    pub fn integer(&mut self, name: impl Into<String>, value: i64) {
        self.0.push((name.into(), KeyValue::Integer(value)));
    }

    /// Adds a label.
    pub fn text(&mut self, name: impl Into<String>, value: impl Into<String>) {
        self.0.push((name.into(), KeyValue::Text(value.into())));
    }

    /// `name = value` lines: the snapshot format.
    pub fn to_snapshot(&self) -> String {
        self.0.iter().map(|(k, v)| format!("{k} = {v}\n")).collect()
    }

    /// A JSON object in insertion order.
    pub fn to_json(&self) -> Value {
        let mut m = Map::new();
        for (k, v) in &self.0 {
            let v = match v {
                KeyValue::Integer(i) => Value::from(*i),
                KeyValue::Float { value, .. } => Value::from(*value),
                KeyValue::Text(s) => Value::from(s.clone()),
            };
            m.insert(k.clone(), v);
        }
        Value::Object(m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn significant_figures_not_decimal_places() {
        assert_eq!(format_sig(1234.5678, 3), "1.23e3");
        assert_eq!(format_sig(0.00012345, 2), "1.2e-4");
        assert_eq!(round_sig(39.27467, 4), 39.27);
    }
}
