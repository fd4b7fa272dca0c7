"""Bad input: a ValueError carrying the command line's one-line message (with the Python
argument's name where the command line names its flag), and a hostile user's every attempt —
wrong lengths, NaN, negative or huge counts, wrong types — a Python exception, never a crash
or a hang (run in a child process with a time limit, so a crash fails the test by name)."""

from __future__ import annotations

import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any, Callable

import numpy as np
import pytest

import impacting_cantilever as ic

from conftest import Cli

BASE = ["--modes", "3", "--zeta1", "0.01", "--omega", "2", "--periods", "1"]


def model(**changes: Any) -> ic.Model:
    p: dict[str, Any] = {"modes": 3, "zeta1": 0.01, "omega": 2.0, **changes}
    return ic.compliant(p.pop("modes"), **p)


def rigid(**changes: Any) -> ic.Model:
    law = changes.pop("law", "impulse-response")
    r = changes.pop("r", 0.8)
    return ic.rigid(model(**changes), law=law, restitution=r)


def flags(*changed: str) -> list[str]:
    """BASE with some flags replaced (given as flag, value pairs)."""
    out = list(BASE)
    pairs = dict(zip(changed[::2], changed[1::2]))
    for i in range(0, len(out), 2):
        if out[i] in pairs:
            out[i + 1] = pairs.pop(out[i])
    for k, v in pairs.items():
        out += [k, v]
    return out


# (Python call, its argument's name, the command line's arguments, the flag's name)
CASES: list[tuple[Callable[[], object], str, list[str], str]] = [
    (lambda: model(modes=0), "modes (N)", flags("--modes", "0"), "--modes (N)"),
    (lambda: model(modes=401), "modes (N)", flags("--modes", "401"), "--modes (N)"),
    (lambda: model(stop_stiffness=-1), "stop_stiffness (k/k₁)",
     flags("--stop-stiffness", "-1"), "--stop-stiffness (k/k₁)"),
    (lambda: model(stop_stiffness=float("nan")), "stop_stiffness (k/k₁)",
     flags("--stop-stiffness", "NaN"), "--stop-stiffness (k/k₁)"),
    (lambda: model(stop_stiffness=1e13), "stop_stiffness (k/k₁)",
     flags("--stop-stiffness", "1e13"), "--stop-stiffness (k/k₁)"),
    (lambda: model(gap=2e6), "gap (d₀)", flags("--gap", "2e6"), "--gap (d₀)"),
    (lambda: model(zeta1=0), "zeta1 (ζ₁)", flags("--zeta1", "0"), "--zeta1 (ζ₁)"),
    (lambda: model(zeta1=float("inf")), "zeta1 (ζ₁)", flags("--zeta1", "inf"), "--zeta1 (ζ₁)"),
    (lambda: model(viscous=-1), "viscous (α)", flags("--viscous", "-1"), "--viscous (α)"),
    (lambda: model(omega=1e5), "omega (ω/(β₁⁻)²)", flags("--omega", "1e5"), "--omega (ω/(β₁⁻)²)"),
    (lambda: model(forcing="loud"), "forcing", flags("--forcing", "loud"), "--forcing"),
    (lambda: model(forcing=1e-200), "forcing (f₁)", flags("--forcing", "1e-200"),
     "--forcing (f₁)"),
    (lambda: rigid(r=1.5), "restitution (r)",
     flags("--model", "rigid", "--law", "impulse-response", "--restitution", "1.5"),
     "--restitution (r)"),
    (lambda: rigid(law="newton"), "law newton",
     flags("--model", "rigid", "--law", "newton"), "--law newton"),
    (lambda: ic.simulate(rigid(gap=-0.5), 1), "gap (d₀)",
     flags("--model", "rigid", "--gap", "-0.5"), "--gap (d₀)"),
    (lambda: ic.simulate(rigid(), 1, seed=3), "seed", flags("--model", "rigid", "--seed", "3"),
     "--seed"),
    (lambda: ic.simulate(model(), 200_000_000), "periods", flags("--periods", "200000000"),
     "--periods"),
    (lambda: ic.simulate(model(), 1, 200_000), "record", flags("--record", "200000"), "--record"),
    (lambda: ic.simulate(model(), 0, 0), "periods/record",
     flags("--periods", "0", "--record", "0"), "--periods/--record"),
    (lambda: ic.simulate(model(), 1, max_period=0), "max_period", flags("--max-period", "0"),
     "--max-period"),
    (lambda: ic.simulate(model(), 1, dense_per_period=10_001), "dense_per_period",
     flags("--dense-per-period", "10001", "--dense", "/dev/null"), "--dense-per-period"),
    (lambda: ic.simulate(model(), 1, periodicity_tolerance=1.0), "periodicity_tolerance",
     flags("--periodicity-tolerance", "1"), "--periodicity-tolerance"),
]


def name_and_rest(message: str) -> tuple[str, str]:
    assert message.startswith("invalid ") and ": got " in message, message
    name, rest = message.removeprefix("invalid ").split(": got ", 1)
    return name, rest


@pytest.mark.parametrize("case", range(len(CASES)))
def test_bad_input_says_what_the_command_line_says(cli: Cli, case: int) -> None:
    call, py_name, args, cli_name = CASES[case]
    with pytest.raises(ValueError) as e:
        call()
    expected = cli.error("simulate", *args)
    assert name_and_rest(str(e.value)) == (py_name, name_and_rest(expected)[1])
    assert name_and_rest(expected)[0] == cli_name


def test_a_start_state_is_checked_as_an_initial_state_file(cli: Cli, tmp_path: Path) -> None:
    for state in [[0.1] * 5, [2e6] * 6, [1e-120] * 6]:
        path = tmp_path / "x.json"
        path.write_text(str(state))
        with pytest.raises(ValueError) as e:
            ic.simulate(model(), 1, start=state)
        expected = cli.error("simulate", *BASE, "--initial-state", str(path))
        assert name_and_rest(str(e.value)) == ("start", name_and_rest(expected)[1])


def test_library_messages_are_passed_on_verbatim(cli: Cli) -> None:
    with pytest.raises(ValueError) as e:
        ic.modes_needed(1e7)
    assert str(e.value) == cli.error("modes-needed", "--stop-stiffness", "1e7")
    with pytest.raises(ValueError) as e:
        ic.problems.figure4(3).modal_state([0.0, 1.0], [0.0, float("nan")], [0.0, 0.0])
    assert str(e.value).startswith("invalid profile: ")
    with pytest.raises(ic.errors.UnsupportedError, match="^unsupported: r_E"):
        ic.find_orbit(rigid(), restitution=True)


def test_a_rigid_run_that_stops_before_its_window_is_an_error(cli: Cli) -> None:
    # from rest on the stop, a law without a sticking limit chatters at t = 0
    with pytest.raises(ic.errors.ChatterError) as e:
        ic.simulate(rigid(law="stiffness-limit", gap=0.0), 0, 2)
    p = cli.run("simulate", *flags("--model", "rigid", "--law", "stiffness-limit",
                                   "--restitution", "0.8", "--gap", "0", "--periods", "0",
                                   "--record", "2"))
    # the exit status of a chatter (ic.errors documents each kind's)
    assert p.returncode == 5, (p.stdout, p.stderr)
    expected = p.stderr.strip().removeprefix("error: ")
    assert expected.startswith("chatter: nothing recorded"), expected
    assert str(e.value) == expected


HOSTILE = Path(__file__).with_name("hostile.py")


def test_a_hostile_user_gets_exceptions_never_a_crash_or_a_hang() -> None:
    p = subprocess.run(
        [sys.executable, str(HOSTILE)], capture_output=True, text=True, timeout=300
    )
    lines = p.stdout.splitlines()
    assert p.returncode == 0, f"crashed after: {lines[-1:]}\n{p.stderr[-2000:]}"
    assert lines and lines[-1].startswith("all "), p.stdout
    bad = [line for line in lines if "NO EXCEPTION" in line]
    assert not bad, bad


def test_long_work_releases_the_interpreter_and_reports_progress() -> None:
    reports: list[tuple[str, int, int]] = []
    ticks = 0
    done = threading.Event()

    def work() -> None:
        ic.simulate(ic.problems.figure4(10), 3000, 1, progress=lambda *a: reports.append(a))
        done.set()

    t = threading.Thread(target=work)
    t.start()
    while not done.is_set():
        ticks += 1  # runs while the simulation holds no lock
        time.sleep(0.001)
    t.join()
    assert ticks > 10
    assert reports and reports[-1] == ("simulate: periods", 3001, 3001)
    assert all(what == "simulate: periods" and total == 3001 for what, _, total in reports)


def test_a_callback_that_raises_stops_the_work_with_its_exception() -> None:
    def stop(what: str, done: int, total: int) -> None:
        if done > 0:
            raise KeyError("stop here")

    with pytest.raises(KeyError, match="stop here"):
        ic.continue_branch(ic.problems.figure4(3), "stop_stiffness", 300, progress=stop)
    with pytest.raises(KeyError, match="stop here"):
        ic.simulate(rigid(gap=0.5), 3000, progress=stop)
    assert np.isfinite(ic.find_orbit(ic.problems.figure4(1)).spectral_radius)


def test_models_pickle_and_serve_many_threads_at_once() -> None:
    """A model travels to another process by pickling (rebuilt from its parameters, the same
    bits), and one model serves several threads at once, each getting the same orbit."""
    import pickle
    from concurrent.futures import ThreadPoolExecutor

    models = [
        ic.problems.figure4(3),
        ic.rigid(ic.compliant(1, zeta1=0.01, omega=2), law="newton", restitution=0.8),
        ic.oscillator(stiffness=1.0, damping=0.05, forcing=1.0, omega=0.8, gap=0.5,
                      stop_stiffness=100.0),
    ]  # fmt: skip
    for m in models:
        again = pickle.loads(pickle.dumps(m))
        assert again.parameters() == m.parameters() and repr(again) == repr(m)
        a, b = ic.simulate(m, 50, 4), ic.simulate(again, 50, 4)
        assert a.final_state.tobytes() == b.final_state.tobytes()
    m = models[0]
    with ThreadPoolExecutor(4) as pool:
        orbits = list(pool.map(lambda _: ic.find_orbit(m), range(4)))
    assert len({o.multipliers.tobytes() for o in orbits}) == 1
