//! A Dormand–Prince 5(4) integrator with event location: the independent second method
//! for cross-verification of the exact simulator ([`crate::engine::sim`]): adaptive
//! Dormand–Prince 5(4) (Dormand & Prince 1980; Hairer, Nørsett & Wanner,
//! *Solving ODEs I*, §II.5) on ẋ = A^± x + F^±(t), written from the Butcher tableau and
//! sharing nothing with the exact method but the model's matrices.
//!
//! Event location does not use a dense-output interpolant (one crate's DOP853 dense output
//! was found to be wrong): when an accepted step ends on the other side of the switching
//! surface, the step length h_e ∈ (0, h] that lands exactly on it is found by Brent's
//! method, each trial being one fresh Runge–Kutta step from the step's start. The switch
//! is then taken at that point and integration restarts with the other region's
//! right-hand side. Like every sampled method it can miss a double crossing inside one
//! step; the exact simulator cannot.

use crate::base::numerics::brent;
use crate::model::galerkin::{GalerkinModel, Region};
use nalgebra::DVector;

/// Tolerances of the reference integrator.
#[derive(Debug, Clone, Copy)]
pub struct Tolerances {
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance.
    pub atol: f64,
}

/// A switching event found by the reference integrator.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct RefEvent {
    /// t, the time of the event (non-dimensional beam time).
    pub time: f64,
    /// Entering contact.
    pub entering: bool,
}

/// The result of a reference run.
#[derive(Debug, Clone)]
pub struct RefRun {
    /// Switching events in order.
    pub events: Vec<RefEvent>,
    /// The state at the end.
    pub state: DVector<f64>,
    /// Accepted steps.
    pub steps: u64,
    /// Right-hand-side evaluations.
    pub evaluations: u64,
}

// Dormand–Prince 5(4) tableau.
const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights (= the last row of A: the method is FSAL).
const B: [f64; 7] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
    0.0,
];
/// 4th-order embedded weights.
const B4: [f64; 7] = [
    5179.0 / 57600.0,
    0.0,
    7571.0 / 16695.0,
    393.0 / 640.0,
    -92097.0 / 339200.0,
    187.0 / 2100.0,
    1.0 / 40.0,
];

/// The right-hand side of eq (35) in one region, in O(N) (K⁺ is diagonal plus rank one).
struct Rhs<'a> {
    model: &'a GalerkinModel,
    omega: f64,
}

impl Rhs<'_> {
    fn eval(&self, region: Region, t: f64, x: &[f64], out: &mut [f64]) {
        let m = self.model;
        let n = m.modes();
        let cos = (self.omega * t).cos();
        let stop = if region == Region::Contact {
            // −(k/4) φ(1) (φ(1)ᵀη − d₀) = −K_stop η + F_preload
            let pen: f64 = (0..n).map(|i| m.tip()[i] * x[i]).sum::<f64>() - m.params().gap;
            m.params().stop_stiffness / 4.0 * pen
        } else {
            0.0
        };
        for j in 0..n {
            out[j] = x[n + j];
            out[n + j] = m.forcing_amplitude()[j] * cos
                - m.modal_stiffness()[j] * x[j]
                - m.damping()[j] * x[n + j]
                - stop * m.tip()[j];
        }
    }
}

/// One Dormand–Prince step: (5th-order solution, error estimate vector).
fn step(
    rhs: &Rhs,
    region: Region,
    t: f64,
    x: &[f64],
    h: f64,
    k: &mut [Vec<f64>; 7],
) -> (Vec<f64>, Vec<f64>) {
    let n2 = x.len();
    let mut stage = vec![0.0; n2];
    for s in 0..7 {
        for i in 0..n2 {
            stage[i] = x[i] + h * (0..s).map(|j| A[s][j] * k[j][i]).sum::<f64>();
        }
        let (ks, _) = k.split_at_mut(s + 1);
        rhs.eval(region, t + C[s] * h, &stage, &mut ks[s]);
    }
    let mut y = vec![0.0; n2];
    let mut err = vec![0.0; n2];
    for i in 0..n2 {
        y[i] = x[i] + h * (0..7).map(|s| B[s] * k[s][i]).sum::<f64>();
        err[i] = h * (0..7).map(|s| (B[s] - B4[s]) * k[s][i]).sum::<f64>();
    }
    (y, err)
}

/// Integrates from (0, x0) to t_end with event location.
///
/// # Errors
/// [`crate::error::Error::Parameter`] for a state of the wrong length or not finite, or a
/// t_end that is not a finite number ≥ 0.
pub fn integrate(
    model: &GalerkinModel,
    x0: &DVector<f64>,
    t_end: f64,
    tol: Tolerances,
) -> Result<RefRun, crate::error::Error> {
    crate::engine::sim::check_state(x0, 2 * model.modes(), "the reference integrator")?;
    crate::error::finite_non_negative("end time t_end", t_end)?;
    let omega = model.params().forcing.as_ref().map_or(0.0, |f| f.omega);
    let rhs = Rhs { model, omega };
    let n = model.modes();
    let n2 = 2 * n;
    let gap = model.params().gap;
    let tip_gap = |x: &[f64]| (0..n).map(|i| model.tip()[i] * x[i]).sum::<f64>() - gap;
    let mut x: Vec<f64> = x0.iter().cloned().collect();
    // the model's rule (shared with the simulator): on the surface, velocity then
    // acceleration decide
    let mut region = model.starting_region(x0, 0.0)?;
    let mut t = 0.0;
    let scale_t = if omega > 0.0 {
        2.0 * std::f64::consts::PI / omega
    } else {
        1.0
    };
    let mut h = 1e-4 * scale_t;
    let mut k: [Vec<f64>; 7] = std::array::from_fn(|_| vec![0.0; n2]);
    let (mut steps, mut evaluations) = (0u64, 0u64);
    let mut events = Vec::new();
    while t < t_end {
        let h_try = h.min(t_end - t);
        let (y, err) = step(&rhs, region, t, &x, h_try, &mut k);
        evaluations += 7;
        let e = (0..n2)
            .map(|i| {
                let sc = tol.atol + tol.rtol * x[i].abs().max(y[i].abs());
                (err[i] / sc).powi(2)
            })
            .sum::<f64>()
            / n2 as f64;
        let e = e.sqrt();
        if e > 1.0 {
            h = h_try * (0.9 * e.powf(-0.2)).max(0.2);
            continue;
        }
        steps += 1;
        let g_new = tip_gap(&y);
        let crossed = match region {
            Region::Free => g_new > 0.0,
            Region::Contact => g_new < 0.0,
        };
        if crossed {
            // the step length that lands on the surface, each trial a fresh RK step
            let mut count = 0;
            let h_e = brent(
                |he| {
                    count += 1;
                    let mut kk: [Vec<f64>; 7] = std::array::from_fn(|_| vec![0.0; n2]);
                    tip_gap(&step(&rhs, region, t, &x, he, &mut kk).0)
                },
                0.0,
                h_try,
                1e-15,
            )
            .unwrap_or(h_try);
            evaluations += 7 * count;
            let (ye, _) = step(&rhs, region, t, &x, h_e, &mut k);
            t += h_e;
            x = ye;
            events.push(RefEvent {
                time: t,
                entering: region == Region::Free,
            });
            region = match region {
                Region::Free => Region::Contact,
                Region::Contact => Region::Free,
            };
        } else {
            t += h_try;
            x = y;
        }
        h = h_try * (0.9 * e.max(1e-10).powf(-0.2)).min(5.0);
    }
    Ok(RefRun {
        events,
        state: DVector::from_vec(x),
        steps,
        evaluations,
    })
}
