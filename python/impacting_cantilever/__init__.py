"""The impacting cantilever from Python.

Reproduces J. T. Melcher, A. R. Champneys & D. J. Wagg, *The impacting cantilever: modal
non-convergence and the importance of stiffness matching*, Phil. Trans. R. Soc. A 371
(2013) 20120434, with the exact engine of the Rust library ``impacting-cantilever``: every
number here is computed by the same code as the ``cantilever`` command line, bit for bit.

>>> import impacting_cantilever as ic
>>> orbit = ic.find_orbit(ic.problems.figure4(10))        # the Fig 4 N = 10 orbit
>>> orbit.multipliers                                    # Floquet multipliers, complex
>>> sim = ic.simulate(ic.problems.figure4(3), periods=1000, record=32, dense_per_period=200)
>>> sim.events.time, sim.dense.tip                       # numpy arrays

Units (the paper's §5): time of the non-dimensional beam (EI = ρA = L = 1); stop stiffness k
in units of k₁ = (β₁⁻)⁴ ≈ 12.36; forcing frequency ω in units of (β₁⁻)² ≈ 3.516; lengths in
units of the free tip amplitude at resonance. Each kind of failure raises its own class
(:mod:`impacting_cantilever.errors`, the main ones also here): bad input a
``ParameterError`` (also a ``ValueError``) with the library's one-line message (the
parameter, what was given, what is allowed); no period a ``NoPeriodError``; Newton's
failure a ``NotConvergedError`` (both a ``NoOrbitError``); and so on. ``sweep`` finds the
orbits over a parameter's values in one call, a failure per value recorded, not raised.
"""

from __future__ import annotations

from . import _core, atlas, citation, errors, problems, scenes
from ._api import (
    continue_branch,
    continue_curve,
    energetic_restitution,
    find_orbit,
    modes_needed,
    simulate,
    sweep,
)
from ._progress import Progress
from ._sweep import Failure, Sweep
from ._units import in_free_units
from .errors import (
    CancelledError,
    CantileverError,
    ChatterError,
    NoOrbitError,
    NoPeriodError,
    NotConvergedError,
    ParameterError,
    UnsupportedError,
)
from ._core import __version__
from ._models import Model, compliant, oscillator, replace, rigid
from ._motion import Motion, motion
from ._results import (
    Bifurcation,
    Branch,
    CodimTwo,
    Continuation,
    Curve,
    Dense,
    EnergeticRestitution,
    Events,
    ModesNeeded,
    Orbit,
    Simulation,
    Study,
)

#: (β₁⁻)², the frequency unit, and k₁ = (β₁⁻)⁴, the stiffness unit.
FREQUENCY_UNIT, STIFFNESS_UNIT = _core.units()

__all__ = [
    "__version__",
    "FREQUENCY_UNIT",
    "STIFFNESS_UNIT",
    "Model",
    "compliant",
    "rigid",
    "oscillator",
    "replace",
    "in_free_units",
    "problems",
    "simulate",
    "find_orbit",
    "sweep",
    "continue_branch",
    "continue_curve",
    "energetic_restitution",
    "modes_needed",
    "motion",
    "Motion",
    "scenes",
    "atlas",
    "citation",
    "errors",
    "Progress",
    "Simulation",
    "Events",
    "Dense",
    "Orbit",
    "Branch",
    "Bifurcation",
    "Continuation",
    "Curve",
    "CodimTwo",
    "EnergeticRestitution",
    "ModesNeeded",
    "Study",
    "Sweep",
    "Failure",
    "CantileverError",
    "ParameterError",
    "NoOrbitError",
    "NoPeriodError",
    "NotConvergedError",
    "ChatterError",
    "UnsupportedError",
    "CancelledError",
]
