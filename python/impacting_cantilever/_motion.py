"""What a motion is — chaotic, quasi-periodic, periodic or undecided — from its two largest
Lyapunov exponents (exact monodromy, saltation at the impacts, QR over segments with a 95 %
interval), a period search and its rotation number: ``cantilever motion``, to the bit."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal, Optional

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from ._models import Model
from ._progress import Progress, callback
from ._results import _Result


@dataclass(frozen=True, repr=False, eq=False)
class Motion(_Result):
    """A classified motion and its evidence (the atlas's rule for its non-periodic cells)."""

    #: "periodic", "chaotic", "quasi-periodic" or "undecided".
    kind: Literal["periodic", "chaotic", "quasi-periodic", "undecided"]
    #: λ₁, λ₂, the two largest Lyapunov exponents, per unit time.
    exponents: NDArray[np.float64]
    #: Their 95 % half-widths over the independent segments, per unit time.
    half_widths: NDArray[np.float64]
    #: The period m found among the iterates (P^m(x) = x to 1e-8), else None.
    period_m: Optional[int]
    #: ρ, the rotation number of the iterates, turns per forcing period in [0, 1/2].
    rotation_number: float
    #: How much ρ of the record's two halves differ.
    rotation_halves_differ: float
    #: The options used: transient, segments, periods (per segment), iterates,
    #: longest_period and resolution ε (per unit time; λ₁ is zero within ±ε).
    options: dict[str, Any]
    #: Where the run started.
    start: str
    document: dict[str, Any] = field(compare=False)

    def __repr__(self) -> str:
        (l1, l2), (h1, h2) = self.exponents, self.half_widths
        return (
            f"Motion({self.kind}: λ₁ = {l1:.4e} ± {h1:.1e}, λ₂ = {l2:.4e} ± {h2:.1e}, "
            f"ρ = {self.rotation_number:.4f})"
        )


def motion(
    model: Model,
    start: Optional[ArrayLike] = None,
    *,
    seed: Optional[int] = None,
    transient: int = 300,
    segments: Optional[int] = None,
    segment_periods: Optional[int] = None,
    iterates: Optional[int] = None,
    longest_period: Optional[int] = None,
    resolution: Optional[float] = None,
    progress: Progress = None,
) -> Motion:
    """What the motion of ``model`` from ``start`` (rest by default) is after ``transient``
    forcing periods, by the book's rule — ``cantilever motion``, to the bit. Options left
    None are the book's (the atlas's): 20 segments of 50 periods, 256 iterates, periods up
    to 64, and ε a quarter of mode 1's free decay rate.

    Args:
        transient: forcing periods run first (at most 1e8).
        segments: segments of the Lyapunov record (2 to 30); segment_periods: periods per
            segment; iterates: iterates for the period and the rotation number (4 to 1e6, at
            least twice longest_period); resolution: ε per unit time.

    Raises:
        ParameterError: options out of range. UnsupportedError: a model without the
            Jacobian the exponents need. ChatterError: a rigid run that chatters.
    """
    from ._api import _state

    d = _core.motion(
        model,
        _state(start),
        seed,
        transient,
        segments,
        segment_periods,
        iterates,
        longest_period,
        resolution,
        callback(progress),
    )
    return Motion(
        kind=d["class"],
        exponents=np.array(d["exponents"], dtype=np.float64),
        half_widths=np.array(d["half_widths"], dtype=np.float64),
        period_m=d["period_m"],
        rotation_number=d["rotation"]["turns"],
        rotation_halves_differ=d["rotation"]["halves_differ"],
        options=d["options"],
        start=d["start"],
        document=d,
    )
