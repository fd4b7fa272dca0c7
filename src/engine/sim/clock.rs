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
