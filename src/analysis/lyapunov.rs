//! Lyapunov exponents of a trajectory of any model with an exact period-map Jacobian
//! (beyond the paper): the growth rates that tell a chaotic motion (largest exponent > 0)
//! from a quasi-periodic one (largest exponent 0) and a periodic one (all < 0).
//!
//! **Method** (Benettin et al. 1980; Eckmann & Ruelle, Rev. Mod. Phys. 57, 1985, §IV.C):
//! along the stroboscopic trajectory x_{i+1} = P(x_i), the k leading exponents are the mean
//! logarithms of the diagonal of R in the QR factorisations DP(x_i) Q_i = Q_{i+1} R_i,
//! divided by the forcing period T. DP is the exact Jacobian of one forcing period — the
//! product of the segments' exponentials and, for the rigid-impact model, the saltation
//! matrix of each impact ([`crate::engine::map::PeriodMap::map_with_jacobian`]) — so the
//! only approximations are the finite record and round-off.
//!
//! **Uncertainty** (batch means): after a transient of the state and one segment's worth of
//! periods to align Q, the record is cut into consecutive segments of equal length; each
//! gives an estimate, and the 95 % interval is mean ± t·s/√m over the m segments (Student's
//! t with m − 1 degrees of freedom). It is a statistical statement about the finite record
//! (the segments are assumed nearly independent), not a bound.

use crate::base::progress::Progress;
use crate::engine::map::PeriodMap;
use crate::error::Error;
use crate::model::ranges::Count;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// Segments of the record.
pub const SEGMENTS: Count = Count {
    name: "segments",
    symbol: "",
    min: 2,
    max: 30,
    why: "an interval needs two segments; the t quantiles are tabulated to 29 degrees of \
          freedom",
};

/// What to measure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LyapunovOptions {
    /// Forcing periods run from the start before anything is measured.
    pub transient: u64,
    /// [`SEGMENTS`].
    pub segments: usize,
    /// Forcing periods per segment (≥ 1).
    pub periods: u64,
    /// How many exponents, largest first (1 to the state's dimension).
    pub exponents: usize,
}

/// The exponents of one trajectory.
#[derive(Debug, Clone, Serialize)]
pub struct Lyapunov {
    /// λ₁ ≥ λ₂ ≥ …, per unit time (the mean over segments).
    pub exponents: Vec<f64>,
    /// The 95 % half-width of each (batch means over the segments).
    pub half_width: Vec<f64>,
    /// Each segment's estimates, per unit time.
    pub segments: Vec<Vec<f64>>,
    /// The forcing period T.
    pub period: f64,
    /// The state after the record.
    pub end_state: Vec<f64>,
}

/// Student's t quantile 0.975 for 1…29 degrees of freedom.
const T975: [f64; 29] = [
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
    2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
    2.052, 2.048, 2.045,
];

/// One period of the QR iteration.
struct Step {
    /// The state a period later.
    next: DVector<f64>,
    /// The new orthonormal columns.
    q: DMatrix<f64>,
    /// ln |R_jj|.
    logs: Vec<f64>,
}

fn step<M: PeriodMap + ?Sized>(
    model: &M,
    x: &DVector<f64>,
    q: &DMatrix<f64>,
) -> Result<Step, Error> {
    let (next, jacobian, _) = model.map_with_jacobian(x, 1)?;
    let qr = (jacobian * q).qr();
    let (q_new, r) = (qr.q(), qr.r());
    // the sign of R_jj is folded into Q's column, so Q stays continuous from period to
    // period; |R_jj| = 0 (a direction contracted to round-off) gives −∞, kept as such
    let logs = (0..r.nrows()).map(|j| r[(j, j)].abs().ln()).collect();
    Ok(Step {
        next,
        q: q_new,
        logs,
    })
}

/// The `options.exponents` leading Lyapunov exponents of the trajectory of `model` from
/// `x0`.
///
/// # Errors
/// [`Error::Parameter`] for options out of range or a bad state; the model's run and
/// Jacobian errors ([`Error::Unsupported`] for a model without a Jacobian,
/// [`Error::Chatter`] for a rigid motion that chatters); [`Error::Interrupted`] when
/// `progress` is cancelled.
pub fn lyapunov<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    options: &LyapunovOptions,
    progress: &dyn Progress,
) -> Result<Lyapunov, Error> {
    let n = model.dimension();
    model.check_state("start state", x0)?;
    let m = SEGMENTS.check(options.segments as i128)? as usize;
    let bad = |name: &str, got: String, allowed: &str| -> Error {
        crate::error::ParameterError::new(name, got, allowed).into()
    };
    if options.periods == 0 {
        return Err(bad(
            "periods",
            "0".into(),
            "at least one period per segment",
        ));
    }
    if options.exponents == 0 || options.exponents > n {
        return Err(bad(
            "exponents",
            options.exponents.to_string(),
            &format!("1 to the state's dimension, {n}"),
        ));
    }
    let task = progress.task(
        "Lyapunov exponents: periods",
        options.transient + (m as u64 + 1) * options.periods,
    );
    let mut x = model.advance_reporting(x0, 0, options.transient, task.as_ref(), progress)?;
    let mut q = DMatrix::identity(n, options.exponents);
    let period = model.period();
    let mut segments = Vec::with_capacity(m);
    // segment 0 aligns Q with the leading directions and is not counted
    for s in 0..=m {
        let mut sums = vec![0.0; options.exponents];
        for _ in 0..options.periods {
            if progress.cancelled() {
                return Err(Error::Interrupted);
            }
            let s = step(model, &x, &q)?;
            for (a, b) in sums.iter_mut().zip(&s.logs) {
                *a += b;
            }
            (x, q) = (s.next, s.q);
            task.advance(1);
        }
        if s > 0 {
            let per_time = options.periods as f64 * period;
            segments.push(sums.iter().map(|v| v / per_time).collect::<Vec<_>>());
        }
    }
    let t = T975[m - 2];
    let mut exponents = Vec::with_capacity(options.exponents);
    let mut half_width = Vec::with_capacity(options.exponents);
    for j in 0..options.exponents {
        let values: Vec<f64> = segments.iter().map(|s| s[j]).collect();
        let mean = values.iter().sum::<f64>() / m as f64;
        let var = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (m - 1) as f64;
        exponents.push(mean);
        half_width.push(t * (var / m as f64).sqrt());
    }
    Ok(Lyapunov {
        exponents,
        half_width,
        segments,
        period,
        end_state: x.iter().copied().collect(),
    })
}

/// Student's t at 0.975 for `dof` degrees of freedom (1…29), for tests and reports.
pub fn t975(dof: usize) -> Option<f64> {
    T975.get(dof.wrapping_sub(1)).copied()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn t_table_matches_known_quantiles() {
        // the two quantiles with closed forms: one degree of freedom (Cauchy),
        // t = tan(π(p − ½)); two, t = (2p − 1)/√(2p(1 − p)); the table has 3 decimals
        let t1 = (0.475 * std::f64::consts::PI).tan();
        assert!((t975(1).unwrap() - t1).abs() < 5e-4);
        let p: f64 = 0.975;
        let t2 = (2.0 * p - 1.0) / (2.0 * p * (1.0 - p)).sqrt();
        assert!((t975(2).unwrap() - t2).abs() < 5e-4);
        assert!(t975(0).is_none() && t975(30).is_none());
    }
}
