//! Observers: what a run records. The driver ([`super::Simulator`]) hands every observer
//! each exact segment before the state moves on, each switching event, and each period
//! boundary; an observer keeps what it needs. A scene adds an observable by writing an
//! observer, not by editing the driver. Nothing is computed that no observer asks for.
//!
//! **Observing never perturbs.** Where a run's segments end depends only on the run (its
//! start, its end and its events), never on its observers: a period boundary inside a
//! segment is reported with the exact state there ([`SegmentView::state`]), and samples
//! on a grid are taken inside segments. So events, strobe and final state are the same
//! bits whatever is observed (tested over observers, models and laws).
//!
//! Several observers run together as a tuple: `sim.run(&x0, 100, &mut (&mut events, &mut
//! energy))`; `&mut ()` observes nothing.

use super::clock::Clock;
use super::energy::{segment_energy, stored_energy, EnergyBudget};
use super::maximum::maximum;
use super::signal::TipSignal;
use super::{Simulator, Stats};
use crate::engine::flow::RegionFlow;
use crate::model::galerkin::Region;
use nalgebra::DVector;

/// One exact segment of the run: the flow of `region` from `start` for a duration `end`.
pub struct SegmentView<'a> {
    pub(super) sim: &'a Simulator,
    pub(super) flow: &'a RegionFlow,
    pub(super) y: &'a DVector<f64>,
    pub(super) phase0: f64,
    pub(super) signal: &'a TipSignal,
    /// When the segment starts.
    pub start: Clock,
    /// Its duration S: it covers [start, start + S].
    pub end: f64,
    /// The region it lies in.
    pub region: Region,
}

impl SegmentView<'_> {
    /// Tip displacement and velocity at s ∈ [0, S] (exact).
    pub fn tip(&self, s: f64) -> (f64, f64) {
        self.signal.tip(s)
    }

    /// The state [η; η̇] at s ∈ [0, S] (exact).
    pub fn state(&self, s: f64) -> DVector<f64> {
        self.flow.state(self.y, self.phase0, s)
    }

    /// The tip signal with its derivative bounds (for certified searches).
    pub fn signal(&self) -> &TipSignal {
        self.signal
    }

    /// The region's exact flow.
    pub fn flow(&self) -> &RegionFlow {
        self.flow
    }

    /// The segment's real modal coordinates y ([`RegionFlow::modal`]) at its start.
    pub fn modal_coordinates(&self) -> &DVector<f64> {
        self.y
    }

    /// The forcing phase ω·offset at its start.
    pub fn phase(&self) -> f64 {
        self.phase0
    }

    /// The simulator running it.
    pub fn simulator(&self) -> &Simulator {
        self.sim
    }
}

/// A switching event as the driver sees it.
pub struct EventView<'a> {
    /// When, as a clock (whole forcing periods and the time into the current one).
    pub clock: Clock,
    /// Entering contact (`true`) or leaving it.
    pub entering: bool,
    /// A grazing touch (zero normal velocity): recorded, no switch.
    pub grazing: bool,
    /// Tip velocity φ(1)ᵀη̇ at the event.
    pub tip_velocity: f64,
    /// The state [η; η̇] at the event.
    pub state: &'a DVector<f64>,
}

/// What a run reports to. Every method has an empty default.
pub trait Observer {
    /// Whether [`Observer::period_boundary`] is wanted (the state at each period boundary
    /// inside a segment then costs one evaluation of the exact flow). It does not change
    /// where segments end.
    fn wants_period_boundaries(&self) -> bool {
        false
    }
    /// Whether the run should stop now (the caller's Ctrl-C, say): polled after every
    /// segment; the run then ends with [`crate::error::Error::Interrupted`].
    fn interrupted(&self) -> bool {
        false
    }
    /// The run starts from state x at `clock`.
    fn begin(&mut self, _sim: &Simulator, _clock: &Clock, _x: &DVector<f64>) {}
    /// An exact segment, before the state advances past it.
    fn segment(&mut self, _segment: &SegmentView) {}
    /// A switching event (after the segment that ends at it).
    fn event(&mut self, _event: &EventView) {}
    /// A period boundary reached at `clock` in state x (only where segments end there).
    fn period_boundary(&mut self, _clock: &Clock, _x: &DVector<f64>) {}
    /// The run ends in state x at `clock`, with its work counters.
    fn end(&mut self, _sim: &Simulator, _clock: &Clock, _x: &DVector<f64>, _stats: &Stats) {}
}

impl Observer for () {}

/// An observer that may be switched off: `None` observes nothing and costs nothing (the
/// energy budget of `simulate --no-energy`).
impl<O: Observer> Observer for Option<O> {
    fn wants_period_boundaries(&self) -> bool {
        self.as_ref().is_some_and(|o| o.wants_period_boundaries())
    }
    fn interrupted(&self) -> bool {
        self.as_ref().is_some_and(|o| o.interrupted())
    }
    fn begin(&mut self, sim: &Simulator, clock: &Clock, x: &DVector<f64>) {
        if let Some(o) = self {
            o.begin(sim, clock, x)
        }
    }
    fn segment(&mut self, segment: &SegmentView) {
        if let Some(o) = self {
            o.segment(segment)
        }
    }
    fn event(&mut self, event: &EventView) {
        if let Some(o) = self {
            o.event(event)
        }
    }
    fn period_boundary(&mut self, clock: &Clock, x: &DVector<f64>) {
        if let Some(o) = self {
            o.period_boundary(clock, x)
        }
    }
    fn end(&mut self, sim: &Simulator, clock: &Clock, x: &DVector<f64>, stats: &Stats) {
        if let Some(o) = self {
            o.end(sim, clock, x, stats)
        }
    }
}

impl<O: Observer + ?Sized> Observer for &mut O {
    fn wants_period_boundaries(&self) -> bool {
        (**self).wants_period_boundaries()
    }
    fn interrupted(&self) -> bool {
        (**self).interrupted()
    }
    fn begin(&mut self, sim: &Simulator, clock: &Clock, x: &DVector<f64>) {
        (**self).begin(sim, clock, x)
    }
    fn segment(&mut self, segment: &SegmentView) {
        (**self).segment(segment)
    }
    fn event(&mut self, event: &EventView) {
        (**self).event(event)
    }
    fn period_boundary(&mut self, clock: &Clock, x: &DVector<f64>) {
        (**self).period_boundary(clock, x)
    }
    fn end(&mut self, sim: &Simulator, clock: &Clock, x: &DVector<f64>, stats: &Stats) {
        (**self).end(sim, clock, x, stats)
    }
}

macro_rules! tuple_observer {
    ($($name:ident),+) => {
        impl<$($name: Observer),+> Observer for ($($name,)+) {
            fn wants_period_boundaries(&self) -> bool {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                false $(|| $name.wants_period_boundaries())+
            }
            fn interrupted(&self) -> bool {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                false $(|| $name.interrupted())+
            }
            fn begin(&mut self, sim: &Simulator, clock: &Clock, x: &DVector<f64>) {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                $($name.begin(sim, clock, x);)+
            }
            fn segment(&mut self, segment: &SegmentView) {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                $($name.segment(segment);)+
            }
            fn event(&mut self, event: &EventView) {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                $($name.event(event);)+
            }
            fn period_boundary(&mut self, clock: &Clock, x: &DVector<f64>) {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                $($name.period_boundary(clock, x);)+
            }
            fn end(&mut self, sim: &Simulator, clock: &Clock, x: &DVector<f64>, stats: &Stats) {
                #[allow(non_snake_case)]
                let ($($name,)+) = self;
                $($name.end(sim, clock, x, stats);)+
            }
        }
    };
}
tuple_observer!(A);
tuple_observer!(A, B);
tuple_observer!(A, B, C);
tuple_observer!(A, B, C, D);
tuple_observer!(A, B, C, D, E);

/// A recorded switching event.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Event {
    /// When, as a clock (whole forcing periods and the time into the current one).
    pub clock: Clock,
    /// t, the time of the event (non-dimensional beam time).
    pub time: f64,
    /// Entering contact (`true`) or leaving it.
    pub entering: bool,
    /// A grazing touch (zero normal velocity): recorded, no switch.
    pub grazing: bool,
    /// Tip velocity φ(1)ᵀη̇ at the event.
    pub tip_velocity: f64,
    /// The state [η; η̇], if asked for.
    pub state: Option<Vec<f64>>,
}

/// Records switching events (with the full state at each if `with_states`).
#[derive(Debug, Clone, Default)]
pub struct Events {
    /// Also keep the state [η; η̇] at each event.
    pub with_states: bool,
    /// The events, in order.
    pub events: Vec<Event>,
}

impl Events {
    /// Events with their states.
    pub fn with_states() -> Self {
        Self {
            with_states: true,
            events: Vec::new(),
        }
    }
}

impl Observer for Events {
    fn event(&mut self, e: &EventView) {
        self.events.push(Event {
            clock: e.clock,
            time: e.clock.time(),
            entering: e.entering,
            grazing: e.grazing,
            tip_velocity: e.tip_velocity,
            state: self.with_states.then(|| e.state.as_slice().to_vec()),
        });
    }
}

/// The state at the start and at every period boundary (ωt = 0 mod 2π): the
/// stroboscopic Poincaré map of §5.2.
#[derive(Debug, Clone, Default)]
pub struct Strobe {
    /// (cycle, state) pairs.
    pub samples: Vec<(i64, DVector<f64>)>,
    /// Keep only the last this many (0: all): a period search over m ≤ M needs M + 1, and
    /// a long window then costs no memory for the rest.
    pub keep_last: usize,
}

impl Strobe {
    /// A strobe that keeps only its last `n` samples (all if `n` is 0).
    pub fn keeping_last(n: usize) -> Self {
        Self {
            samples: Vec::new(),
            keep_last: n,
        }
    }

    fn push(&mut self, cycle: i64, x: &DVector<f64>) {
        // a run continued from where the last one ended begins at the boundary that run
        // ended on: one sample per cycle
        if self.samples.last().is_some_and(|(c, _)| *c == cycle) {
            return;
        }
        if self.keep_last > 0 && self.samples.len() >= self.keep_last {
            let excess = self.samples.len() + 1 - self.keep_last;
            self.samples.drain(..excess);
        }
        self.samples.push((cycle, x.clone()));
    }

    /// The states alone.
    pub fn states(&self) -> Vec<DVector<f64>> {
        self.samples.iter().map(|(_, x)| x.clone()).collect()
    }
}

impl Observer for Strobe {
    fn wants_period_boundaries(&self) -> bool {
        true
    }
    fn begin(&mut self, _: &Simulator, clock: &Clock, x: &DVector<f64>) {
        self.push(clock.cycles, x);
    }
    fn period_boundary(&mut self, clock: &Clock, x: &DVector<f64>) {
        self.push(clock.cycles, x);
    }
}

/// One dense sample: (t, tip displacement, tip velocity, in contact).
pub type Sample = (f64, f64, f64, bool);

/// Samples of the tip on the grid t = cycles·T + j·T/`per_period`.
#[derive(Debug, Clone, Default)]
pub struct Dense {
    /// Samples per forcing period.
    pub per_period: usize,
    /// The samples, in order.
    pub samples: Vec<Sample>,
}

impl Dense {
    /// `per_period` samples per period.
    pub fn new(per_period: usize) -> Self {
        Self {
            per_period,
            samples: Vec::new(),
        }
    }
}

impl Observer for Dense {
    fn segment(&mut self, seg: &SegmentView) {
        for (s, t) in seg.start.grid(seg.end, self.per_period) {
            let (d, v) = seg.tip(s);
            self.samples.push((t, d, v, seg.region == Region::Contact));
        }
    }
}

/// One dense sample of the whole state: t, in contact, tip displacement and velocity, and
/// [η; η̇].
pub type StateSample = (f64, bool, f64, f64, DVector<f64>);

/// Samples of the whole state [η; η̇] (and the tip) on the grid t = cycles·T +
/// j·T/`per_period`: the dense output of `simulate`.
#[derive(Debug, Clone, Default)]
pub struct DenseStates {
    /// Samples per forcing period.
    pub per_period: usize,
    /// The samples, in order.
    pub samples: Vec<StateSample>,
}

impl DenseStates {
    /// `per_period` samples per period.
    pub fn new(per_period: usize) -> Self {
        Self {
            per_period,
            samples: Vec::new(),
        }
    }
}

impl Observer for DenseStates {
    fn segment(&mut self, seg: &SegmentView) {
        for (s, t) in seg.start.grid(seg.end, self.per_period) {
            let (d, v) = seg.tip(s);
            let x = seg.state(s);
            self.samples
                .push((t, seg.region == Region::Contact, d, v, x));
        }
    }
}

/// The energy budget of the run, with every segment's work and dissipation in closed form.
#[derive(Debug, Clone, Default)]
pub struct Energy {
    /// The budget (complete after the run).
    pub budget: EnergyBudget,
}

impl Observer for Energy {
    fn begin(&mut self, sim: &Simulator, _: &Clock, x: &DVector<f64>) {
        self.budget.initial = stored_energy(sim.model(), x);
    }
    fn segment(&mut self, seg: &SegmentView) {
        let tables = seg.sim.energy_tables(seg.region);
        let (w, d) = segment_energy(seg.flow, seg.y, seg.phase0, tables, seg.end);
        self.budget.work += w;
        self.budget.dissipated += d;
        self.budget.gross += w.abs() + d.abs();
    }
    fn end(&mut self, sim: &Simulator, _: &Clock, x: &DVector<f64>, _: &Stats) {
        self.budget.last = stored_energy(sim.model(), x);
    }
}

/// The largest tip displacement d = φ(1)ᵀη of a run, found by certified level crossings
/// ([`super::maximum`]): no value of d on the run exceeds `value` by more than `tolerance`,
/// down to the search's resolution (a peak narrower than the shortest step, 1e-13 T,
/// rising less than ≈ M·h_min²/2 above that level could pass unseen).
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct TipMaximum {
    /// Where it is attained.
    pub clock: Clock,
    /// t, the time of the event (non-dimensional beam time).
    pub time: f64,
    /// max d.
    pub value: f64,
    /// The certificate's slack: 64ε times the tip signal's magnitude scale.
    pub tolerance: f64,
}

/// Observes the certified maximum of the tip displacement.
#[derive(Debug, Clone, Default)]
pub struct TipMax {
    /// The maximum so far (none before the first segment).
    pub maximum: Option<TipMaximum>,
    /// Switching-function evaluations spent on it.
    pub evaluations: u64,
}

impl Observer for TipMax {
    fn segment(&mut self, seg: &SegmentView) {
        let mut work = Stats::default();
        let floor = self.maximum.map(|m| m.value);
        let (best, tolerance) = maximum(seg.signal, seg.end, floor, seg.sim.h_min(), &mut work);
        self.evaluations += work.evaluations;
        // the certificate's slack is the largest over all segments
        let tolerance = self
            .maximum
            .map_or(tolerance, |m| m.tolerance.max(tolerance));
        if let Some((s, value)) = best {
            let mut at = seg.start;
            at.advance(s);
            self.maximum = Some(TipMaximum {
                clock: at,
                time: at.time(),
                value,
                tolerance,
            });
        } else if let Some(m) = self.maximum.as_mut() {
            m.tolerance = tolerance;
        }
    }
}
