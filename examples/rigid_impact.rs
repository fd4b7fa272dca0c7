//! The rigid-impact model (§3) with a restitution law of your choice: three modes, the
//! paper's forcing at resonance (ω = (β₁⁻)², free tip amplitude 1) with the stop
//! at d₀ = 0.5, and the impulse-response law `[R]_IR` with r = 0.8 (try
//! `restitution::stiffness_limit(3, 0.8)` or `restitution::collocation`).
//!
//! `cargo run --release --example rigid_impact`

use impacting_cantilever::prelude::*;

pub fn main() -> Result<(), Error> {
    let case = Forced {
        gap: 0.5,
        omega_over_w1: 1.0,
        ..problems::figure4(3)
    };
    let sim = Simulator::new(case.model()?)?;
    let periods = 30.0;
    let t_end = periods * sim.period();
    let law = restitution::impulse_response(3, 0.8)?;
    let run = RigidImpact::new(sim, law)?.run(&DVector::zeros(6), t_end)?;
    let impacts = run.impacts();
    for (t, vin, vout) in impacts.iter().rev().take(4).rev() {
        println!("t = {t:10.6}: tip velocity {vin:+.5} → {vout:+.5}");
    }
    println!(
        "{} impacts in {periods} periods; outcome {:?}",
        impacts.len(),
        run.outcome
    );
    Ok(())
}
