//! The command line's and the Python package's use cases, as the library calls they make: a
//! model from its specification (the paper's units and ranges), `simulate` (the transient
//! and a recorded window), `find_orbit`, and each failure told apart by its kind.
//!
//! `cargo run --release --example use_cases`

use impacting_cantilever::analysis::find_orbit::{find_orbit, OrbitOptions};
use impacting_cantilever::analysis::simulate::{simulate, SimulateOptions};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::built::BuiltModel;
use impacting_cantilever::error::Error;
use impacting_cantilever::model::problems::{self, Forced};
use impacting_cantilever::model::spec::{Law, ModelSpec, Start};

pub fn main() -> Result<(), Error> {
    // `cantilever simulate --modes 10 --stop-stiffness 100 --zeta1 0.01 --omega 2
    //  --periods 1000 --record 32`, and Python's `ic.simulate(ic.problems.figure4(10), 1000)`
    let spec = ModelSpec::from(problems::figure4(10));
    let model = BuiltModel::build(&spec)?;
    let (rest, _) = model.start(&Start::Rest)?;
    let options = SimulateOptions {
        periods: 1000,
        ..SimulateOptions::default()
    };
    let run = simulate(&model, &rest, &options, &Silent)?;
    println!(
        "compliant: period {:?}, {:?} contacts per period, energy imbalance {:.1e}",
        run.period_m,
        run.impacts_n,
        run.energy_imbalance.unwrap_or(f64::NAN)
    );
    // three modes at resonance against a rigid stop at d₀ = 0.5, each law: an orbit that
    // chatters or settles on no period is an error of that kind, not a number
    let beam = ModelSpec::from(Forced {
        gap: 0.5,
        omega_over_w1: 1.0,
        ..problems::figure4(3)
    });
    for law in [Law::ImpulseResponse, Law::StiffnessLimit, Law::Collocation] {
        let model = BuiltModel::build(&beam.rigid(law, 0.8))?;
        let (rest, _) = model.start(&Start::Rest)?;
        match find_orbit(&model, &rest, &OrbitOptions::default()) {
            Ok(o) => println!(
                "{law:?}: ({}, {}) orbit, stable {}",
                o.period_m, o.impacts_n, o.stable
            ),
            Err(Error::NoPeriod(why)) => println!("{law:?}: no period ({why})"),
            Err(Error::Chatter(why)) => println!("{law:?}: chatters ({why})"),
            Err(Error::NotConverged { residual, .. }) => {
                println!("{law:?}: Newton stopped at residual {residual:?}")
            }
            Err(other) => return Err(other),
        }
    }
    // bad input names the parameter and its range
    let bad = ModelSpec::from(Forced {
        omega_over_w1: 1e-300,
        ..problems::figure4(3)
    });
    if let Err(Error::Parameter(e)) = BuiltModel::build(&bad) {
        println!("{e}");
    }
    Ok(())
}
