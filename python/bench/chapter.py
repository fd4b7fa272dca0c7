"""Regenerates the measured parts of the book's chapter *From Python* (book/src/python.md):

- ``book/src/python/NAME-output.txt``: what each of the chapter's scripts
  (``book/src/python/NAME.py``: the worked example, a sweep with failures, interrupted
  calls) prints, and ``bifurcation.png``, the figure the worked example draws (when
  matplotlib is installed); the package's tests rerun the scripts and fail when an output
  differs from the committed one (``python/tests/test_chapter.py``), so the printed outputs
  are always this build's;
- ``book/src/python/error-example.txt``: the message a bad argument raises;
- ``book/src/python/overhead.md`` and ``overhead.json``: the cost of a call from Python
  against the same call in Rust, measured now on this machine.

Run it from the repository root with the package installed (``pip install "./python[plot]"``):

    python python/bench/chapter.py [--out DIR]

``--out`` writes the files into DIR instead (the names are the same): ``cantilever book``
runs it so into ``book/src/generated/python/`` when the package of its own build is
installed, so that the chapter shows what that build prints and measures.

The Rust reference is timed inside the extension (``_core.time_rust``): the same library
calls with no Python in the loop, so the difference is exactly what the binding adds —
argument checks, releasing and retaking the interpreter, and turning results into numpy
arrays and result objects.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import platform
import runpy
import signal
import statistics
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np

import impacting_cantilever as ic
from impacting_cantilever import _core

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "book" / "src" / "python"


#: The chapter's scripts (book/src/python/NAME.py), each printing what the chapter shows
#: as NAME-output.txt: the worked example (which also draws bifurcation.png when matplotlib
#: is installed), a sweep with failures, and interrupted long calls.
SCRIPTS = ["example", "sweep", "interrupt"]


def error_text() -> str:
    """The message a bad argument raises, as the chapter shows it."""
    call = "ic.compliant(3, zeta1=0, omega=2)"
    try:
        ic.compliant(3, zeta1=0, omega=2)
    except ValueError as e:
        return f">>> {call}\nimpacting_cantilever.errors.{type(e).__name__}: {e}\n"
    raise AssertionError(f"{call} was accepted")


def script_output(name: str, directory: Path) -> str:
    """What book/src/python/NAME.py prints, run in ``directory`` (where its files land)."""
    buffer = io.StringIO()
    cwd = os.getcwd()
    os.chdir(directory)
    # Python's Ctrl-C handler, which a process started in the background goes without (it
    # inherits SIGINT ignored): the interrupted calls would otherwise run to their end
    handler = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with contextlib.redirect_stdout(buffer):
            runpy.run_path(str(OUT / f"{name}.py"), run_name="__main__")
    finally:
        signal.signal(signal.SIGINT, handler)
        os.chdir(cwd)
    return buffer.getvalue()


def outputs(out: Path) -> None:
    """Writes every printed output of the chapter (and its figure) into ``out``."""
    (out / "error-example.txt").write_text(error_text())
    for name in SCRIPTS:
        text = script_output(name, out)
        (out / f"{name}-output.txt").write_text(text)
        print(text)


def python_times(call: Callable[[], object]) -> tuple[float, float]:
    """(wall time, processor time of the process) of one call: a parallel call runs its
    work on a pool thread while the calling thread watches for Ctrl-C, where the calling
    thread's own time would leave the work out; the process's counts every thread (and
    nothing else runs)."""
    wall, cpu = time.perf_counter(), time.process_time()
    call()
    return time.perf_counter() - wall, time.process_time() - cpu


# (what the reader sees, the Python call, the Rust reference's arguments, repeats)
def cases() -> list[tuple[str, Callable[[], object], dict[str, Any], int]]:
    fig4_3, fig4_10 = ic.problems.figure4(3), ic.problems.figure4(10)
    return [
        (
            "`simulate(figure4(3), periods=0, record=1)`: one forcing period",
            lambda: ic.simulate(fig4_3, 0, 1),
            {"model": fig4_3, "what": "simulate", "periods": 0, "record": 1},
            2000,
        ),
        (
            "`find_orbit(figure4(10))`: 1065 periods and Newton shooting",
            lambda: ic.find_orbit(fig4_10),
            {"model": fig4_10, "what": "find_orbit"},
            50,
        ),
        (
            "`simulate(figure4(10), 100, 100, dense_per_period=200)`: 20 000 dense samples of 20 states",
            lambda: ic.simulate(fig4_10, 100, 100, dense_per_period=200),
            {
                "model": fig4_10,
                "what": "simulate",
                "periods": 100,
                "record": 100,
                "dense_per_period": 200,
            },
            50,
        ),
    ]


def seconds(x: float) -> str:
    if abs(x) < 1e-5:
        return f"{x * 1e6:.1f} µs"
    if abs(x) < 1e-3:
        return f"{x * 1e6:.0f} µs"
    if abs(x) < 1:
        return f"{x * 1e3:.2f} ms"
    return f"{x:.2f} s"


def measure(out: Path) -> None:
    rows, raw, overheads = [], [], []
    for label, call, reference, repeats in cases():
        call()  # warm up (first-use tables, page faults)
        _core.time_rust(repeats=1, **reference)
        rust, py = [], []
        for _ in range(repeats):  # interleaved, so that a slow spell of the machine hits both
            rust += _core.time_rust(repeats=1, **reference)
            py.append(python_times(call))
        # processor time (Rust: the calling thread, which does the work; Python: the
        # process, whatever thread does it — the work is single-threaded), the fastest of
        # the repeats: what the other processes on the machine disturb least
        r, p = min(c for _, c in rust), min(c for _, c in py)
        # how much the Rust call alone varies between repeats: the resolution of the overhead
        spread = statistics.median(c for _, c in rust) - r
        def stats(samples: list[tuple[float, float]]) -> dict[str, float]:
            walls, cpus = [w for w, _ in samples], [c for _, c in samples]
            return {
                "thread_seconds_min": min(cpus),
                "thread_seconds_median": statistics.median(cpus),
                "wall_seconds_min": min(walls),
                "wall_seconds_median": statistics.median(walls),
            }

        raw.append({"call": label, "repeats": repeats, "rust": stats(rust), "python": stats(py)})
        overheads.append((p - r, (p - r) / r, spread))
        rows.append(
            f"| {label} | {seconds(r)} | {seconds(p)} | {seconds(p - r)} | "
            f"{100 * (p - r) / r:+.1f} % | {seconds(spread)} |"
        )
    info = (
        f"Measured with {platform.python_implementation()} {platform.python_version()} and "
        f"numpy {np.__version__} on {os.cpu_count()} cores ({platform.machine()}), "
        f"impacting-cantilever {ic.__version__} (commit {ic.citation.build()['commit'][:12]}), "
        f"{time.strftime('%Y-%m-%d', time.gmtime())}; processor time (for Rust, of the thread doing the work; for Python, of the whole process, since a parallel call runs its work on a pool thread while the calling thread watches for Ctrl-C), the fastest of the repeated calls, Rust and Python interleaved."
    )
    table = "\n".join(
        [
            "| call | Rust | Python | overhead | relative | spread of the Rust call |",
            "|---|---:|---:|---:|---:|---:|",
            *rows,
        ]
    )
    def said(overhead: float, relative: float, spread: float) -> str:
        if abs(overhead) <= spread:
            return f"less than the call's own spread between repeats ({seconds(spread)})"
        return f"{seconds(overhead)} ({100 * relative:.1f} %)"

    small, orbit, dense = overheads
    summary = (
        f"The binding adds {seconds(small[0])} to the shortest call, a single forcing period "
        f"({100 * small[1]:.0f} % of it); to a periodic orbit it adds {said(*orbit)}, and to a "
        f"run whose dense output of several megabytes becomes numpy arrays {said(*dense)}. "
        "The spread is the median of the Rust call's repeats less their fastest."
    )
    (out / "overhead.md").write_text(f"{table}\n\n{info}\n\n{summary}\n")
    (out / "overhead.json").write_text(json.dumps({"info": info, "calls": raw}, indent=1) + "\n")
    print(table)
    print(info)


if __name__ == "__main__":
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=OUT, help="the folder to write into")
    out = parser.parse_args().out.resolve()
    if not out.is_dir():
        parser.error(f"--out: {out} is not a folder")
    outputs(out)
    measure(out)
