"""Models as values, results in the book's units, and the units where ``help()`` shows them."""

from __future__ import annotations

import pickle
import pydoc
import re

import numpy as np
import pytest

import impacting_cantilever as ic


def test_equal_models_are_equal_and_hash_alike() -> None:
    a, b = ic.problems.figure4(10), ic.problems.figure4(10)
    assert a == b and hash(a) == hash(b) and len({a, b}) == 1
    assert pickle.loads(pickle.dumps(a)) == a
    assert ic.replace(a, omega=2.0) == a  # the same value given again
    assert ic.replace(a, omega=2.5) != a and ic.problems.figure4(3) != a
    assert ic.rigid(a) != a and ic.rigid(a) == ic.rigid(b)
    assert ic.rigid(a, restitution=0.5) != ic.rigid(a, restitution=0.6)
    assert a != "Model(N = 10)" and a != None  # noqa: E711
    assert {a: 1}[b] == 1


def _published(scene: str, key: str) -> tuple[float, float]:
    """A published key number's value and the half-width its print and ± allow."""
    text = ic.citation.number(scene, key)
    # the sentence names the number in words ("The first impact velocity …: 1.60201 ± …");
    # the listing under it gives its key
    assert re.search(rf"^\s+key\s+{re.escape(key)}$", text, re.M), text
    m = re.match(r"[^\n]*?: ([-0-9.e]+) ± ([0-9.e-]+) ", text)
    assert m, text
    value, plus_minus = float(m.group(1)), float(m.group(2))
    digits = m.group(1).split("e")[0]
    last = 10.0 ** -(len(digits.split(".")[1]) if "." in digits else 0)
    return value, plus_minus + last / 2


def test_results_in_the_units_of_the_book() -> None:
    model = ic.problems.figure4(3)
    run = ic.simulate(model, 2000, 1, dense_per_period=50)
    free = ic.in_free_units(run, model)
    amplitude, velocity = model.free_tip_amplitude
    entries = free.events.entering & ~free.events.grazing
    # Figure 4's published impact velocity of the N = 3 orbit is in units of ωA_free
    value, allowed = _published("fig4", "N=3 impact_velocity_1")
    assert abs(free.events.tip_velocity[entries][0] - value) <= allowed
    assert abs(run.events.tip_velocity[entries][0] - value) > 100 * allowed  # the raw one is not
    # every length by A_free, every velocity by ωA_free, nothing else changed
    n = model.modes
    assert np.array_equal(free.dense.tip, run.dense.tip / amplitude)
    assert np.array_equal(free.dense.state[:, :n], run.dense.state[:, :n] / amplitude)
    assert np.array_equal(free.dense.state[:, n:], run.dense.state[:, n:] / velocity)
    assert np.array_equal(free.events.time, run.events.time)
    assert free.max_tip == run.max_tip / amplitude and free.period_m == run.period_m
    orbit = ic.find_orbit(model)
    assert np.array_equal(ic.in_free_units(orbit, model).state[n:], orbit.state[n:] / velocity)
    with pytest.raises(ic.ParameterError, match="invalid result"):
        ic.in_free_units(orbit, ic.problems.figure4(10))
    with pytest.raises(ic.ParameterError, match="invalid result"):
        ic.in_free_units(ic.sweep(model, "omega", [2.0]), model)  # type: ignore[type-var]


def test_help_shows_each_fields_meaning_and_the_units() -> None:
    text = pydoc.render_doc(ic.Events, renderer=pydoc.plaintext)
    assert "tip_velocity:" in text and "The tip velocity φ(1)ᵀη̇ at the event" in text
    assert "Units: time of the non-dimensional beam" in text and "in_free_units()" in text
    for cls in [ic.Simulation, ic.Orbit, ic.Dense, ic.Branch, ic.Curve, ic.Sweep, ic.Failure]:
        assert "Attributes:" in (cls.__doc__ or ""), cls


def test_an_undamped_oscillator_at_resonance_is_refused_up_front() -> None:
    # the forced response grows like t there: no periodic part for the exact flow to use
    with pytest.raises(ic.ParameterError, match="with no damping") as e:
        ic.oscillator(stiffness=1.0, damping=0.0, forcing=1.0, omega=1.0)
    assert str(e.value).startswith("invalid oscillator forcing frequency ω: got 1;")
    # damped, or off resonance, it runs
    for damping, omega in [(0.01, 1.0), (0.0, 1.1)]:
        run = ic.simulate(ic.oscillator(stiffness=1.0, damping=damping, forcing=1.0, omega=omega), 10, 2)
        assert np.isfinite(run.final_state).all()
    # unforced at resonance there is no forced response: the free motion x = cos t, which
    # after 12 periods (2π each, ω = 1) is back at its start
    free = ic.oscillator(stiffness=1.0, damping=0.0, forcing=0.0, omega=1.0, gap=2.0)
    run = ic.simulate(free, 10, 2, start=[1.0, 0.0])
    assert np.abs(run.final_state - [1.0, 0.0]).max() < 1e-13
