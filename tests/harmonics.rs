//! The exact harmonic spectrum of the tip velocity: a closed form for the linear response,
//! and a discrete Fourier transform of dense samples for a multi-tap orbit.

use impacting_cantilever::analysis::harmonics::TipHarmonics;
use impacting_cantilever::analysis::orbit::{self, OrbitKind};
use impacting_cantilever::engine::sim::{Dense, Simulator};
use impacting_cantilever::model::problems;
use nalgebra::DVector;
use num_complex::Complex64;

#[test]
fn the_linear_response_is_one_harmonic() {
    // stop out of reach: on the forced response v(t) = Re(iωP e^{iωt}), so c₁ = iωP and
    // every other harmonic is zero — to round-off of the sum of O(N) terms
    let sim = Simulator::new(problems::out_of_reach(10, 0.01, 1.7).model().unwrap()).unwrap();
    let flow = sim.flow(impacting_cantilever::model::galerkin::Region::Free);
    let x0 = flow.particular(0.0);
    let mut h = TipHarmonics::new(6);
    sim.run(&x0, 3, &mut h).unwrap();
    let c = h.coefficients();
    let expect = Complex64::new(0.0, sim.omega()) * flow.tip_forced();
    assert!(
        (c[0] - expect).norm() < 1e-13 * expect.norm(),
        "{} vs {expect}",
        c[0]
    );
    for (n, cn) in c.iter().enumerate().skip(1) {
        assert!(
            cn.norm() < 1e-13 * expect.norm(),
            "harmonic {}: {cn}",
            n + 1
        );
    }
}

/// c_n by the discrete Fourier transform of `per_period` samples per period.
fn dft(
    sim: &Simulator,
    x: &DVector<f64>,
    start: i64,
    per_period: usize,
    harmonics: usize,
) -> Vec<Complex64> {
    let mut dense = Dense::new(per_period);
    sim.run_from(x, sim.clock_at_cycle(start), 1, &mut dense)
        .unwrap();
    let omega = sim.omega();
    (1..=harmonics)
        .map(|n| {
            dense
                .samples
                .iter()
                .map(|&(t, _, v, _)| {
                    v * impacting_cantilever::base::numerics::polar(1.0, -(n as f64) * omega * t)
                })
                .sum::<Complex64>()
                * (2.0 / per_period as f64)
        })
        .collect()
}

#[test]
fn a_multi_tap_orbit_agrees_with_the_dft_of_dense_samples() {
    // Figure 9's model (N = 10 here) settles on a (1,4) orbit. The contact force (k/4)(d − d₀)₊
    // is continuous at a switch but its rate is not, so the tip velocity is C¹ with jumps in
    // its second derivative: the DFT of M samples per period (the trapezoidal rule) is off
    // by O(M⁻³). Doubling M should cut its difference to the exact coefficients about
    // eight times (at least four, second order, is asserted), and the exact values must
    // lie within the Richardson estimate of the finer DFT's error
    let n = 10;
    let sim = Simulator::new(problems::figure9(n, 0.0).model().unwrap()).unwrap();
    let o = orbit::settle(&sim, &DVector::zeros(2 * n), 600, 20, 0).unwrap();
    assert_eq!(o.kind, OrbitKind::Periodic { m: 1, n: 4 });
    let start = 620;
    let mut h = TipHarmonics::new(25);
    sim.run_from(&o.state, sim.clock_at_cycle(start), 1, &mut h)
        .unwrap();
    let exact = h.coefficients();
    let (coarse, fine) = (
        dft(&sim, &o.state, start, 2048, 25),
        dft(&sim, &o.state, start, 4096, 25),
    );
    let scale = exact.iter().map(|c| c.norm()).fold(0.0, f64::max);
    let mut ratios = Vec::new();
    for k in 0..25 {
        let (e1, e2) = ((coarse[k] - exact[k]).norm(), (fine[k] - exact[k]).norm());
        let richardson = (coarse[k] - fine[k]).norm() / 3.0;
        assert!(
            e2 <= 2.0 * richardson + 1e-12 * scale,
            "n = {}: {e2:e} vs {richardson:e}",
            k + 1
        );
        if e2 > 1e-9 * scale {
            ratios.push(e1 / e2);
        }
    }
    // better than second order on average (measured: a mean ratio of about 16)
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    assert!(mean >= 4.0, "mean error ratio {mean}, {ratios:?}");
}
