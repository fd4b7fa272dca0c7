//! What-ifs without editing code: the parameters of a scene a user may set
//! (`cantilever scene NAME --set key=value`), each with its supported range.
//!
//! A scene lists its settable parameters in [`crate::results::scene::Scene::SETTABLE`]:
//! physical parameters of its result (ζ₁, ω, k, d₀, …) and run lengths, each with a range
//! inside the model's supported one and, for run lengths, a cap that keeps a run within
//! minutes. Everything else a scene computes with (its list of truncations, its grids, the
//! checks it runs) stays as the scene declares it: changing those changes what the result
//! *is*, not a value of it. A value is checked against its range before any work; the
//! parameters written into the outputs are the ones computed with, and the provenance
//! lists the settings, so `diff` against the published numbers shows what moved.

use crate::error::ParameterError;
use crate::model::ranges::{Count, Range};
use serde::Serialize;

/// A settable parameter's kind and range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SettingKind {
    /// A real number in a range.
    Real(Range),
    /// An integer in a range.
    Count(Count),
}

/// One parameter of a scene a user may set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    /// Its key in the scene's parameters (as written into `key_numbers.json`).
    pub key: &'static str,
    /// What it is, in a few words.
    pub meaning: &'static str,
    /// Its kind and supported range.
    pub kind: SettingKind,
}

impl Setting {
    /// A real parameter `key` with the range `lo ..= hi` (symbol and reason as given).
    pub const fn real(
        key: &'static str,
        symbol: &'static str,
        meaning: &'static str,
        (lo, hi): (f64, f64),
        why: &'static str,
    ) -> Self {
        Self {
            key,
            meaning,
            kind: SettingKind::Real(Range {
                name: key,
                symbol,
                lo,
                hi,
                why,
            }),
        }
    }

    /// An integer parameter `key` with the range `min ..= max`.
    pub const fn count(
        key: &'static str,
        meaning: &'static str,
        (min, max): (u64, u64),
        why: &'static str,
    ) -> Self {
        Self {
            key,
            meaning,
            kind: SettingKind::Count(Count {
                name: key,
                symbol: "",
                min,
                max,
                why,
            }),
        }
    }

    /// The allowed values, in words ("a number from 1e-8 to 1").
    pub fn allowed(&self) -> String {
        match self.kind {
            SettingKind::Real(r) => r.allowed(),
            SettingKind::Count(c) => format!("an integer from {} to {}", c.min, c.max),
        }
    }

    /// Why the range ends where it does.
    pub fn why(&self) -> &'static str {
        match self.kind {
            SettingKind::Real(r) => r.why,
            SettingKind::Count(c) => c.why,
        }
    }

    /// The value `text` parsed and checked against the range, as JSON.
    fn value(&self, text: &str) -> Result<serde_json::Value, ParameterError> {
        let refuse = || ParameterError::new(&format!("--set {}", self.key), text, &self.allowed());
        match self.kind {
            SettingKind::Real(r) => {
                let x: f64 = text.trim().parse().map_err(|_| refuse())?;
                r.check(x).map_err(|_| refuse())?;
                serde_json::Number::from_f64(x)
                    .map(serde_json::Value::Number)
                    .ok_or_else(refuse)
            }
            SettingKind::Count(c) => {
                let n: i128 = text.trim().parse().map_err(|_| refuse())?;
                let n = c.check(n).map_err(|_| refuse())?;
                Ok(serde_json::Value::from(n))
            }
        }
    }
}

/// ζ₁ as the scenes take it.
pub const ZETA1: Setting = Setting::real(
    "zeta1",
    "ζ₁",
    "the first mode's damping ratio (material damping)",
    (1e-4, 1.0),
    "below 1e-4 a transient outlasts the scenes' run lengths (decay over ~1/(2πζ₁) periods); \
     above 1 the first mode is over-damped, outside the paper's lightly damped setting",
);
/// ω/(β₁⁻)² as the scenes take it.
pub const OMEGA: Setting = Setting::real(
    "omega_over_w1",
    "ω/(β₁⁻)²",
    "the forcing frequency over the first natural frequency",
    (0.1, 10.0),
    "the paper's figures lie within 0.5–3; the scenes' run lengths are set in forcing \
     periods, so far below resonance a run spans few periods of the first mode",
);
/// k/k₁ as the scenes take it.
pub const STOP_STIFFNESS: Setting = Setting::real(
    "k_over_k1",
    "k/k₁",
    "the stop stiffness over the first modal stiffness",
    (1e-2, 1e6),
    "the paper's range; stiffer stops need more modes than the scenes' truncations hold \
     and chatter runs longer (the command line's simulate takes up to 1e12)",
);
/// d₀ as the scenes take it.
pub const GAP: Setting = Setting::real(
    "gap",
    "d₀",
    "the gap between the tip at rest and the stop (units of the free tip amplitude at \
     resonance; negative: preloaded)",
    (-10.0, 10.0),
    "beyond ±10 the stop is either never reached or the beam rests on it: the result is \
     then that of the free or the preloaded linear beam",
);
/// The seed of a scene's random starts.
pub const SEED: Setting = Setting::count(
    "seed",
    "the seed of the random starts",
    (0, u64::MAX),
    "any seed; the same seed gives the same starts whatever the thread count",
);

/// A setting as applied: the key and the value it was given.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Applied {
    /// The parameter's key.
    pub key: String,
    /// The value as given on the command line.
    pub value: String,
}

impl std::fmt::Display for Applied {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}={}", self.key, self.value)
    }
}

/// Splits `key=value` (the command line's `--set`).
///
/// # Errors
/// [`ParameterError`] naming `--set` when there is no `=` or no key.
pub fn parse_assignment(text: &str) -> Result<(String, String), ParameterError> {
    match text.split_once('=') {
        Some((k, v)) if !k.trim().is_empty() => Ok((k.trim().to_string(), v.trim().to_string())),
        _ => Err(ParameterError::new(
            "--set",
            text,
            "KEY=VALUE, a parameter of the scene and its value (see --list-parameters)",
        )),
    }
}

/// Applies `assignments` to the scene `scene`'s parameters `params` (JSON), each checked
/// against the scene's `settable` list and its range before any work. The values replace
/// the scene's; every other parameter is left as it is.
///
/// # Errors
/// [`ParameterError`] naming `--set` for a key the scene does not let a user set (the error
/// lists those it does), a key given twice, or a value outside its range.
pub fn apply(
    scene: &str,
    settable: &[Setting],
    params: &mut serde_json::Value,
    assignments: &[(String, String)],
) -> Result<Vec<Applied>, ParameterError> {
    let mut applied: Vec<Applied> = Vec::new();
    for (key, text) in assignments {
        let Some(setting) = settable.iter().find(|s| s.key == key) else {
            let keys: Vec<&str> = settable.iter().map(|s| s.key).collect();
            let allowed = if keys.is_empty() {
                format!("nothing: scene {scene} has no parameters a user may set")
            } else {
                format!(
                    "a parameter of scene {scene} a user may set: {} (see `cantilever scene \
                     {scene} --list-parameters`)",
                    keys.join(", ")
                )
            };
            return Err(ParameterError::new("--set", key, &allowed));
        };
        if applied.iter().any(|a| &a.key == key) {
            return Err(ParameterError::new(
                "--set",
                key,
                "each parameter once (it is given twice)",
            ));
        }
        let value = setting.value(text)?;
        let Some(slot) = params.get_mut(setting.key) else {
            return Err(ParameterError::new(
                "--set",
                key,
                &format!("a parameter scene {scene} has (this build's list is wrong)"),
            ));
        };
        *slot = value;
        applied.push(Applied {
            key: key.clone(),
            value: text.clone(),
        });
    }
    Ok(applied)
}

/// The scene's settable parameters as a table: key, value at `params`, range, meaning.
pub fn table(settable: &[Setting], params: &serde_json::Value) -> String {
    let mut s = String::from("| parameter | value | allowed | what it is |\n|---|---|---|---|\n");
    for set in settable {
        let value = params.get(set.key).map_or("—".into(), |v| v.to_string());
        s.push_str(&format!(
            "| `{}` | {} | {} | {} |\n",
            set.key,
            value,
            set.allowed(),
            set.meaning
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    const SET: [Setting; 2] = [
        Setting::real("zeta1", "ζ₁", "damping", (1e-4, 1.0), "why"),
        Setting::count("transient", "periods", (1, 10), "why"),
    ];

    #[test]
    fn values_are_checked_and_applied_by_key() {
        let mut p = serde_json::json!({"zeta1": 0.01, "transient": 5, "other": 1});
        let a = [("zeta1".to_string(), "0.011".to_string())];
        let applied = apply("s", &SET, &mut p, &a).unwrap();
        assert_eq!(p["zeta1"], 0.011);
        assert_eq!(p["other"], 1);
        assert_eq!(applied[0].to_string(), "zeta1=0.011");
        for bad in [
            ("zeta1", "2"),
            ("zeta1", "nan"),
            ("zeta1", "x"),
            ("transient", "0"),
            ("transient", "1.5"),
            ("transient", "-1"),
            ("other", "1"),
        ] {
            let a = [(bad.0.to_string(), bad.1.to_string())];
            let e = apply("s", &SET, &mut p.clone(), &a)
                .unwrap_err()
                .to_string();
            assert!(e.contains("--set"), "{bad:?}: {e}");
        }
        let twice = [
            ("zeta1".to_string(), "0.1".to_string()),
            ("zeta1".to_string(), "0.2".to_string()),
        ];
        assert!(apply("s", &SET, &mut p, &twice).is_err());
        assert!(parse_assignment("zeta1").is_err());
        assert!(parse_assignment("=1").is_err());
        assert_eq!(
            parse_assignment(" zeta1 = 0.2").unwrap(),
            ("zeta1".into(), "0.2".into())
        );
    }
}
