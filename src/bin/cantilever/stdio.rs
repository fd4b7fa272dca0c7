//! A closed standard output (`>&-`). Rust's runtime reopens a closed fd 0–2 on /dev/null
//! before `main`, so every print would then succeed into nothing and the run exit 0 with
//! its results lost. Once that is done a closed stdout looks like any /dev/null opened
//! read-write — `1<> /dev/null`, or Python's `subprocess.DEVNULL`, which are legitimate —
//! so the state of fd 1 is recorded *before* the runtime touches it: by a function in the
//! ELF `.init_array`, which the dynamic loader runs before the C `main` that starts Rust's
//! runtime. Elsewhere than on Linux nothing is detected.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set when fd 1 was not open as the process started.
static CLOSED_AT_START: AtomicBool = AtomicBool::new(false);

/// Runs before the Rust runtime's start-up (and so before it fills a closed fd 1).
#[cfg(target_os = "linux")]
extern "C" fn record_stdout_at_start() {
    // /proc/self/fd/1 names every open fd 1, whatever it is; it is absent when fd 1 is not
    // open. (If /proc is not mounted nothing is recorded: no false alarm.)
    let proc_mounted = std::path::Path::new("/proc/self/fd").exists();
    if proc_mounted && std::fs::symlink_metadata("/proc/self/fd/1").is_err() {
        CLOSED_AT_START.store(true, Ordering::Relaxed);
    }
}

#[cfg(target_os = "linux")]
#[used]
#[link_section = ".init_array"]
static RECORD_STDOUT_AT_START: extern "C" fn() = record_stdout_at_start;

/// Whether fd 1 was closed when the process started (and is now the runtime's /dev/null).
pub fn stdout_was_closed() -> bool {
    CLOSED_AT_START.load(Ordering::Relaxed)
}
