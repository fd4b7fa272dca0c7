//! The model matrices of one forced problem as JSON, for the peer scripts of `peers/`
//! (scipy, Siconos): they integrate exactly the equations this library solves, with the
//! numbers taken from here rather than derived again. The flags are those of
//! `cantilever simulate` (ω in units of (β₁⁻)², k in units of k₁, d₀ in units of the free
//! tip amplitude at resonance, material damping from ζ₁, eq (37) forcing corrected).
//!
//! ```text
//! η̈ + C η̇ + K^± η = f cos ωt + F^±,   K⁺ = K⁻ + (k/4)φ(1)φ(1)ᵀ,   tip = φ(1)ᵀη
//! ```
//!
//! `cargo run --release --example peer_problem -- --modes 10 --stop-stiffness 100 --zeta1 0.01 --omega 2 --gap 0 --restitution 0.8`

use impacting_cantilever::prelude::*;
use impacting_cantilever::results::peers;

fn flag(args: &[String], name: &str, default: Option<f64>) -> Result<f64, Error> {
    let value = args
        .iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .map(|v| v.parse::<f64>());
    match (value, default) {
        (Some(Ok(v)), _) => Ok(v),
        (None, Some(d)) => Ok(d),
        _ => Err(ParameterError::new(name, "missing or not a number", "a number").into()),
    }
}

pub fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().collect();
    let case = Forced {
        modes: flag(&args, "--modes", None)? as usize,
        k_over_k1: flag(&args, "--stop-stiffness", Some(100.0))?,
        zeta1: flag(&args, "--zeta1", None)?,
        omega_over_w1: flag(&args, "--omega", None)?,
        gap: flag(&args, "--gap", Some(0.0))?,
        printed_eq37_amplitude: false,
    };
    let json = peers::matrices(&case, flag(&args, "--restitution", Some(0.8))?)?;
    println!(
        "{}",
        serde_json::to_string_pretty(&json).expect("plain numbers")
    );
    Ok(())
}
