//! Basins of attraction of one atlas cell: rest is the atlas's start, the result does not
//! depend on the thread count, each start's orbit is where a brute-force transient (the §5.2
//! test, no shooting) settles, and bad parameters are refused by name.

use impacting_cantilever::analysis::atlas::basins::{basins, BasinParams};
use impacting_cantilever::analysis::atlas::cell::CellSearch;
use impacting_cantilever::analysis::orbit::{settle, OrbitKind};
use impacting_cantilever::base::progress::Silent;
use impacting_cantilever::engine::sim::Simulator;
use nalgebra::DVector;

#[test]
fn basins_agree_with_the_atlas_and_with_brute_force_for_any_thread_count() {
    let p = BasinParams {
        points: 7,
        ..BasinParams::test()
    };
    let d = basins(&p, &Silent).unwrap();
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap()
        .install(|| basins(&p, &Silent).unwrap());
    assert_eq!(d, one);
    // the centre start is rest: the atlas's start 0 at this cell reaches the same orbit
    let a = &p.atlas;
    let (k, w) = (a.k_over_k1(p.cell.0), a.omega_over_w1(p.cell.1));
    let sim = Simulator::new(a.model(p.modes, k, w).unwrap().model().unwrap()).unwrap();
    let search = CellSearch::new(a, &sim, p.cell);
    let rest = search.from_start(0).unwrap().unwrap();
    let centre = d.from_rest().unwrap();
    assert_eq!(
        (centre.period_m, centre.impacts_n),
        (rest.period_m, rest.impacts_n)
    );
    // two orbits coexist here, each reached from some start
    assert!(d.orbits.len() >= 2, "{:?}", d.orbits);
    // every start: a 1000-period transient settles (to 1e-9) on the orbit's (m, n)
    let (amplitude, velocity) = sim.model().free_tip_amplitude();
    let mut confirmed = 0;
    for (row, &v) in d.reached.iter().zip(&d.velocity) {
        for (r, &x) in row.iter().zip(&d.displacement) {
            let mut start = DVector::zeros(2 * p.modes);
            start[0] = 0.5 * x * amplitude;
            start[p.modes] = 0.5 * v * velocity;
            let o = settle(&sim, &start, 1000, 40, 0).unwrap();
            if let (Some(i), OrbitKind::Periodic { m, n }) = (r, o.kind) {
                let a = &d.orbits[*i];
                assert_eq!((a.period_m, a.impacts_n as u64), (m, n), "d = {x}, v = {v}");
                confirmed += 1;
            }
        }
    }
    // measured: all 49 settle within 1000 periods
    assert!(confirmed >= 45, "{confirmed} of 49 confirmed");
}

#[test]
fn bad_basin_parameters_are_refused_by_name() {
    let bad = |p: BasinParams| basins(&p, &Silent).unwrap_err().to_string();
    let p = BasinParams::test();
    assert!(bad(BasinParams {
        points: 10,
        ..p.clone()
    })
    .contains("basin points"));
    assert!(bad(BasinParams {
        points: 1,
        ..p.clone()
    })
    .contains("basin points"));
    assert!(bad(BasinParams {
        extent: f64::NAN,
        ..p.clone()
    })
    .contains("basin extent"));
    assert!(bad(BasinParams {
        extent: 0.0,
        ..p.clone()
    })
    .contains("basin extent"));
    assert!(bad(BasinParams {
        cell: (128, 0),
        ..p.clone()
    })
    .contains("basin cell"));
    assert!(bad(BasinParams { modes: 0, ..p }).contains("N"));
}
