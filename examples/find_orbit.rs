//! A model of your own and its periodic orbit in one call: 6 modes, a stop of 300k₁ at
//! half the free tip amplitude at the forcing frequency, material damping ζ₁ = 0.01 with
//! viscous damping α = 0.02, forced at ω = 1.8(β₁⁻)²; the orbit with its Floquet
//! multipliers, stability and energetic coefficient of restitution r_E (eq 39).
//!
//! `cargo run --release --example find_orbit`

use impacting_cantilever::prelude::*;

pub fn main() -> Result<(), Error> {
    let params = GalerkinParams::new(6, 300.0 * first_modal_stiffness())
        .with_zeta1(0.01)
        .with_viscous_damping(0.02)
        .with_forcing(Forcing {
            omega: 1.8 * first_frequency(),
            profile: SpatialProfile::UnitTipAtResonance,
        });
    let model = GalerkinModel::new(params)?.with_gap_over_free(0.5)?;
    let sim = Simulator::new(model)?;
    let options = OrbitOptions {
        restitution: true,
        ..OrbitOptions::default()
    };
    let orbit = find_orbit(&sim, &sim.rest(), &options)?;
    println!(
        "({}, {}) orbit, {}, spectral radius {:.6}, r_E = {:?}",
        orbit.period_m,
        orbit.impacts_n,
        if orbit.stable { "stable" } else { "unstable" },
        orbit.spectral_radius(),
        orbit.energetic_restitution
    );
    for mu in orbit.multipliers.iter().take(4) {
        println!("  μ = {mu:.6}  |μ| = {:.6}", mu.norm());
    }
    Ok(())
}
