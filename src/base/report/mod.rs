//! Key numbers of a scene as citable values: each float with its uncertainty, how that
//! uncertainty was obtained, its unit, and the significant figures the method resolves;
//! integers and labels exact. For `--json`, `cantilever cite`, the book's prose and tables
//! (by name), and the snapshots.

mod read;

use serde::Serialize;
use serde_json::{json, Map, Value};

/// How well a number is known, and how we know.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Uncertainty {
    /// An absolute bound or estimate (≥ 0), in the number's unit.
    pub value: f64,
    /// How it was obtained: a round-off bound, a convergence estimate from a refinement
    /// study, the grid interval of a sweep, the agreement of two independent methods, a
    /// certificate…
    pub basis: String,
}

impl Uncertainty {
    /// An uncertainty of `value` (absolute) obtained by `basis`.
    pub fn new(value: f64, basis: impl Into<String>) -> Self {
        Self {
            value: value.abs(),
            basis: basis.into(),
        }
    }

    /// A round-off bound: `relative` of |x|, for the reason given.
    pub fn round_off(x: f64, relative: f64, why: &str) -> Self {
        Self::new(x.abs() * relative, format!("round-off bound: {why}"))
    }
}

/// A cited float.
#[derive(Debug, Clone, Serialize)]
pub struct Cited {
    /// The value, rounded to `digits` significant figures.
    pub value: f64,
    /// The value as computed, before rounding (read back from a file: the printed value).
    pub computed: f64,
    /// Significant figures kept (never more than the uncertainty supports).
    pub digits: usize,
    /// The uncertainty of `value`: the method's, plus the rounding to `digits` when that
    /// is larger (so |value − computed| ≤ uncertainty always holds).
    pub uncertainty: Uncertainty,
    /// The unit or scale ("" for a pure number).
    pub unit: String,
    /// The method's own uncertainty of `computed`, before any widening by the rounding
    /// (what "the computed value is good to …" states; read back from a file that does not
    /// record it: 0, [`NOT_RECORDED`]). Not part of a value's identity.
    #[serde(skip)]
    pub method: Uncertainty,
}

impl PartialEq for Cited {
    fn eq(&self, other: &Self) -> bool {
        (
            self.value,
            self.computed,
            self.digits,
            &self.uncertainty,
            &self.unit,
        ) == (
            other.value,
            other.computed,
            other.digits,
            &other.uncertainty,
            &other.unit,
        )
    }
}

impl Cited {
    /// `computed` to `digits` figures (fewer if `uncertainty` does not support them), its
    /// uncertainty widened by the rounding when the rounding is the larger: a printed
    /// value never lies outside its own uncertainty.
    pub fn new(computed: f64, digits: usize, uncertainty: Uncertainty, unit: &str) -> Self {
        let digits = digits
            .min(supported_digits(computed, uncertainty.value))
            .max(1);
        let value = round_sig(computed, digits);
        let method = uncertainty.clone();
        let rounding = (value - computed).abs();
        let uncertainty = if rounding > uncertainty.value {
            Uncertainty::new(
                uncertainty.value + rounding,
                format!(
                    "the rounding to {digits} figures (the computed value is good to {}: {})",
                    format_sig(uncertainty.value, 1),
                    uncertainty.basis,
                ),
            )
        } else {
            uncertainty
        };
        Self {
            value,
            computed,
            digits,
            uncertainty,
            unit: unit.to_string(),
            method,
        }
    }
}

/// The basis of [`Cited::method`] read back from a file that does not record it.
pub const NOT_RECORDED: &str = "not recorded";

/// One key number.
#[derive(Debug, Clone, PartialEq)]
pub enum KeyValue {
    /// An exact integer (mode counts, orbit periods, impact counts).
    Integer(i64),
    /// A float with its uncertainty.
    Float(Cited),
    /// A label.
    Text(String),
    /// A list of cited floats (a spectrum, a profile), in order.
    Series(Vec<Cited>),
}

/// What a unit of the key numbers means (the paper's non-dimensional beam: length, time
/// and stiffness scaled as in its §2).
pub fn unit_meaning(unit: &str) -> Option<&'static str> {
    Some(match unit {
        "A_free" => {
            "A_free, the amplitude of the tip without the stop (the linear steady response) \
             at the scene's forcing frequency ω and amplitude"
        }
        "ωA_free" => "ω·A_free, the tip's velocity amplitude without the stop",
        "T" => "the forcing period 2π/ω (a time given as a fraction of it)",
        "k₁" => "k₁ = (β₁⁻)⁴ ≈ 12.3624, the first modal stiffness of the free cantilever",
        _ => return None,
    })
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

/// The significant figures of `x` down to the leading digit of its uncertainty `u` (the
/// convention "value ± u" with the last digit at u's place; at least 1, at most 15).
pub fn supported_digits(x: f64, u: f64) -> usize {
    if u <= 0.0 || x == 0.0 || !x.is_finite() {
        return 15;
    }
    let d = x.abs().log10().floor() - u.log10().floor() + 1.0;
    d.clamp(1.0, 15.0) as usize
}

/// An uncertainty to one significant figure, rounded *up* (a printed ± never claims
/// more than is known): 2.1e-12 → 3e-12, 9.96e-5 → 1e-4.
pub fn round_up_one_figure(u: f64) -> f64 {
    if u <= 0.0 || !u.is_finite() {
        return u;
    }
    let e = u.log10().floor();
    let scale = 10f64.powf(e);
    // (a mantissa within round-off of an integer is that integer, not the next one)
    let m = (u / scale * (1.0 - 4.0 * f64::EPSILON)).ceil();
    format_sig(m * scale, 1).parse().unwrap_or(u)
}

/// An integer as superscript characters: -12 → "⁻¹²" (for 10ⁿ in prose and on plot axes).
pub fn superscript(n: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    n.to_string()
        .chars()
        .map(|c| c.to_digit(10).map_or('⁻', |d| DIGITS[d as usize]))
        .collect()
}

/// x to `digits` significant figures for prose: plain for moderate magnitudes, a × 10ⁿ
/// beyond.
pub fn pretty(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return x.to_string();
    }
    let e = x.abs().log10().floor() as i32;
    if (-3..6).contains(&e) {
        let decimals = (digits as i32 - 1 - e).max(0) as usize;
        return format!("{x:.decimals$}");
    }
    // the exponent of the *rounded* value: 9.96e-5 to one figure is 1 × 10⁻⁴, not
    // "10 × 10⁻⁵"
    let x = round_sig(x, digits.max(1));
    let e = x.abs().log10().floor() as i32;
    let mantissa = x / 10f64.powi(e);
    let superscript = superscript(e);
    if digits <= 1 && (mantissa - 1.0).abs() < 1e-12 {
        format!("10{superscript}")
    } else {
        format!("{:.*} × 10{superscript}", digits.max(1) - 1, mantissa)
    }
}

impl KeyValue {
    /// The value for prose: the number to its figures (with ± its uncertainty and its unit
    /// if `with_uncertainty`), an integer, or a label.
    pub fn prose(&self, with_uncertainty: bool) -> String {
        match self {
            KeyValue::Integer(i) => i.to_string(),
            KeyValue::Text(t) => t.clone(),
            KeyValue::Series(v) => v
                .iter()
                .map(|c| pretty(c.value, c.digits))
                .collect::<Vec<_>>()
                .join(", "),
            KeyValue::Float(c) if !with_uncertainty => pretty(c.value, c.digits),
            KeyValue::Float(c) => {
                let unit = if c.unit.is_empty() {
                    String::new()
                } else {
                    format!(" {}", c.unit)
                };
                if c.uncertainty.value > 0.0 {
                    format!(
                        "{} ± {}{unit}",
                        pretty(c.value, c.digits),
                        pretty(round_up_one_figure(c.uncertainty.value), 1)
                    )
                } else {
                    format!("{}{unit}", pretty(c.value, c.digits))
                }
            }
        }
    }
}

impl std::fmt::Display for KeyValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            KeyValue::Integer(i) => write!(f, "{i}"),
            KeyValue::Float(c) => {
                write!(f, "{}", format_sig(c.value, c.digits))?;
                if c.uncertainty.value > 0.0 {
                    let u = round_up_one_figure(c.uncertainty.value);
                    write!(f, " ± {}", format_sig(u, 1))?;
                } else {
                    write!(f, " (exact)")?;
                }
                if !c.unit.is_empty() {
                    write!(f, " {}", c.unit)?;
                }
                Ok(())
            }
            KeyValue::Text(s) => write!(f, "{s}"),
            KeyValue::Series(v) => {
                let items: Vec<String> = v
                    .iter()
                    .map(|c| {
                        format!(
                            "{} ± {}",
                            format_sig(c.value, c.digits),
                            format_sig(round_up_one_figure(c.uncertainty.value), 1)
                        )
                    })
                    .collect();
                write!(f, "[{}]", items.join(", "))?;
                match v.first() {
                    Some(c) if !c.unit.is_empty() => write!(f, " {}", c.unit),
                    _ => Ok(()),
                }
            }
        }
    }
}

/// The indent of a snapshot line that gives the basis of the uncertainty above it.
const SNAPSHOT_BASIS_INDENT: &str = "    ";

/// An ordered list of named key numbers.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct KeyNumbers(pub Vec<(String, KeyValue)>);

impl KeyNumbers {
    /// Adds a float kept to `digits` significant figures (fewer if its uncertainty does not
    /// support them), with its uncertainty and unit.
    pub fn cited(
        &mut self,
        name: impl Into<String>,
        value: f64,
        digits: usize,
        uncertainty: Uncertainty,
        unit: &str,
    ) {
        self.0.push((
            name.into(),
            KeyValue::Float(Cited::new(value, digits, uncertainty, unit)),
        ));
    }

    /// Adds a value already cited (rounded, its rounding folded into its uncertainty).
    pub fn push(&mut self, name: impl Into<String>, value: Cited) {
        self.0.push((name.into(), KeyValue::Float(value)));
    }

    /// Adds the unit of a forced scene's lengths and velocities: the free tip amplitude
    /// A_free at the scene's ω (keys `"{prefix}A_free"` and `"{prefix}omega A_free"`), in the
    /// model's length unit, the free tip amplitude at resonance.
    pub fn free_amplitude(&mut self, prefix: &str, (a_free, v_free): (f64, f64)) {
        let basis = "closed form of the linear steady response (round-off)";
        self.cited(
            format!("{prefix}A_free"),
            a_free,
            6,
            Uncertainty::new(a_free * 1e-15, basis),
            "× the free tip amplitude at resonance",
        );
        self.cited(
            format!("{prefix}omega A_free"),
            v_free,
            6,
            Uncertainty::new(v_free * 1e-15, basis),
            "× the free tip amplitude at resonance per unit time",
        );
    }

    /// Adds a list of floats, each kept to the digits its uncertainty supports (at most
    /// `digits`), with one unit and one basis for the uncertainties.
    pub fn series(
        &mut self,
        name: impl Into<String>,
        values: &[(f64, f64)],
        digits: usize,
        basis: &str,
        unit: &str,
    ) {
        let cited = values
            .iter()
            .map(|&(value, u)| Cited::new(value, digits, Uncertainty::new(u, basis), unit))
            .collect();
        self.0.push((name.into(), KeyValue::Series(cited)));
    }

    /// Adds an integer.
    pub fn integer(&mut self, name: impl Into<String>, value: i64) {
        self.0.push((name.into(), KeyValue::Integer(value)));
    }

    /// Adds a label.
    pub fn text(&mut self, name: impl Into<String>, value: impl Into<String>) {
        self.0.push((name.into(), KeyValue::Text(value.into())));
    }

    /// The number called `name`.
    pub fn get(&self, name: &str) -> Option<&KeyValue> {
        self.0.iter().find(|(k, _)| k == name).map(|(_, v)| v)
    }

    /// `name = value ± uncertainty unit` lines: the snapshot format (the uncertainty to one
    /// figure, rounded up, so a last-digit change of an estimate does not show), each
    /// uncertain float followed by an indented line `    (how the uncertainty was
    /// obtained)` — so that the committed snapshots carry all a citation needs.
    pub fn to_snapshot(&self) -> String {
        let mut out = String::new();
        for (k, v) in &self.0 {
            out += &format!("{k} = {v}\n");
            let basis = match v {
                KeyValue::Float(c) if c.uncertainty.value > 0.0 => Some(&c.uncertainty.basis),
                KeyValue::Series(s) => s
                    .iter()
                    .find(|c| c.uncertainty.value > 0.0)
                    .map(|c| &c.uncertainty.basis),
                _ => None,
            };
            if let Some(b) = basis.filter(|b| !b.is_empty()) {
                out += &format!("{SNAPSHOT_BASIS_INDENT}({})\n", b.replace('\n', " "));
            }
        }
        out
    }

    /// A JSON object in insertion order: each entry {"value": …} for integers and labels,
    /// {"value", "uncertainty", "uncertainty_basis", "unit", "digits"} for floats.
    pub fn to_json(&self) -> Value {
        let mut m = Map::new();
        for (k, v) in &self.0 {
            let v = match v {
                KeyValue::Integer(i) => json!({ "value": i }),
                KeyValue::Text(s) => json!({ "value": s }),
                KeyValue::Series(v) => json!({
                    "values": v.iter().map(|c| c.value).collect::<Vec<_>>(),
                    "computed": v.iter().map(|c| c.computed).collect::<Vec<_>>(),
                    "uncertainties": v.iter().map(|c| c.uncertainty.value).collect::<Vec<_>>(),
                    "uncertainty_basis": v.first().map(|c| c.uncertainty.basis.clone()),
                    "digits": v.iter().map(|c| c.digits).collect::<Vec<_>>(),
                    "good_to": v.iter().map(|c| c.method.value).collect::<Vec<_>>(),
                    "good_to_basis": v.first().map(|c| c.method.basis.clone()),
                    "unit": v.first().map(|c| c.unit.clone()),
                    "unit_meaning": v.first().and_then(|c| unit_meaning(&c.unit)),
                }),
                KeyValue::Float(c) => json!({
                    "value": c.value,
                    "computed": c.computed,
                    "uncertainty": c.uncertainty.value,
                    "uncertainty_basis": c.uncertainty.basis,
                    "unit": c.unit,
                    "unit_meaning": unit_meaning(&c.unit),
                    "digits": c.digits,
                    "good_to": c.method.value,
                    "good_to_basis": c.method.basis,
                }),
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

    #[test]
    fn digits_never_exceed_what_the_uncertainty_supports() {
        // 1.2345678 ± 3e-4: the last digit kept is at the 1e-4 place, uncertain by 3
        assert_eq!(supported_digits(1.2345678, 3e-4), 5);
        let mut k = KeyNumbers::default();
        k.cited("x", 1.2345678, 12, Uncertainty::new(3e-4, "test"), "m");
        assert_eq!(k.to_snapshot(), "x = 1.2346e0 ± 3e-4 m\n    (test)\n");
        // and reads back with its basis
        let back = KeyNumbers::from_snapshot(&k.to_snapshot()).unwrap();
        let Some(KeyValue::Float(c)) = back.get("x") else {
            panic!()
        };
        assert_eq!(
            (c.uncertainty.value, c.uncertainty.basis.as_str()),
            (3e-4, "test")
        );
        assert_eq!(k.to_json()["x"]["digits"], 5);
    }

    #[test]
    fn a_printed_value_never_lies_outside_its_uncertainty() {
        // 6 figures asked of a number known to 2e-12: the rounding (4e-7) is folded in
        let mut k = KeyNumbers::default();
        k.cited(
            "v",
            1.6020139571539405,
            6,
            Uncertainty::new(2e-12, "test"),
            "",
        );
        let Some(KeyValue::Float(c)) = k.get("v") else {
            panic!()
        };
        assert_eq!(c.value, 1.60201);
        assert!((c.value - c.computed).abs() <= c.uncertainty.value);
        assert!(k
            .to_snapshot()
            .starts_with("v = 1.60201e0 ± 4e-6\n    (the rounding to 6 figures"));
        // uncertainties print rounded up, and the prose formatter rounds before it picks
        // the exponent
        assert_eq!(round_up_one_figure(2.1e-12), 3e-12);
        assert_eq!(round_up_one_figure(3e-4), 3e-4);
        assert_eq!(pretty(9.96e-5, 1), "10⁻⁴");
        assert_eq!(pretty(0.0009996, 2), "1.0 × 10⁻³");
    }
}
