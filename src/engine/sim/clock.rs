//! Time in a forced run: t = cycles·T + offset with offset ∈ [0, T), so the forcing phase
//! ω·offset never loses precision over long runs (§5.2 integrates for 1000 periods and
//! more).

/// A point in time: t = cycles·period + offset.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Clock {
    /// T = 2π/ω (or 1 without forcing).
    pub period: f64,
    /// Whole periods elapsed.
    pub cycles: i64,
    /// Time since the start of the current period, in [0, T).
    pub offset: f64,
}

impl Clock {
    /// The start of cycle `cycles` of a run with forcing period `period`.
    pub fn at_cycle(period: f64, cycles: i64) -> Self {
        Self {
            period,
            cycles,
            offset: 0.0,
        }
    }

    /// The clock reading of time t ≥ 0 (t = cycles·T + offset, offset ∈ [0, T)).
    pub fn at_time(period: f64, t: f64) -> Self {
        let cycles = (t / period).floor();
        let mut c = Self {
            period,
            cycles: cycles as i64,
            offset: t - cycles * period,
        };
        // the division may round up to the next whole period or leave a tiny negative
        // offset: carry so that 0 ≤ offset < T
        if c.offset < 0.0 {
            c.offset += period;
            c.cycles -= 1;
        }
        c.advance(0.0);
        c
    }

    /// t, the time (non-dimensional beam time, EI = ρA = L = 1).
    pub fn time(&self) -> f64 {
        self.cycles as f64 * self.period + self.offset
    }

    /// Advances the clock by s (whole periods are carried into `cycles`).
    pub fn advance(&mut self, s: f64) {
        self.offset += s;
        while self.offset >= self.period {
            self.offset -= self.period;
            self.cycles += 1;
        }
    }

    /// The points of the dense grid t = c·T + j·T/`per_period` (j = 0 … per_period − 1)
    /// that fall in [self, self + span): each as (s, t), its offset s from this reading
    /// and its time t. The one grid every dense output uses, whatever spans it is asked
    /// for (segments of a run, flights of the rigid model, one or many periods).
    pub fn grid(&self, span: f64, per_period: usize) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        if per_period == 0 || span.is_nan() || span <= 0.0 {
            return out;
        }
        let dt = self.period / per_period as f64;
        // the first grid point at or after the offset; j = per_period is the next cycle's
        // j = 0 (its rounded j·dt may fall a hair before T)
        let (mut cycle, mut j) = (0i64, (self.offset / dt).ceil() as i64);
        loop {
            if j >= per_period as i64 {
                (cycle, j) = (cycle + 1, 0);
            }
            let s = cycle as f64 * self.period + j as f64 * dt - self.offset;
            if s >= span {
                return out;
            }
            let t = (self.cycles + cycle) as f64 * self.period + j as f64 * dt;
            out.push((s, t));
            j += 1;
        }
    }

    /// Whether this reading is strictly before `other` (same period assumed).
    pub fn before(&self, other: &Clock) -> bool {
        self.cycles < other.cycles || (self.cycles == other.cycles && self.offset < other.offset)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn at_time_round_trips_and_keeps_the_offset_in_range() {
        let period = 2.0 * std::f64::consts::PI / 7.0;
        for t in [0.0, 1e-3, period, 3.5 * period, 1000.25 * period] {
            let c = Clock::at_time(period, t);
            assert!(c.offset >= 0.0 && c.offset < period, "t = {t}");
            // t and back: one rounding of cycles·T + offset
            assert!((c.time() - t).abs() <= 4.0 * f64::EPSILON * t.max(1.0));
        }
        assert!(Clock::at_cycle(period, 2).before(&Clock::at_time(period, 2.5 * period)));
    }
}
