//! The model and start options shared by `simulate`, `orbit` and `continue`: flags mapped
//! onto the library's [`ModelSpec`] and [`Start`], nothing checked here that the library
//! checks (its ranges and messages are the library's). An option that does not apply to
//! the model asked for is refused naming it, never ignored.

use clap::builder::PossibleValuesParser;
use impacting_cantilever::error::ParameterError;
use impacting_cantilever::model::spec::{
    defaults, Cantilever, DampingReading, ForcingSpec, GapUnit, Law, ModelSpec, Named, Start, Stop,
    Structure,
};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The names of a choice, for clap.
fn names<T: Named>() -> PossibleValuesParser {
    PossibleValuesParser::new(T::ALL.iter().map(|(_, n)| *n))
}

/// The model (units: k in k₁ = (β₁⁻)⁴; ω in (β₁⁻)²; d₀ in units of the free tip amplitude
/// at resonance, or of A_free(ω) with --gap-unit free).
#[derive(Debug, Clone, clap::Args)]
pub struct ModelArgs {
    /// N, the number of modes (1 to 400).
    #[arg(long)]
    pub modes: usize,
    /// The model: compliant (eq 34, a stop of stiffness k) or rigid (§3, a restitution law).
    #[arg(long, value_parser = ["compliant", "rigid"], default_value = "compliant")]
    pub model: String,
    /// Stop stiffness as k/k₁, k₁ = (β₁⁻)⁴ ≈ 12.36 (0 to 1e12; default 100; compliant model
    /// only).
    #[arg(long, allow_hyphen_values = true)]
    pub stop_stiffness: Option<f64>,
    /// Gap d₀ between the tip at rest and the stop (|d₀| ≤ 1e6; negative: preloaded).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub gap: f64,
    /// The unit of --gap: resonance (the free tip amplitude at resonance, the paper's) or
    /// free (A_free(ω), the free tip amplitude at the forcing frequency).
    #[arg(long, value_parser = names::<GapUnit>(), default_value = "resonance")]
    pub gap_unit: String,
    /// ζ₁, the first mode's damping ratio (material damping; 1e-8 to 1e3).
    #[arg(long, allow_hyphen_values = true)]
    pub zeta1: f64,
    /// How ζ₁ sets γ: fig9 (γ = 2ζ₁/(β₁⁻)²) or fig4-literal (γ = 2ζ₁(β₁⁻)²).
    #[arg(long, value_parser = names::<DampingReading>(), default_value = "fig9")]
    pub damping_reading: String,
    /// Viscous damping α (0 to 1e6, entering as 2α, eq 1).
    #[arg(long, allow_hyphen_values = true, default_value_t = 0.0)]
    pub viscous: f64,
    /// Forcing frequency as ω/(β₁⁻)² (1e-3 to 1e4).
    #[arg(long, allow_hyphen_values = true)]
    pub omega: f64,
    /// Forcing amplitude: `unit` (eq 37 corrected: free tip amplitude 1 at resonance),
    /// `printed` (eq 37 as printed, 1/(4ζ₁²) larger), or a number f₁ (the profile φ₁(s),
    /// modal force f₁ cos ωt on mode 1).
    #[arg(long, allow_hyphen_values = true, default_value = "unit")]
    pub forcing: String,
    /// The rigid model's law (default stiffness-limit; rigid model only): stiffness-limit
    /// ([R]_N, eq 29, r_e = --restitution), impulse-response ([R]_IR, eq 14), collocation
    /// ([R]_C at equally spaced points, eq 12) or newton (η̇⁺ = −rη̇⁻, N = 1 only).
    #[arg(long, value_parser = names::<Law>())]
    pub law: Option<String>,
    /// The rigid model's coefficient of restitution r (r_e for the stiffness limit), in
    /// [0, 1] (default 0.8; rigid model only).
    #[arg(long, allow_hyphen_values = true)]
    pub restitution: Option<f64>,
}

/// A flag given for a model it does not apply to: `allowed` says which it is for.
fn not_for(flag: &str, value: impl std::fmt::Display, allowed: &str) -> ParameterError {
    ParameterError::new(flag, value, allowed)
}

impl ModelArgs {
    /// The specification the flags describe.
    pub fn spec(&self) -> Result<ModelSpec, ParameterError> {
        let structure = Structure::Cantilever(Cantilever {
            modes: self.modes,
            gap: self.gap,
            gap_unit: GapUnit::parse(&self.gap_unit)?,
            zeta1: self.zeta1,
            damping_reading: DampingReading::parse(&self.damping_reading)?,
            viscous: self.viscous,
            omega: self.omega,
            forcing: ForcingSpec::parse(&self.forcing)?,
        });
        let stop = if self.model == "rigid" {
            if let Some(k) = self.stop_stiffness {
                return Err(not_for(
                    "--stop-stiffness",
                    k,
                    "no stop stiffness with --model rigid (a rigid stop has none; it is the \
                     compliant model's)",
                ));
            }
            Stop::Rigid {
                law: match &self.law {
                    Some(name) => Law::parse(name)?,
                    None => defaults::LAW,
                },
                restitution: self.restitution.unwrap_or(defaults::RESTITUTION),
            }
        } else {
            if let Some(law) = &self.law {
                return Err(not_for(
                    "--law",
                    law,
                    "no law with the compliant model (a law is the rigid model's: --model rigid)",
                ));
            }
            if let Some(r) = self.restitution {
                return Err(not_for(
                    "--restitution",
                    r,
                    "no coefficient of restitution with the compliant model (it is the rigid \
                     model's: --model rigid)",
                ));
            }
            Stop::Compliant {
                stop_stiffness: self.stop_stiffness.unwrap_or(defaults::STOP_STIFFNESS),
            }
        };
        Ok(ModelSpec { structure, stop })
    }
}

/// Where the run starts (rest if none is given).
#[derive(Debug, Clone, clap::Args)]
pub struct StartArgs {
    /// Start from a modal state [η; η̇] in a JSON file (an array of 2N numbers, or the
    /// object written by `simulate --final-state`: of the same N, and ended at a period
    /// boundary, as every run starts at phase 0 of the forcing).
    #[arg(long, conflicts_with_all = ["initial_profile", "seed"])]
    pub initial_state: Option<PathBuf>,
    /// Start from displacement and velocity profiles in a JSON file
    /// {"s": [...], "w": [...], "w_t": [...]} on [0, 1], interpolated linearly and
    /// projected onto the N modes.
    #[arg(long, conflicts_with = "seed")]
    pub initial_profile: Option<PathBuf>,
    /// Start from a random state (each η_j uniform in ±2A_free/N, η̇_j in ±2ωA_free/N) of
    /// this seed. The rigid model refuses a seed whose start puts the tip beyond its stop.
    #[arg(long)]
    pub seed: Option<u64>,
}

fn read_json(flag: &str, path: &Path) -> Result<Value, ParameterError> {
    // a state of 2N ≤ 800 numbers (or a profile) is far below 16 MiB
    let text = impacting_cantilever::results::files::read_capped(
        flag,
        path,
        16 << 20,
        "a readable JSON file",
    )?;
    serde_json::from_str(&text)
        .map_err(|e| ParameterError::new(flag, path.display(), &format!("valid JSON ({e})")))
}

fn numbers(flag: &str, v: &Value, what: &str) -> Result<Vec<f64>, ParameterError> {
    v.as_array()
        .and_then(|a| {
            a.iter()
                .map(|x| x.as_f64().filter(|f| f.is_finite()))
                .collect()
        })
        .ok_or_else(|| ParameterError::new(flag, what, "an array of finite numbers"))
}

impl StartArgs {
    /// The start the flags give, read from its file for `modes` modes, and the file it
    /// came from.
    pub fn start(&self, modes: usize) -> Result<(Start, Option<String>), ParameterError> {
        if let Some(path) = &self.initial_state {
            let v = read_json("--initial-state", path)?;
            let state = v.get("state").unwrap_or(&v);
            // a --final-state file says what it is: N and the forcing phase it ended at
            if let Some(m) = v.get("modes") {
                if m.as_u64() != Some(modes as u64) {
                    return Err(ParameterError::new(
                        "--initial-state",
                        format!("a state of {m} modes"),
                        &format!("a state of the model's N = {modes} modes"),
                    ));
                }
            }
            if let Some(phase) = v.get("phase").and_then(Value::as_f64) {
                // a run starts at phase 0 of the forcing: a state from mid-period (a run
                // that stopped early) would be continued with the forcing out of phase
                if phase.abs() > 1e-9 && (1.0 - phase).abs() > 1e-9 {
                    return Err(ParameterError::new(
                        "--initial-state",
                        format!("a state at phase {phase:.6} of the forcing period"),
                        "a state at the start of a forcing period (phase 0), where every \
                         run starts",
                    ));
                }
            }
            let x = numbers("--initial-state", state, "the state")?;
            return Ok((
                Start::State(x),
                Some(format!("state from {}", path.display())),
            ));
        }
        if let Some(path) = &self.initial_profile {
            let v = read_json("--initial-profile", path)?;
            let get = |key: &str| {
                v.get(key)
                    .ok_or_else(|| ParameterError::new("--initial-profile", key, "keys s, w, w_t"))
                    .and_then(|a| numbers("--initial-profile", a, key))
            };
            let start = Start::Profile {
                s: get("s")?,
                w: get("w")?,
                w_t: get("w_t")?,
            };
            return Ok((start, Some(format!("profiles from {}", path.display()))));
        }
        Ok((self.seed.map_or(Start::Rest, Start::Seed), None))
    }
}

/// A count given as an integer or in e-notation ("1e8", as the ranges in `--help` print
/// them): exact whole numbers only, up to 2⁵³ (beyond, e-notation is not exact).
pub fn whole(text: &str) -> Result<u64, String> {
    if let Ok(n) = text.parse::<u64>() {
        return Ok(n);
    }
    match text.parse::<f64>() {
        Ok(x) if x >= 0.0 && x.fract() == 0.0 && x <= 9_007_199_254_740_992.0 => Ok(x as u64),
        _ => Err("a whole number (e.g. 20 or 1e8)".into()),
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn counts_are_taken_as_the_help_prints_them() {
        use super::whole;
        assert_eq!(whole("20"), Ok(20));
        assert_eq!(whole("1e8"), Ok(100_000_000));
        assert_eq!(whole("2E1"), Ok(20));
        for bad in ["1.5", "-1", "nan", "inf", "1e300", "", "x"] {
            assert!(whole(bad).is_err(), "{bad}");
        }
    }
}
