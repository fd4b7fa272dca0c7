//! Progress and cancellation of long work: one small pair of traits every runner reports
//! to and polls. The command line shows a bar on a terminal and wires Ctrl-C; the Python
//! package wires its callback and the interpreter's signals; the library prints nothing.

/// Reports the progress of long work (sweeps). The command line shows a bar on a
/// terminal; the library itself prints nothing.
pub trait Progress: Sync {
    /// A task of `total` units named `what` starts; its units are reported to the handle,
    /// and it ends when the handle is dropped.
    fn task(&self, what: &str, total: u64) -> Box<dyn Task + '_>;
    /// Whether the caller asked the work to stop: runners poll it (at least once per
    /// segment of a run) and end with [`crate::error::Error::Interrupted`].
    fn cancelled(&self) -> bool {
        false
    }
}

/// One task's progress.
pub trait Task: Sync {
    /// `units` more are done.
    fn advance(&self, units: u64);
}

/// Progress that goes nowhere.
#[derive(Debug, Clone, Copy, Default)]
pub struct Silent;

impl Task for Silent {
    fn advance(&self, _: u64) {}
}

impl Progress for Silent {
    fn task(&self, _: &str, _: u64) -> Box<dyn Task + '_> {
        Box::new(Silent)
    }
}

/// Another progress's cancellation without its tasks: for work run many times over (a
/// sweep's values), whose own tasks would flood the caller's report, but which must still
/// stop when asked.
#[derive(Clone, Copy)]
pub struct CancelOnly<'a>(pub &'a dyn Progress);

impl Progress for CancelOnly<'_> {
    fn task(&self, _: &str, _: u64) -> Box<dyn Task + '_> {
        Box::new(Silent)
    }
    fn cancelled(&self) -> bool {
        self.0.cancelled()
    }
}
