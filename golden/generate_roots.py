"""Independent reference roots of the paper's eq (3), computed with mpmath at 50 digits.

This script is the provenance of golden/roots.json. It shares no code with the Rust crate:
it solves eq (3) as printed, multiplied through by 4*beta^3 (no rescaling), with mpmath's
findroot started from the classical asymptotic guesses. Run: python3 golden/generate_roots.py
"""
import json
import mpmath as mp

mp.mp.dps = 50


def char_eq(k):
    # eq (3) times 4 beta^3 / cosh(beta): the division only keeps findroot's absolute
    # residual test meaningful for beta up to 630 (cosh ~ 1e273); 50 digits absorb it.
    return lambda b: (4 * b**3 * (mp.cos(b) * mp.cosh(b) + 1) + k * (
        mp.sin(b) * mp.cosh(b) - mp.cos(b) * mp.sinh(b))) / mp.cosh(b)


def free_root(i):
    f = lambda b: mp.cos(b) + 1 / mp.cosh(b)
    return mp.findroot(f, (2 * i - 1) * mp.pi / 2 + (-1) ** (i + 1) * 0.3 / i**2)


def pinned_root(i):
    f = lambda b: mp.tan(b) - mp.tanh(b)
    return mp.findroot(f, (4 * i + 1) * mp.pi / 4)


def bracketed(k, i):
    lo, hi = free_root(i), pinned_root(i)
    return mp.findroot(char_eq(k), (lo + mp.mpf("1e-30"), hi - mp.mpf("1e-30")), solver="illinois", tol=mp.mpf("1e-80"), maxsteps=400)


out = {
    "source": "mpmath %s, findroot at %d decimal digits (golden/generate_roots.py)" % (mp.__version__, mp.mp.dps),
    "free": {str(i): mp.nstr(free_root(i), 25) for i in [1, 2, 3, 4, 5, 10, 20, 50, 100, 200]},
    "clamped_pinned": {str(i): mp.nstr(pinned_root(i), 25) for i in [1, 2, 3, 4, 5, 10, 20, 50, 100, 200]},
}
k1 = free_root(1) ** 4
out["k1"] = mp.nstr(k1, 25)
out["finite_k"] = {}
for ratio in ["1e-6", "1", "100", "1000", "1e6", "1e12"]:
    k = mp.mpf(ratio) * k1
    out["finite_k"][ratio] = {str(i): mp.nstr(bracketed(k, i), 25) for i in [1, 2, 3, 10, 50, 100, 200]}
print(json.dumps(out, indent=2))
