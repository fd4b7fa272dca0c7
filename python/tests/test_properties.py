"""Properties over random models (hypothesis): the Python package and the command line give
the same numbers, bit for bit, for random valid specifications — the compliant model from
soft to 1e12 k₁ stops, every rigid law with r from 0 to 1 — and every failure is the
exception class of its kind, with the command line's exit status of the same kind.

The cases are drawn from a fixed seed (the same on every machine); the library's own
property tests (``tests/properties.rs``) try many more without the command line's cost."""

from __future__ import annotations

import math

import pytest
from hypothesis import HealthCheck, given, seed, settings
from hypothesis import strategies as st

import impacting_cantilever as ic
from impacting_cantilever import errors

from conftest import Cli, same_bits

# the command line's exit status of each exception class (the book's *Output formats*)
STATUS = {
    errors.ParameterError: 2,
    errors.NoPeriodError: 3,
    errors.NotConvergedError: 4,
    errors.ChatterError: 5,
    errors.UnsupportedError: 6,
}

LAWS = ["stiffness-limit", "impulse-response", "collocation", "newton"]


@st.composite
def specs(draw: st.DrawFn) -> dict:
    rigid = draw(st.booleans())
    law = draw(st.sampled_from(LAWS)) if rigid else None
    modes = 1 if law == "newton" else draw(st.integers(1, 5))
    k = 0.0 if draw(st.integers(0, 9)) == 0 else 10 ** draw(st.floats(-1, 12))
    return {
        "modes": modes,
        "zeta1": draw(st.floats(1e-3, 0.2)),
        "omega": draw(st.floats(0.3, 3.0)),
        # in units of the free amplitude at ω, so that the stop is within reach
        "gap": draw(st.floats(0.0 if rigid else -0.5, 1.5)),
        "stop_stiffness": None if rigid else k,
        "law": law,
        "restitution": draw(st.floats(0.0, 1.0)) if rigid else None,
        "periods": draw(st.integers(0, 15)),
    }


def build(s: dict) -> ic.Model:
    base = ic.compliant(
        s["modes"], zeta1=s["zeta1"], omega=s["omega"], gap=s["gap"], gap_unit="free",
        **({"stop_stiffness": s["stop_stiffness"]} if s["law"] is None else {}),
    )  # fmt: skip
    if s["law"] is None:
        return base
    return ic.rigid(base, law=s["law"], restitution=s["restitution"])


def flags(s: dict) -> list[str]:
    out = ["--modes", str(s["modes"]), "--zeta1", repr(s["zeta1"]), "--omega", repr(s["omega"]),
           "--gap", repr(s["gap"]), "--gap-unit", "free", "--periods", str(s["periods"]),
           "--record", "4"]  # fmt: skip
    if s["law"] is None:
        out += ["--stop-stiffness", repr(s["stop_stiffness"])]
    else:
        out += ["--model", "rigid", "--law", s["law"], "--restitution", repr(s["restitution"])]
    return out


@seed(2013)
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(specs())
def test_python_and_the_command_line_give_the_same_bits(cli: Cli, s: dict) -> None:
    p = cli.run("simulate", *flags(s), "--json")
    try:
        sim = ic.simulate(build(s), s["periods"], 4)
    except errors.CantileverError as e:
        # the same failure, of the same kind
        assert p.returncode == STATUS.get(type(e), 1), (p.returncode, str(e))
        assert p.stderr.strip().removeprefix("error: ").split(":")[0] in str(e)
        return
    import json

    assert p.returncode in (0, 5), p.stderr  # 5: a rigid window cut short by a chatter
    doc = json.loads(p.stdout)
    assert same_bits(sim.events.time, [e["time"] for e in doc["events"]])
    assert same_bits(sim.events.tip_velocity, [e["tip_velocity"] for e in doc["events"]])
    assert sim.final_time == doc["final_time"]
    assert (sim.period_m, sim.impacts_n) == (doc["period_m"], doc["impacts_n"])
    for name in ["energy_imbalance", "max_tip", "periodicity_residual"]:
        a, b = getattr(sim, name), doc[name]
        assert (a is None and b is None) or a == b or (math.isnan(a) and b is None), name


def test_each_kind_of_failure_is_its_own_class_with_the_command_lines_status(cli: Cli) -> None:
    # bad input: a ParameterError, also a ValueError (code written for ValueError still works)
    with pytest.raises(ValueError) as bad:
        ic.compliant(0, zeta1=0.01, omega=2)
    assert isinstance(bad.value, errors.ParameterError)
    assert isinstance(bad.value, errors.CantileverError)
    # no period within the window: a NoPeriodError, not a ValueError
    quasi = ic.compliant(3, zeta1=0.01, omega=2.45, gap=0.05)
    with pytest.raises(errors.NoPeriodError) as none:
        ic.find_orbit(quasi, transient=0, window=3)
    assert not isinstance(none.value, ValueError)
    p = cli.run("orbit", "--modes", "3", "--zeta1", "0.01", "--omega", "2.45", "--gap", "0.05",
                "--periods", "0", "--record", "3")  # fmt: skip
    assert p.returncode == 3 and p.stderr.strip() == f"error: {none.value}"
    # Newton's failure carries its residual
    with pytest.raises(errors.NotConvergedError) as newton:
        ic.find_orbit(ic.problems.figure4(3), transient=0, period=1, max_iterations=1)
    assert newton.value.residual is not None and newton.value.residual > 1e-12
    p = cli.run("orbit", "--modes", "3", "--stop-stiffness", "100", "--zeta1", "0.01",
                "--omega", "2", "--periods", "0", "--period", "1", "--max-iterations", "1")  # fmt: skip
    assert p.returncode == 4 and p.stderr.strip() == f"error: {newton.value}"
    # the rigid model is not continued: unsupported, status 6
    r = ic.rigid(ic.compliant(1, zeta1=0.01, omega=2), law="newton", restitution=0.8)
    with pytest.raises(errors.UnsupportedError) as unsupported:
        ic.continue_branch(r, "omega", 2.2)
    p = cli.run("continue", "--model", "rigid", "--law", "newton", "--modes", "1",
                "--zeta1", "0.01", "--omega", "2", "--parameter", "omega", "--to", "2.2")  # fmt: skip
    assert p.returncode == 6 and p.stderr.strip() == f"error: {unsupported.value}"
