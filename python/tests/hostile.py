"""A hostile user's calls, run as a script by test_errors.py: each must raise a Python
exception (printed as "raised <type>"), a few may also return ("returned"); a call that
returns where it must raise prints "NO EXCEPTION". A crash ends the script, and the last line
printed names the case it was in."""

from __future__ import annotations

import json
import sys

import numpy as np

import impacting_cantilever as ic

m = ic.problems.figure4(3)
r = ic.rigid(m, law="impulse-response")
p = ic.atlas.params("test")
nan, inf = float("nan"), float("inf")


def kw(**changes: object) -> dict[str, object]:
    return {"zeta1": 0.01, "omega": 2.0, **changes}


# (name, call, whether it may also return normally)
CASES = [
    ("negative N", lambda: ic.compliant(-3, **kw()), False),
    ("huge N", lambda: ic.compliant(10**30, **kw()), False),
    ("N as text", lambda: ic.compliant("10", **kw()), False),  # type: ignore[arg-type]
    ("N as a float", lambda: ic.compliant(10.5, **kw()), False),  # type: ignore[arg-type]
    ("NaN ζ₁", lambda: ic.compliant(3, **kw(zeta1=nan)), False),
    ("infinite ω", lambda: ic.compliant(3, **kw(omega=inf)), False),
    ("k = 1e308", lambda: ic.compliant(3, **kw(stop_stiffness=1e308)), False),
    ("gap unit", lambda: ic.compliant(3, **kw(gap_unit="metres")), False),
    ("gap 1e300 of A_free", lambda: ic.compliant(3, **kw(gap=1e300, gap_unit="free")), False),
    ("damping reading", lambda: ic.compliant(3, **kw(damping_reading="x")), False),
    ("forcing None", lambda: ic.compliant(3, **kw(forcing=None)), False),
    ("forcing list", lambda: ic.compliant(3, **kw(forcing=[1, 2])), False),
    ("forcing NaN", lambda: ic.compliant(3, **kw(forcing=nan)), False),
    ("model as text", lambda: ic.simulate("figure4", 10), False),  # type: ignore[arg-type]
    ("negative periods", lambda: ic.simulate(m, -1), False),
    ("huge periods", lambda: ic.simulate(m, 10**20), False),
    ("start too short", lambda: ic.simulate(m, 1, start=[1.0, 2.0, 3.0]), False),
    ("start too long", lambda: ic.simulate(m, 1, start=np.zeros(600)), False),
    ("start NaN", lambda: ic.simulate(m, 1, start=np.full(6, nan)), False),
    ("start inf", lambda: ic.simulate(m, 1, start=np.full(6, inf)), False),
    ("start 2-D", lambda: ic.simulate(m, 1, start=np.ones((2, 3))), False),
    ("start 1e300", lambda: ic.simulate(m, 1, start=np.full(6, 1e300)), False),
    ("start 1e-300", lambda: ic.simulate(m, 1, start=np.full(6, 1e-300)), False),
    ("start text", lambda: ic.simulate(m, 1, start="abc"), False),
    ("start of objects", lambda: ic.simulate(m, 1, start=[{}] * 6), False),
    ("start and seed", lambda: ic.simulate(m, 1, start=np.zeros(6), seed=1), False),
    ("negative seed", lambda: ic.simulate(m, 1, seed=-1), False),
    ("non-contiguous start", lambda: ic.simulate(m, 1, start=np.zeros(12)[::2]), True),
    ("int start", lambda: ic.simulate(m, 1, start=[0, 0, 0, 0, 0, 1]), True),
    ("dense 0", lambda: ic.simulate(m, 1, dense_per_period=0), False),
    ("dense huge", lambda: ic.simulate(m, 1, dense_per_period=10**9), False),
    ("dense of 1e9 samples", lambda: ic.simulate(m, 0, 100_000, dense_per_period=10_000), False),
    ("NaN tolerance", lambda: ic.simulate(m, 1, periodicity_tolerance=nan), False),
    ("negative max period", lambda: ic.simulate(m, 1, max_period=-4), False),
    ("progress not callable", lambda: ic.simulate(m, 10, progress=3), False),  # type: ignore[arg-type]
    ("progress raises", lambda: ic.simulate(m, 10, progress=lambda *a: 1 / 0), False),
    ("stiffest stop chatters", lambda: ic.simulate(
        ic.compliant(10, **kw(stop_stiffness=1e12)), 0, 1), True),
    ("negative transient", lambda: ic.find_orbit(m, transient=-5), False),
    ("window 1", lambda: ic.find_orbit(m, window=1), False),
    ("period 0", lambda: ic.find_orbit(m, period=0), False),
    ("period 100", lambda: ic.find_orbit(m, period=100), False),
    ("no Newton steps", lambda: ic.find_orbit(m, max_iterations=0), False),
    ("tolerance 2", lambda: ic.find_orbit(m, period_tolerance=2.0), False),
    ("r_E of rigid", lambda: ic.find_orbit(r, restitution=True), False),
    ("no period found", lambda: ic.find_orbit(m, transient=0, window=2), True),
    ("continue in gap", lambda: ic.continue_branch(m, "gap", 2.0), False),  # type: ignore[arg-type]
    ("continue to NaN", lambda: ic.continue_branch(m, "omega", nan), False),
    ("continue to start", lambda: ic.continue_branch(m, "stop_stiffness", 100.0), False),
    ("continue step 1", lambda: ic.continue_branch(m, "omega", 3.0, max_step=1.0), False),
    ("continue doubling 0", lambda: ic.continue_branch(m, "omega", 3.0, doubling_up_to=0), False),
    ("continue rigid", lambda: ic.continue_branch(r, "omega", 3.0), False),
    ("continue oscillator", lambda: ic.continue_branch(
        ic.oscillator(stiffness=1, damping=0.1, forcing=1, omega=1), "omega", 3.0), False),
    ("r_E window 1", lambda: ic.energetic_restitution(m, window=1), False),
    ("r_E window 0", lambda: ic.energetic_restitution(m, window=0), False),
    ("r_E huge transient", lambda: ic.energetic_restitution(m, transient=10**9), False),
    ("r_E of rigid", lambda: ic.energetic_restitution(r), False),
    ("modes needed NaN", lambda: ic.modes_needed(nan), False),
    ("modes needed 1e9", lambda: ic.modes_needed(1e9), False),
    ("modes needed tolerance 0", lambda: ic.modes_needed(100, 0.0), False),
    ("modes needed ζ₁ < 0", lambda: ic.modes_needed(100, 1e-3, -1.0), False),
    ("law", lambda: ic.rigid(m, law="magic"), False),  # type: ignore[arg-type]
    ("law r NaN", lambda: ic.rigid(m, restitution=nan), False),
    ("law r < 0", lambda: ic.rigid(m, restitution=-0.1), False),
    ("oscillator k < 0", lambda: ic.oscillator(stiffness=-1, damping=0, forcing=1, omega=1), False),
    ("oscillator NaN", lambda: ic.oscillator(stiffness=nan, damping=0, forcing=1, omega=1), False),
    ("oscillator g = 0", lambda: ic.oscillator(
        stiffness=1, damping=0, forcing=1, omega=1, tip_gain=0), False),
    ("oscillator profile", lambda: ic.oscillator(
        stiffness=1, damping=0.1, forcing=1, omega=1).modal_state([0, 1], [0, 0], [0, 0]), False),
    ("profile lengths", lambda: m.modal_state([0, 1], [0, 1, 2], [0, 0]), False),
    ("profile decreasing", lambda: m.modal_state([1, 0], [0, 0], [0, 0]), False),
    ("profile short", lambda: m.modal_state([0.2, 1], [0, 0], [0, 0]), False),
    ("replace unknown", lambda: ic.replace(m, bogus=1), False),
    ("unpickle nonsense", lambda: ic._models._from_parameters({"model": "boat"}), False),
    ("replace bad", lambda: ic.replace(m, modes=0), False),
    ("problem N = 0", lambda: ic.problems.figure4(0), False),
    ("problem gap NaN", lambda: ic.problems.figure9(10, nan), False),
    ("scene unknown", lambda: ic.scenes.run("nope"), False),
    ("scene resolution", lambda: ic.scenes.run("spectrum", "huge"), False),  # type: ignore[arg-type]
    ("scene out is a file", lambda: ic.scenes.run("spectrum", out="/dev/null"), False),
    ("cite unknown key", lambda: ic.scenes.run("spectrum").cite("nothing"), False),
    ("shard 3 of 2", lambda: ic.atlas.compute_shard(p, 3, 2), False),
    ("shard -1", lambda: ic.atlas.compute_shard(p, -1, 2), False),
    ("shard of 0", lambda: ic.atlas.compute_shard(p, 0, 0), False),
    ("atlas k_points 0", lambda: ic.atlas.compute_shard({**p, "k_points": 0}, 0, 1), False),
    ("atlas k_points -1", lambda: ic.atlas.compute_shard({**p, "k_points": -1}, 0, 1), False),
    ("atlas k_points 1e30", lambda: ic.atlas.compute_shard({**p, "k_points": 10**30}, 0, 1), False),
    ("atlas k_points text", lambda: ic.atlas.compute_shard({**p, "k_points": "9"}, 0, 1), False),
    ("atlas NaN range", lambda: ic.atlas.compute_shard({**p, "zeta1": nan}, 0, 1), False),
    ("atlas unknown field", lambda: ic.atlas.params("test", bogus=1), False),
    ("atlas missing field", lambda: ic.atlas.compute_shard({"modes": 10}, 0, 1), False),
    ("merge nothing", lambda: ic.atlas.merge([]), False),
    ("merge text", lambda: ic.atlas.merge(["not json"]), False),
    ("merge empty object", lambda: ic.atlas.merge(["{}"]), False),
    ("merge a tampered shard", lambda: ic.atlas.merge(
        [json.dumps({**json.loads(ic.atlas.compute_shard(
            {**p, "k_points": 2, "omega_points": 2}, 0, 1)), "rows": []})]), False),
]

raised = 0
for name, call, may_return in CASES:
    print(f"case {name}: ", end="", flush=True)
    try:
        call()
    except Exception as e:  # noqa: BLE001 - every exception type is the point
        raised += 1
        print(f"raised {type(e).__name__}: {str(e)[:160]}", flush=True)
    else:
        print("returned" if may_return else "NO EXCEPTION", flush=True)
print(f"all {len(CASES)} cases done, {raised} raised")
sys.exit(0)
