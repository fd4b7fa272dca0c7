"""Independent high-precision references (mpmath), written without the library's code:

- `oscillator`: the 1-DOF impact oscillator η̈ + cη̇ + kη = f cos ωt, stop at gη = d₀,
  Newton's law η̇⁺ = −rη̇⁻, in closed form (free flight is a damped cosine plus the
  harmonic response); impacts located by bracketing and Illinois iteration at 40 digits; a
  chatter is followed impact by impact until the incoming velocity is below 1e-12 (a bounce
  then lasts 2v/a ≈ 1e-12 and rises v²/2a ≈ 1e-24, resolved at 40 digits), its remaining
  bounces summed as a geometric series (exact to O(τ²) ≈ 1e-24 in time), then the mass rests
  on the stop until the closed-form release time arccos(k d₀/(g f))/ω.
- `piecewise`: the N-mode model (compliant or rigid with a law) by the eigendecomposition
  of A^± at 40 digits: x(t) = V e^{Λτ} V⁻¹ (x₀ − x_p(t₀)) + x_p(t); crossings bracketed on a
  grid (double precision, with every near-tangency of the grid refined at 40 digits) and
  located at 40 digits.

The model's numbers (k_j, C, f, ω, the law) are the library's doubles, taken as exact.
"""

import mpmath as mp
import numpy as np

DPS = 40


def _illinois(fun, a, b, fa, fb, tol):
    """A root of fun in [a, b] (fa, fb of opposite signs or one zero), Illinois method."""
    side = 0
    for _ in range(400):
        if fa == 0:
            return a
        if fb == 0:
            return b
        c = (a * fb - b * fa) / (fb - fa)
        fc = fun(c)
        if (fc > 0) == (fb > 0):
            b, fb = c, fc
            if side == -1:
                fa /= 2
            side = -1
        else:
            a, fa = c, fc
            if side == 1:
                fb /= 2
            side = 1
        if abs(b - a) < tol * (1 + abs(a)):
            return c
    raise RuntimeError("Illinois iteration did not converge")


# ------------------------------------------------------------------ 1-DOF, closed form

class Oscillator:
    """The 1-DOF impact oscillator in closed form."""

    def __init__(self, k, c, f, omega, tip, gap, r):
        mp.mp.dps = DPS
        self.k, self.c, self.f, self.w = (mp.mpf(k), mp.mpf(c), mp.mpf(f), mp.mpf(omega))
        self.g, self.d0, self.r = mp.mpf(tip), mp.mpf(gap), mp.mpf(r)
        den = (self.k - self.w ** 2) ** 2 + (self.c * self.w) ** 2
        self.P = self.f * (self.k - self.w ** 2) / den
        self.Q = self.f * self.c * self.w / den
        self.wd = mp.sqrt(self.k - self.c ** 2 / 4)
        self.T = 2 * mp.pi / self.w
        self.xs = self.d0 / self.g  # the displacement at the stop

    def xp(self, t):
        return self.P * mp.cos(self.w * t) + self.Q * mp.sin(self.w * t)

    def vp(self, t):
        return self.w * (-self.P * mp.sin(self.w * t) + self.Q * mp.cos(self.w * t))

    def flight(self, t0, x0, v0):
        """The free flight from (t0, x0, v0): t ↦ (x, v)."""
        a = x0 - self.xp(t0)
        b = (v0 - self.vp(t0) + self.c / 2 * a) / self.wd

        def at(t):
            tau = t - t0
            e = mp.exp(-self.c * tau / 2)
            co, si = mp.cos(self.wd * tau), mp.sin(self.wd * tau)
            h = a * co + b * si
            return (self.xp(t) + e * h,
                    self.vp(t) + e * (-self.c / 2 * h + self.wd * (-a * si + b * co)))

        return at

    def acceleration_at_stop(self, t):
        return self.f * mp.cos(self.w * t) - self.k * self.xs

    def release(self, t):
        """The first time ≥ t at which the stop stops pushing (f cos ωt = k x_s, falling)."""
        ratio = self.k * self.xs / self.f
        if ratio >= 1:
            return None  # pulls away at once
        phase = mp.acos(ratio)  # cos ωt = ratio with sin ωt > 0: cos falling
        m = mp.ceil((self.w * t - phase) / (2 * mp.pi))
        return (phase + 2 * mp.pi * m) / self.w

    def next_impact(self, t0, x0, v0, t_end):
        """The first time in (t0, t_end] with gx = d₀ and ẋ > 0, or None."""
        at = self.flight(t0, x0, v0)
        s = lambda t: self.g * at(t)[0] - self.d0
        h_max = min(self.T, 2 * mp.pi / self.wd) / 64
        # a first step inside the next flight: half the ballistic return time 2|v|/a
        acc = self.f * mp.cos(self.w * t0) - self.k * x0 - self.c * v0
        h = h_max
        if v0 < 0 and acc > 0:
            h = min(h_max, abs(v0) / acc)
        t_prev, s_prev, v_prev = t0, s(t0), v0
        if s_prev > 0:
            s_prev = mp.mpf(0)
        while t_prev < t_end:
            t = min(t_prev + h, t_end)
            x, v = at(t)
            st = self.g * x - self.d0
            if st >= 0 and s_prev <= 0 and t > t0:
                lo = t_prev
                if s_prev == 0:  # the left end is the last impact: step inside
                    lo = t_prev + (t - t_prev) / 2 ** 20
                    while s(lo) >= 0:
                        lo = t_prev + (lo - t_prev) / 2 ** 20
                return _illinois(s, lo, t, s(lo), st, mp.mpf(10) ** (-DPS + 5))
            if v_prev > 0 and v < 0:  # a maximum below the stop: a tangency in between?
                vel = lambda tt: at(tt)[1]
                tm = _illinois(vel, t_prev, t, v_prev, v, mp.mpf(10) ** (-DPS + 5))
                sm = s(tm)
                if sm >= 0:
                    return _illinois(s, t_prev, tm, s_prev, sm, mp.mpf(10) ** (-DPS + 5))
            t_prev, s_prev, v_prev = t, st, v
            h = min(2 * h, h_max)
        return None

    def run(self, periods, x0=0, v0=0, v_stick=mp.mpf("1e-12")):
        """From (0, x0, v0) over `periods` forcing periods: the impacts (t, incoming
        velocity), the sticking intervals, the state at the end of every period and the
        final (x, v)."""
        t_end = self.T * periods
        t, x, v = mp.mpf(0), mp.mpf(x0), mp.mpf(v0)
        impacts, sticks, strobe = [], [], []
        k = 1  # the next strobe, at kT

        def flight_strobes(t0, x0, v0, t1):
            nonlocal k
            at = self.flight(t0, x0, v0)
            while k <= periods and k * self.T <= t1:
                strobe.append(at(k * self.T))
                k += 1

        def stuck_strobes(t1):
            nonlocal k
            while k <= periods and k * self.T <= t1:
                strobe.append((self.xs, mp.mpf(0)))
                k += 1

        if x == self.xs and v == 0 and self.acceleration_at_stop(t) > 0:
            tr = self.release(t)  # starts resting on a stop that pushes
            sticks.append((t, tr))
            stuck_strobes(min(tr, t_end))
            t = tr
        while t < t_end:
            ti = self.next_impact(t, x, v, t_end)
            if ti is None:
                flight_strobes(t, x, v, t_end)
                x, v = strobe[-1]
                break
            flight_strobes(t, x, v, ti)
            _, vin = self.flight(t, x, v)(ti)
            impacts.append((ti, vin))
            t, x, v = ti, self.xs, -self.r * vin
            if vin < v_stick and self.acceleration_at_stop(t) > 0:
                # the chatter's limit: the remaining bounces last 2|v|/a/(1 − r) in all
                t += 2 * abs(v) / self.acceleration_at_stop(t) / (1 - self.r)
                tr = self.release(t)
                sticks.append((t, tr))
                stuck_strobes(t_end if tr is None else min(tr, t_end))
                if tr is None or tr >= t_end:
                    x, v = self.xs, mp.mpf(0)
                    break
                t, x, v = tr, self.xs, mp.mpf(0)
        return {"impacts": impacts, "sticks": sticks, "strobe": strobe, "state": (x, v)}


# ------------------------------------------------------------------ N modes, eigenvectors

class Region:
    """The exact flow ẋ = Ax + [0; f cos ωt + b] at 40 digits."""

    def __init__(self, a, f, b, omega):
        mp.mp.dps = DPS
        m = a.shape[0]
        n = m // 2
        self.n = n
        self.A = mp.matrix([[mp.mpf(float(v)) for v in row] for row in a])
        self.lam, self.V = mp.eig(self.A)
        self.Vinv = mp.inverse(self.V)
        residual = mp.mnorm(self.A * self.V - self.V * mp.diag(self.lam), 1)
        assert residual < mp.mpf(10) ** (-DPS + 10) * mp.mnorm(self.A, 1), residual
        self.w = mp.mpf(omega)
        force = mp.matrix(m, 1)
        const = mp.matrix(m, 1)
        for j in range(n):
            force[n + j] = mp.mpf(float(f[j]))
            const[n + j] = mp.mpf(float(b[j]))
        # x_p(t) = Re(X e^{iωt}) + x_c
        self.X = mp.lu_solve(mp.mpc(0, 1) * self.w * mp.eye(m) - self.A, force)
        self.xc = -mp.lu_solve(self.A, const) if any(const[i] != 0 for i in range(m)) else mp.matrix(m, 1)
        self.lam_np = np.array([complex(l) for l in self.lam])
        self.V_np = np.array([[complex(self.V[i, j]) for j in range(m)] for i in range(m)])

    def particular(self, t):
        e = mp.expjpi(self.w * t / mp.pi)
        return mp.matrix([mp.re(self.X[i] * e) + self.xc[i] for i in range(self.X.rows)])

    def segment(self, t0, x0):
        """t ↦ x(t) from (t0, x0), with its modal coefficients."""
        alpha = self.Vinv * (x0 - self.particular(t0))
        return alpha


class Piecewise:
    """The N-mode model at 40 digits: compliant (two regions) or rigid (free flow + law)."""

    def __init__(self, model, law=None):
        mp.mp.dps = DPS
        self.model = model
        self.law = None if law is None else mp.matrix([[mp.mpf(float(v)) for v in row] for row in law])
        self.tip = [mp.mpf(float(v)) for v in model.tip]
        self.d0 = mp.mpf(model.gap)
        self.regions = {"free": Region(model.a["free"], model.f, model.constant["free"], model.omega)}
        if law is None:
            self.regions["contact"] = Region(model.a["contact"], model.f, model.constant["contact"], model.omega)
        self.T = mp.mpf(model.period)

    def _state(self, reg, t0, alpha, t):
        tau = t - t0
        e = mp.matrix([alpha[i] * mp.exp(reg.lam[i] * tau) for i in range(len(reg.lam))])
        h = reg.V * e
        p = reg.particular(t)
        return mp.matrix([mp.re(h[i]) + p[i] for i in range(h.rows)])

    def _s(self, reg, t0, alpha, t):
        x = self._state(reg, t0, alpha, t)
        return sum(self.tip[j] * x[j] for j in range(reg.n)) - self.d0

    def _s_dot(self, reg, t0, alpha, t):
        x = self._state(reg, t0, alpha, t)
        return sum(self.tip[j] * x[reg.n + j] for j in range(reg.n))

    def _grid_s(self, reg, t0, alpha, taus):
        """s on a grid of τ in double precision (bracketing only)."""
        n = reg.n
        tip = np.array([float(v) for v in self.tip])
        u = tip @ reg.V_np[:n, :] * np.array([complex(a) for a in alpha])
        hom = (np.exp(np.outer(taus, reg.lam_np)) @ u).real
        t = float(t0) + taus
        xp = np.array([complex(reg.X[j]) for j in range(n)])
        xc = np.array([float(reg.xc[j]) for j in range(n)])
        part = (np.exp(1j * float(reg.w) * t) * (tip @ xp)).real + tip @ xc
        return hom + part - float(self.d0)

    def _crossing(self, reg, t0, alpha, t_end, direction):
        """The first τ in (0, t_end − t0] where s crosses zero in `direction` (+1 rising,
        −1 falling), refined at 40 digits; None if none."""
        fast = max(abs(l.imag) for l in reg.lam_np)
        h = min(float(self.T) / 64, 2 * np.pi / max(fast, 1e-300) / 12)
        span = float(t_end - t0)
        start = np.geomspace(1e-12 * float(self.T), min(h, span), 40)
        taus = np.concatenate([start, np.arange(h, span, h)[1:], [span]])
        taus = np.unique(taus[taus <= span])
        s = direction * self._grid_s(reg, t0, alpha, taus)
        tol = mp.mpf(10) ** (-DPS + 5)
        s_fun = lambda t: direction * self._s(reg, t0, alpha, t)
        sd_fun = lambda t: direction * self._s_dot(reg, t0, alpha, t)
        for i in range(len(taus)):
            if s[i] >= 0:
                a = t0 + (mp.mpf(taus[i - 1]) if i > 0 else mp.mpf(0))
                b = t0 + mp.mpf(taus[i])
                fa = s_fun(a) if i > 0 else mp.mpf(-1)
                fb = s_fun(b)
                if i == 0:  # inside the first grid step: find a point on the old side
                    a = t0 + mp.mpf(taus[0]) / 2 ** 30
                    fa = s_fun(a)
                if fa < 0 <= fb:
                    return _illinois(s_fun, a, b, fa, fb, tol)
            # a local maximum of s below zero: is there a tangency or a double crossing?
            if 0 < i < len(taus) - 1 and s[i - 1] < s[i] > s[i + 1] and s[i] < 0 \
                    and s[i] > -1e-3 * max(1.0, float(abs(s).max())):
                a, b = t0 + mp.mpf(taus[i - 1]), t0 + mp.mpf(taus[i + 1])
                da, db = sd_fun(a), sd_fun(b)
                if da > 0 > db:
                    tm = _illinois(sd_fun, a, b, da, db, tol)
                    sm = s_fun(tm)
                    if sm >= 0:
                        return _illinois(s_fun, a, tm, s_fun(a), sm, tol)
        return None

    def run(self, x0, periods, region=None, v_stick=mp.mpf("1e-12")):
        """From x0 at t = 0 over `periods` forcing periods: the events (t, entering) or
        (t, impact, incoming tip velocity), the state at the end of every period and the
        final state."""
        t = mp.mpf(0)
        t_end = self.T * periods
        x = mp.matrix([mp.mpf(v) for v in x0])
        region = region or ("free" if self.law is not None else self.model.starting_region(np.array([float(v) for v in x0]), 0.0))
        events, strobe = [], []
        k = 1
        n = self.model.n
        while True:
            reg = self.regions[region]
            alpha = reg.segment(t, x)
            direction = 1 if region == "free" else -1
            tc = self._crossing(reg, t, alpha, t_end, direction)
            t1 = t_end if tc is None else tc
            while k <= periods and k * self.T <= t1:
                xs = self._state(reg, t, alpha, k * self.T)
                strobe.append([xs[i] for i in range(xs.rows)])
                k += 1
            if tc is None:
                return {"events": events, "strobe": strobe, "state": strobe[-1]}
            x = self._state(reg, t, alpha, tc)
            t = tc
            if self.law is None:
                events.append((t, region == "free"))
                region = "contact" if region == "free" else "free"
            else:
                v = mp.matrix([x[n + j] for j in range(n)])
                vin = sum(self.tip[j] * v[j] for j in range(n))
                if vin < v_stick:
                    raise RuntimeError("chatter in the N-mode reference: not supported")
                vout = -(self.law * v)
                for j in range(n):
                    x[n + j] = vout[j]
                events.append((t, True, vin))
