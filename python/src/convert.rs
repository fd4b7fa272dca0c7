//! Conversions at the boundary: the library's JSON-shaped results to Python objects, numpy
//! arrays, and the progress callback.

use crate::Res;
use impacting_cantilever::error::Error;
use impacting_cantilever::model::ranges::THREADS;
use impacting_cantilever::results::scene::{Progress, Task};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use pyo3::IntoPyObjectExt;
use serde_json::Value;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

/// A JSON value as the Python object `json.loads` would give (numbers keep their exact bits:
/// the value is converted, never printed and parsed).
pub fn json_to_py<'py>(py: Python<'py>, v: &Value) -> Res<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => b.into_bound_py_any(py)?,
        Value::Number(n) => {
            if let Some(u) = n.as_u64() {
                u.into_bound_py_any(py)?
            } else if let Some(i) = n.as_i64() {
                i.into_bound_py_any(py)?
            } else {
                n.as_f64().unwrap_or(f64::NAN).into_bound_py_any(py)?
            }
        }
        Value::String(s) => s.into_bound_py_any(py)?,
        Value::Array(a) => {
            let list = PyList::empty(py);
            for x in a {
                list.append(json_to_py(py, x)?)?;
            }
            list.into_any()
        }
        Value::Object(o) => {
            let dict = PyDict::new(py);
            for (k, x) in o {
                dict.set_item(k, json_to_py(py, x)?)?;
            }
            dict.into_any()
        }
    })
}

/// Rows of equal length `cols` as a 2-D array (`cols` columns even when there are none),
/// copied once into the array's buffer.
pub fn matrix<'py, 'a, T: numpy::Element + Copy + 'a>(
    py: Python<'py>,
    rows: impl ExactSizeIterator<Item = &'a [T]>,
    cols: usize,
) -> Res<Bound<'py, PyArray2<T>>> {
    let n = rows.len();
    let mut flat: Vec<T> = Vec::with_capacity(n * cols);
    for r in rows {
        flat.extend_from_slice(r);
    }
    let a = Array2::from_shape_vec((n, cols), flat)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

/// The optional progress callback `progress(what, done, total)` of a long call, used from
/// the worker threads while the interpreter is released. Reports are throttled to about ten
/// a second (and the last one of each task); a callback that raises, or a pending
/// KeyboardInterrupt, stops further reports, and the exception is raised when the call
/// returns (work that can stop early stops at its next check of [`Reporter::stopped`]).
pub struct Reporter {
    callback: Option<Py<PyAny>>,
    /// Parallel work: run on a pool of this many threads (None: one per core).
    parallel: Option<Option<usize>>,
    /// Serial work, run on the calling thread: that thread, which checks for Ctrl-C when
    /// the work asks whether it is cancelled, and when it last did.
    caller: Option<(std::thread::ThreadId, Mutex<Instant>)>,
    error: Mutex<Option<PyErr>>,
    stopped: AtomicBool,
    last: Mutex<Option<Instant>>,
}

/// How often the calling thread checks for Ctrl-C while the work runs.
const SIGNAL_POLL: Duration = Duration::from_millis(20);

/// The shortest interval between two reports of a task.
const THROTTLE: Duration = Duration::from_millis(100);

impl Reporter {
    /// A reporter for `callback` (None: silent, but still sees KeyboardInterrupt).
    pub fn new(callback: Option<Py<PyAny>>) -> Self {
        Self {
            callback,
            parallel: None,
            caller: None,
            error: Mutex::new(None),
            stopped: AtomicBool::new(false),
            last: Mutex::new(None),
        }
    }

    /// The work is parallel: it runs on a pool of `threads` threads (None: one per core,
    /// the number checked against [`THREADS`]). Serial work (without this) runs on the
    /// calling thread.
    pub fn threads(mut self, threads: Option<i64>) -> Res<Self> {
        let n = match threads {
            Some(n) => Some(THREADS.check(n.into()).map_err(crate::py_error)? as usize),
            None => None,
        };
        self.parallel = Some(n);
        Ok(self)
    }

    /// Whether the callback raised or the user interrupted.
    pub fn stopped(&self) -> bool {
        self.stopped.load(Ordering::Relaxed)
    }

    /// Reports `done` of `total` units of `what` (throttled unless `done == total`).
    pub fn report(&self, what: &str, done: u64, total: u64) {
        self.report_unless_throttled(what, done, total, false)
    }

    /// [`Self::report`], never throttled when `now` (a task's first unit: the callback then
    /// sees the work start moving at once, and can stop it).
    fn report_unless_throttled(&self, what: &str, done: u64, total: u64, first: bool) {
        if self.stopped() {
            return;
        }
        {
            let mut last = self.last.lock().unwrap_or_else(|p| p.into_inner());
            let now = Instant::now();
            let due = last.is_none_or(|t| now.duration_since(t) >= THROTTLE);
            if !(due || first || done == total) {
                return;
            }
            *last = Some(now);
        }
        Python::attach(|py| {
            let result = match &self.callback {
                Some(cb) => cb.call1(py, (what, done, total)).map(|_| ()),
                None => Ok(()),
            };
            if let Err(e) = result.and_then(|()| py.check_signals()) {
                self.stopped.store(true, Ordering::Relaxed);
                let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(e);
            }
        });
    }

    /// Runs `work` (given this reporter as its progress) with the interpreter released,
    /// checking for Ctrl-C from the calling thread about every 20 ms: Python runs signal
    /// handlers only in its main thread, so a check from other threads would never see one.
    /// Serial work runs on the calling thread, which checks when the work asks whether it is
    /// cancelled (every period of a run); parallel work ([`Self::threads`]) runs on the
    /// call's pool while the calling thread waits and checks. A KeyboardInterrupt or a
    /// raising callback cancels the work, which stops at its next check of
    /// [`Progress::cancelled`] (every period of a run, every cell of an atlas), and the
    /// exception is raised; the partial work is dropped. (Serial work on a thread of its own
    /// cost ~75 µs of thread wake-ups per call, three times a one-period run.)
    pub fn run<T: Send>(
        mut self,
        py: Python<'_>,
        work: impl FnOnce(&Reporter) -> Result<T, Error> + Send,
    ) -> Res<T> {
        let Some(threads) = self.parallel else {
            self.caller = Some((std::thread::current().id(), Mutex::new(Instant::now())));
            let result = py.detach(|| work(&self));
            return self.finish(result);
        };
        let result = py.detach(|| {
            if rayon::current_thread_index().is_some() {
                // called from inside a call's work (a progress callback that calls the
                // library): run here, as this thread would otherwise wait on a job queued
                // behind itself; the outer call's thread watches for Ctrl-C
                return work(&self);
            }
            let pool = pool(threads)?;
            let mut result = None;
            let (done, finished) = std::sync::mpsc::channel();
            let this = &self;
            let slot = &mut result;
            pool.in_place_scope(|s| {
                s.spawn(move |_| {
                    *slot = Some(work(this));
                    let _ = done.send(());
                });
                // until the work is done, or has panicked (the sender dropped); the scope
                // then waits for it and passes a panic on
                while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
                    finished.recv_timeout(SIGNAL_POLL)
                {
                    this.poll_signals();
                }
            });
            result.unwrap_or_else(|| Err(Error::Unsupported("the work did not run".into())))
        });
        self.finish(result)
    }

    /// Checks for a pending signal (Ctrl-C) from the calling thread; one stops the work.
    fn poll_signals(&self) {
        if self.stopped() {
            return;
        }
        Python::attach(|py| {
            if let Err(e) = py.check_signals() {
                self.stopped.store(true, Ordering::Relaxed);
                let mut slot = self.error.lock().unwrap_or_else(|p| p.into_inner());
                slot.get_or_insert(e);
            }
        });
    }

    /// The work's result, unless the callback raised or the user interrupted: then that
    /// exception (the library's error, if any, came from the stop itself).
    pub fn finish<T>(self, result: Result<T, Error>) -> Res<T> {
        let error = self.error.into_inner().unwrap_or_else(|p| p.into_inner());
        match error {
            Some(e) => Err(e),
            None => result.map_err(crate::py_error),
        }
    }
}

/// This process's thread pool for calls without `threads`, with the process it was built in.
static POOL: Mutex<Option<(u32, Arc<rayon::ThreadPool>)>> = Mutex::new(None);

/// The pool a call's work runs in: `threads` threads, or this process's pool of one thread
/// per core. Never rayon's global pool: a child forked from a process whose pool was
/// running inherits the pool's state but none of its threads, and work handed to it would
/// wait forever (a `ProcessPoolExecutor` with the fork method on Linux). A forked child
/// builds its own pool instead, and the parent's is left alone (not dropped: dropping
/// would signal threads the child does not have).
fn pool(threads: Option<usize>) -> Result<Arc<rayon::ThreadPool>, Error> {
    let build = |n: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map(Arc::new)
            .map_err(|e| Error::Unsupported(format!("no thread pool of {n} threads: {e}")))
    };
    if let Some(n) = threads {
        return build(n);
    }
    let pid = std::process::id();
    let mut slot = POOL.lock().unwrap_or_else(|p| p.into_inner());
    match slot.as_ref() {
        Some((owner, p)) if *owner == pid => Ok(p.clone()),
        _ => {
            if let Some(inherited) = slot.take() {
                std::mem::forget(inherited);
            }
            let p = build(0)?;
            *slot = Some((pid, p.clone()));
            Ok(p)
        }
    }
}

/// One task of a [`Reporter`], counted in units.
struct Counted<'a> {
    reporter: &'a Reporter,
    what: String,
    total: u64,
    done: AtomicU64,
}

impl Task for Counted<'_> {
    fn advance(&self, units: u64) {
        let before = self.done.fetch_add(units, Ordering::Relaxed);
        let done = before + units;
        self.reporter
            .report_unless_throttled(&self.what, done, self.total, before == 0);
    }
}

impl Progress for Reporter {
    fn cancelled(&self) -> bool {
        // serial work asks on the calling thread: check for Ctrl-C there, every 20 ms
        if let Some((caller, last)) = &self.caller {
            if std::thread::current().id() == *caller {
                let mut last = last.lock().unwrap_or_else(|p| p.into_inner());
                if last.elapsed() >= SIGNAL_POLL {
                    *last = Instant::now();
                    drop(last);
                    self.poll_signals();
                }
            }
        }
        self.stopped()
    }
    fn task(&self, what: &str, total: u64) -> Box<dyn Task + '_> {
        self.report(what, 0, total);
        Box::new(Counted {
            reporter: self,
            what: what.to_string(),
            total,
            done: AtomicU64::new(0),
        })
    }
}
