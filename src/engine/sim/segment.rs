//! One segment of a region's exact flow and the flight built on it: the tip gap of the
//! segment as an exponential sum with derivative bounds ([`super::signal`]), searched for
//! its first certified crossing ([`super::crossing`]).

use super::signal::{Signal, Target, Term, TipSignal};
use super::{crossing, Clock, Simulator, Stats};
use crate::engine::flow::{RegionFlow, TermKind};
use crate::model::galerkin::Region;
use nalgebra::DVector;

/// One segment: a region's flow from modal coordinates y at forcing phase θ₀.
pub(super) struct Segment<'a> {
    pub(super) flow: &'a RegionFlow,
    pub(super) y: DVector<f64>,
    pub(super) phase0: f64,
    pub(super) signal: TipSignal,
    /// 2|ḋ_modal(0) − ḋ_state|: the representation error of the tip velocity.
    pub(super) velocity_floor: f64,
    /// +1 in free flight (g = d − d₀), −1 in contact (g = d₀ − d).
    pub(super) sign: f64,
    pub(super) gap: f64,
}

impl<'a> Segment<'a> {
    pub(super) fn new(
        flow: &'a RegionFlow,
        x: &DVector<f64>,
        phase0: f64,
        gap: f64,
        tip: &DVector<f64>,
    ) -> Self {
        let y = flow.modal(x, phase0);
        let terms = flow.terms().iter().map(|t| {
            let a = t.tip * flow.coefficient(&y, t);
            match t.kind {
                TermKind::Pair => Term::Pair {
                    a,
                    lambda: t.lambda,
                },
                TermKind::Real => Term::Real {
                    a: a.re,
                    lambda: t.lambda.re,
                },
                TermKind::Block { block, tip, .. } => Term::Block {
                    block,
                    tip,
                    y: [y[t.slot], y[t.slot + 1]],
                },
            }
        });
        let signal = TipSignal::new(
            flow.omega(),
            phase0,
            flow.tip_forced(),
            flow.tip_static(),
            gap.abs(),
            terms,
        );
        // the modal representation's error at s = 0, against the state itself
        let n = flow.modes();
        let (d_state, v_state) = (tip.dot(&x.rows(0, n)), tip.dot(&x.rows(n, n)));
        let (d_modal, v_modal) = signal.tip(0.0);
        // A segment that starts on the wrong side of the surface starts at a switch whose
        // state carries the previous region's error (its flow good to κε, κ up to 1e8 for
        // the stiffest stops): that offset is uncertainty too, not a crossing.
        let wrong_side = if flow.region() == Region::Free {
            (d_state - gap).max(0.0)
        } else {
            (gap - d_state).max(0.0)
        };
        let floor = (2.0 * (d_modal - d_state).abs()).max(2.0 * wrong_side);
        let signal = signal.with_floor(floor);
        Self {
            flow,
            phase0,
            signal,
            velocity_floor: 2.0 * (v_modal - v_state).abs(),
            y,
            sign: if flow.region() == Region::Free {
                1.0
            } else {
                -1.0
            },
            gap,
        }
    }

    /// The first switch into the other region, or touch of the surface, in (0, s_max],
    /// certified.
    pub(super) fn next_switch(
        &self,
        s_max: f64,
        h_min: f64,
        rel_tol: f64,
        stats: &mut Stats,
    ) -> Option<crossing::Found> {
        let surface = Target {
            sign: self.sign,
            level: self.gap,
        };
        crossing::first_event(&self.signal, surface, 0.0, s_max, h_min, rel_tol, stats)
    }

    pub(super) fn state(&self, s: f64) -> DVector<f64> {
        self.flow.state(&self.y, self.phase0, s)
    }
}

/// The end of one region's flight ([`Simulator::flight`]).
#[derive(Debug, Clone)]
pub struct Flight {
    /// The time after the start at which the state left the region, if within the horizon.
    pub exit: Option<f64>,
    /// The state then (or at the horizon).
    pub state: DVector<f64>,
    /// The tip velocity then.
    pub tip_velocity: f64,
}

impl Simulator {
    /// Free flight (the − region's exact flow) from `x` at `clock` for at most `horizon`:
    /// the certified first time the tip reaches d₀, if any, and the state then (or at the
    /// horizon). The rigid-impact model ([`crate::engine::rigid`]) is built on it.
    pub fn free_flight(
        &self,
        x: &DVector<f64>,
        clock: &Clock,
        horizon: f64,
        stats: &mut Stats,
    ) -> (Option<f64>, DVector<f64>) {
        let f = self.flight(Region::Free, x, clock, horizon, stats);
        (f.exit, f.state)
    }

    /// One region's exact flow from `x` at `clock` for at most `horizon`, to the first
    /// certified crossing *out of* `region` (touches are passed through), whatever side of
    /// the surface `x` starts on. This is the building block of drivers whose state changes
    /// at a switch (the two-basis truncation, [`crate::engine::two_basis`]): there a state projected
    /// into a new basis may lie just beyond the surface. If it does and moves back into
    /// `region`, the flight goes on from where it re-enters; if it moves on out (or rests),
    /// the flight ends at once (s = 0).
    pub fn flight(
        &self,
        region: Region,
        x: &DVector<f64>,
        clock: &Clock,
        horizon: f64,
        stats: &mut Stats,
    ) -> Flight {
        let gap = self.model.params().gap;
        let seg = Segment::new(
            self.flow(region),
            x,
            self.omega() * clock.offset,
            gap,
            self.model.tip(),
        );
        stats.segments += 1;
        let out = Target {
            sign: seg.sign,
            level: gap,
        };
        let p = seg.signal.local(0.0, out);
        let mut from = 0.0;
        if p.g > p.noise() {
            // beyond the surface: wait for the re-entry, or leave at once
            let back = Target {
                sign: -seg.sign,
                level: gap,
            };
            let entry = (p.gd < 0.0)
                .then(|| {
                    crossing::first_crossing(
                        &seg.signal,
                        back,
                        0.0,
                        horizon,
                        self.h_min(),
                        self.settings.root_tolerance,
                        stats,
                    )
                })
                .flatten();
            match entry {
                Some(s) => from = s,
                None if p.gd < 0.0 => {
                    // still beyond the surface at the horizon
                    return Flight {
                        exit: None,
                        state: seg.state(horizon),
                        tip_velocity: seg.signal.tip(horizon).1,
                    };
                }
                None => {
                    return Flight {
                        exit: Some(0.0),
                        state: x.clone(),
                        tip_velocity: seg.signal.tip(0.0).1,
                    }
                }
            }
        }
        let exit = loop {
            let found = crossing::first_event(
                &seg.signal,
                out,
                from,
                horizon,
                self.h_min(),
                self.settings.root_tolerance,
                stats,
            );
            match found {
                Some(crossing::Found::Touch(s)) if s > from => from = s,
                Some(crossing::Found::Crossing(s)) => break Some(s),
                _ => break None,
            }
        };
        let s = exit.unwrap_or(horizon);
        Flight {
            exit,
            state: seg.state(s),
            tip_velocity: seg.signal.tip(s).1,
        }
    }
}
