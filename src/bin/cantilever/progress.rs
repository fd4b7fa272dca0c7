//! Progress bars on a terminal (hidden when stderr is not one: CI, pipes), for the
//! library's [`Progress`] reports.

use impacting_cantilever::results::scene::{Progress, Task};
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};

/// Bars for every task, stacked.
#[derive(Default)]
pub struct Bars(MultiProgress);

struct Bar(ProgressBar);

impl Task for Bar {
    fn advance(&self, units: u64) {
        self.0.inc(units);
    }
}

impl Drop for Bar {
    fn drop(&mut self) {
        self.0.finish_and_clear();
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
        Box::new(Bar(bar))
    }
}
