//! What a motion is when it settles on no periodic orbit of short period (beyond the paper):
//! chaotic, quasi-periodic, periodic after all (a longer period or a slower transient), or
//! undecided — each with its evidence.
//!
//! **Evidence.** Three measurements along one trajectory of the stroboscopic map P:
//! - the two leading Lyapunov exponents λ₁ ≥ λ₂ with their 95 % batch-means intervals
//!   ([`crate::analysis::lyapunov`]): a chaotic attractor has λ₁ > 0; an invariant closed
//!   curve of P (a torus of the flow, a quasi-periodic motion) has λ₁ = 0 and λ₂ < 0; a
//!   stable periodic orbit has every exponent < 0;
//! - the iterates after the record: the least m ≤ [`MotionOptions::longest_period`] with
//!   P^m(x) = x to [`PERIODIC`] (the §5.2 test at a longer period);
//! - the rotation number ρ of the iterates about their mean in the plane in which they spread
//!   most ([`rotation_about`]), over the whole record and its two halves: on an invariant
//!   closed curve the halves agree.
//!
//! **Rule** (first that applies), with ε = [`MotionOptions::resolution`], the smallest rate
//! the record is asked to resolve: *periodic* when a period is found; *chaotic* when λ₁'s
//! interval lies above ε; *quasi-periodic* when λ₁'s interval lies inside (−ε, ε), λ₂'s
//! below −ε, and ρ of the two halves differ by less than [`ROTATION_AGREE`]; *undecided*
//! otherwise (λ₁ < 0 without a period found is a longer period or a slower transient; λ₁
//! near 0 with a wide interval is a record too short to tell a torus from weak chaos). The
//! margin ε keeps round-off (an isometry's λ₁ of 1e-16 "above zero") and an interval that
//! misses zero by chance from deciding a class. The intervals are statistical statements
//! about a finite record, so the classes are too: a chaotic attractor with λ₁ below ε, or a
//! period beyond the longest searched, is not resolved by this record.

use crate::analysis::lyapunov::{lyapunov, LyapunovOptions};
use crate::base::progress::Progress;
use crate::engine::map::PeriodMap;
use crate::error::Error;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// A period is found when P^m(x) and x agree to this relative distance: far above the
/// round-off of a converged orbit (~1e-12) and far below a quasi-periodic motion's return
/// distance at the longest period searched (measured ≥ 1e-3 on the book's atlas).
pub const PERIODIC: f64 = 1e-8;

/// Two halves of the record turning by rotation numbers this close (turns per period) are
/// one invariant curve's: both halves of a torus's record agree to ~1/(iterates/2) turns (the
/// angle unwrapped over a half is wrong by less than one turn).
pub const ROTATION_AGREE: f64 = 1e-2;

/// What to measure.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MotionOptions {
    /// Forcing periods run from the start before anything is measured.
    pub transient: u64,
    /// Segments of the Lyapunov record (2–30).
    pub segments: usize,
    /// Forcing periods per segment.
    pub periods: u64,
    /// Iterates recorded after it, for the period and the rotation number (≥ 4, and at least
    /// twice the longest period).
    pub iterates: usize,
    /// The longest period m searched among them.
    pub longest_period: u64,
    /// ε, the smallest rate (per unit time) the record is asked to resolve: λ₁ is zero when
    /// its interval lies inside (−ε, ε), positive when above ε.
    pub resolution: f64,
}

/// The most forcing periods any part of a classification may ask for (transient, each
/// segment, the iterates): 1e8 periods is ~20 min at N = 10; more is no longer a
/// classification but a hang.
pub const MAX_PERIODS: u64 = 100_000_000;

/// The most iterates recorded (each one state kept in memory).
pub const MAX_ITERATES: usize = 1_000_000;

impl MotionOptions {
    /// The book's classification (the atlas's) of a motion of `model` after `transient`
    /// periods: 20 segments of 50 periods for λ₁ and λ₂ (measured on Figure 5's
    /// quasi-periodic band at N = 10: λ₁'s interval is ±0.004–0.006 per unit time), 256
    /// iterates for a period up to 64 and the rotation number, and a resolution ε of a
    /// quarter of mode 1's free decay rate C₁₁/2 = ζ₁ω₁ (0.0088 per unit time at
    /// ζ₁ = 0.01): an exponent within ε of zero is four times slower than any decay of the
    /// beam without the stop, and a λ₁ interval wider than 2ε cannot tell a torus from weak
    /// chaos.
    pub fn for_model(model: &crate::model::galerkin::GalerkinModel, transient: u64) -> Self {
        Self {
            transient,
            segments: 20,
            periods: 50,
            iterates: 256,
            longest_period: 64,
            resolution: model.damping()[0] / 2.0 / 4.0,
        }
    }
}

/// The options a front end may change, each `None` for the book's ([`MotionOptions::for_model`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MotionOverrides {
    /// [`MotionOptions::segments`].
    pub segments: Option<usize>,
    /// [`MotionOptions::periods`].
    pub periods: Option<u64>,
    /// [`MotionOptions::iterates`].
    pub iterates: Option<usize>,
    /// [`MotionOptions::longest_period`].
    pub longest_period: Option<u64>,
    /// [`MotionOptions::resolution`].
    pub resolution: Option<f64>,
}

impl MotionOptions {
    /// The book's options for `model` after `transient` periods, with the given ones
    /// changed (checked by [`classify`]).
    pub fn for_model_with(
        model: &crate::model::galerkin::GalerkinModel,
        transient: u64,
        changed: &MotionOverrides,
    ) -> Self {
        let book = Self::for_model(model, transient);
        Self {
            segments: changed.segments.unwrap_or(book.segments),
            periods: changed.periods.unwrap_or(book.periods),
            iterates: changed.iterates.unwrap_or(book.iterates),
            longest_period: changed.longest_period.unwrap_or(book.longest_period),
            resolution: changed.resolution.unwrap_or(book.resolution),
            ..book
        }
    }
}

/// The class of a motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MotionClass {
    /// P^m(x) = x for some m ≤ the longest period searched.
    Periodic,
    /// λ₁ above the resolution with 95 % confidence.
    Chaotic,
    /// λ₁ = 0 to the resolution, λ₂ < 0, a consistent rotation number.
    QuasiPeriodic,
    /// None of these.
    Undecided,
}

impl MotionClass {
    /// The class in words.
    pub fn words(self) -> &'static str {
        match self {
            Self::Periodic => "periodic",
            Self::Chaotic => "chaotic",
            Self::QuasiPeriodic => "quasi-periodic",
            Self::Undecided => "undecided",
        }
    }
}

/// ρ of a record and how much its two halves differ.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rotation {
    /// ρ over the whole record, folded into [0, 1/2] (turns per forcing period).
    pub turns: f64,
    /// |ρ(first half) − ρ(second half)|.
    pub halves_differ: f64,
}

/// A classified motion and its evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Motion {
    /// The class.
    pub class: MotionClass,
    /// λ₁, λ₂ per unit time.
    pub exponents: [f64; 2],
    /// Their 95 % half-widths.
    pub half_widths: [f64; 2],
    /// The period found, if any.
    pub period_m: Option<u64>,
    /// The rotation number of the iterates.
    pub rotation: Rotation,
}

/// ρ of a sequence of points in the plane: the mean angle turned per step about `centre`,
/// in turns, folded into [0, 1/2] (the sense of turning is a matter of axes).
pub fn rotation_number(points: &[(f64, f64)], (cx, cy): (f64, f64)) -> f64 {
    if points.len() < 2 {
        return 0.0;
    }
    let n = points.len() as f64;
    let turns: f64 = points
        .windows(2)
        .map(|w| {
            let a = (w[0].1 - cy).atan2(w[0].0 - cx);
            let b = (w[1].1 - cy).atan2(w[1].0 - cx);
            // the step's angle in (−π, π]: a step never turns by more than half a turn
            let mut d = b - a;
            while d > std::f64::consts::PI {
                d -= std::f64::consts::TAU;
            }
            while d <= -std::f64::consts::PI {
                d += std::f64::consts::TAU;
            }
            d
        })
        .sum::<f64>()
        / std::f64::consts::TAU
        / (n - 1.0);
    let r = turns.abs().rem_euclid(1.0);
    r.min(1.0 - r)
}

/// ρ of iterates about `centre`, in the plane in which they spread most (their two principal
/// directions about their mean): projections on fixed coordinates (the tip's position and
/// velocity, say) can fold an invariant curve over itself, the principal plane does not for
/// the curves met here (Figure 5's band).
pub fn rotation_about(iterates: &[DVector<f64>], centre: &DVector<f64>) -> Rotation {
    let dim = centre.len();
    let n = iterates.len().max(1) as f64;
    let mean = iterates.iter().fold(DVector::zeros(dim), |a, x| a + x) / n;
    let mut cov = DMatrix::zeros(dim, dim);
    for x in iterates {
        let y = x - &mean;
        cov += &y * y.transpose() / n;
    }
    let eig = nalgebra::SymmetricEigen::new(cov);
    let mut order: Vec<usize> = (0..dim).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[j].total_cmp(&eig.eigenvalues[i]));
    let (u, v) = (
        eig.eigenvectors.column(order[0]),
        eig.eigenvectors.column(order[1.min(dim - 1)]),
    );
    let points: Vec<(f64, f64)> = iterates
        .iter()
        .map(|x| {
            let y = x - centre;
            (u.dot(&y), v.dot(&y))
        })
        .collect();
    let (a, b) = points.split_at(points.len() / 2);
    let origin = (0.0, 0.0);
    Rotation {
        turns: rotation_number(&points, origin),
        halves_differ: (rotation_number(a, origin) - rotation_number(b, origin)).abs(),
    }
}

/// The class the rule of this module gives to the evidence.
pub fn decide(
    exponents: [f64; 2],
    half_widths: [f64; 2],
    period_m: Option<u64>,
    rotation: Rotation,
    resolution: f64,
) -> MotionClass {
    let ([l1, l2], [h1, h2]) = (exponents, half_widths);
    if period_m.is_some() {
        MotionClass::Periodic
    } else if l1 - h1 >= resolution {
        MotionClass::Chaotic
    } else if l1 - h1 > -resolution
        && l1 + h1 < resolution
        && l2 + h2 < -resolution
        && rotation.halves_differ < ROTATION_AGREE
    {
        MotionClass::QuasiPeriodic
    } else {
        MotionClass::Undecided
    }
}

impl Motion {
    /// Whether the motion's evidence is well formed (finite exponents, half
    /// widths ≥ 0, a period within `longest_period`, ρ in [0, 1/2]) and its class is the one
    /// the rule gives it at `resolution`: what a file holding a motion is checked against.
    pub fn consistent(&self, longest_period: u64, resolution: f64) -> bool {
        let finite = self
            .exponents
            .iter()
            .chain(&self.half_widths)
            .all(|v| v.is_finite());
        finite
            && self.half_widths.iter().all(|h| *h >= 0.0)
            && self
                .period_m
                .is_none_or(|m| (1..=longest_period).contains(&m))
            && (0.0..=0.5).contains(&self.rotation.turns)
            && (0.0..=0.5).contains(&self.rotation.halves_differ)
            && self.class
                == decide(
                    self.exponents,
                    self.half_widths,
                    self.period_m,
                    self.rotation,
                    resolution,
                )
    }
}

/// Classifies the motion of `model` from `x0` by the rule of this module.
///
/// # Errors
/// [`Error::Parameter`] for options out of range or a bad state (of a model whose state has
/// fewer than two entries); the model's run and
/// Jacobian errors ([`Error::Unsupported`] for a model without a Jacobian,
/// [`Error::Chatter`]); [`Error::Interrupted`] when `progress` is cancelled.
pub fn classify<M: PeriodMap + ?Sized>(
    model: &M,
    x0: &DVector<f64>,
    options: &MotionOptions,
    progress: &dyn Progress,
) -> Result<Motion, Error> {
    let bad = |name: &str, got: String, allowed: &str| -> Error {
        crate::error::ParameterError::new(name, got, allowed).into()
    };
    for (name, value) in [
        ("transient", options.transient),
        ("periods", options.periods),
    ] {
        if value > MAX_PERIODS {
            return Err(bad(name, value.to_string(), "at most 1e8 forcing periods"));
        }
    }
    if options.iterates > MAX_ITERATES {
        return Err(bad(
            "iterates",
            options.iterates.to_string(),
            "at most 1000000 (each is kept in memory)",
        ));
    }
    if options.longest_period == 0
        || options.iterates < 4
        || (options.iterates as u64) < options.longest_period.saturating_mul(2)
    {
        return Err(bad(
            "iterates",
            format!(
                "{} with a longest period of {}",
                options.iterates, options.longest_period
            ),
            "at least 4, and at least twice the longest period (≥ 1)",
        ));
    }
    if !(options.resolution.is_finite() && options.resolution > 0.0) {
        return Err(bad(
            "resolution",
            options.resolution.to_string(),
            "a positive rate",
        ));
    }
    let l = lyapunov(
        model,
        x0,
        &LyapunovOptions {
            transient: options.transient,
            segments: options.segments,
            periods: options.periods,
            exponents: 2,
        },
        progress,
    )?;
    let end = DVector::from_column_slice(&l.end_state);
    let cycle = options.transient as i64 + (options.segments as i64 + 1) * options.periods as i64;
    let record = model.advance(&end, cycle, options.iterates as u64, true)?;
    let iterates = record.strobe;
    let last = &iterates[iterates.len() - 1];
    let period_m = (1..=options.longest_period)
        .find(|&m| model.residual(last, &iterates[iterates.len() - 1 - m as usize]) < PERIODIC);
    let n = iterates.len() as f64;
    let mean = iterates
        .iter()
        .fold(DVector::zeros(model.dimension()), |a, x| a + x)
        / n;
    let rotation = rotation_about(&iterates, &mean);
    let (l1, h1) = (l.exponents[0], l.half_width[0]);
    let (l2, h2) = (l.exponents[1], l.half_width[1]);
    if ![l1, h1, l2, h2].iter().all(|v| v.is_finite()) {
        // a direction contracted to round-off in a period (a rigid motion that sticks): ln 0
        return Err(Error::Unsupported(format!(
            "the Lyapunov exponents of this motion of {} are not finite (a direction \
             contracted to zero within a period): it cannot be classified by them",
            model.name()
        )));
    }
    let class = decide([l1, l2], [h1, h2], period_m, rotation, options.resolution);
    Ok(Motion {
        class,
        exponents: [l1, l2],
        half_widths: [h1, h2],
        period_m,
        rotation,
    })
}
