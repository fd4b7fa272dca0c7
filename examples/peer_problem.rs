//! The model matrices of one forced problem as JSON, for the peer scripts of `peers/`
//! (scipy, Siconos): they integrate exactly the equations this library solves, with the
//! numbers taken from here rather than derived again. The flags are those of
//! `cantilever simulate` (ω in units of (β₁⁻)², k in units of k₁, d₀ in units of the free
//! tip amplitude at resonance, material damping from ζ₁, eq (37) forcing corrected).
//!
//! ```text
//! η̈ + C η̇ + K^± η = f cos ωt + F⁺_preload,   K⁺ = K⁻ + (k/4)φ(1)φ(1)ᵀ,   tip = φ(1)ᵀη
//! ```
//!
//! `cargo run --release --example peer_problem -- --modes 10 --stop-stiffness 100 --zeta1 0.01 --omega 2 --gap 0 --restitution 0.8`

use impacting_cantilever::prelude::*;
use serde_json::json;

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

fn matrix(m: &DMatrix<f64>) -> Vec<Vec<f64>> {
    m.row_iter().map(|r| r.iter().copied().collect()).collect()
}

fn vector(v: &DVector<f64>) -> Vec<f64> {
    v.iter().copied().collect()
}

/// The problem the flags describe, as JSON.
pub fn problem(args: &[String]) -> Result<serde_json::Value, Error> {
    let case = Forced {
        modes: flag(args, "--modes", None)? as usize,
        k_over_k1: flag(args, "--stop-stiffness", Some(100.0))?,
        zeta1: flag(args, "--zeta1", None)?,
        omega_over_w1: flag(args, "--omega", None)?,
        gap: flag(args, "--gap", Some(0.0))?,
        printed_eq37_amplitude: false,
    };
    let r = flag(args, "--restitution", Some(0.8))?;
    let model = case.model()?;
    let n = model.modes();
    let sim = Simulator::new(model.clone())?;
    Ok(json!({
        "source": "examples/peer_problem.rs: problems::Forced::model(), the model `cantilever simulate` builds from the same flags",
        "modes": n,
        "stop_stiffness_over_k1": case.k_over_k1,
        "zeta1": case.zeta1,
        "omega_over_beta1_squared": case.omega_over_w1,
        "gap": case.gap,
        "beta1_squared": first_frequency(),
        "k1": first_modal_stiffness(),
        "stop_stiffness": model.params().stop_stiffness,
        "material_damping_gamma": model.params().material_damping,
        "omega": model.omega(),
        "period": sim.period(),
        "modal_stiffness": vector(model.modal_stiffness()),
        "tip": vector(model.tip()),
        "damping": vector(model.damping()),
        "forcing_amplitude": vector(model.forcing_amplitude()),
        "K_minus": matrix(&model.stiffness(Region::Free)),
        "K_plus": matrix(&model.stiffness(Region::Contact)),
        "contact_preload": vector(&model.stop_preload(Region::Contact)),
        "free_tip_amplitude": model.free_tip_amplitude().0,
        "restitution": r,
        "law_impulse_response": matrix(&restitution::impulse_response(n, r)?),
        "law_stiffness_limit": matrix(&restitution::stiffness_limit(n, r)?),
    }))
}

pub fn main() -> Result<(), Error> {
    let args: Vec<String> = std::env::args().collect();
    let p = problem(&args)?;
    println!("{}", serde_json::to_string_pretty(&p).expect("plain numbers"));
    Ok(())
}
