"""Results in the units of the book's key numbers: lengths in A_free(ω), the free tip
amplitude at the forcing frequency, and velocities in ωA_free — where the results of the
computations are in units of the free tip amplitude at resonance (the model's length unit).
"""

from __future__ import annotations

import dataclasses
from typing import Optional, TypeVar

import numpy as np
from numpy.typing import NDArray

from ._models import Model
from ._results import Dense, Events, Orbit, Simulation
from .errors import ParameterError

R = TypeVar("R", Simulation, Orbit, Events, Dense)


def in_free_units(result: R, model: Model) -> R:
    """The result (a :class:`Simulation`, :class:`Orbit`, :class:`Events` or :class:`Dense`
    of ``model``) with every length divided by A_free(ω) and every velocity by ωA_free
    (``model.free_tip_amplitude``): tip displacements, tip velocities, modal coordinates η
    and modal velocities η̇, the certified maximum tip and the flow's resolution. Times,
    counts and residuals are unchanged. The book's key numbers (e.g. Figure 4's impact
    velocities, in ωA_free) are in these units.

    Raises:
        ParameterError: a result of another model size, or not one of those four.
    """
    amplitude, velocity = model.free_tip_amplitude
    n = model.modes

    def state(x: NDArray[np.float64]) -> NDArray[np.float64]:
        if x.shape[-1] != 2 * n:
            raise ParameterError(
                f"invalid result: got states of {x.shape[-1]} numbers; allowed: a result of "
                f"this model (2N = {2 * n})"
            )
        return np.concatenate([x[..., :n] / amplitude, x[..., n:] / velocity], axis=-1)

    def v(x: Optional[NDArray[np.float64]]) -> Optional[NDArray[np.float64]]:
        return None if x is None else x / velocity

    def length(x: Optional[float]) -> Optional[float]:
        return None if x is None else x / amplitude

    if isinstance(result, Events):
        return dataclasses.replace(
            result,
            tip_velocity=result.tip_velocity / velocity,
            modal_velocities=result.modal_velocities / velocity,
            outgoing_tip_velocity=v(result.outgoing_tip_velocity),
            modal_velocities_after=v(result.modal_velocities_after),
        )
    if isinstance(result, Dense):
        return dataclasses.replace(
            result,
            tip=result.tip / amplitude,
            tip_velocity=result.tip_velocity / velocity,
            state=state(result.state),
        )
    if isinstance(result, Orbit):
        return dataclasses.replace(result, state=state(result.state))
    if isinstance(result, Simulation):
        return dataclasses.replace(
            result,
            events=in_free_units(result.events, model),
            dense=None if result.dense is None else in_free_units(result.dense, model),
            flight_resolution=result.flight_resolution / amplitude,
            max_tip=length(result.max_tip),
            max_tip_tolerance=length(result.max_tip_tolerance),
            final_state=state(result.final_state),
        )
    raise ParameterError(
        f"invalid result: got {type(result).__name__}; allowed: a Simulation, Orbit, Events "
        "or Dense"
    )
