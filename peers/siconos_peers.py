"""Siconos 4.4 (Debian's python3-siconos) on the rigid-impact problems: the modes as a
LagrangianLinearTIDS (M = I, K⁻, C, the forcing f cos ωt through a C plugin), the stop as a
LagrangianLinearTIR y = d₀ − tipᵀη ≥ 0 with a NewtonImpactNSL of coefficient r (the impulse
acts along tip = M⁻¹Hᵀ: Newton's law at the tip, the library's [R]_IR law; N = 1: Newton's
law), integrated by

- `ed`: EventDriven with LsodarOSI (LSODAR: Adams/BDF with root finding), tolerance rtol,
  atol = 1e-3 rtol;
- `ed-maxstep`: the same with LSODAR's largest step set to T/100;
- `mj`: TimeStepping with MoreauJeanOSI (θ = 1/2) and an LCP, fixed step h.

Runs under the Python that has Siconos (Debian's /usr/bin/python3). One run per call:

    /usr/bin/python3 peers/siconos_peers.py MATRICES.json METHOD RTOL_OR_STEPS PERIODS X0

(X0: the initial state [η; η̇] as JSON) prints one JSON object: CPU seconds of the
integration (process time, set-up excluded), the state at the end of every period and at
the end, the impacts (time, incoming tip velocity) and how the run ended (an exception
of the integrator is an outcome, not a crash).
"""

import json
import os
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
PLUGIN_SRC = os.path.join(HERE, "siconos_forcing.c")


def plugin():
    """The forcing plugin, compiled next to its source's hash (cc -O2)."""
    import hashlib
    digest = hashlib.sha256(open(PLUGIN_SRC, "rb").read()).hexdigest()[:12]
    cache = os.path.join(os.environ.get("XDG_CACHE_HOME", os.path.expanduser("~/.cache")), "cantilever-peers")
    os.makedirs(cache, exist_ok=True)
    so = os.path.join(cache, f"siconos_forcing-{digest}.so")
    if not os.path.exists(so):
        subprocess.run(["cc", "-O2", "-shared", "-fPIC", "-o", so + ".tmp", PLUGIN_SRC, "-lm"], check=True)
        os.replace(so + ".tmp", so)
    return so


def run(m, method, setting, periods, x0):
    import siconos.kernel as sk
    n = int(m["modes"])
    k = np.array(m["K_minus"], dtype=float)
    c = np.diag(np.array(m["damping"], dtype=float))
    tip = np.array(m["tip"], dtype=float)
    period = float(m["period"])
    r = float(m["restitution"])
    t_end = periods * period
    ds = sk.LagrangianLinearTIDS(list(x0[:n]), list(x0[n:]), np.eye(n), k, c)
    ds.setzPtr([float(m["omega"])] + [float(v) for v in m["forcing_amplitude"]])
    ds.setComputeFExtFunction(plugin(), "forcing")
    relation = sk.LagrangianLinearTIR((-tip).reshape(1, n), [float(m["gap"])])
    inter = sk.Interaction(sk.NewtonImpactNSL(r), relation)
    nsds = sk.NonSmoothDynamicalSystem(0.0, t_end)
    nsds.insertDynamicalSystem(ds)
    nsds.link(inter, ds)
    if method.startswith("ed"):
        sim = sk.EventDriven(nsds, sk.TimeDiscretisation(0.0, period))
        osi = sk.LsodarOSI()
        osi.setTol(1, setting, 1e-3 * setting)
        sim.insertIntegrator(osi)
        sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_IMPACT)
        sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_SMOOTH_ACC)
        max_events = 1000 * periods
        if method == "ed-maxstep":
            # LSODAR's largest step T/100 (its work arrays exist only after initialisation;
            # before it, setMinMaxStepSizes aborts the process)
            sim.initialize()
            osi.setMinMaxStepSizes(0.0, period / 100)
    else:
        steps = int(setting)
        sim = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, period / steps))
        osi = sk.MoreauJeanOSI(0.5)
        sim.insertIntegrator(osi)
        sim.insertNonSmoothProblem(sk.LCP())
        max_events = steps * periods + 10
    state = lambda: list(np.array(ds.q(), dtype=float)) + list(np.array(ds.velocity(), dtype=float))
    impacts, strobe = [], []
    outcome = "completed"
    em = sim.eventsManager() if method.startswith("ed") else None
    cpu0 = time.process_time()
    try:
        count, in_contact = 0, False
        while sim.hasNextEvent():
            if em is not None:
                sim.advanceToEvent()
                event = em.nextEvent()
                kind, now = event.getType(), event.getDoubleTimeOfEvent()
                v_before = float(tip @ np.array(ds.velocity()))
                sim.processEvents()
                if kind == sk.NS_EVENT and v_before > 0:
                    impacts.append((now, v_before))
                elif kind == sk.TD_EVENT:
                    strobe.append(state())
            else:
                v_before = float(tip @ np.array(ds.velocity()))
                sim.computeOneStep()
                now = sim.nextTime()
                # an impact: the first step of a contact episode (a nonzero impulse)
                active = float(np.array(inter.lambda_(1))[0]) > 0
                sim.nextStep()
                if active and not in_contact:
                    impacts.append((now, v_before))
                in_contact = active
                if (count + 1) % steps == 0:
                    strobe.append(state())
            count += 1
            if count > max_events:
                outcome = f"stopped at t = {now:.6g}: more than {max_events} events"
                break
    except Exception as e:  # an integrator that throws is a recorded outcome
        outcome = f"threw at t = {sim.startingTime():.6g}: {type(e).__name__}: {' '.join(str(e).split())[:300]}"
    cpu = time.process_time() - cpu0
    return {
        "cpu_seconds": cpu,
        "state": state(),
        "time": float(sim.startingTime()),
        "impacts": impacts,
        "strobe": strobe,
        "outcome": outcome,
    }


def main():
    problem, method, setting, periods, x0 = sys.argv[1:6]
    m = json.load(open(problem))
    out = run(m, method, float(setting), int(periods), json.loads(x0))
    print("\n" + json.dumps(out))  # the last line (Siconos may print above it)


if __name__ == "__main__":
    main()
