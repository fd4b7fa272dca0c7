"""The N-mode model in first-order form, built from the library's matrices
(examples/peer_problem.rs), as a peer would write it:

    x = [η; η̇],  ẋ = A^± x + [0; f cos ωt + F^±],  A^± = [[0, I], [−K^±, −C]],
    free flight while tipᵀη < d₀ (K⁻), contact while tipᵀη ≥ d₀ (K⁺, F⁺ = contact preload).

The rigid model uses the free flow only and a restitution law η̇⁺ = −[R] η̇⁻ at
tipᵀη = d₀ with tipᵀη̇ > 0.
"""

import numpy as np


class Model:
    def __init__(self, m):
        self.doc = m
        self.n = int(m["modes"])
        self.k_minus = np.array(m["K_minus"], dtype=float)
        self.k_plus = np.array(m["K_plus"], dtype=float)
        self.c = np.array(m["damping"], dtype=float)
        self.f = np.array(m["forcing_amplitude"], dtype=float)
        self.omega = float(m["omega"])
        self.period = float(m["period"])
        self.tip = np.array(m["tip"], dtype=float)
        self.gap = float(m["gap"])
        self.preload = np.array(m["contact_preload"], dtype=float)
        self.law_ir = np.array(m["law_impulse_response"], dtype=float)
        n = self.n
        self.a = {}
        for region, k in (("free", self.k_minus), ("contact", self.k_plus)):
            a = np.zeros((2 * n, 2 * n))
            a[:n, n:] = np.eye(n)
            a[n:, :n] = -k
            a[n:, n:] = -np.diag(self.c)
            self.a[region] = a
        self.constant = {"free": np.zeros(n), "contact": self.preload}

    def rhs(self, region):
        a, n, f, w, b = self.a[region], self.n, self.f, self.omega, self.constant[region]

        def fun(t, x):
            dx = a @ x
            dx[n:] += f * np.cos(w * t) + b
            return dx

        return fun

    def jac(self, region):
        a = self.a[region]
        return lambda t, x: a

    def g(self, x):
        """The switching function tipᵀη − d₀ (< 0 free, ≥ 0 contact)."""
        return float(self.tip @ x[: self.n]) - self.gap

    def tip_velocity(self, x):
        return float(self.tip @ x[self.n:])

    def starting_region(self, x, t):
        """The library's rule: contact if d > d₀; on the surface, if the tip moves into the
        stop or, at rest, if its free acceleration does."""
        n = self.n
        d, v = self.g(x), self.tip_velocity(x)
        acc = self.tip @ (self.f * np.cos(self.omega * t) - self.k_minus @ x[:n] - self.c * x[n:])
        inward = d > 0 or (d == 0 and (v > 0 or (v == 0 and acc > 0)))
        return "contact" if inward else "free"
