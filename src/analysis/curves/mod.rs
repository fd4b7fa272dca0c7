//! Two-parameter continuation of codimension-one points of periodic orbits (beyond the
//! paper): the curves of folds, period doublings, Neimark–Sacker points and grazings in a
//! plane of two parameters —
//! (k, ω) or (ω, d₀) of the compliant model — that bound the regions of the atlas. Folds and
//! period doublings are traced for any model with an exact period-map Jacobian as well (the
//! rigid-impact model with its saltation matrices, [`Family2::of_maps`]); grazings read the
//! compliant model's tip.
//!
//! **The extended system.** A point of a curve is z = (ξ, u, v): the orbit's scaled state
//! at the start of a forcing period and u = ln p, v = ln q. It solves the n equations of the
//! shooting problem G = P^m(x) − x = 0 and one test function s = 0 (`defining`: bordered
//! determinants of M ∓ I for folds and period doublings; |μ| − 1 of the complex pair for
//! Neimark–Sacker points; the signed distance of the extremum nearest the stop for
//! grazings). Those are n + 1 equations in n + 2 unknowns: a
//! curve, traced by pseudo-arclength (Keller) exactly as one-parameter branches are
//! ([`crate::analysis::continuation`]), and started by Newton on (ξ, u) at fixed q from an
//! orbit near the point (e.g. a bifurcation a one-parameter run reported).
//!
//! **Each point is then polished** by shooting at its (p, q) to the shooting tolerance and
//! reported with two residuals: the orbit's, and the test's own measure — the distance of
//! the nearest multiplier from +1 or −1, of the complex pair from the unit circle, or
//! |d_ext − d₀|/A_free.
//!
//! **Codimension-two points** are found between consecutive points: where the multipliers
//! other than the critical one have one cross the unit circle (the curve meets a fold, a
//! period-doubling or a Neimark–Sacker curve: fold–flip, 1:1 and 1:2 resonances,
//! fold–Neimark–Sacker, …), and on fold and period-doubling curves where the number of
//! contacts per period changes (the curve meets a grazing curve). Each is placed by linear
//! interpolation in arclength of its test quantity and lies between its two points.

mod codim_two;
mod defining;
mod family;
pub mod request;

pub use codim_two::{CodimTwo, Meets};
pub use family::{Family2, Member};

use crate::analysis::continuation::{tangent, Scaled, ShapeObserver};
use crate::analysis::orbit::relative_residual;
use crate::analysis::shooting;
use crate::base::progress::Progress;
use crate::error::{Error, ParameterError};
use defining::{initial_borders, Borders, Linear, System};
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::ops::AddAssign;

/// Which codimension-one point a curve follows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CurveKind {
    /// A multiplier at +1.
    Fold,
    /// A multiplier at −1.
    PeriodDoubling,
    /// An extremum of the tip displacement at the stop.
    Grazing,
    /// A complex pair of multipliers on the unit circle.
    NeimarkSacker,
}

impl std::fmt::Display for CurveKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            CurveKind::Fold => "fold",
            CurveKind::PeriodDoubling => "period doubling",
            CurveKind::Grazing => "grazing",
            CurveKind::NeimarkSacker => "Neimark–Sacker",
        })
    }
}

/// Step control and limits of a curve.
#[derive(Debug, Clone, Serialize)]
pub struct CurveSettings {
    /// The interval of p the curve is traced in.
    pub range_p: (f64, f64),
    /// The interval of q.
    pub range_q: (f64, f64),
    /// First arclength step (in ξ, ln p, ln q).
    pub initial_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Smallest step before a direction is given up.
    pub min_step: f64,
    /// Points in each direction from the start at most.
    pub max_points: usize,
}

impl CurveSettings {
    /// Defaults for the rectangle `range_p` × `range_q`.
    pub fn new(range_p: (f64, f64), range_q: (f64, f64)) -> Self {
        Self {
            range_p,
            range_q,
            initial_step: 0.01,
            max_step: 0.05,
            min_step: 1e-6,
            max_points: 400,
        }
    }
}

/// One point of a curve.
#[derive(Debug, Clone, Serialize)]
pub struct CurvePoint {
    /// p.
    pub p: f64,
    /// q.
    pub q: f64,
    /// The orbit's state [η; η̇] at the start of a forcing period.
    pub state: Vec<f64>,
    /// n: contacts per orbit period.
    pub impacts_n: usize,
    /// Floquet multipliers [re, im], largest modulus first.
    pub multipliers: Vec<[f64; 2]>,
    /// ‖P^m(x) − x‖∞/‖x‖∞ after polishing.
    pub orbit_residual: f64,
    /// How far the polished orbit is from the condition: |μ ∓ 1| of the nearest multiplier,
    /// ||μ| − 1| of the complex multiplier nearest the unit circle, or |d_ext − d₀|/A_free.
    pub test_residual: f64,
}

/// A traced curve of codimension-one points.
#[derive(Debug, Clone, Serialize)]
pub struct Curve {
    /// What it follows.
    pub kind: CurveKind,
    /// m: forcing periods per orbit period.
    pub period_m: u64,
    /// The symbols of p and q.
    pub parameters: (&'static str, &'static str),
    /// The points in arclength order.
    pub points: Vec<CurvePoint>,
    /// Where it meets other curves.
    pub codim_two: Vec<CodimTwo>,
    /// Why each end ends (the first point's end, the last point's end).
    pub ends: (String, String),
}

/// Newton iterations of one correction.
const MAX_CORRECTOR: usize = 8;
/// Newton iterations locating the first point.
const MAX_LOCATE: usize = 30;
/// The corrector's tolerance on the orbit's relative residual and on the test function.
/// At fixed (p, q) both are evaluated to round-off; only their parameter derivatives carry
/// the ~1e-12 noise of a new simulator per parameter value (divided by the difference step:
/// ~1e-6 relative), which slows Newton but does not move its limit. The polish that follows
/// moves the orbit by about this much, and the test quantity with it.
const TOLERANCE: f64 = 1e-11;

/// The largest test residual of a polished point: a point whose orbit, converged by
/// shooting with the model's own contacts, misses the curve's condition by more is not on
/// the curve (the extended system, with its contacts held, followed an orbit the model
/// does not have: it passes through the stop, or lost a contact). A fold's multiplier
/// lies up to ~1e-5 from 1 when its condition is met to round-off (square-root
/// sensitivity); every other condition is met to ~1e-11.
const POLISHED_TEST_LIMIT: f64 = 1e-4;

fn validate(settings: &CurveSettings, p0: f64, q0: f64) -> Result<(), Error> {
    let bad = |what: &str| -> Result<(), Error> {
        Err(ParameterError::new("curve settings", "these", what).into())
    };
    for (a, b) in [settings.range_p, settings.range_q] {
        if !(a > 0.0 && b > a && b.is_finite()) {
            return bad("each range must satisfy 0 < from < to, finite");
        }
    }
    let inside = |x: f64, r: (f64, f64)| x >= r.0 && x <= r.1;
    if !(inside(p0, settings.range_p) && inside(q0, settings.range_q)) {
        return bad("the starting (p, q) must lie in the ranges");
    }
    if !(settings.min_step > 0.0
        && settings.initial_step >= settings.min_step
        && settings.max_step >= settings.initial_step
        && settings.max_points >= 2)
    {
        return bad("steps must satisfy 0 < min ≤ initial ≤ max, and points ≥ 2");
    }
    Ok(())
}

/// The tracer's state for one curve.
struct Tracer<'s, 'f, 'a> {
    system: &'s System<'f, 'a>,
    settings: &'s CurveSettings,
}

impl Tracer<'_, '_, '_> {
    fn n(&self, z: &DVector<f64>) -> usize {
        z.len() - 2
    }

    /// Whether z lies in the rectangle.
    fn inside(&self, z: &DVector<f64>) -> bool {
        let n = self.n(z);
        let (p, q) = (z[n].exp(), z[n + 1].exp());
        let r = (self.settings.range_p, self.settings.range_q);
        p >= r.0 .0 && p <= r.0 .1 && q >= r.1 .0 && q <= r.1 .1
    }

    /// Keller's corrector with fixed borders; None if it does not converge.
    fn correct(
        &self,
        z_pred: &DVector<f64>,
        t: &DVector<f64>,
        borders: &Borders,
        max_distance: f64,
    ) -> Result<Option<(DVector<f64>, Linear, usize)>, Error> {
        let d = z_pred.len();
        let mut z = z_pred.clone();
        for it in 0..=MAX_CORRECTOR {
            let lin = match self.system.linearise(&z, borders) {
                Ok(l) => l,
                // a step out of the model's range, into a broken run or a singular test
                // system: not converged, a shorter step is tried
                Err(e) if recoverable(&e) => return Ok(None),
                Err(e) => return Err(e),
            };
            let arc = t.dot(&(&z - z_pred));
            let test = lin.f[d - 2].abs();
            if lin.residual <= TOLERANCE && test <= TOLERANCE && arc.abs() <= 1e-10 {
                return Ok(Some((z, lin, it)));
            }
            if it == MAX_CORRECTOR {
                break;
            }
            let mut a = DMatrix::zeros(d, d);
            a.view_mut((0, 0), (d - 1, d)).copy_from(&lin.jacobian);
            a.row_mut(d - 1).copy_from(&t.transpose());
            let mut rhs = DVector::zeros(d);
            rhs.rows_mut(0, d - 1).copy_from(&(-&lin.f));
            rhs[d - 1] = -arc;
            let Some(step) = a.lu().solve(&rhs) else {
                return Ok(None);
            };
            z += step;
            if !z.iter().all(|v| v.is_finite()) || (&z - z_pred).norm() > max_distance {
                return Ok(None);
            }
        }
        Ok(None)
    }

    /// The point at z polished by shooting at its (p, q); None if shooting fails there or
    /// the polished orbit misses the condition by more than [`POLISHED_TEST_LIMIT`].
    fn polish(&self, z: &DVector<f64>) -> Result<Option<CurvePoint>, Error> {
        let n = self.n(z);
        let (p, q) = (z[n].exp(), z[n + 1].exp());
        let sys = self.system;
        let member = sys.family.member(p, q)?;
        let x = sys.state(z);
        let Ok(orbit) =
            shooting::shoot_at_period(member.map(), &x, sys.m, shooting::MAX_ITERATIONS)
        else {
            return Ok(None);
        };
        let distance = |target: f64| {
            orbit
                .multipliers
                .iter()
                .map(|z| (z[0] - target).hypot(z[1]))
                .fold(f64::INFINITY, f64::min)
        };
        let test_residual = match sys.kind {
            CurveKind::Fold => distance(1.0),
            CurveKind::PeriodDoubling => distance(-1.0),
            // | |μ| − 1 | of the complex multiplier nearest the unit circle
            CurveKind::NeimarkSacker => orbit
                .multipliers
                .iter()
                .filter(|z| z[1].abs() > defining::COMPLEX * z[0].hypot(z[1]))
                .map(|z| (z[0].hypot(z[1]) - 1.0).abs())
                .fold(f64::INFINITY, f64::min),
            CurveKind::Grazing => {
                let sim = member.simulator()?;
                let mut obs = ShapeObserver::new(sim);
                sim.run(&DVector::from_vec(orbit.state.clone()), sys.m, &mut obs)?;
                obs.finish()
                    .nearest_extremum
                    .map_or(f64::INFINITY, f64::abs)
                    / sim.model().free_tip_amplitude().0
            }
        };
        if test_residual.is_nan() || test_residual > POLISHED_TEST_LIMIT {
            return Ok(None);
        }
        Ok(Some(CurvePoint {
            p,
            q,
            state: orbit.state,
            impacts_n: orbit.impacts_n,
            multipliers: orbit.multipliers,
            orbit_residual: orbit.residual,
            test_residual,
        }))
    }

    /// Follows the curve from z0 along t0 until it ends; the points after the first, and
    /// why it ended.
    fn walk(
        &self,
        z0: &DVector<f64>,
        t0: &DVector<f64>,
        borders0: &Borders,
        progress: &dyn Progress,
    ) -> Result<(Vec<CurvePoint>, String), Error> {
        let s = self.settings;
        let (mut z, mut t, mut borders) = (z0.clone(), t0.clone(), borders0.clone());
        let mut h = s.initial_step;
        let mut points = Vec::new();
        let end = loop {
            if progress.cancelled() {
                return Err(Error::Interrupted);
            }
            if points.len() + 1 >= s.max_points {
                break format!("{} points reached", s.max_points);
            }
            if !self.inside(&z) {
                break "left the parameter rectangle".to_string();
            }
            let pred = &z + &t * h;
            let corrected = self.correct(&pred, &t, &borders, 2.0 * h)?;
            // why a step fails: the corrector, or the point's polished orbit
            let mut off_condition = false;
            let accepted = match corrected {
                Some((zn, lin, its)) => match tangent(&lin.jacobian, &t) {
                    Some(tn) if tn.dot(&t) >= 0.95 || h <= s.min_step => {
                        let polished = self.polish(&zn)?;
                        off_condition = polished.is_none();
                        polished.map(|pt| (zn, lin, its, tn, pt))
                    }
                    _ => None,
                },
                None => None,
            };
            match accepted {
                Some((zn, lin, its, tn, point)) => {
                    points.push(point);
                    borders = lin.next_borders(&borders);
                    (z, t) = (zn, tn);
                    if its <= 3 {
                        h = (h * 1.4).min(s.max_step);
                    } else if its >= 6 {
                        h *= 0.7;
                    }
                    if points.len() > 10 && (&z - z0).norm() < 1.5 * h {
                        break "closed curve: back at its first point".to_string();
                    }
                }
                None => {
                    h *= 0.5;
                    if h < s.min_step {
                        let n = self.n(&z);
                        let what = if off_condition {
                            "the model's orbit leaves the curve's condition"
                        } else {
                            "corrector failed"
                        };
                        break format!(
                            "{what} at (p, q) = ({:.6}, {:.6}) with steps below {:.0e}",
                            z[n].exp(),
                            z[n + 1].exp(),
                            s.min_step
                        );
                    }
                }
            }
        };
        Ok((points, end))
    }
}

/// Traces the curve of `kind` points of period-m orbits through the point nearest the
/// orbit near `x0` at (p0, q0), in both directions, until it leaves the rectangle of
/// `settings`, closes, or its corrector fails. `x0` need not be on the orbit and (p0, q0)
/// need only be near the curve: the first point is located by Newton at fixed q = q0.
///
/// # Errors
/// [`Error::Parameter`] for bad settings or a start outside the rectangle; shooting's errors
/// at (p0, q0); [`Error::Unsupported`] when shooting converges to a divisor of m or the start
/// has no tangent; [`Error::NotConverged`] when no point of the curve is found at q0;
/// [`Error::Interrupted`] when `progress` is cancelled.
#[allow(clippy::too_many_arguments)]
pub fn trace_curve(
    family: &Family2,
    kind: CurveKind,
    x0: &DVector<f64>,
    (p0, q0): (f64, f64),
    m: u64,
    settings: &CurveSettings,
    progress: &dyn Progress,
) -> Result<Curve, Error> {
    validate(settings, p0, q0)?;
    let (system, z0, lin0, borders) = start(family, kind, x0, (p0, q0), m)?;
    let d = z0.len();
    let mut prev = DVector::zeros(d);
    prev[d - 1] = 1.0;
    let t0 = tangent(&lin0.jacobian, &prev).ok_or_else(|| {
        Error::Unsupported("no tangent at the first point: a singular point of the curve".into())
    })?;
    let tracer = Tracer {
        system: &system,
        settings,
    };
    let first = tracer.polish(&z0)?.ok_or_else(|| Error::NotConverged {
        message: "the first point of the curve could not be polished (shooting failed, or the \
                  model's orbit misses the curve's condition there)"
            .into(),
        residual: None,
    })?;
    // the two directions are independent: traced in parallel (each is deterministic, so
    // the curve does not depend on the thread count)
    let back = -&t0;
    let (forward, backward) = rayon::join(
        || tracer.walk(&z0, &t0, &borders, progress),
        || tracer.walk(&z0, &back, &borders, progress),
    );
    let ((forward, end_forward), (backward, end_backward)) = (forward?, backward?);
    let closed = end_forward.starts_with("closed");
    let mut points: Vec<CurvePoint> = if closed {
        Vec::new()
    } else {
        backward.into_iter().rev().collect()
    };
    points.push(first);
    points.extend(forward);
    let codim_two = codim_two::detect(kind, &points);
    Ok(Curve {
        kind,
        period_m: m,
        parameters: family.symbols,
        points,
        codim_two,
        ends: if closed {
            (end_forward.clone(), end_forward)
        } else {
            (end_backward, end_forward)
        },
    })
}

/// The extended system of `kind` and its first point, located at fixed q0 from the orbit
/// near x0 at p0: (system, z0, its linearisation, borders).
fn start<'f, 'a>(
    family: &'f Family2<'a>,
    kind: CurveKind,
    x0: &DVector<f64>,
    (p0, q0): (f64, f64),
    m: u64,
) -> Result<(System<'f, 'a>, DVector<f64>, Linear, Borders), Error> {
    let member0 = family.member(p0, q0)?;
    let sim0 = member0.map();
    if kind == CurveKind::Grazing {
        member0.simulator()?;
    }
    // a state already on a period-m orbit (a branch point a one-parameter run reported) is
    // taken as it is: shooting at fixed p is ill-conditioned next to a fold, where the
    // extended system is not
    let on_orbit = {
        sim0.check_state("start state", x0)?;
        let px = sim0.advance(x0, 0, m, false)?.state;
        relative_residual(&px, x0) <= 1e-8
    };
    let x = if on_orbit {
        x0.clone()
    } else {
        let start = shooting::shoot(sim0, x0, m)?;
        if start.period_m != m {
            return Err(Error::Unsupported(format!(
                "shooting for period {m} at (p, q) = ({p0}, {q0}) converged to an orbit of \
                 period {}",
                start.period_m
            )));
        }
        DVector::from_vec(start.state)
    };
    let system = System {
        family,
        kind,
        m,
        sc: Scaled::new(&x, member0.floor()),
    };
    let (_, mono, _) = shooting::map_with_jacobian(sim0, &x, m)?;
    let borders = initial_borders(kind, &system.sc, &mono)?;
    let (z0, lin0, borders) = locate(&system, &x, p0, q0, borders)?;
    Ok((system, z0, lin0, borders))
}

/// The point of the `kind` curve at q = q0 nearest the period-m orbit near x0 at p0, found
/// by Newton on (x, p) at fixed q and polished: one point of the curve, without tracing it
/// (to check a curve where it was not started, or to place a point exactly).
///
/// # Errors
/// As [`trace_curve`]'s start.
pub fn locate_point(
    family: &Family2,
    kind: CurveKind,
    x0: &DVector<f64>,
    (p0, q0): (f64, f64),
    m: u64,
) -> Result<CurvePoint, Error> {
    let (system, z0, _, _) = start(family, kind, x0, (p0, q0), m)?;
    let settings = CurveSettings::new((p0, p0), (q0, q0));
    let tracer = Tracer {
        system: &system,
        settings: &settings,
    };
    tracer.polish(&z0)?.ok_or_else(|| Error::NotConverged {
        message: "the located point could not be polished".into(),
        residual: None,
    })
}

/// Whether a Newton step that ends in this error may be retried shorter: a state or model
/// out of range, a run that breaks, chatters, or a singular test system.
fn recoverable(e: &Error) -> bool {
    matches!(
        e,
        Error::Parameter(_)
            | Error::Invariant(_)
            | Error::Flow(_)
            | Error::Chatter(_)
            | Error::NotConverged { .. }
    )
}

/// Newton on (ξ, u) at fixed v = ln q0 from the orbit x at p0: the first point, its
/// linearisation and borders.
fn locate(
    system: &System,
    x: &DVector<f64>,
    p0: f64,
    q0: f64,
    mut borders: Borders,
) -> Result<(DVector<f64>, Linear, Borders), Error> {
    let n = x.len();
    let mut z = DVector::zeros(n + 2);
    z.rows_mut(0, n).copy_from(&system.sc.to_xi(x));
    z[n] = p0.ln();
    z[n + 1] = q0.ln();
    let mut last = f64::NAN;
    // the last accepted point and the step taken from it, halved while a step lands where
    // the model refuses the state or the run breaks (a rigid tip beyond the stop)
    let mut back: Option<(DVector<f64>, DVector<f64>)> = None;
    let mut halvings = 0;
    for _ in 0..MAX_LOCATE {
        let lin = match system.linearise(&z, &borders) {
            Ok(lin) => lin,
            Err(e) if recoverable(&e) && halvings < 20 => {
                let Some((z_back, step)) = back.as_mut() else {
                    return Err(e);
                };
                *step *= 0.5;
                z = z_back.clone();
                z.rows_mut(0, n + 1).add_assign(&*step);
                halvings += 1;
                continue;
            }
            Err(e) => return Err(e),
        };
        halvings = 0;
        last = lin.f[n].abs();
        if lin.residual <= TOLERANCE && last <= TOLERANCE {
            return Ok((z, lin, borders));
        }
        let a = lin.jacobian.columns(0, n + 1).into_owned();
        let Some(mut step) = a.lu().solve(&(-&lin.f)) else {
            break;
        };
        // at most a factor e^0.25 in p per step: the test function is only locally linear
        let cap = 0.25 / step[n].abs().max(0.25);
        step *= cap;
        back = Some((z.clone(), step.clone()));
        z.rows_mut(0, n + 1).add_assign(&step);
        borders = lin.next_borders(&borders);
        if !z.iter().all(|v| v.is_finite()) {
            break;
        }
    }
    Err(Error::NotConverged {
        message: format!(
            "no {} point found near p = {p0} at q = {q0}: start nearer the point",
            system.kind
        ),
        residual: last.is_finite().then_some(last),
    })
}
