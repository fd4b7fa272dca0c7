//! Progress bars on a terminal (hidden when stderr is not one: CI, pipes), for the
//! library's [`Progress`] reports. A task that will take long says so early, on a terminal
//! or not: one line with the time it projects from its measured rate — the units done
//! since its first one (its set-up is not a rate: an atlas that spends seconds matching N
//! to k before its first cell once projected "23 hours" for a run of 68 s), and only once
//! enough of them are done. The bar's own remaining time is that projection too ("rest
//! measuring…" until then), not the bar library's estimate, which counts the set-up and
//! showed hours for the first ticks of a run of seconds.

use impacting_cantilever::results::scene::{Progress, Task};
use indicatif::{HumanDuration, MultiProgress, ProgressBar, ProgressStyle};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long a task runs, after its first unit, before its rate is trusted for a projection.
const MEASURED_FOR: Duration = Duration::from_secs(2);
/// How many units (after the first) a rate is measured over at least.
const MEASURED_UNITS: u64 = 16;
/// A projected remainder beyond this is announced.
const LONG: Duration = Duration::from_secs(600);

/// Bars for every task, stacked.
#[derive(Default)]
pub struct Bars(MultiProgress);

/// When a task's first unit was done, and how many were done then (shared with its bar's
/// remaining-time field).
type First = std::sync::Arc<std::sync::Mutex<Option<(Instant, u64)>>>;

struct Bar {
    bar: ProgressBar,
    what: String,
    first: First,
    announced: AtomicBool,
}

/// The time the rest of a task takes at its measured rate: `done` units in `elapsed` since
/// its first unit, `left` units to go; None until [`MEASURED_FOR`] and [`MEASURED_UNITS`]
/// have passed (a rate from one unit, or one that includes the set-up, says nothing).
pub fn projected_rest(elapsed: Duration, done: u64, left: u64) -> Option<Duration> {
    if elapsed < MEASURED_FOR || done < MEASURED_UNITS || left == 0 {
        return None;
    }
    let per_unit = elapsed.as_secs_f64() / done as f64;
    Duration::try_from_secs_f64(per_unit * left as f64).ok()
}

impl Task for Bar {
    fn advance(&self, units: u64) {
        self.bar.inc(units);
        if self.announced.load(Ordering::Relaxed) {
            return;
        }
        let (done, total) = (self.bar.position(), self.bar.length().unwrap_or(0));
        let (since, at) = {
            let mut first = self.first.lock().unwrap_or_else(|p| p.into_inner());
            *first.get_or_insert((Instant::now(), done))
        };
        let measured = done.saturating_sub(at);
        let Some(rest) = projected_rest(since.elapsed(), measured, total.saturating_sub(done))
        else {
            return;
        };
        if rest > LONG && !self.announced.swap(true, Ordering::Relaxed) {
            let line = format!(
                "{}: about {} more at the rate so far ({done} of {total} done); \
                 Ctrl-C stops it",
                self.what,
                HumanDuration(rest)
            );
            if self.bar.is_hidden() {
                eprintln!("{line}");
            } else {
                self.bar.println(line);
            }
        }
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

/// The bar's remaining-time field: [`projected_rest`] from the units done since the first.
fn rest_field(first: &First, done: u64, total: u64) -> String {
    let at = *first.lock().unwrap_or_else(|p| p.into_inner());
    at.and_then(|(since, at)| {
        projected_rest(
            since.elapsed(),
            done.saturating_sub(at),
            total.saturating_sub(done),
        )
    })
    .map_or("measuring…".to_string(), |rest| {
        format!("about {}", HumanDuration(rest))
    })
}

impl Progress for Bars {
    fn task(&self, what: &str, total: u64) -> Box<dyn Task + '_> {
        let first: First = Default::default();
        let shared = first.clone();
        let style = ProgressStyle::with_template(
            "{msg} {elapsed_precise} [{bar:30}] {pos}/{len}, rest {rest}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .with_key(
            "rest",
            move |state: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let total = state.len().unwrap_or(0);
                let _ = w.write_str(&rest_field(&shared, state.pos(), total));
            },
        )
        .progress_chars("=> ");
        let bar = self.0.add(
            ProgressBar::new(total)
                .with_style(style)
                .with_message(what.to_string()),
        );
        Box::new(Bar {
            bar,
            what: what.to_string(),
            first,
            announced: AtomicBool::new(false),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rest_is_projected_from_the_rate_once_measured() {
        let s = Duration::from_secs;
        // too early, too few units measured (the atlas's "1 of 16384"), or nothing left
        assert_eq!(projected_rest(s(1), 20, 80), None);
        assert_eq!(projected_rest(s(60), 1, 16383), None);
        assert_eq!(projected_rest(s(5), 20, 0), None);
        // 20 units in 4 s: 80 more take 16 s
        assert_eq!(projected_rest(s(4), 20, 80), Some(s(16)));
        // 1e8 periods at 25 ms each: weeks, no overflow
        let rest = projected_rest(s(2), 80, 100_000_000).unwrap();
        assert!((rest.as_secs_f64() - 0.025 * 1e8).abs() < 1e-6, "{rest:?}");
    }

    #[test]
    fn the_bar_shows_no_remaining_time_until_the_rate_is_measured() {
        let first: First = Default::default();
        // before the first unit, and just after it: no projection from the set-up
        assert_eq!(rest_field(&first, 0, 16384), "measuring…");
        *first.lock().unwrap() = Some((Instant::now(), 1));
        assert_eq!(rest_field(&first, 2, 16384), "measuring…");
        // 40 units in the 4 s since the first: 0.1 s each
        *first.lock().unwrap() = Some((Instant::now() - Duration::from_secs(4), 1));
        let field = rest_field(&first, 41, 641);
        // 60 s, give or take the time this test takes
        assert!(
            field.starts_with("about 6") && field.ends_with("seconds"),
            "{field}"
        );
    }
}
