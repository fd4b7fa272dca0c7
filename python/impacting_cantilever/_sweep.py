"""A failure returned instead of raised, and a sweep of periodic orbits over one parameter's
values — arrays with a status per value, so that a sweep through a region without a period
is one call that skips what fails and stops on a mistake."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, ClassVar, Optional

import numpy as np
from numpy.typing import NDArray

from . import errors
from ._results import Orbit, _Result
from ._tables import Table


@dataclass(frozen=True, repr=False, eq=False)
class Failure(_Result):
    """A computation that failed, returned instead of raised when asked for with
    ``raise_on_failure=False`` (as scipy's ``OptimizeResult`` has ``success`` False): no
    orbit, chatter, a broken invariant or a flow that could not be built. Bad input,
    unsupported models and interruptions raise all the same."""

    #: False.
    success: ClassVar[bool] = False  # type: ignore[misc]
    #: The exception class it would have raised, e.g. ``"NoPeriodError"``.
    status: str
    #: The library's one-line message (what the command line prints after ``error:``).
    message: str
    #: Where Newton stopped, for ``"NotConvergedError"`` (None if not measured).
    residual: Optional[float] = None

    def error(self) -> errors.CantileverError:
        """The exception it stands for (``raise failure.error()`` raises it)."""
        e = getattr(errors, self.status)(self.message)
        if self.residual is not None:
            e.residual = self.residual
        return e

    def __repr__(self) -> str:
        return f"Failure({self.status}: {self.message})"


def _failure(e: errors.CantileverError) -> Failure:
    return Failure(type(e).__name__, str(e), getattr(e, "residual", None))


@dataclass(frozen=True, repr=False, eq=False)
class Sweep(_Result, Table):
    """The periodic orbits of a model at each value of one parameter, from the same start
    (:func:`~impacting_cantilever.sweep`). Arrays have one entry per value; where a value
    failed, its numbers are NaN (0 for the integer counts) and ``status`` says why."""

    #: The parameter swept (a keyword of :func:`~impacting_cantilever.compliant`, …).
    parameter: str
    #: Its values, in the order given.
    values: NDArray[np.float64]
    #: Whether an orbit was found at each value.
    found: NDArray[np.bool_]
    #: ``"ok"``, or the exception class of the failure (``"NoPeriodError"``, …).
    status: NDArray[np.str_]
    #: The failure's one-line message ("" where an orbit was found).
    message: NDArray[np.str_]
    #: m, the period in forcing periods (0 where none was found).
    period_m: NDArray[np.int64]
    #: n, entries into contact (impacts) per period (0 where none was found).
    impacts_n: NDArray[np.int64]
    #: All multipliers inside the unit circle (False where none was found).
    stable: NDArray[np.bool_]
    #: The largest multiplier modulus.
    spectral_radius: NDArray[np.float64]
    #: ‖P^m(x) − x‖∞/‖x‖∞ of each orbit.
    residual: NDArray[np.float64]
    #: r_E (eq 39), where asked for and defined.
    r_E: NDArray[np.float64]
    #: The orbit's state [η; η̇] at the start of a forcing period, shape (values, 2N).
    state: NDArray[np.float64]
    #: Each value's :class:`~impacting_cantilever.Orbit` or :class:`Failure`.
    orbits: list[Any] = field(compare=True)

    def __len__(self) -> int:
        return len(self.values)

    def __repr__(self) -> str:
        ok = int(np.count_nonzero(self.found))
        return f"Sweep({self.parameter}: {ok} of {len(self)} values with an orbit)"

    def _columns(self) -> dict[str, Any]:
        return {
            self.parameter: self.values,
            "found": self.found,
            "status": self.status,
            "message": self.message,
            "period_m": self.period_m,
            "impacts_n": self.impacts_n,
            "stable": self.stable,
            "spectral_radius": self.spectral_radius,
            "residual": self.residual,
            "r_E": self.r_E,
        }


def _sweep(parameter: str, values: NDArray[np.float64], entries: list[Any], modes: int) -> Sweep:
    """The sweep's arrays from each value's Orbit or Failure."""
    orbits = entries
    nan = float("nan")

    def of(attr: str, default: Any) -> list[Any]:
        return [getattr(o, attr) if isinstance(o, Orbit) else default for o in orbits]

    return Sweep(
        parameter=parameter,
        values=values,
        found=np.array([o.success for o in orbits], dtype=np.bool_),
        status=np.array(["ok" if o.success else o.status for o in orbits], dtype=np.str_),
        message=np.array(["" if o.success else o.message for o in orbits], dtype=np.str_),
        period_m=np.array(of("period_m", 0), dtype=np.int64),
        impacts_n=np.array(of("impacts_n", 0), dtype=np.int64),
        stable=np.array(of("stable", False), dtype=np.bool_),
        spectral_radius=np.array(of("spectral_radius", nan), dtype=np.float64),
        residual=np.array(of("residual", nan), dtype=np.float64),
        r_E=np.array(
            [nan if r is None else r for r in of("energetic_restitution", nan)],
            dtype=np.float64,
        ),
        state=np.array(
            [o.state if isinstance(o, Orbit) else np.full(2 * modes, nan) for o in orbits],
            dtype=np.float64,
        ).reshape(len(orbits), 2 * modes),
        orbits=orbits,
    )
