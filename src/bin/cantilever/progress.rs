//! Progress bars on a terminal (hidden when stderr is not one: CI, pipes), for the
//! library's [`Progress`] reports. A task that will take long says so early, on a terminal
//! or not: one line with the time it projects from its rate so far.

use impacting_cantilever::results::scene::{Progress, Task};
use indicatif::{HumanDuration, MultiProgress, ProgressBar, ProgressStyle};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long a task runs before its rate is trusted for a projection.
const MEASURED_FOR: Duration = Duration::from_secs(2);
/// A projected remainder beyond this is announced.
const LONG: Duration = Duration::from_secs(600);

/// Bars for every task, stacked.
#[derive(Default)]
pub struct Bars(MultiProgress);

struct Bar {
    bar: ProgressBar,
    what: String,
    started: Instant,
    announced: AtomicBool,
}

/// The time the rest of a task takes at the rate so far (`done` of `total` units in
/// `elapsed`), once it has run for [`MEASURED_FOR`]; None before, or with nothing done.
pub fn projected_rest(elapsed: Duration, done: u64, total: u64) -> Option<Duration> {
    if elapsed < MEASURED_FOR || done == 0 || done >= total {
        return None;
    }
    let per_unit = elapsed.as_secs_f64() / done as f64;
    Duration::try_from_secs_f64(per_unit * (total - done) as f64).ok()
}

impl Task for Bar {
    fn advance(&self, units: u64) {
        self.bar.inc(units);
        if self.announced.load(Ordering::Relaxed) {
            return;
        }
        let (done, total) = (self.bar.position(), self.bar.length().unwrap_or(0));
        let Some(rest) = projected_rest(self.started.elapsed(), done, total) else {
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

impl Progress for Bars {
    fn task(&self, what: &str, total: u64) -> Box<dyn Task + '_> {
        let style = ProgressStyle::with_template(
            "{msg} {elapsed_precise} [{bar:30}] {pos}/{len}, eta {eta}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> ");
        let bar = self.0.add(
            ProgressBar::new(total)
                .with_style(style)
                .with_message(what.to_string()),
        );
        Box::new(Bar {
            bar,
            what: what.to_string(),
            started: Instant::now(),
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
        // too early, nothing done, or done
        assert_eq!(projected_rest(s(1), 10, 100), None);
        assert_eq!(projected_rest(s(5), 0, 100), None);
        assert_eq!(projected_rest(s(5), 100, 100), None);
        // 10 units in 4 s: 90 more take 36 s
        assert_eq!(projected_rest(s(4), 10, 100), Some(s(36)));
        // 1e8 periods at 25 ms each: weeks, no overflow
        let rest = projected_rest(s(2), 80, 100_000_000).unwrap();
        assert!(
            (rest.as_secs_f64() - 0.025 * (1e8 - 80.0)).abs() < 1e-6,
            "{rest:?}"
        );
    }
}
