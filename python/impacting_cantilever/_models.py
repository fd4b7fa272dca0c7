"""Models: the compliant N-mode cantilever, the rigid-impact model with a law, the one-mode
impact oscillator.

Units throughout (as on the ``cantilever`` command line and in the paper's §5): time of the
non-dimensional beam (EI = ρA = L = 1); the stop stiffness k in units of k₁ = (β₁⁻)⁴ ≈ 12.36;
the forcing frequency ω in units of (β₁⁻)² ≈ 3.516; lengths (d₀, tip displacement) in units
of the free tip amplitude at resonance (1 with the corrected eq (37) forcing), velocities in
those lengths per unit time. The oscillator takes its own units.
"""

from __future__ import annotations

from typing import Any, Literal, Union

from . import _core
from .errors import ParameterError

#: A model built by :func:`compliant`, :func:`rigid`, :func:`oscillator` or ``problems``.
Model = _core.Model

Law = Literal["stiffness-limit", "impulse-response", "collocation", "newton"]
Forcing = Union[Literal["unit", "printed"], float]


def compliant(
    modes: int,
    *,
    zeta1: float,
    omega: float,
    stop_stiffness: float = _core.DEFAULT_STOP_STIFFNESS,
    gap: float = 0.0,
    gap_unit: Literal["resonance", "free"] = "resonance",
    damping_reading: Literal["fig9", "fig4-literal"] = "fig9",
    viscous: float = 0.0,
    forcing: Forcing = "unit",
) -> Model:
    """The compliant (bilinear) N-mode model, eq (34), under the eq (37) forcing f(s) cos ωt.

    Args:
        modes: N, the number of free cantilever modes (1 to 400).
        zeta1: ζ₁, the first mode's damping ratio (material damping; 1e-8 to 1e3).
        omega: the forcing frequency ω in units of (β₁⁻)² (1e-3 to 1e4).
        stop_stiffness: k in units of k₁ = (β₁⁻)⁴ (0 to 1e12); the stop itself has k/4 (eq 1).
        gap: d₀, the gap between the tip at rest and the stop (|d₀| ≤ 1e6; negative: preloaded).
        gap_unit: ``"resonance"``: d₀ in units of the free tip amplitude at resonance (the
            paper's); ``"free"``: in units of A_free(ω), the free tip amplitude at the
            forcing frequency, so that ``gap=0.5`` is half the motion actually forced.
        damping_reading: how ζ₁ sets the material damping γ: ``"fig9"``, γ = 2ζ₁/(β₁⁻)², so
            mode 1's damping ratio is ζ₁; ``"fig4-literal"``, γ = 2ζ₁(β₁⁻)² (the Figure 4
            caption read literally; see the book's errata).
        viscous: α, mass-proportional viscous damping entering as 2α (eq 1), ≥ 0.
        forcing: ``"unit"`` (eq 37 corrected: free tip amplitude 1 at resonance),
            ``"printed"`` (eq 37 as printed, 1/(4ζ₁²) larger), or a number f₁ (the profile
            φ₁(s): modal force f₁ cos ωt on mode 1 alone).

    Raises:
        ParameterError: a parameter out of range, with the library's one-line message
            (also a ``ValueError``).
    """
    return _core.compliant(
        modes, stop_stiffness, gap, zeta1, omega, gap_unit, damping_reading, viscous, forcing
    )


def rigid(
    base: Model,
    *,
    law: Law = "stiffness-limit",
    restitution: float = _core.DEFAULT_RESTITUTION,
) -> Model:
    """The same beam against a rigid stop: the rigid-impact model of §3 with a modal
    restitution law [R], η̇⁺ = −[R]η̇⁻ at each impact (eq 11).

    Args:
        base: the beam (a :func:`compliant` model, a named problem or an oscillator); its
            stop stiffness is not part of the rigid model (``parameters()`` omits it).
        law: ``"stiffness-limit"`` ([R]_N, eq 29, with r_e = ``restitution``),
            ``"impulse-response"`` ([R]_IR, eq 14), ``"collocation"`` ([R]_C, eq 12, equally
            spaced points) or ``"newton"`` (η̇⁺ = −rη̇⁻, N = 1 only).
        restitution: the coefficient r (r_e for the stiffness limit), in [0, 1].
    """
    return _core.rigid(base, law, restitution)


def oscillator(
    *,
    stiffness: float,
    damping: float,
    forcing: float,
    omega: float,
    tip_gain: float = 1.0,
    gap: float = 0.0,
    stop_stiffness: float = 0.0,
    restitution: float | None = None,
) -> Model:
    """The one-degree-of-freedom impact oscillator ẍ + cẋ + kx = F cos ωt with the stop at
    gx = d₀, in its own units (not the beam's).

    Args:
        stiffness: k > 0. damping: c ≥ 0. forcing: F. omega: ω > 0. tip_gain: g > 0.
        gap: d₀. stop_stiffness: k_s ≥ 0 of the compliant contact, which adds
            (k_s/4)g²(x − d₀/g) beyond the stop (0 for the rigid model alone).
        restitution: if given, the rigid-impact oscillator with Newton's law η̇⁺ = −rη̇⁻.
    """
    model = _core.oscillator(stiffness, damping, forcing, omega, tip_gain, gap, stop_stiffness)
    if restitution is None:
        return model
    return _core.rigid(model, "newton", restitution)


def _from_parameters(p: dict[str, Any]) -> Model:
    """The model of ``Model.parameters()`` (how a model is pickled)."""
    p = dict(p)
    kind = p.pop("model")
    law = p.pop("law", None)
    restitution = p.pop("restitution", None)
    if kind == "oscillator":
        base = oscillator(**p)
    else:
        base = compliant(p.pop("modes"), **p)
    return base if law is None else _core.rigid(base, law, restitution)


def replace(model: Model, **changes: Any) -> Model:
    """The same model with some parameters changed, e.g. ``replace(m, omega=2.5)`` (or
    ``law=``, ``restitution=`` for the rigid model)."""
    p = dict(model.parameters())
    allowed = set(p) - {"model"} | {"law", "restitution"}
    unknown = set(changes) - allowed
    if unknown:
        raise ParameterError(
            f"invalid parameter {sorted(unknown)[0]}: got a value; "
            f"allowed: one of {', '.join(sorted(allowed))}"
        )
    p.update(changes)
    return _from_parameters(p)
