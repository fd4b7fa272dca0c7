"""Sweeps that skip what fails and stop on a mistake, failures returned instead of raised,
progress to a tqdm bar, threads per call, and worker processes forked after the parent has
computed."""

from __future__ import annotations

import io
import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import impacting_cantilever as ic

# Figure 4's N = 10 model swept in k/k₁ through the windows where the motion from rest has
# no period of at most 64 (k/k₁ = 11.29 is inside one)
FIG4_K = np.sort(np.r_[np.linspace(1.0, 20.0, 19), 11.29])


def test_a_sweep_is_find_orbit_at_each_value_with_failures_recorded() -> None:
    m = ic.problems.figure4(10)
    s = ic.sweep(m, "stop_stiffness", FIG4_K)
    assert len(s) == 20 and s.parameter == "stop_stiffness"
    assert np.array_equal(s.values, FIG4_K)
    for k, entry in zip(FIG4_K, s.orbits):
        # each entry is the orbit (or the failure) find_orbit gives for that model alone
        alone = ic.find_orbit(ic.replace(m, stop_stiffness=float(k)), raise_on_failure=False)
        assert entry == alone, k
    i = int(np.flatnonzero(FIG4_K == 11.29)[0])
    assert not s.found[i] and s.status[i] == "NoPeriodError"
    assert s.message[i].startswith("no period: the 10-mode compliant model settles on no period")
    assert s.period_m[i] == 0 and np.isnan(s.spectral_radius[i]) and np.isnan(s.state[i]).all()
    # the windows without a period, and the orbits around them, as a table gives them
    assert set(s.status) == {"ok", "NoPeriodError"}
    assert np.array_equal(s.found, s.status == "ok") and (s.period_m[s.found] >= 1).all()
    assert (s.message[s.found] == "").all() and np.isfinite(s.state[s.found]).all()
    assert s.residual[s.found].max() <= 1e-12
    assert s.state.shape == (20, 20) and not s.state.flags.writeable
    # the same whatever the threads
    assert ic.sweep(m, "stop_stiffness", FIG4_K, threads=1) == s


def test_a_sweep_table() -> None:
    pd = pytest.importorskip("pandas")
    s = ic.sweep(ic.problems.figure4(3), "omega", [1.5, 2.0])
    t = s.to_pandas()
    assert isinstance(t, pd.DataFrame) and len(t) == 2
    assert list(t["omega"]) == [1.5, 2.0] and list(t["status"]) == ["ok", "ok"]
    assert list(t["period_m"]) == list(s.period_m)
    run = ic.simulate(ic.problems.figure4(3), 100, 4)
    events = run.events.to_pandas()
    assert list(events["time"]) == list(run.events.time) and len(events) == len(run.events)
    assert list(events["modal_velocity_3"]) == list(run.events.modal_velocities[:, 2])
    branch = ic.continue_branch(ic.problems.figure4(2), "stop_stiffness", to=150, one_way=True)
    points = branch.branches[0].to_pandas()
    assert list(points["parameter"]) == list(branch.branches[0].parameter)


def test_no_orbit_is_caught_and_a_bad_argument_is_not() -> None:
    model = ic.replace(ic.problems.figure4(10), stop_stiffness=11.29)
    with pytest.raises(ic.NoOrbitError) as e:
        ic.find_orbit(model)
    assert type(e.value) is ic.NoPeriodError
    failure = ic.find_orbit(model, raise_on_failure=False)
    assert isinstance(failure, ic.Failure) and not failure.success
    assert failure.status == "NoPeriodError" and failure.message == str(e.value)
    assert type(failure.error()) is ic.NoPeriodError
    assert ic.find_orbit(ic.problems.figure4(10), raise_on_failure=False).success
    # bad input is never a failure to skip: it raises, whatever raise_on_failure says
    for call in [
        lambda: ic.find_orbit(model, transient=-1, raise_on_failure=False),
        lambda: ic.sweep(model, "stop_stiffness", [1.0, -2.0]),
        lambda: ic.sweep(model, "stiffness", [1.0]),
        lambda: ic.sweep(model, "stop_stiffness", [[1.0]]),
        lambda: ic.sweep(model, "stop_stiffness", [1.0], threads=0),
    ]:
        with pytest.raises(ic.ParameterError):
            try:
                call()
            except ic.NoOrbitError:
                pytest.fail("a bad argument was raised as a missing orbit")


def test_energetic_restitution_follows_find_orbits_convention() -> None:
    model = ic.replace(ic.problems.figure4(10), stop_stiffness=11.29)
    with pytest.raises(ic.NoPeriodError) as e:
        ic.energetic_restitution(model)
    assert "r_E (eq 39) is defined on a periodic orbit" in str(e.value)
    f = ic.energetic_restitution(model, raise_on_failure=False)
    assert isinstance(f, ic.Failure) and f.message == str(e.value)
    r = ic.energetic_restitution(ic.problems.figure6b(3), raise_on_failure=False)
    assert isinstance(r, ic.EnergeticRestitution) and r.success and r.r_E is not None
    with pytest.raises(ic.UnsupportedError):  # not a failure of the computation
        ic.energetic_restitution(ic.rigid(ic.problems.figure4(3)), raise_on_failure=False)


def test_progress_to_a_tqdm_bar() -> None:
    tqdm = pytest.importorskip("tqdm")
    out = io.StringIO()
    with tqdm.tqdm(file=out, mininterval=0) as bar:
        ic.simulate(ic.problems.figure4(3), 3000, 2, progress=bar, energy=False)
        assert bar.n == bar.total == 3002
    assert "3002/3002" in out.getvalue()
    with tqdm.tqdm(file=io.StringIO()) as bar:
        ic.sweep(ic.problems.figure4(3), "omega", [1.5, 2.0, 2.5], progress=bar)
        assert (bar.n, bar.total, bar.desc) == (3, 3, "sweep: orbits")
    with pytest.raises(ic.ParameterError, match="invalid progress"):
        ic.simulate(ic.problems.figure4(3), 10, progress=5)


def test_threads_change_nothing_but_the_threads() -> None:
    p = ic.atlas.params("test")
    one = ic.atlas.compute_shard(p, 1, 4, threads=1)
    assert ic.atlas.compute_shard(p, 1, 4, threads=3) == one == ic.atlas.compute_shard(p, 1, 4)
    with pytest.raises(ic.ParameterError, match="invalid threads: got 0"):
        ic.atlas.compute_shard(p, 1, 4, threads=0)
    with pytest.raises(ic.ParameterError, match="invalid threads"):
        ic.modes_needed(100, threads=2000)


@pytest.mark.skipif(not hasattr(os, "fork"), reason="fork is a POSIX call")
def test_a_child_forked_after_the_parent_computed_computes_too() -> None:
    # the parent's thread pool has run; a forked child inherits it without its threads, and
    # work handed to it would wait forever — each process builds its own pool instead
    p = ic.atlas.params("test")
    expected = ic.atlas.compute_shard(p, 2, 4)
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: the shard's text through the pipe, then out without cleanup
        try:
            os.close(read)
            text = ic.atlas.compute_shard(p, 2, 4).encode()
            while text:
                text = text[os.write(write, text) :]
            os.close(write)
        finally:
            os._exit(0)
    os.close(write)
    chunks, deadline = [], time.monotonic() + 120
    os.set_blocking(read, False)
    while time.monotonic() < deadline:
        try:
            chunk = os.read(read, 1 << 16)
        except BlockingIOError:
            time.sleep(0.05)
            continue
        if not chunk:
            break
        chunks.append(chunk)
    else:
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        pytest.fail("the forked child's atlas shard hung")
    os.close(read)
    _, status = os.waitpid(pid, 0)
    assert os.waitstatus_to_exitcode(status) == 0
    assert b"".join(chunks).decode() == expected


def test_a_progress_callback_may_call_the_library() -> None:
    # the callback runs on a thread of the call's pool: a call made there runs in place
    # (queued behind itself on a one-thread pool it would wait forever) — in a child
    # process, so that a hang fails the test instead of stopping the suite
    code = """
import impacting_cantilever as ic
inner = []
def progress(what, done, total):
    if not inner:
        inner.append(ic.find_orbit(ic.problems.figure4(3)).period_m)
s = ic.sweep(ic.problems.figure4(3), "omega", [1.5, 2.0], progress=progress, threads=1)
print(inner, s.found.tolist())
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip() == "[1] [True, True]"
