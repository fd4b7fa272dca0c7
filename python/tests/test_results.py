"""Results behave as values: two equal computations compare equal (arrays element by
element; a measured wall time is not part of the result), a different one does not, and a
frozen result cannot be changed through its arrays."""

from __future__ import annotations

import numpy as np
import pytest

import impacting_cantilever as ic


def test_equal_results_compare_equal_and_different_ones_do_not() -> None:
    m = ic.problems.figure4(2)
    assert ic.find_orbit(m) == ic.find_orbit(m)
    assert ic.simulate(m, 20, 4) == ic.simulate(m, 20, 4)
    assert ic.simulate(m, 20, 4) != ic.simulate(m, 21, 4)
    assert ic.energetic_restitution(m) == ic.energetic_restitution(m)
    assert ic.find_orbit(m) != ic.find_orbit(ic.problems.figure4(3))
    with pytest.raises(TypeError):
        hash(ic.find_orbit(m))  # equal by value, so not hashable by identity


def test_arrays_of_a_result_are_read_only() -> None:
    m = ic.problems.figure4(2)
    orbit = ic.find_orbit(m)
    run = ic.simulate(m, 20, 4, dense_per_period=8)
    for a in (orbit.state, orbit.multipliers, run.final_state, run.events.time, run.dense.state):
        assert isinstance(a, np.ndarray)
        with pytest.raises(ValueError, match="read-only"):
            a[0] = 0


def test_a_complex_start_is_refused_not_made_real() -> None:
    m = ic.problems.figure4(1)
    with pytest.raises(ic.errors.ParameterError, match="complex"):
        ic.find_orbit(m, np.array([0.1 + 1j, 0.0]))
    with pytest.raises(ValueError, match="complex"):
        ic.simulate(m, 10, start=np.zeros(2, dtype=complex))


def test_a_rigid_run_without_impacts_has_empty_arrays() -> None:
    base = ic.compliant(1, zeta1=0.01, omega=2, stop_stiffness=100, gap=50)
    run = ic.simulate(ic.rigid(base, law="newton", restitution=0.8), 10, 2)
    assert len(run.events) == 0
    assert run.events.outgoing_tip_velocity is not None
    assert run.events.outgoing_tip_velocity.shape == (0,)
    assert run.events.modal_velocities_after is not None
    assert run.events.modal_velocities_after.shape == (0, 1)
    # the compliant model has no outgoing velocities at all
    assert ic.simulate(base, 10, 2).events.outgoing_tip_velocity is None
