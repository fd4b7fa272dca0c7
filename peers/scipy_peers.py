"""scipy.integrate.solve_ivp with events: the compliant model (switching between the free
and the contact flow at each crossing of tipᵀη = d₀) and the rigid model (a terminal event
at tipᵀη = d₀ approached from below, then η̇⁺ = −[R]η̇⁻), as a researcher would write them.

Each run goes from x0 at t = 0 over a number of forcing periods and returns a dict: the state
at the end of every period (`strobe`), the final state, the events (time, entering or
impact), the number of right-hand-side evaluations, and how it ended ("completed", or what
stopped it).
"""

import numpy as np
from scipy.integrate import solve_ivp

# Runs stop rather than loop for ever: the most events a run may take, per forcing period.
MAX_EVENTS_PER_PERIOD = 1000


def _options(model, region, method, rtol, atol):
    # "DOP853/100": DOP853 with its step capped at T/100, so that an excursion beyond the
    # stop shorter than a step is less often stepped over
    method, _, parts = method.partition("/")
    opts = {"method": method, "rtol": rtol, "atol": atol}
    if parts:
        opts["max_step"] = model.period / float(parts)
    if method in ("Radau", "BDF", "LSODA"):
        opts["jac"] = model.jac(region)
    return opts


def _strobes(model, periods, t):
    """The period ends kT after t."""
    k = np.arange(1, periods + 1) * model.period
    return k[k > t]


def _result(x, t, events, nfev, strobe, outcome):
    return {"state": np.asarray(x).tolist(), "time": t, "events": events, "nfev": nfev,
            "strobe": strobe, "outcome": outcome}


def compliant(model, x0, periods, method, rtol, atol):
    """The compliant model from x0 at t = 0 over `periods` forcing periods."""
    x, t = np.array(x0, dtype=float), 0.0
    t_end = periods * model.period
    region = model.starting_region(x, t)
    events, nfev, strobe = [], 0, []
    cap = MAX_EVENTS_PER_PERIOD * max(1, periods)
    while t < t_end:
        def g(_t, y):
            return model.g(y)
        g.terminal = True
        # free flight ends when the tip rises through the stop, contact when it falls back
        g.direction = 1 if region == "free" else -1
        try:
            sol = solve_ivp(model.rhs(region), (t, t_end), x, events=g,
                            t_eval=_strobes(model, periods, t),
                            **_options(model, region, method, rtol, atol))
        except Exception as e:  # scipy's event location can throw: a recorded outcome
            return _result(x, t, events, nfev, strobe,
                           f"threw at t = {t:.6g}: {type(e).__name__}: {e}")
        nfev += int(sol.nfev)
        strobe += np.asarray(sol.y).T.tolist() if np.size(sol.y) else []
        if sol.status == -1:
            return _result(x, t, events, nfev, strobe, f"failed at t = {t:.6g}: {sol.message}")
        if sol.status == 1 and len(sol.t_events[0]) > 0:
            t, x = float(sol.t_events[0][0]), np.array(sol.y_events[0][0])
            events.append((t, region == "free"))
            region = "contact" if region == "free" else "free"
            if len(events) > cap:
                return _result(x, t, events, nfev, strobe,
                               f"stopped at t = {t:.6g}: more than {int(cap)} switches")
        else:
            t, x = t_end, sol.y[:, -1]
    return _result(x, t, events, nfev, strobe, "completed")


def rigid(model, law, x0, periods, method, rtol, atol):
    """The rigid-impact model (free flow, law η̇⁺ = −[R]η̇⁻) from x0 at t = 0 over `periods`
    forcing periods.

    No chatter policy: impacts are taken one at a time. A run whose impacts pile up (more
    than MAX_EVENTS_PER_PERIOD per period, or 50 in a row without time advancing by 1e-12 T)
    stops and says so."""
    n = model.n
    x, t = np.array(x0, dtype=float), 0.0
    t_end = periods * model.period
    events, nfev, strobe = [], 0, []
    cap = MAX_EVENTS_PER_PERIOD * max(1, periods)
    stalled, last = 0, t
    while t < t_end:
        def g(_t, y):
            return model.g(y)
        g.terminal = True
        g.direction = 1
        try:
            sol = solve_ivp(model.rhs("free"), (t, t_end), x, events=g,
                            t_eval=_strobes(model, periods, t),
                            **_options(model, "free", method, rtol, atol))
        except Exception as e:  # scipy's event location can throw: a recorded outcome
            return _result(x, t, events, nfev, strobe,
                           f"threw at t = {t:.6g}: {type(e).__name__}: {e}")
        nfev += int(sol.nfev)
        strobe += np.asarray(sol.y).T.tolist() if np.size(sol.y) else []
        if sol.status == -1:
            return _result(x, t, events, nfev, strobe, f"failed at t = {t:.6g}: {sol.message}")
        if sol.status == 1 and len(sol.t_events[0]) > 0:
            t, x = float(sol.t_events[0][0]), np.array(sol.y_events[0][0])
            v_in = model.tip_velocity(x)
            if v_in > 0:
                x[n:] = -law @ x[n:]
                events.append((t, True, v_in, model.tip_velocity(x)))
            stalled = stalled + 1 if t - last < 1e-12 * model.period else 0
            last = t
            if stalled >= 50:
                return _result(x, t, events, nfev, strobe,
                               f"stalled at t = {t:.6g}: 50 impacts without time advancing by 1e-12 T (impacts accumulate: chatter)")
            if len(events) > cap:
                return _result(x, t, events, nfev, strobe,
                               f"stopped at t = {t:.6g}: more than {int(cap)} impacts (impacts accumulate: chatter)")
        else:
            t, x = t_end, sol.y[:, -1]
    return _result(x, t, events, nfev, strobe, "completed")
