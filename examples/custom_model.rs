//! A model of your own: 8 modes, viscous damping α, a gap, a forcing profile f(s) = s² of
//! your choosing, and an initial deflection w(s) projected onto the modes; simulated
//! exactly with its contact events and the energy budget.
//!
//! `cargo run --release --example custom_model`

use impacting_cantilever::prelude::*;

pub fn main() -> Result<(), Error> {
    let forcing = Forcing::from_fn(1.3 * first_frequency(), |s| 40.0 * s * s);
    let params = GalerkinParams::new(8, 500.0 * first_modal_stiffness())
        .with_gap(0.3)
        .with_viscous_damping(0.05)
        .with_forcing(forcing);
    let model = GalerkinModel::new(params)?;
    // bent as under a tip load, released at rest
    let x0 = model.modal_state(&|s| 0.1 * s * s * (3.0 - s), &|_| 0.0)?;
    let sim = Simulator::new(model)?;
    let (mut events, mut energy) = (Events::default(), Energy::default());
    sim.run(&x0, 40, &mut (&mut events, &mut energy))?;
    for e in events.events.iter().take(6) {
        println!(
            "t = {:.6} entering {} v = {:+.3e}",
            e.time, e.entering, e.tip_velocity
        );
    }
    let (n, imbalance) = (events.events.len(), energy.budget.relative_imbalance());
    println!("{n} events, energy imbalance {imbalance:.1e}");
    Ok(())
}
