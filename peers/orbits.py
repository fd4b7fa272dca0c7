"""A periodic orbit and its Floquet multipliers the way a researcher would get them with an
ODE solver: Newton's method on P(x) − x = 0 for the stroboscopic map P over one forcing
period (scipy_peers.compliant), with the monodromy ∂P/∂x by central differences (2·2N extra
periods per Newton step); the multipliers are the eigenvalues of that monodromy at the
converged state.
"""

import numpy as np

from scipy_peers import compliant


def period_map(model, method, rtol, atol):
    def p(x, counter):
        counter[0] += 1
        r = compliant(model, x, 1, method, rtol, atol)
        if r["outcome"] != "completed":
            raise RuntimeError(r["outcome"])
        return np.array(r["state"]), len(r["events"])
    return p


def shoot(model, x0, method, rtol, atol, tol=1e-10, max_iter=12):
    """Newton with a finite-difference monodromy from x0. Returns the orbit's state, its
    multipliers (largest modulus first), the relative residual, the Newton steps taken,
    the periods integrated and how it ended."""
    p = period_map(model, method, rtol, atol)
    counter = [0]
    x = np.array(x0, dtype=float)
    # central differences: the step balancing truncation (h²) against the map's own
    # error (rtol/h), relative to each component's scale
    scale = np.maximum(np.abs(x), 1e-3 * np.abs(x).max())
    h = np.cbrt(max(rtol, 1e-16)) * scale
    steps = 0
    outcome = "converged"
    while True:
        px, switches = p(x, counter)
        residual = np.abs(px - x).max() / np.abs(x).max()
        jac = np.empty((x.size, x.size))
        for j in range(x.size):
            e = np.zeros_like(x)
            e[j] = h[j]
            jac[:, j] = (p(x + e, counter)[0] - p(x - e, counter)[0]) / (2 * h[j])
        if residual < tol:
            break
        if steps >= max_iter:
            outcome = f"not converged after {steps} Newton steps (residual {residual:.1e})"
            break
        x = x - np.linalg.solve(jac - np.eye(x.size), px - x)
        steps += 1
    mu = np.linalg.eigvals(jac)
    mu = mu[np.argsort(-np.abs(mu), kind="stable")]
    return {
        "state": x.tolist(),
        "multipliers": [[float(z.real), float(z.imag)] for z in mu],
        "residual": float(residual),
        "newton_steps": steps,
        "periods_integrated": counter[0],
        "switches_per_period": switches,
        "outcome": outcome,
    }


def multiplier_error(mu, ref):
    """The largest distance from a multiplier of `ref` to its match in `mu`, matched
    greedily in order of decreasing modulus of ref."""
    left = [complex(a, b) for a, b in mu]
    worst = 0.0
    for a, b in ref:
        z = complex(a, b)
        i = min(range(len(left)), key=lambda k: abs(left[k] - z))
        worst = max(worst, abs(left[i] - z))
        left.pop(i)
    return worst
