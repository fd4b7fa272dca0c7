//! What continuation needs to know about one period of an orbit besides its state: the
//! impact velocities, the largest tip displacement, and how close the orbit is to
//! **grazing**, where its event signature (its number n of contacts per period) changes.
//!
//! n changes when an interior local extremum of the tip displacement d(t) crosses the stop
//! d₀: a contact's deepest point rises to d₀ (the contact vanishes), a near miss in free
//! flight reaches it (a contact appears), a dip inside a contact phase falls to d₀ (the
//! contact splits in two), or the short free interval between two contacts closes (they
//! merge). The **grazing distance** is therefore the smallest |d_ext − d₀| over the orbit's
//! interior local extrema: it tends to 0 at every grazing, whichever kind.
//!
//! Extrema are found from sign changes of ḋ sampled at least eight times per period of the
//! fastest mode (its frequency bounded by the largest row sum of the contact stiffness);
//! per segment the one nearest the stop is refined by bisection on ḋ to round-off. The
//! largest tip displacement is the certified maximum ([`crate::engine::sim::maximum`]).

use crate::engine::sim::maximum::maximum;
use crate::engine::sim::{EventView, Observer, SegmentView, Simulator, Stats};
use crate::model::galerkin::Region;
use nalgebra::{DMatrix, DVector};

/// One period of an orbit, seen from the tip.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct OrbitShape {
    /// Tip velocity at each entry into contact, in time order.
    pub impact_velocities: Vec<f64>,
    /// The smallest |d_ext − d₀| over interior local extrema of d (None if d has none).
    pub grazing_distance: Option<f64>,
    /// d_ext − d₀ for that extremum, signed: it passes through 0 at a grazing (the test
    /// function of a grazing curve, [`crate::analysis::curves`]).
    #[serde(skip)]
    pub nearest_extremum: Option<f64>,
    /// When that extremum occurs (t from the run's start clock's origin).
    #[serde(skip)]
    pub nearest_extremum_time: Option<f64>,
    /// The largest tip displacement.
    pub max_tip: f64,
}

/// Collects an [`OrbitShape`] over a run.
#[derive(Debug, Clone)]
pub struct ShapeObserver {
    shape: OrbitShape,
    gap: f64,
    /// Highest angular frequency in the model (sampling density of the extremum search).
    fastest: f64,
    /// The last sample of the previous segment (d, ḋ), to see an extremum that falls on a
    /// segment boundary.
    last: Option<(f64, f64)>,
}

impl ShapeObserver {
    /// For a run of `sim`.
    pub fn new(sim: &Simulator) -> Self {
        let k = sim.model().stiffness(Region::Contact);
        let row_sum = (0..k.nrows())
            .map(|i| k.row(i).iter().map(|v| v.abs()).sum::<f64>())
            .fold(0.0, f64::max);
        Self {
            shape: OrbitShape {
                max_tip: f64::NEG_INFINITY,
                ..Default::default()
            },
            gap: sim.model().params().gap,
            fastest: row_sum.sqrt().max(sim.omega()),
            last: None,
        }
    }

    /// The shape seen.
    pub fn finish(self) -> OrbitShape {
        self.shape
    }
}

impl Observer for ShapeObserver {
    fn segment(&mut self, seg: &SegmentView) {
        let sig = seg.signal();
        let mut stats = Stats::default();
        let (best, _) = maximum(sig, seg.end, None, seg.simulator().h_min(), &mut stats);
        let top = best.map_or(sig.tip(0.0).0, |(_, d)| d);
        self.shape.max_tip = self.shape.max_tip.max(top);
        let samples = ((seg.end * self.fastest / std::f64::consts::FRAC_PI_4).ceil() as usize)
            .clamp(16, 1 << 16);
        let h = seg.end / samples as f64;
        let mut prev = match self.last {
            Some((d, v)) => (-h, d, v),
            None => {
                let (d, v) = sig.tip(0.0);
                (0.0, d, v)
            }
        };
        // every extremum's bracket: (start, ḋ > 0 at start). Each is refined: choosing one
        // by its sampled distance from the stop picks the wrong one where two extrema come
        // within the samples' error (½|d̈|h²) of the stop, as where the extremum nearest the
        // stop changes from one to another
        let mut brackets: Vec<(f64, bool)> = Vec::new();
        for j in 1..=samples {
            let s = j as f64 * h;
            let (d, v) = sig.tip(s);
            if (prev.2 > 0.0) != (v > 0.0) {
                brackets.push((prev.0.max(0.0), prev.2 > 0.0));
            }
            prev = (s, d, v);
        }
        self.last = Some((prev.1, prev.2));
        for (a, rising) in brackets {
            // bisection on ḋ over [a, a + h]: ḋ keeps the sign `rising` at lo
            let (mut lo, mut hi) = (a, (a + h).min(seg.end));
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if (sig.tip(mid).1 > 0.0) == rising {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let signed = sig.tip(0.5 * (lo + hi)).0 - self.gap;
            if self.shape.grazing_distance.is_none_or(|g| signed.abs() < g) {
                self.shape.grazing_distance = Some(signed.abs());
                self.shape.nearest_extremum = Some(signed);
                self.shape.nearest_extremum_time = Some(seg.start.time() + 0.5 * (lo + hi));
            }
        }
    }

    fn event(&mut self, e: &EventView) {
        if e.entering && !e.grazing {
            self.shape.impact_velocities.push(e.tip_velocity);
        }
    }
}

/// The tip displacement minus the gap at one time t of a run (None if the run does not
/// reach t). At an extremum of the tip displacement its derivative in the start state or
/// a parameter is that of the extremum's value (the extremum's time moves, but ḋ = 0
/// there), so a grazing test's differences need the tip at the base run's extremum time
/// only, not a new search for the extremum.
#[derive(Debug, Clone)]
pub struct TipAt {
    t: f64,
    gap: f64,
    value: Option<f64>,
}

impl TipAt {
    /// At time `t`, for a run of `sim`.
    pub fn new(sim: &Simulator, t: f64) -> Self {
        Self {
            t,
            gap: sim.model().params().gap,
            value: None,
        }
    }

    /// d(t) − d₀, if the run reached t.
    pub fn finish(self) -> Option<f64> {
        self.value
    }
}

impl Observer for TipAt {
    fn segment(&mut self, seg: &SegmentView) {
        let t0 = seg.start.time();
        // (a t at the run's very end may exceed the last segment's end by round-off)
        let slack = 1e-12 * (1.0 + self.t.abs());
        if self.value.is_none() && self.t >= t0 - slack && self.t <= t0 + seg.end + slack {
            self.value = Some(seg.tip((self.t - t0).clamp(0.0, seg.end)).0 - self.gap);
        }
    }
}

/// ∂(d(t) − d₀)/∂x: the tip displacement's row of the run's Jacobian Φ(t, 0) at one time t
/// (None if the run does not reach t). Φ(t, 0) is the product of the segments' exact
/// exponentials up to t, carried in modal coordinates as the monodromy is
/// ([`crate::engine::sim::Monodromy`]; the saltation at a switch of the compliant model is
/// the identity). One run gives the whole row, where differences of [`TipAt`] take one run
/// per state coordinate.
#[derive(Debug, Clone)]
pub struct TipRowAt {
    t: f64,
    /// E ⋯ E·T up to the last segment before t, in the modal coordinates of its region.
    modal: Option<(Region, DMatrix<f64>)>,
    row: Option<DVector<f64>>,
}

impl TipRowAt {
    /// At time `t`, for a run.
    pub fn new(t: f64) -> Self {
        Self {
            t,
            modal: None,
            row: None,
        }
    }

    /// The row ∂d(t)/∂x as a vector of the state's length, if the run reached t.
    pub fn finish(self) -> Option<DVector<f64>> {
        self.row
    }
}

impl Observer for TipRowAt {
    fn segment(&mut self, seg: &SegmentView) {
        if self.row.is_some() {
            return;
        }
        let flow = seg.flow();
        let mut product = match self.modal.take() {
            None => flow.to_modal().clone(),
            Some((region, p)) if region == seg.region => p,
            Some((_, p)) => seg.simulator().switch_map(seg.region) * p,
        };
        let t0 = seg.start.time();
        // as TipAt: a t at the run's very end may exceed the last segment's end by round-off
        let slack = 1e-12 * (1.0 + self.t.abs());
        if self.t <= t0 + seg.end + slack {
            flow.evolve_rows((self.t - t0).clamp(0.0, seg.end), &mut product);
            // d = φ(1)ᵀη: the tip's row of the state map F, times the product
            let tip = seg.simulator().model().tip();
            let f = flow.from_modal();
            let c = f.rows(0, tip.len()).tr_mul(tip);
            self.row = Some(product.tr_mul(&c));
        } else {
            flow.evolve_rows(seg.end, &mut product);
            self.modal = Some((seg.region, product));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{TipAt, TipRowAt};
    use crate::engine::sim::{Events, Simulator};
    use nalgebra::DVector;

    /// The row from the run's Jacobian is the derivative of the tip at a fixed time:
    /// central differences of [`TipAt`] agree to their own error, over runs whose tip
    /// enters and leaves the stop before t (so the product crosses switches both ways).
    #[test]
    fn the_tip_row_is_the_derivative_of_the_tip_at_a_fixed_time() {
        for (modes, k) in [(3, 100.0), (10, 1000.0)] {
            // Figure 4's model at another stop stiffness
            let forced = crate::model::problems::Forced {
                k_over_k1: k,
                ..crate::model::problems::figure4(modes)
            };
            let sim = Simulator::new(forced.model().unwrap()).unwrap();
            let x0 = DVector::from_fn(2 * modes, |i, _| 0.3 / (1.0 + i as f64).powi(2));
            let t = 1.37 * sim.period();
            let mut events = Events::default();
            sim.run(&x0, 2, &mut events).unwrap();
            let switches = events.events.iter().filter(|e| e.time < t).count();
            assert!(switches >= 2, "N = {modes}: {switches} switches before t");
            let mut obs = TipRowAt::new(t);
            sim.run(&x0, 2, &mut obs).unwrap();
            let row = obs.finish().unwrap();
            let tip = |x: &DVector<f64>| {
                let mut obs = TipAt::new(&sim, t);
                sim.run(x, 2, &mut obs).unwrap();
                obs.finish().unwrap()
            };
            // a central difference errs by its round-off, ~ε·|d|/h ≈ 2e-9 of the row at
            // h = 1e-7, and by O(h²) (the flow is smooth in x between switches, C¹ across
            // them); 5e-9 measured, 1e-7 allowed
            let h = 1e-7;
            for j in 0..2 * modes {
                let mut e = DVector::zeros(2 * modes);
                e[j] = h;
                let fd = (tip(&(&x0 + &e)) - tip(&(&x0 - &e))) / (2.0 * h);
                let err = (fd - row[j]).abs();
                assert!(
                    err <= 1e-7 * row.amax(),
                    "N = {modes}, column {j}: {fd} against {} ({err:e})",
                    row[j]
                );
            }
        }
    }
}
