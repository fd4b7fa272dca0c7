//! Names in words for the key numbers and the parameters of the scenes: what `cite` prints,
//! what `diff` labels its rows with and what `key_numbers.json` carries beside each key.
//!
//! A key (`N=3 impact_velocity_1`) stays the identifier a user types and the tests compare;
//! its name ("the first impact velocity of the periodic orbit (N = 3)") is how a reader
//! refers to it. A key is read as a few leading qualifiers (`N=3`, `k/k1=1000`, `i=2`,
//! `eps=1.000e-4`, `omega=2`, `k=1e6`, `tol=1e-2`) and a quantity: the quantity is named by
//! the scene's vocabulary (the private module `vocabulary`), or, for a quantity already
//! written in words, by spelling its symbols ([`symbols`]); the qualifiers that the name does
//! not use follow in parentheses. The test below names every published key number of every
//! scene and fails for one whose name keeps a code spelling, or for two keys of a scene with
//! the same name.

pub mod parameters;
mod vocabulary;

/// The qualifiers at the start of a key, in their order, and the rest (the quantity).
#[derive(Debug, Default)]
pub struct Qualifiers {
    /// (symbol, value) as written in the key: ("N", "3"), ("k/k1", "1000"), ("eps", "1.000e-4").
    pub all: Vec<(String, String)>,
}

impl Qualifiers {
    /// The value of qualifier `symbol`.
    pub fn get(&self, symbol: &str) -> Option<&str> {
        self.all
            .iter()
            .find(|(s, _)| s == symbol)
            .map(|(_, v)| v.as_str())
    }

    /// The qualifiers not in `used`, in words: "N = 3, k = 1000k₁".
    fn context(&self, used: &[&str]) -> String {
        self.all
            .iter()
            .filter(|(s, _)| !used.contains(&s.as_str()))
            .map(|(s, v)| qualifier_words(s, v))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The key's leading `symbol=value` tokens (the symbols the scenes use) and its quantity.
pub fn split(key: &str) -> (Qualifiers, &str) {
    const SYMBOLS: [&str; 7] = ["N", "k/k1", "i", "eps", "omega", "k", "tol"];
    let mut q = Qualifiers::default();
    let mut rest = key;
    loop {
        let (token, after) = rest.split_once(' ').unwrap_or((rest, ""));
        match token.split_once('=') {
            Some((s, v)) if SYMBOLS.contains(&s) && !v.is_empty() && !after.is_empty() => {
                q.all
                    .push((s.to_string(), v.trim_end_matches(',').to_string()));
                rest = after;
            }
            _ => return (q, rest),
        }
    }
}

/// One qualifier in words: `N=3` is "N = 3", `k/k1=1000` and `k=1e6` are stop stiffnesses
/// in units of k₁, `eps=1.000e-4` is ε = 10⁻⁴, `tol=1e-2` a tolerance.
fn qualifier_words(symbol: &str, value: &str) -> String {
    match symbol {
        "k/k1" | "k" => format!("k = {}k₁", number(value)),
        "eps" => format!("ε = {}", number(value)),
        "omega" => format!("ω = {}", number(value)),
        "tol" => format!("tolerance {}", number(value)),
        "i" => format!("mode {value}"),
        other => format!("{other} = {}", number(value)),
    }
}

/// A number as a reader writes it: `1e6` is 10⁶, `1.000e-4` is 10⁻⁴, `1.778e-4` is
/// 1.778 × 10⁻⁴; anything else as written.
pub fn number(v: &str) -> String {
    let Some((mantissa, exponent)) = v.split_once('e') else {
        return v.to_string();
    };
    let (Ok(m), Ok(e)) = (mantissa.parse::<f64>(), exponent.parse::<i32>()) else {
        return v.to_string();
    };
    let power = match e {
        0..=2 => 10i32.pow(e as u32).to_string(),
        _ => format!("10{}", superscript(&e.to_string())),
    };
    if m == 1.0 {
        power
    } else {
        format!(
            "{} × {power}",
            mantissa.trim_end_matches('0').trim_end_matches('.')
        )
    }
}

/// Digits and a minus sign as superscripts.
pub fn superscript(s: &str) -> String {
    s.chars()
        .map(|c| match c {
            '-' => '⁻',
            '0' => '⁰',
            '1' => '¹',
            '2' => '²',
            '3' => '³',
            '4' => '⁴',
            '5' => '⁵',
            '6' => '⁶',
            '7' => '⁷',
            '8' => '⁸',
            '9' => '⁹',
            c => c,
        })
        .collect()
}

/// Digits as subscripts.
pub fn subscript(s: &str) -> String {
    s.chars()
        .map(|c| {
            c.to_digit(10)
                .map_or(c, |d| char::from_u32(0x2080 + d).unwrap_or(c))
        })
        .collect()
}

/// "first" … "tenth", then "11th", "12th", "21st".
pub fn ordinal(i: &str) -> String {
    const WORDS: [&str; 10] = [
        "first", "second", "third", "fourth", "fifth", "sixth", "seventh", "eighth", "ninth",
        "tenth",
    ];
    match i.parse::<usize>() {
        Ok(n @ 1..=10) => WORDS[n - 1].to_string(),
        Ok(n) if n % 10 == 1 && n % 100 != 11 => format!("{n}st"),
        Ok(n) if n % 10 == 2 && n % 100 != 12 => format!("{n}nd"),
        Ok(n) if n % 10 == 3 && n % 100 != 13 => format!("{n}rd"),
        Ok(n) => format!("{n}th"),
        Err(_) => i.to_string(),
    }
}

/// The symbols of a phrase already in words, spelled as the book spells them: ω, k₁,
/// d₀/A_free, k = 10³k₁, N ≥ 2, β_N³, A⁻, ε = 10⁻⁴.
pub fn symbols(phrase: &str) -> String {
    phrase
        .split(' ')
        .map(|w| {
            // a trailing comma or colon stays where it was
            let (word, tail) = match w.strip_suffix([',', ':']) {
                Some(s) => (s, &w[s.len()..]),
                None => (w, ""),
            };
            let spelled = match word {
                "omega" => "ω".to_string(),
                "k1" => "k₁".to_string(),
                "k2" => "k₂".to_string(),
                "f1" => "f₁".to_string(),
                "d0" => "d₀".to_string(),
                "d0/A_free" => "d₀/A_free".to_string(),
                "k/k1" => "k/k₁".to_string(),
                "A-" => "A⁻".to_string(),
                "N>=2" => "N ≥ 2".to_string(),
                "N+10" => "N + 10".to_string(),
                "(beta_N^3" => "(β_N³".to_string(),
                "e^(-c1" => "e^(−c₁T/2)".to_string(),
                "T/2)" => String::new(),
                w if w.ends_with("k1") && w[..w.len() - 2].parse::<f64>().is_ok() => {
                    format!("{}k₁", &w[..w.len() - 2])
                }
                w if w.contains('e') && w.parse::<f64>().is_ok() => number(w),
                w => match w.split_once('=') {
                    Some((s, v)) if !s.is_empty() && !v.is_empty() => qualifier_words(s, v),
                    _ => w.to_string(),
                },
            };
            spelled + tail
        })
        .filter(|w| !w.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The name of key `key` of scene `scene` in words.
pub fn name(scene: &str, key: &str) -> String {
    let (lead, rest) = vocabulary::lead(scene, key);
    let (q, quantity) = if vocabulary::keeps_order(scene) {
        (Qualifiers::default(), rest)
    } else {
        split(rest)
    };
    let (phrase, used) = vocabulary::quantity(scene, quantity, &q)
        .unwrap_or_else(|| (symbols(quantity), Vec::new()));
    // the case (Fig 6(b), the exact engine, N = 3) follows the quantity, in parentheses
    let case: Vec<String> = lead
        .into_iter()
        .chain(Some(q.context(&used)).filter(|c| !c.is_empty()))
        .collect();
    match case.is_empty() {
        true => phrase,
        false => format!("{phrase} ({})", case.join(", ")),
    }
}

/// A key-number document's `key_numbers` object (key → its fields) with each number's
/// name added as its `name` field.
pub fn annotate(scene: &str, key_numbers: &mut serde_json::Value) {
    if let serde_json::Value::Object(m) = key_numbers {
        for (key, v) in m.iter_mut() {
            if let serde_json::Value::Object(fields) = v {
                fields.insert("name".into(), serde_json::Value::String(name(scene, key)));
            }
        }
    }
}

/// "partly reproduced" → "Partly reproduced", "the first impact velocity …" → "The first
/// …"; a sentence that starts with a symbol (r_E, k/k₁, ω, d₀) keeps it as it is: a symbol
/// is a single letter other than the word "a".
pub fn capitalised(s: &str) -> String {
    let word: String = s.chars().take_while(|c| c.is_alphabetic()).collect();
    let after = s[word.len()..].chars().next();
    if word.chars().count() < 2 && !(word == "a" && after == Some(' ')) {
        return s.to_string();
    }
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// What a name must not contain: a code spelling a reader would have to decode (a word with
/// an underscore other than the paper's A_free, r_E, r_e and β_N; a symbol spelled in
/// letters; `x=1` without spaces).
pub fn code_spelling(name: &str) -> Option<String> {
    const SPELLED: [&str; 9] = [
        "k1", "k2", "omega", "eps", "d0", "lambda", "beta", "kappa", "phi1",
    ];
    const PAPER: [&str; 4] = ["A_free", "r_E", "r_e", "β_N"];
    name.split(|c: char| c.is_whitespace() || "(),;:".contains(c))
        .find(|w| {
            let bare = PAPER.iter().fold(w.to_string(), |w, p| w.replace(p, ""));
            bare.contains('_')
                || SPELLED.contains(w)
                || w.split('/').any(|part| SPELLED.contains(&part))
                || w.split_once('=')
                    .is_some_and(|(a, b)| !a.is_empty() && !b.is_empty())
        })
        .map(str::to_string)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_and_qualifiers_read_as_written_by_hand() {
        assert_eq!(number("1e6"), "10⁶");
        assert_eq!(number("1e1"), "10");
        assert_eq!(number("1.000e-4"), "10⁻⁴");
        assert_eq!(number("1.778e-4"), "1.778 × 10⁻⁴");
        assert_eq!(number("1000"), "1000");
        assert_eq!(ordinal("1"), "first");
        assert_eq!(ordinal("21"), "21st");
        assert_eq!(ordinal("12"), "12th");
        let (q, rest) = split("N=10 k/k1=1000 i=10 lambda");
        assert_eq!(rest, "lambda");
        assert_eq!(q.context(&["i"]), "N = 10, k = 1000k₁");
        assert_eq!(
            symbols("grazing omega at k=50, N=3"),
            "grazing ω at k = 50k₁, N = 3"
        );
    }

    #[test]
    fn a_name_that_starts_with_a_symbol_keeps_it() {
        assert_eq!(capitalised("k/k₁ of the pin"), "k/k₁ of the pin");
        assert_eq!(capitalised("ε where k = k₂"), "ε where k = k₂");
        assert_eq!(capitalised("the orbit"), "The orbit");
    }

    #[test]
    fn the_issue_s_example_reads_in_words() {
        assert_eq!(
            name("fig4", "N=3 impact_velocity_1"),
            "the first impact velocity of the periodic orbit (N = 3)"
        );
    }
}
