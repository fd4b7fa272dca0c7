"""The exceptions of ``impacting_cantilever``, one class per kind of failure, so that a sweep
can tell them apart: ``except NoPeriodError`` skips a point that did not settle, while bad
input (``ParameterError``) still stops the sweep. Every message is the library's one line
(the text the ``cantilever`` command line prints after ``error:``), and every class derives
from :class:`CantileverError`. The command line's exit status follows the same kinds.

==============================  ===========  =================================================
class                           exit status  when
==============================  ===========  =================================================
``ParameterError``              2            a parameter out of its supported range, or an
                                             option that does not apply to the model (also a
                                             ``ValueError``)
``NoOrbitError``                3 or 4       no periodic orbit was found: the class of the
                                             two below
``NoPeriodError``               3            the motion settled on no period within the window
``NotConvergedError``           4            Newton or a corrector did not converge
                                             (``residual``: where it stopped, or None)
``ChatterError``                5            contacts or impacts accumulate where the model has
                                             no limit for them
``UnsupportedError``            6            legal input this model or method does not support
``CancelledError``              130          the work was asked to stop (Ctrl-C, a progress
                                             callback that raised)
``OutputError``                 1            a file could not be written (also an ``OSError``)
``InvariantError``              1            a run broke an invariant of the exact solution
``NumericalError``              1            a flow could not be built, or a plot drawn
==============================  ===========  =================================================

``find_orbit``, ``energetic_restitution`` and ``sweep`` return a
:class:`~impacting_cantilever.Failure` (``success`` False, the class's name and the message)
instead of raising, with ``raise_on_failure=False``, for the failures of the computation
itself (:data:`COMPUTATION_FAILURES`); bad input, unsupported models and interruptions still
raise.
"""

from __future__ import annotations

from typing import Optional


class CantileverError(Exception):
    """Any failure of the library."""


class ParameterError(CantileverError, ValueError):
    """A parameter out of its supported range, or an option that does not apply."""


class NoOrbitError(CantileverError):
    """No periodic orbit was found: the motion settled on no period
    (:class:`NoPeriodError`), or Newton's method did not converge on one
    (:class:`NotConvergedError`). What a sweep skips over."""


class NoPeriodError(NoOrbitError):
    """The motion settled on no period within the window searched."""


class NotConvergedError(NoOrbitError):
    """An iteration did not converge; ``residual`` is where it stopped (None if not
    measured)."""

    residual: Optional[float] = None


class ChatterError(CantileverError):
    """Contacts or impacts accumulate where the model has no limit for them."""


class UnsupportedError(CantileverError):
    """Legal input this model or method does not support."""


class CancelledError(CantileverError):
    """The work was asked to stop."""


class OutputError(CantileverError, OSError):
    """A file could not be written."""


class InvariantError(CantileverError):
    """A run broke an invariant of the exact solution."""


class NumericalError(CantileverError):
    """A region's flow could not be built, or a plot drawn."""


#: The failures of a computation itself, which ``raise_on_failure=False`` returns as a
#: :class:`~impacting_cantilever.Failure`: no orbit, chatter, a broken invariant, a flow
#: that could not be built.
COMPUTATION_FAILURES: tuple[type[CantileverError], ...] = (
    NoOrbitError,
    ChatterError,
    InvariantError,
    NumericalError,
)

__all__ = [
    "CantileverError",
    "ParameterError",
    "NoOrbitError",
    "NoPeriodError",
    "NotConvergedError",
    "ChatterError",
    "UnsupportedError",
    "CancelledError",
    "OutputError",
    "InvariantError",
    "NumericalError",
    "COMPUTATION_FAILURES",
]
