"""The Python results equal the command line's, bit for bit: the same orbits and multipliers,
the same events, dense output and final states, the same branches and bifurcations, the
same modes-needed study (the command line prints floats in shortest round-trip form, so
its JSON carries every bit)."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import numpy as np
import pytest

import impacting_cantilever as ic

from conftest import Cli, same_bits

FIG4 = ["--stop-stiffness", "100", "--zeta1", "0.01", "--omega", "2"]


def check_orbit(o: ic.Orbit, doc: dict) -> None:
    assert (o.period_m, o.impacts_n, o.stable, o.iterations) == (
        doc["period_m"],
        doc["impacts_n"],
        doc["stable"],
        doc["iterations"],
    )
    assert same_bits(o.state, doc["state"])
    assert same_bits(o.multipliers.real, [m[0] for m in doc["multipliers"]])
    assert same_bits(o.multipliers.imag, [m[1] for m in doc["multipliers"]])
    assert same_bits(o.residual, doc["residual"])


def test_the_readme_line_prints_the_command_lines_fig4_multipliers(cli: Cli) -> None:
    o = ic.find_orbit(ic.problems.figure4(10))
    doc = cli.json("orbit", "--modes", "10", *FIG4, "--periods", "1000", "--record", "65")
    check_orbit(o, doc)
    assert (o.period_m, o.impacts_n) == (1, 1)


@pytest.mark.parametrize("modes", [1, 2, 3])
def test_fig4_orbits_with_a_given_period_and_transient(cli: Cli, modes: int) -> None:
    o = ic.find_orbit(ic.problems.figure4(modes), transient=300, period=1)
    doc = cli.json("orbit", "--modes", str(modes), *FIG4, "--periods", "300", "--period", "1")
    check_orbit(o, doc)


def test_rigid_orbit_with_newtons_law(cli: Cli) -> None:
    base = ic.compliant(1, zeta1=0.01, omega=2)
    o = ic.find_orbit(ic.rigid(base, law="newton", restitution=0.8), transient=500, window=32)
    doc = cli.json(
        "orbit", "--model", "rigid", "--law", "newton", "--restitution", "0.8",
        "--modes", "1", "--zeta1", "0.01", "--omega", "2", "--periods", "500",
    )  # fmt: skip
    check_orbit(o, doc)


def check_events(s: ic.Simulation, doc: dict) -> None:
    ev = doc["events"]
    assert len(s.events) == len(ev)
    assert same_bits(s.events.time, [e["time"] for e in ev])
    assert same_bits(s.events.phase, [e["phase"] for e in ev])
    assert s.events.cycle.tolist() == [e["cycle"] for e in ev]
    assert s.events.entering.tolist() == [e["entering"] for e in ev]
    assert s.events.grazing.tolist() == [e["grazing"] for e in ev]
    assert same_bits(s.events.tip_velocity, [e["tip_velocity"] for e in ev])
    n = s.final_state.size // 2
    assert same_bits(
        s.events.modal_velocities, np.array([e["modal_velocities"] for e in ev]).reshape(-1, n)
    )
    if s.events.outgoing_tip_velocity is not None:
        assert same_bits(s.events.outgoing_tip_velocity, [e["outgoing_tip_velocity"] for e in ev])
        after = np.array([e["modal_velocities_after"] for e in ev]).reshape(-1, n)
        assert same_bits(s.events.modal_velocities_after, after)
    for key in [
        "period_m", "impacts_n", "contacts_in_window", "max_period_searched", "outcome",
    ]:  # fmt: skip
        assert getattr(s, key) == doc[key], key
    for key in [
        "periodicity_residual", "max_tip", "max_tip_time", "max_tip_tolerance",
        "energy_imbalance", "eigenvector_condition", "final_time",
    ]:  # fmt: skip
        value = getattr(s, key)
        assert (value is None) == (doc[key] is None), key
        if value is not None:
            assert same_bits(value, doc[key]), key


def check_files(s: ic.Simulation, final: Path, dense: Path) -> None:
    state = json.loads(final.read_text())
    assert same_bits(s.final_state, state["state"])
    assert (s.final_cycle, s.final_phase) == (state["cycle"], state["phase"])
    with dense.open() as f:
        rows = list(csv.reader(f))[1:]
    assert s.dense is not None and len(s.dense) == len(rows)
    table = np.array([[float(x) for x in r] for r in rows])  # 17 significant digits: exact
    assert same_bits(s.dense.t, table[:, 0])
    assert s.dense.in_contact.tolist() == (table[:, 1] == 1).tolist()
    assert same_bits(s.dense.tip, table[:, 2])
    assert same_bits(s.dense.tip_velocity, table[:, 3])
    assert same_bits(s.dense.state, table[:, 4:])


def test_simulate_compliant_from_rest_with_dense_output(cli: Cli, tmp_path: Path) -> None:
    s = ic.simulate(ic.problems.figure4(3), 1000, 32, dense_per_period=50)
    final, dense = tmp_path / "s.json", tmp_path / "d.csv"
    doc = cli.json(
        "simulate", "--modes", "3", *FIG4, "--periods", "1000", "--record", "32",
        "--dense", str(dense), "--dense-per-period", "50", "--final-state", str(final),
    )  # fmt: skip
    check_events(s, doc)
    check_files(s, final, dense)
    assert s.energy_imbalance is not None and s.energy_imbalance < 1e-12


def test_simulate_every_model_option(cli: Cli, tmp_path: Path) -> None:
    """Gap, viscous damping, the literal damping reading and a modal forcing amplitude, from
    a random seed; then chained from the final state as a given start."""
    m = ic.compliant(
        4, zeta1=0.02, omega=1.3, stop_stiffness=500, gap=0.3, viscous=0.05,
        damping_reading="fig4-literal", forcing=3.5,
    )  # fmt: skip
    flags = [
        "--modes", "4", "--zeta1", "0.02", "--omega", "1.3", "--stop-stiffness", "500",
        "--gap", "0.3", "--viscous", "0.05", "--damping-reading", "fig4-literal",
        "--forcing", "3.5",
    ]  # fmt: skip
    s = ic.simulate(m, 50, 8, seed=7, max_period=4)
    final = tmp_path / "s.json"
    doc = cli.json(
        "simulate", *flags, "--periods", "50", "--record", "8", "--seed", "7",
        "--max-period", "4", "--final-state", str(final),
    )  # fmt: skip
    check_events(s, doc)
    again = ic.simulate(m, 0, 6, start=s.final_state, periodicity_tolerance=1e-6)
    doc = cli.json(
        "simulate", *flags, "--periods", "0", "--record", "6",
        "--initial-state", str(final), "--periodicity-tolerance", "1e-6",
    )  # fmt: skip
    check_events(again, doc)


def test_simulate_rigid_with_each_law(cli: Cli, tmp_path: Path) -> None:
    for law, n in [("impulse-response", 3), ("stiffness-limit", 2), ("collocation", 2)]:
        m = ic.rigid(
            ic.compliant(n, zeta1=0.01, omega=1, gap=0.5), law=law, restitution=0.7  # type: ignore[arg-type]
        )
        s = ic.simulate(m, 100, 4, dense_per_period=20)
        final, dense = tmp_path / f"{law}.json", tmp_path / f"{law}.csv"
        doc = cli.json(
            "simulate", "--model", "rigid", "--law", law, "--restitution", "0.7",
            "--modes", str(n), "--gap", "0.5", "--zeta1", "0.01", "--omega", "1",
            "--periods", "100", "--record", "4", "--dense", str(dense),
            "--dense-per-period", "20", "--final-state", str(final),
        )  # fmt: skip
        check_events(s, doc)
        check_files(s, final, dense)


def test_continuation_in_k_with_its_grazings(cli: Cli) -> None:
    c = ic.continue_branch(ic.problems.figure4(3), "stop_stiffness", 300)
    doc = cli.json(
        "continue", "--modes", "3", *FIG4, "--periods", "1000", "--record", "65",
        "--parameter", "stop-stiffness", "--to", "300",
    )  # fmt: skip
    assert c.document == doc  # every float equal: JSON numbers converted, never reprinted
    kinds = [b.kind for b in c.branches[0].bifurcations]
    assert kinds == ["Grazing", "Grazing"]
    first = doc["branches"][0]["points"]
    assert same_bits(c.branches[0].parameter, [p["parameter"] for p in first])


def test_continuation_in_omega_one_way(cli: Cli) -> None:
    c = ic.continue_branch(ic.problems.figure4(2), "omega", 2.2, one_way=True, max_step=0.05)
    doc = cli.json(
        "continue", "--modes", "2", *FIG4, "--periods", "1000", "--record", "65",
        "--parameter", "omega", "--to", "2.2", "--one-way", "--max-step", "0.05",
    )  # fmt: skip
    assert c.document == doc
    assert len(c.branches) == 1 and c.branches[0].bifurcations  # folds and doublings


def test_curve_of_grazings_in_k_and_omega(cli: Cli) -> None:
    m = ic.replace(ic.problems.figure4(3), stop_stiffness=126.0)
    c = ic.continue_curve(
        m, "grazing", "stop_stiffness", "omega", (10.0, 1000.0), (1.9, 2.1)
    )
    doc = cli.json(
        "continue2", "--modes", "3", "--stop-stiffness", "126", "--zeta1", "0.01",
        "--omega", "2", "--periods", "1000", "--record", "65", "--kind", "grazing",
        "--parameter", "stop-stiffness", "--second", "omega", "--range", "10", "1000",
        "--second-range", "1.9", "2.1",
    )  # fmt: skip
    assert c.document == doc
    assert same_bits(c.p, [p["p"] for p in doc["curve"]["points"]])
    assert len(c) > 10 and c.kind == "grazing" and c.parameters == ("k/k₁", "ω/(β₁⁻)²")
    assert c.test_residual.max() <= 1e-9
    with pytest.raises(ic.errors.ParameterError, match="second"):
        ic.continue_curve(m, "grazing", "omega", "omega", (1.0, 3.0), (1.0, 3.0))
    with pytest.raises(ic.errors.ParameterError, match="kind"):
        ic.continue_curve(m, "cusp", "omega", "gap", (1.0, 3.0), (1.0, 3.0))  # type: ignore[arg-type]
    with pytest.raises(ic.errors.ParameterError, match="range"):
        ic.continue_curve(m, "fold", "omega", "stop_stiffness", (3.0, 1.0), (10.0, 300.0))


def test_curve_of_neimark_sacker_points(cli: Cli) -> None:
    m = ic.replace(ic.problems.figure4(2), stop_stiffness=7.5)
    c = ic.continue_curve(
        m, "neimark_sacker", "stop_stiffness", "omega", (2.0, 40.0), (1.9, 2.1)
    )
    doc = cli.json(
        "continue2", "--modes", "2", "--stop-stiffness", "7.5", "--zeta1", "0.01",
        "--omega", "2", "--periods", "1000", "--record", "65", "--kind", "neimark-sacker",
        "--parameter", "stop-stiffness", "--second", "omega", "--range", "2", "40",
        "--second-range", "1.9", "2.1",
    )  # fmt: skip
    assert c.document == doc
    assert c.kind == "neimark_sacker" and len(c) > 10
    assert c.test_residual.max() <= 1e-9


def test_modes_needed(cli: Cli) -> None:
    m = ic.modes_needed(5000, 1e-4)
    doc = cli.json("modes-needed", "--stop-stiffness", "5000", "--tolerance", "1e-4")
    assert m.document == doc
    assert m.needed == doc["needed"]["Scanned"]
    assert same_bits(m.studies["contact duration"].limit, doc["studies"][0][1]["limit"])


def test_energetic_restitution_two_ways() -> None:
    """r_E (eq 39) of the settled orbit and of the orbit found by shooting: the same orbit,
    reached two ways, to the orbit's convergence (1e-12 residual, amplified by the eq 39
    balance's conditioning)."""
    m = ic.problems.figure6b(10)
    settled = ic.energetic_restitution(m)
    shot = ic.find_orbit(m, restitution=True)
    assert settled.period_m == shot.period_m and settled.impacts_n == shot.impacts_n
    assert settled.r_E is not None and shot.energetic_restitution is not None
    assert abs(settled.r_E - shot.energetic_restitution) < 1e-9


def test_motion_is_the_command_lines(cli: Cli) -> None:
    # the quasi-periodic motion of Figure 4's model at k = 11.29k₁, where no orbit is found
    m = ic.motion(ic.replace(ic.problems.figure4(10), stop_stiffness=11.29))
    doc = cli.json("motion", "--modes", "10", "--stop-stiffness", "11.29", "--zeta1", "0.01",
                   "--omega", "2")
    assert m.kind == doc["class"] == "quasi-periodic"
    assert same_bits(m.exponents, doc["exponents"]) and same_bits(m.half_widths, doc["half_widths"])
    assert same_bits(m.rotation_number, doc["rotation"]["turns"])
    assert m.options == doc["options"] and m.period_m is None and m.start == doc["start"]
    # changed options are the command line's flags
    m = ic.motion(ic.problems.figure4(3), segments=4, segment_periods=20, iterates=64,
                  longest_period=8, transient=100)
    doc = cli.json("motion", "--modes", "3", *FIG4, "--segments", "4", "--segment-periods",
                   "20", "--iterates", "64", "--longest-period", "8", "--transient", "100")
    assert m.kind == doc["class"] and m.period_m == doc["period_m"] == 1
    assert same_bits(m.exponents, doc["exponents"]) and m.options == doc["options"]
    # refusals are the command line's, with the keyword for the flag
    for keyword, flag, value in [("iterates", "--iterates", 3), ("segment_periods",
                                  "--segment-periods", 10**9)]:
        with pytest.raises(ic.ParameterError) as e:
            ic.motion(ic.problems.figure4(3), **{keyword: value})
        said = cli.error("motion", "--modes", "3", *FIG4, flag, str(value))
        assert str(e.value) == said.replace(flag, keyword)
