"""The paper's parameter sets as named problems (the library's ``model::problems``): the same
models the book's scenes and the ``cantilever`` command line use.

Each returns a compliant :class:`~impacting_cantilever.Model` (``rigid(problem, law=…)``
puts the same beam against a rigid stop). Units as in :mod:`impacting_cantilever._models`.
"""

from __future__ import annotations

from . import _core
from ._models import Model

__all__ = ["figure4", "figure6a", "figure6b", "figure9", "out_of_reach"]


def figure4(modes: int) -> Model:
    """Figure 4 and §5.3: k = 100k₁, ζ₁ = 0.01, d₀ = 0, ω = 2(β₁⁻)², α = 0 (the paper's
    N = 1, 2, 3, 10). Figure 5 sweeps its k."""
    return _core.problem("figure4", modes)


def figure6a(modes: int) -> Model:
    """Figure 6(a), §5.4: k = 1000k₁, d₀ = 0.8, ω = 1.15(β₁⁻)², ζ₁ = 0.1 (a (1,1) orbit near
    grazing; N = 20 in the paper)."""
    return _core.problem("figure6a", modes)


def figure6b(modes: int) -> Model:
    """Figure 6(b), §5.4: k = 1000k₁, d₀ = 0, ω = 2(β₁⁻)², ζ₁ = 0.01 (multiple taps; N = 20
    in the paper)."""
    return _core.problem("figure6b", modes)


def figure9(modes: int, gap: float) -> Model:
    """Figure 9, §6 (the experiment's parameters): ζ₁ = 7.7e-4, ω = 1.7(β₁⁻)², k = 1000k₁;
    the paper does not state the gap d₀ (units of the free tip amplitude at resonance)."""
    return _core.problem("figure9", modes, gap=gap)


def out_of_reach(modes: int, zeta1: float, omega: float) -> Model:
    """The linear model with the stop out of reach (d₀ = 10⁶, k = 100k₁), material damping
    ζ₁, the eq (37) forcing at ω in units of (β₁⁻)²: the flow never switches."""
    return _core.problem("out_of_reach", modes, zeta1=zeta1, omega=omega)
