"""Every long call stops within a fraction of a second of Ctrl-C or of a progress callback
that raises, whatever thread the work runs in: serial work runs on the calling thread,
which checks for signals when the work asks whether to stop (every period), and parallel
work runs on the call's pool while the calling thread checks; the work stops at its next
period (a run) or cell (an atlas). Each call below would run for several seconds to minutes; the
bound of one second on the stop leaves room for a loaded machine (measured: ≤ 0.05 s)."""

from __future__ import annotations

import os
import signal
import threading
import time
from typing import Any, Callable

import pytest

import impacting_cantilever as ic
from impacting_cantilever import atlas

#: From the signal (or the raising callback) to the exception in the caller, at most.
PROMPT = 1.0


def _interrupted_after(delay: float, call: Callable[[], Any]) -> float:
    """Sends SIGINT to this process `delay` seconds into `call`; returns the seconds from the
    signal to the KeyboardInterrupt."""
    sent: list[float] = []

    def interrupt() -> None:
        sent.append(time.monotonic())
        os.kill(os.getpid(), signal.SIGINT)

    # Python installs its KeyboardInterrupt handler only when SIGINT is not ignored at its
    # start, and a shell starts background jobs with SIGINT ignored: install it here
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    timer = threading.Timer(delay, interrupt)
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
        return time.monotonic() - sent[0]
    finally:
        timer.cancel()
        signal.signal(signal.SIGINT, previous)


LONG_CALLS: dict[str, Callable[[], Any]] = {
    # each runs for 20 s or more without the stop
    "simulate": lambda: ic.simulate(ic.problems.figure4(10), 2_000_000, 1),
    "find_orbit": lambda: ic.find_orbit(ic.problems.figure4(10), transient=10**7),
    "energetic_restitution": lambda: ic.energetic_restitution(
        ic.problems.figure4(10), transient=10**7
    ),
    "continue_branch": lambda: ic.continue_branch(
        ic.problems.figure4(10), "stop_stiffness", 1e6, transient=10**7
    ),
    "sweep": lambda: ic.sweep(
        ic.problems.figure4(10), "omega", [1.9, 2.0, 2.1], transient=10**7
    ),
    "atlas shard": lambda: atlas.compute_shard(
        atlas.params("test", k_points=64, omega_points=64), 0, 1
    ),
}


@pytest.mark.parametrize("name", list(LONG_CALLS))
def test_ctrl_c_stops_a_long_call_promptly(name: str) -> None:
    waited = _interrupted_after(0.5, LONG_CALLS[name])
    assert waited < PROMPT, f"{name} stopped {waited:.2f} s after Ctrl-C"
    # and the package works on afterwards
    assert ic.find_orbit(ic.problems.figure4(1)).period_m == 1


def test_a_raising_callback_stops_an_atlas_shard_run_in_worker_threads() -> None:
    raised: list[float] = []

    def stop(what: str, done: int, total: int) -> None:
        if done >= 3:
            raised.append(time.monotonic())
            raise KeyError("enough")

    p = atlas.params("test", k_points=64, omega_points=64)
    with pytest.raises(KeyError, match="enough"):
        atlas.compute_shard(p, 0, 1, progress=stop)
    assert time.monotonic() - raised[0] < PROMPT


def test_a_raising_callback_stops_a_hundred_million_periods() -> None:
    raised: list[float] = []

    def stop(what: str, done: int, total: int) -> None:
        if done >= 10_000:
            raised.append(time.monotonic())
            raise KeyError("enough")

    with pytest.raises(KeyError, match="enough"):
        ic.simulate(ic.problems.figure4(10), 10**8, 1, progress=stop)
    assert time.monotonic() - raised[0] < PROMPT
