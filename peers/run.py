#!/usr/bin/env python3
"""Reruns every peer comparison and writes peers/results/*.json (see peers/README.md).

    python3 peers/run.py                       # everything (about an hour on two cores)
    python3 peers/run.py --only oscillator     # one problem (or: chatter, rigid-n2,
                                               # fig4-n3, fig4-n10, orbits)
    python3 peers/run.py --repeats 3 --inner 10 --budget 10 --siconos-python /usr/bin/python3

Timing (every tool alike): the CPU time of the solve alone, set-up apart, one thread, the
best of the repeats. Every run of a problem (this project and each peer at each setting) is
repeated --repeats times, alternated (repeat 1 of every run, then repeat 2, ...); the
compiled tools (this project, its Dormand–Prince, CVODE) also repeat their solve up to
--inner times inside each of those (until 1 s of CPU), their runs being micro- to
milliseconds. The best (smallest) CPU time is kept. A rung of a tolerance ladder whose
first run takes longer than --budget seconds is the last of its ladder: the tighter rungs
are recorded as not run, with the time extrapolated from the last two rungs.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile

# one thread everywhere (BLAS included), as this project's command line runs
for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import mpmath as mp
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
import orbits  # noqa: E402
import reference  # noqa: E402
import scipy_peers  # noqa: E402
from includes import INCLUDES, ORBIT_INCLUDES  # noqa: E402
from model import Model  # noqa: E402

FIG4 = {"model": "compliant", "stop_stiffness_over_k1": 100.0, "zeta1": 0.01,
        "omega_over_beta1_squared": 2.0, "gap": 0.0}

PROBLEMS = {
    "oscillator": {
        "title": "1-DOF impact oscillator, Newton's law",
        "model": "rigid", "law": "newton", "restitution": 0.8, "modes": 1, "zeta1": 0.01,
        "omega_over_beta1_squared": 1.0, "gap": 0.5, "initial_state": [0.0, 0.0], "periods": 50,
        "reference": "closed form (damped cosine + harmonic response), mpmath at 40 digits",
    },
    "chatter": {
        "title": "1-DOF impact oscillator with chatter and sticking",
        "model": "rigid", "law": "newton", "restitution": 0.5, "modes": 1, "zeta1": 0.01,
        "omega_over_beta1_squared": 0.5, "gap": 0.0, "initial_state": [-0.005, 0.0], "periods": 10,
        "reference": "closed form, chatter followed to incoming velocity 1e-12, sticking until the closed-form release, mpmath at 40 digits",
    },
    "rigid-n2": {
        "title": "Rigid-impact model, N = 2, Newton's law at the tip ([R]_IR)",
        "model": "rigid", "law": "impulse-response", "restitution": 0.8, "modes": 2, "zeta1": 0.01,
        "omega_over_beta1_squared": 1.0, "gap": 0.5, "initial_state": [0.0] * 4, "periods": 50,
        "reference": "eigendecomposition of the free flow, mpmath at 40 digits",
    },
    "fig4-n3": dict(FIG4, title="Figure 4 compliant model, N = 3", modes=3,
                    initial_state=[0.0] * 6, periods=20,
                    reference="eigendecomposition of A± in each region, mpmath at 40 digits"),
    "fig4-n10": dict(FIG4, title="Figure 4 compliant model, N = 10", modes=10,
                     initial_state=[0.0] * 20, periods=20,
                     reference="eigendecomposition of A± in each region, mpmath at 40 digits"),
}

RTOLS = [10.0 ** -e for e in range(3, 14)]
MJ_STEPS = [25, 100, 400, 1600, 6400, 25600]
SCIPY_METHODS = ["DOP853", "Radau", "LSODA"]
CVODE_METHODS = [("bdf", "BDF, Newton with the exact Jacobian (dense)"),
                 ("adams", "Adams, fixed-point iteration")]
DOPRI5 = "Dormand–Prince 5(4) with event location (the work-precision chapter's)"

# ------------------------------------------------------------------ helpers

def strobe_error(strobe, ref):
    """max_k ‖x(kT) − x_ref(kT)‖∞ / max_k ‖x_ref(kT)‖∞ over the periods both reached
    (None when the run did not reach every period)."""
    if len(strobe) < len(ref):
        return None
    scale = max(max(abs(v) for v in s) for s in ref)
    return max(max(abs(a - b) for a, b in zip(x, r)) for x, r in zip(strobe, ref)) / scale


def event_error(times, kinds, ref_times, ref_kinds):
    """max |t − t_ref| when the event sequences agree in number and kind, else None."""
    if len(times) != len(ref_times) or list(kinds) != list(ref_kinds):
        return None
    return max((abs(a - b) for a, b in zip(times, ref_times)), default=0.0)


def floats(xs):
    return [float(v) for v in xs]


def cli_flags(p):
    return common.problem_flags(p)


def initial_state_file(p, tmp):
    path = os.path.join(tmp, "x0.json")
    json.dump(p["initial_state"], open(path, "w"))
    return ["--initial-state", path] if any(v != 0 for v in p["initial_state"]) else []


# ------------------------------------------------------------------ our side

def ours_values(p, tmp):
    """This project's exact run: the state at every period end, the events, the final state."""
    dense = os.path.join(tmp, "dense.csv")
    args = ["simulate"] + cli_flags(p) + initial_state_file(p, tmp) + [
        "--periods", "0", "--record", str(p["periods"]), "--dense", dense, "--dense-per-period", "1"]
    report, final, _ = common.run_cantilever(args, final_state=True)
    period = report["units"]["forcing_period_T"]
    n = p["modes"]
    rows = {}
    for line in open(dense):
        if line.startswith("t") or not line.strip():
            continue
        cols = line.split(",")
        k = round(float(cols[0]) / period)
        rows[k] = floats(cols[4:4 + 2 * n])
    strobe = [rows[k] for k in range(1, p["periods"])] + [floats(final)]
    events = [e for e in report["events"] if not e["grazing"]]
    return {
        "command": "cantilever " + " ".join(args[:-4]).replace(tmp + "/", ""),
        "strobe": strobe,
        "final_state": floats(final),
        "event_times": [e["time"] for e in events],
        "event_kinds": [bool(e["entering"]) for e in events],
        "events": len(events),
        "outcome": report["outcome"],
    }


def example_args(mode, p, tmp, inner):
    return [common.example_path(), mode] + cli_flags(p) + initial_state_file(p, tmp) + [
        "--periods", str(p["periods"]), "--repeats", str(inner)]


def ours_timed(p, tmp, inner):
    """This project's run timed by the library (examples/peer_problem.rs `time`): the best
    of up to `inner` solves in one process."""
    r = common.run_json(example_args("time", p, tmp, inner))
    return {"cpu_seconds": min(r["cpu_seconds"]), "solves": len(r["cpu_seconds"]),
            "setup_cpu_seconds": r["setup_cpu_seconds"], "final_state": floats(r["state"])}


# ------------------------------------------------------------------ the peers

def beyond_stop(p, mx, r):
    """A rigid run whose tip ends a period beyond the stop (by more than 1e-6 of the gap
    scale) passed through it: impacts were missed."""
    if p["model"] != "rigid" or not r["outcome"].startswith("completed"):
        return r
    n = p["modes"]
    tip = np.array(mx["tip"])
    worst = max((float(tip @ np.array(x[:n])) - mx["gap"] for x in r["strobe"] + [r["final_state"]]),
                default=0.0)
    if worst > 1e-6 * max(1.0, abs(mx["gap"])):
        r["outcome"] = (f"completed, but the tip passed through the stop (missed impacts): "
                        f"{worst:.3g} beyond it at a period end")
    return r


def scipy_run(p, model, method, rtol):
    x0 = np.array(p["initial_state"], dtype=float)
    if p["model"] == "rigid":
        r, cpu = common.cpu_timed(lambda: scipy_peers.rigid(
            model, model.law_ir, x0, p["periods"], method, rtol, 1e-3 * rtol))
        kinds = [True] * len(r["events"])
    else:
        r, cpu = common.cpu_timed(lambda: scipy_peers.compliant(
            model, x0, p["periods"], method, rtol, 1e-3 * rtol))
        kinds = [e[1] for e in r["events"]]
    return {"cpu_seconds": cpu, "strobe": r["strobe"], "final_state": r["state"],
            "event_times": [e[0] for e in r["events"]], "event_kinds": kinds,
            "outcome": r["outcome"], "rhs_evaluations": r["nfev"]}


def problem_text(p, mx, path):
    """The problem for cvode_peer.c: whitespace-separated numbers (see its header)."""
    flat = lambda m: [v for row in m for v in row]
    nums = [1 if p["model"] == "rigid" else 0, mx["modes"], p["periods"], mx["period"], mx["omega"],
            mx["gap"]] + flat(mx["K_minus"]) + flat(mx["K_plus"]) + mx["damping"] + \
        mx["forcing_amplitude"] + mx["tip"] + mx["contact_preload"] + \
        flat(mx["law_impulse_response"]) + p["initial_state"]
    with open(path, "w") as f:
        f.write("\n".join(repr(float(v)) for v in nums) + "\n")
    return path


def compiled_row(r):
    """A compiled tool's run (CVODE, this project's Dormand–Prince): the best of its solves
    in one process is this repeat's time."""
    return {"cpu_seconds": min(r["cpu_seconds"]), "solves": len(r["cpu_seconds"]),
            "setup_cpu_seconds": r["setup_cpu_seconds"], "strobe": r["strobe"],
            "final_state": r["state"], "event_times": [float(e[0]) for e in r["events"]],
            "event_kinds": [bool(e[1]) for e in r["events"]], "outcome": r["outcome"],
            "rhs_evaluations": r["rhs_evaluations"]}


def cvode_run(problem_file, method, rtol, inner):
    return compiled_row(common.run_json([common.cvode_path(), problem_file, method, repr(rtol), str(inner)]))


def dopri5_run(p, tmp, rtol, inner):
    return compiled_row(common.run_json(example_args("dopri5", p, tmp, inner) + ["--rtol", repr(rtol)]))


def siconos_run(p, matrices_file, method, setting, python):
    out = subprocess.run(
        [python, os.path.join(common.PEERS, "siconos_peers.py"), matrices_file, method,
         repr(setting), str(p["periods"]), json.dumps(p["initial_state"])],
        capture_output=True, text=True)
    last = out.stdout.strip().splitlines()[-1] if out.stdout.strip() else ""
    try:
        r = json.loads(last)
    except json.JSONDecodeError:
        raise RuntimeError(f"siconos_peers.py {method} {setting}: {out.stderr[-500:]}")
    return {"cpu_seconds": r["cpu_seconds"], "strobe": r["strobe"], "final_state": r["state"],
            "event_times": [e[0] for e in r["impacts"]], "event_kinds": [True] * len(r["impacts"]),
            "outcome": r["outcome"]}


def siconos_version(python):
    v = subprocess.run(["dpkg-query", "-W", "-f", "${Version}", "python3-siconos"],
                       capture_output=True, text=True).stdout.strip()
    py = subprocess.run([python, "-c", "import platform, numpy; print(platform.python_version(), numpy.__version__)"],
                        capture_output=True, text=True).stdout.split()
    return {"siconos": f"python3-siconos {v} (Debian)" if v else None,
            "siconos_python": f"{python} {py[0]}" if py else None,
            "siconos_numpy": py[1] if len(py) > 1 else None}


def ladder(rungs, budget, run_one):
    """Runs each rung once (loosest first) until one takes longer than `budget` CPU
    seconds; the rungs after it are not run. Returns a list of (rung, [results] or None)."""
    results, stop = [], None
    for rung in rungs:
        if stop is not None:
            results.append((rung, None))
            continue
        r = run_one(rung)
        results.append((rung, [r]))
        if r["cpu_seconds"] > budget:
            stop = rung
    return results


# ------------------------------------------------------------------ one problem

def run_problem(name, args):
    p = PROBLEMS[name]
    common.log(f"== {name}: {p['title']}")
    spec = {k: v for k, v in p.items()}
    load = list(os.getloadavg())
    with tempfile.TemporaryDirectory() as tmp:
        mx = common.matrices(p)
        model = Model(mx)
        matrices_file = os.path.join(tmp, "matrices.json")
        json.dump(mx, open(matrices_file, "w"))
        problem_file = problem_text(p, mx, os.path.join(tmp, "problem.txt"))
        # the independent reference
        common.log("  reference (mpmath)")
        if p["modes"] == 1:
            osc = reference.Oscillator(mx["modal_stiffness"][0], mx["damping"][0],
                                       mx["forcing_amplitude"][0], mx["omega"], mx["tip"][0],
                                       mx["gap"], p["restitution"])
            (ref, ref_seconds) = common.cpu_timed(lambda: osc.run(p["periods"], *p["initial_state"]))
            ref_strobe = [floats(s) for s in ref["strobe"]]
            ref_times = [float(t) for t, _ in ref["impacts"]]
            ref_kinds = [True] * len(ref_times)
            sticks = [[float(a), None if b is None else float(b)] for a, b in ref["sticks"]]
            x0, v0 = p["initial_state"]
            nudged = osc.run(p["periods"], x0, mp.mpf(v0) + mp.mpf("1e-16"))["strobe"]
        else:
            law = model.law_ir if p["model"] == "rigid" else None
            pw = reference.Piecewise(model, law=law)
            (ref, ref_seconds) = common.cpu_timed(lambda: pw.run(p["initial_state"], p["periods"]))
            ref_strobe = [floats(s) for s in ref["strobe"]]
            ref_times = [float(e[0]) for e in ref["events"]]
            ref_kinds = [bool(e[1]) for e in ref["events"]]
            sticks = []
            x0 = [mp.mpf(v) for v in p["initial_state"]]
            x0[p["modes"]] += mp.mpf("1e-16")
            nudged = pw.run(x0, p["periods"])["strobe"]
        common.log("  this project's values")
        ours = ours_values(p, tmp)
        # each peer's ladder
        peers = []
        if p["model"] == "compliant":
            peers.append(("cantilever", DOPRI5, "rtol", RTOLS,
                          lambda rtol: dopri5_run(p, tmp, rtol, args.inner)))
        for method, label in CVODE_METHODS:
            peers.append(("CVODE", label, "rtol", RTOLS,
                          lambda rtol, m=method: cvode_run(problem_file, m, rtol, args.inner)))
        for method in SCIPY_METHODS + (["DOP853/100"] if p["model"] == "rigid" else []):
            label = method.replace("/100", ", largest step T/100")
            peers.append(("scipy", label, "rtol", RTOLS,
                          lambda rtol, m=method: scipy_run(p, model, m, rtol)))
        if p["model"] == "rigid":
            peers.append(("siconos", "event-driven (LSODAR), largest step T/100", "rtol", [1e-8],
                          lambda rtol: siconos_run(p, matrices_file, "ed-maxstep", rtol, args.siconos_python)))
            peers.append(("siconos", "event-driven (LSODAR)", "rtol", RTOLS,
                          lambda rtol: siconos_run(p, matrices_file, "ed", rtol, args.siconos_python)))
            peers.append(("siconos", "Moreau–Jean time-stepping (θ = 1/2)", "steps per period", MJ_STEPS,
                          lambda steps: siconos_run(p, matrices_file, "mj", steps, args.siconos_python)))
        # repeat 1 (decides which rungs run), then the others, alternated
        common.log("  repeat 1")
        ours_samples = [ours_timed(p, tmp, args.inner)]
        tables = []
        for tool, method, setting_name, rungs, fn in peers:
            def one(rung, fn=fn, tool=tool, method=method):
                r = beyond_stop(p, mx, fn(rung))
                common.log(f"    {tool} {method} {rung:g}: {r['cpu_seconds']:.3g} s, {r['outcome'][:60]}")
                return r
            tables.append((tool, method, setting_name, ladder(rungs, args.budget, one)))
        for rep in range(1, args.repeats):
            common.log(f"  repeat {rep + 1}")
            ours_samples.append(ours_timed(p, tmp, args.inner))
            for (tool, method, setting_name, table), peer in zip(tables, peers):
                for rung, results in table:
                    if results is not None:
                        results.append(beyond_stop(p, mx, peer[4](rung)))
        # the rows
        rows = []
        for tool, method, setting_name, table in tables:
            last_two = []
            for rung, results in table:
                row = {"tool": tool, "method": method, "setting_name": setting_name, "setting": rung}
                if setting_name == "rtol":
                    row["atol"] = 1e-3 * rung
                if results is None:
                    est = None
                    if len(last_two) == 2 and last_two[0][1] > 0:
                        (s0, t0), (s1, t1) = last_two
                        est = t1 * (t1 / t0)
                    row.update({"outcome": f"not run: the previous setting took more than {args.budget:g} s"
                                           + (f"; extrapolated {est:.3g} s" if est else ""),
                                "extrapolated_cpu_seconds": est})
                    rows.append(row)
                    if est:
                        last_two = [last_two[1], (rung, est)]
                    continue
                first = results[0]
                samples = [r["cpu_seconds"] for r in results]
                t_best = min(samples)
                last_two = (last_two + [(rung, t_best)])[-2:]
                row.update({
                    "outcome": first["outcome"],
                    "cpu_seconds": samples,
                    "cpu_seconds_best": t_best,
                    "final_state": first["final_state"],
                    "strobe": first["strobe"],
                    "events": len(first["event_times"]),
                    "event_times": first["event_times"],
                    "event_kinds": first["event_kinds"],
                    "same_events_as_ours": event_error(first["event_times"], first["event_kinds"],
                                                       ours["event_times"], ours["event_kinds"]) is not None,
                    "event_time_error_vs_ours": event_error(first["event_times"], first["event_kinds"],
                                                            ours["event_times"], ours["event_kinds"]),
                    "event_time_error_vs_reference": event_error(first["event_times"], first["event_kinds"],
                                                                 ref_times, ref_kinds),
                    "strobe_error_vs_ours": strobe_error(first["strobe"], ours["strobe"]),
                    "strobe_error_vs_reference": strobe_error(first["strobe"], ref_strobe),
                })
                if "rhs_evaluations" in first:
                    row["rhs_evaluations"] = first["rhs_evaluations"]
                if "solves" in first:
                    row["solves_per_repeat"] = [r["solves"] for r in results]
                    row["setup_cpu_seconds"] = first["setup_cpu_seconds"]
                rows.append(row)
        if p["model"] == "compliant":
            rows.append({"tool": "siconos", "method": "event-driven (LSODAR)", "setting_name": "rtol",
                         "setting": None, "outcome": "not applicable: the compliant stop is a smooth "
                         "piecewise-linear spring, not a nonsmooth law; Siconos would integrate it as a "
                         "plain ODE (LSODAR without a root function, the LSODA rows)"})
        # the timed run is the command line's run
        if common.rel_max_error(ours_samples[0]["final_state"], ours["final_state"]) > 1e-13:
            raise RuntimeError(f"{name}: the timed run does not end where the command line's does")
        ours_doc = dict(ours)
        ours_doc.update({
            "cpu_seconds": [s["cpu_seconds"] for s in ours_samples],
            "cpu_seconds_best": min(s["cpu_seconds"] for s in ours_samples),
            "solves_per_repeat": [s["solves"] for s in ours_samples],
            "setup_cpu_seconds": ours_samples[0]["setup_cpu_seconds"],
            "timed_command": "examples/peer_problem.rs " + " ".join(["time"] + cli_flags(p) + [
                "--periods", str(p["periods"]), "--repeats", str(args.inner)]),
            "timed_final_state": ours_samples[0]["final_state"],
            "strobe_error_vs_reference": strobe_error(ours["strobe"], ref_strobe),
            "event_time_error_vs_reference": event_error(ours["event_times"], ours["event_kinds"],
                                                         ref_times, ref_kinds),
        })
        doc = common.header(spec, mx, siconos_version(args.siconos_python) if p["model"] == "rigid" else None,
                            load_at_start=load)
        doc["protocol"] = protocol(args, INCLUDES if p["model"] == "compliant" else
                                   [i for i in INCLUDES if "Dormand" not in i[0]])
        doc["reference"] = {
            "method": p["reference"],
            "digits": reference.DPS,
            "cpu_seconds": ref_seconds,
            "strobe": ref_strobe,
            "events": len(ref_times),
            "event_times": ref_times,
            "event_kinds": ref_kinds,
            "sticking": sticks,
            # the problem's conditioning: how far the reference moves when η̇₁(0) moves by 1e-16
            "strobe_change_for_1e-16_in_initial_velocity": strobe_error([floats(x) for x in nudged], ref_strobe),
        }
        doc["ours"] = ours_doc
        doc["rows"] = rows
        path = common.write_result(name, doc)
        common.log(f"  wrote {path}")


def protocol(args, includes):
    return {
        "repeats": args.repeats,
        "inner_repeats": args.inner,
        "budget_seconds": args.budget,
        "timing": "Every tool alike: the CPU time of the solve alone (set-up apart), one "
                  "thread, the best of `repeats` runs alternated between the tools; the "
                  "compiled tools (this project, its Dormand–Prince, CVODE) repeat their solve "
                  "up to `inner_repeats` times inside each run (until 1 s of CPU) and report "
                  "the best. Measured from a committed build (versions.commit).",
        "includes": includes,
        "error": "strobe error: max over the period ends kT of ‖x(kT) − x_ref(kT)‖∞ over max "
                 "over k of ‖x_ref(kT)‖∞; event-time error: max |t − t_ref| over the events when "
                 "the two sequences have the same number and kind of events.",
    }


# ------------------------------------------------------------------ orbits

ORBITS = [
    # (modes, transient periods of the start, methods with their rtol ladders)
    (3, 10), (10, 10), (10, 50),
]
ORBIT_RTOLS = {"DOP853": [1e-6, 1e-8, 1e-10], "Radau": [1e-6, 1e-8, 1e-10], "LSODA": [1e-6, 1e-8, 1e-10]}


def run_orbits(args):
    common.log("== orbits")
    problems, rows = [], []
    load = list(os.getloadavg())
    with tempfile.TemporaryDirectory() as tmp:
        runs = []
        for n, start_periods in ORBITS:
            p = dict(FIG4, modes=n)
            mx = common.matrices(p)
            model = Model(mx)
            flags = cli_flags(p)
            start_file = os.path.join(tmp, f"start-{n}-{start_periods}.json")
            _, start, _ = common.run_cantilever(["simulate"] + flags + [
                "--periods", str(start_periods), "--record", "0"], final_state=True)
            json.dump(start, open(start_file, "w"))
            orbit_args = ["orbit"] + flags + ["--initial-state", start_file, "--periods", "0", "--period", "1"]
            case = {"modes": n, "start": f"the state after {start_periods} periods from rest",
                    "start_periods": start_periods, "start_state": floats(start),
                    "command": "cantilever " + " ".join(orbit_args).replace(start_file, "START.json")}
            # an independent check of our orbit: the mpmath period map at our fixed point
            ours, _, _ = common.run_cantilever(orbit_args)
            timed_args = [common.example_path(), "orbit"] + flags + [
                "--initial-state", start_file, "--repeats", str(args.inner)]
            pw = reference.Piecewise(model)
            px = pw.run(ours["state"], 1)["state"]
            case["reference_residual_of_ours"] = common.rel_max_error(floats(px), ours["state"])
            case["ours"] = {"state": ours["state"], "multipliers": ours["multipliers"],
                            "iterations": ours["iterations"], "residual": ours["residual"],
                            "impacts_n": ours["impacts_n"], "cpu_seconds": [], "solves_per_repeat": [],
                            "timed_command": "examples/peer_problem.rs " + " ".join(
                                timed_args[1:]).replace(start_file, "START.json")}
            problems.append(case)
            runs.append(("ours", case, None, None, lambda a=timed_args: common.run_json(a)))
            for method, rtols in ORBIT_RTOLS.items():
                for rtol in rtols:
                    runs.append(("scipy", case, method, rtol,
                                 lambda m=model, s=start, me=method, r=rtol: common.cpu_timed(
                                     lambda: orbits.shoot(m, s, me, r, 1e-3 * r, tol=max(10 * r, 1e-12)))))
        results = {i: [] for i in range(len(runs))}
        skipped = set()
        for rep in range(args.repeats):
            common.log(f"  repeat {rep + 1}")
            for i, (kind, case, method, rtol, fn) in enumerate(runs):
                if i in skipped:
                    continue
                if kind == "ours":
                    r = fn()
                    if common.rel_max_error(r["state"], case["ours"]["state"]) > 1e-13:
                        raise RuntimeError(f"orbit N={case['modes']}: the timed orbit is not the command line's")
                    case["ours"]["cpu_seconds"].append(min(r["cpu_seconds"]))
                    case["ours"]["solves_per_repeat"].append(len(r["cpu_seconds"]))
                    continue
                # a tighter rung of a ladder whose looser rung went over budget is not run
                prev = runs[i - 1]
                if rep == 0 and prev[0] == "scipy" and prev[1] is case and prev[2] == method \
                        and (i - 1 in skipped or (results[i - 1] and results[i - 1][0][1] > args.budget)):
                    skipped.add(i)
                    continue
                results[i].append(fn())
                if rep == 0:
                    common.log(f"    N={case['modes']} from {case['start_periods']}: {method} {rtol:g}: "
                               f"{results[i][-1][1]:.3g} s, {results[i][-1][0]['outcome']}")
        for i, (kind, case, method, rtol, _) in enumerate(runs):
            if kind == "ours":
                o = case["ours"]
                o["cpu_seconds_best"] = min(o["cpu_seconds"])
                continue
            row = {"modes": case["modes"], "start_periods": case["start_periods"], "tool": "scipy",
                   "method": method + " + central-difference monodromy", "setting_name": "rtol",
                   "setting": rtol, "atol": 1e-3 * rtol, "newton_tolerance": max(10 * rtol, 1e-12)}
            if i in skipped:
                row["outcome"] = f"not run: the previous setting took more than {args.budget:g} s"
                rows.append(row)
                continue
            r = results[i][0][0]
            samples = [t for _, t in results[i]]
            row.update({
                "outcome": r["outcome"],
                "cpu_seconds": samples,
                "cpu_seconds_best": min(samples),
                "state": r["state"],
                "multipliers": r["multipliers"],
                "residual": r["residual"],
                "newton_steps": r["newton_steps"],
                "periods_integrated": r["periods_integrated"],
                "state_error_vs_ours": common.rel_max_error(r["state"], case["ours"]["state"]),
                "multiplier_error_vs_ours": orbits.multiplier_error(r["multipliers"], case["ours"]["multipliers"]),
            })
            rows.append(row)
        doc = common.header({"title": "Figure 4 orbit and its Floquet multipliers by Newton shooting",
                             **FIG4, "cases": [{k: v for k, v in c.items() if k != "ours"} for c in problems]},
                            None, load_at_start=load)
        doc["protocol"] = protocol(args, ORBIT_INCLUDES)
        doc["ours"] = [dict(c["ours"], modes=c["modes"], start_periods=c["start_periods"]) for c in problems]
        doc["rows"] = rows
        path = common.write_result("orbits", doc)
        common.log(f"  wrote {path}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", action="append", choices=list(PROBLEMS) + ["orbits"])
    ap.add_argument("--repeats", type=int, default=3,
                    help="alternated timing runs per setting (default 3)")
    ap.add_argument("--inner", type=int, default=10,
                    help="solves of a compiled tool inside each timing run, up to 1 s of CPU (default 10)")
    ap.add_argument("--budget", type=float, default=10.0,
                    help="CPU seconds of a run beyond which a ladder stops (default 10)")
    ap.add_argument("--siconos-python", default="/usr/bin/python3")
    ap.add_argument("--no-build", action="store_true")
    ap.add_argument("--cargo-arg", action="append", default=[],
                    help="extra arguments of cargo build (e.g. --cargo-arg=--all-features)")
    args = ap.parse_args()
    if not args.no_build:
        common.build(args.cargo_arg)
    mp.mp.dps = reference.DPS
    for name in args.only or list(PROBLEMS) + ["orbits"]:
        if name == "orbits":
            run_orbits(args)
        else:
            run_problem(name, args)


if __name__ == "__main__":
    main()
