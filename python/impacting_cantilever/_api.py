"""The computations: ``simulate``, ``find_orbit``, ``sweep``, ``continue_branch``,
``continue_curve``, ``energetic_restitution`` and ``modes_needed``. Each is one call of the
Rust library, run with the interpreter released (other Python threads go on); ``progress=``
takes a callback ``progress(what, done, total)``, called about ten times a second (``total``
is 0 when it is not known in advance), or a tqdm bar. Ctrl-C, or a callback that raises,
stops every long call within a forcing period of a run or a cell of an atlas (measured:
under 0.05 s) and raises that exception; the partial work is dropped. ``threads=``, where a
call has it, caps the threads its parallel work uses (default: one per core).

Failures raise the class of their kind (:mod:`impacting_cantilever.errors`):
``ParameterError`` (also a ``ValueError``) for bad input, ``NoPeriodError`` and
``NotConvergedError`` (both a ``NoOrbitError``), ``ChatterError``, ``UnsupportedError``, ...;
``find_orbit`` and ``energetic_restitution`` return a :class:`Failure` instead with
``raise_on_failure=False``, and ``sweep`` records one per value.
"""

from __future__ import annotations

from typing import Any, Literal, Optional, Sequence, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

from . import _core
from .errors import COMPUTATION_FAILURES, ParameterError
from ._models import Model, replace
from ._progress import Progress, callback
from ._results import (
    Continuation,
    Curve,
    Dense,
    EnergeticRestitution,
    Events,
    ModesNeeded,
    Orbit,
    Simulation,
    Study,
    _branch,
    _curve,
)
from ._sweep import Failure, Sweep, _failure, _sweep


def _state(start: Optional[ArrayLike]) -> Optional[NDArray[np.float64]]:
    """A start state as a contiguous float vector (its length and values are checked by
    the library)."""
    if start is None:
        return None
    if np.iscomplexobj(start):
        # numpy would drop the imaginary parts with a warning only
        raise ParameterError(
            "invalid start: got complex numbers; allowed: a vector of 2N real numbers [η; η̇]"
        )
    x = np.ascontiguousarray(start, dtype=np.float64)
    if x.ndim != 1:
        raise ParameterError(
            f"invalid start: got an array of shape {x.shape}; allowed: a vector of 2N numbers [η; η̇]"
        )
    return x


def simulate(
    model: Model,
    periods: int,
    record: int = 32,
    *,
    start: Optional[ArrayLike] = None,
    seed: Optional[int] = None,
    dense_per_period: Optional[int] = None,
    periodicity_tolerance: float = 1e-9,
    max_period: int = 32,
    progress: Progress = None,
    energy: bool = True,
) -> Simulation:
    """Simulates the model exactly (§5.1–5.2): ``periods`` forcing periods discarded, then
    ``record`` periods recorded — what ``cantilever simulate`` does, to the bit.

    Args:
        model: the compliant or rigid model.
        periods: forcing periods simulated and discarded (0 to 1e8).
        record: periods recorded after that (0 to 1e5).
        start: the initial modal state [η; η̇] (2N numbers, |entries| ≤ 1e6); rest if
            neither it nor ``seed`` is given.
        seed: start from the random state of this seed (``Model.random_state``).
        dense_per_period: dense output of the window, this many samples per forcing
            period (1 to 10 000; at most 1e7 numbers in all, record × dense_per_period ×
            (2N + 4)): record × dense_per_period samples from the window's start, its end
            excluded (the end is the final state); None for none.
        periodicity_tolerance: relative tolerance of the period search on the strobe
            (§5.2's 1e-9).
        max_period: the largest period m searched (1 to 1000; also ≤ record/2).
        progress: ``progress(what, done, total)`` in forcing periods.
        energy: the exact energy budget of the compliant model (about 20% of a run).

    Returns:
        A :class:`Simulation`: events as numpy arrays, dense output, the period m and
        contacts n, the certified max tip, the energy imbalance and the final state.

    Raises:
        ParameterError: bad input (the library's one-line message).
        ChatterError: a compliant stop beyond its contact cap, or a rigid run that stops
            before its window.
        InvariantError: a run that would break an invariant of the exact solution.
    """
    d = _core.simulate(
        model,
        periods,
        record,
        _state(start),
        seed,
        dense_per_period,
        periodicity_tolerance,
        max_period,
        callback(progress),
        energy,
    )
    events = d["events"]
    if model.kind == "rigid" and events["outgoing_tip_velocity"] is None:
        # a rigid run without impacts: empty arrays of the rigid model's fields, not None
        events["outgoing_tip_velocity"] = np.zeros(0)
        events["modal_velocities_after"] = np.zeros((0, model.modes))
    d["events"] = Events(**events)
    if d["dense"] is not None:
        d["dense"] = Dense(**d["dense"])
    return Simulation(**d)


def find_orbit(
    model: Model,
    start: Optional[ArrayLike] = None,
    *,
    seed: Optional[int] = None,
    transient: int = 1000,
    window: int = 65,
    period: Optional[int] = None,
    period_tolerance: float = 1e-3,
    max_iterations: int = 40,
    restitution: bool = False,
    raise_on_failure: bool = True,
) -> Union[Orbit, Failure]:
    """The periodic orbit the model settles on from ``start`` (rest by default): the
    transient, the period m read from the strobe of a window (or given), Newton shooting
    with the exact monodromy, the Floquet multipliers, and r_E (eq 39) if asked for.

    The same as ``cantilever orbit --periods TRANSIENT --record WINDOW [--period M]``.

    Args:
        model: the compliant or rigid model.
        start: the initial state [η; η̇]; ``seed``: a random start instead.
        transient: forcing periods run before the orbit is read (0 to 1e8).
        window: periods whose strobe gives m (2 to 10 000; m ≤ min(64, window − 1)).
        period: the period m, when known (1 to 64).
        period_tolerance: how near the strobe must repeat for m to be taken (relative).
        max_iterations: Newton steps allowed (1 to 1000).
        restitution: also r_E (eq 39) over one period (compliant model only).
        raise_on_failure: False: a failure of the computation itself (no period, Newton,
            chatter) is returned as a :class:`Failure` (``success`` False, ``status`` the
            class's name, ``message``) instead of raised, as scipy's solvers return theirs.

    Raises:
        ParameterError: bad input. NoPeriodError: no period within the window.
        NotConvergedError: Newton did not converge (``.residual``); both are a
        ``NoOrbitError``. UnsupportedError: r_E of the rigid model. ChatterError: an orbit
        that chatters or sticks (rigid model).
    """
    try:
        d = _core.find_orbit(
            model,
            _state(start),
            seed,
            transient,
            window,
            period,
            period_tolerance,
            max_iterations,
            restitution,
        )
    except COMPUTATION_FAILURES as e:
        if raise_on_failure:
            raise
        return _failure(e)
    return Orbit(**d)


def sweep(
    model: Model,
    parameter: str,
    values: Sequence[float],
    *,
    start: Optional[ArrayLike] = None,
    seed: Optional[int] = None,
    transient: int = 1000,
    window: int = 65,
    period: Optional[int] = None,
    period_tolerance: float = 1e-3,
    max_iterations: int = 40,
    restitution: bool = False,
    progress: Progress = None,
    threads: Optional[int] = None,
) -> Sweep:
    """:func:`find_orbit` at each value of one parameter of the model, from the same start,
    in one call: the values run in parallel, each orbit is the one ``find_orbit`` finds
    for that model alone (bit for bit), and a value whose orbit fails (no period, Newton,
    chatter) has its status and message instead of stopping the sweep.

    Args:
        model: the model whose ``parameter`` is swept (any model).
        parameter: a keyword of the model's ``parameters()`` (``"stop_stiffness"``,
            ``"omega"``, ``"gap"``, ``"zeta1"``, ``"restitution"``, …).
        values: its values; every one is checked before any work (a bad one raises
            ``ParameterError``).
        start, seed, transient, window, period, period_tolerance, max_iterations,
            restitution: as in :func:`find_orbit`, for every value.
        progress: ``progress("sweep: orbits", values done, len(values))``, or a tqdm bar.
        threads: threads the values run on (1 to 1024; default one per core).

    Returns:
        A :class:`Sweep`: arrays of m, n, stability, spectral radius, residual, r_E and state
        per value, ``found`` and ``status`` per value, and each value's
        :class:`Orbit` or :class:`Failure`; ``to_pandas()`` for a table.
    """
    xs = np.asarray(values, dtype=np.float64)
    if xs.ndim != 1:
        raise ParameterError(
            f"invalid values: got an array of shape {xs.shape}; allowed: a sequence of numbers"
        )
    models = [replace(model, **{parameter: float(x)}) for x in xs]
    found = _core.find_orbits(
        models,
        _state(start),
        seed,
        transient,
        window,
        period,
        period_tolerance,
        max_iterations,
        restitution,
        callback(progress),
        threads,
    )
    entries = [
        Orbit(**f) if isinstance(f, dict) else Failure(f[0], f[1], f[2]) for f in found
    ]
    return _sweep(parameter, xs, entries, model.modes)


def continue_branch(
    model: Model,
    parameter: Literal["stop_stiffness", "omega", "gap"],
    to: float,
    *,
    one_way: bool = False,
    max_step: float = 0.02,
    doubling_up_to: int = 8,
    start: Optional[ArrayLike] = None,
    seed: Optional[int] = None,
    transient: int = 1000,
    window: int = 65,
    period: Optional[int] = None,
    progress: Progress = None,
) -> Continuation:
    """The branch of periodic orbits through the model's orbit, continued in k/k₁
    (``"stop_stiffness"``), ω/(β₁⁻)² (``"omega"``) or d₀ (``"gap"``) by pseudo-arclength on the shooting
    problem, with its folds, period doublings (followed to the doubled branch),
    Neimark–Sacker points and grazings — ``cantilever continue``, to the bit.

    Args:
        model: a compliant cantilever model; its value of the parameter is the start.
        to: where to continue to (> 0); unless ``one_way``, the branch is also traced the
            other way, to start²/to.
        max_step: largest step in ln p, also the spacing of the points (1e-4 to 0.2).
        doubling_up_to: follow period doublings up to this period (1 = none; up to 64).
        start, seed, transient, window, period: the start orbit, as in :func:`find_orbit`.
        progress: ``progress("continuation: orbits", models built, 0)``.

    Raises:
        UnsupportedError: the rigid-impact model or the oscillator (continuation is built
            for the compliant cantilever). ParameterError: bad input.
    """
    d = _core.continue_branch(
        model,
        parameter,
        to,
        one_way,
        max_step,
        doubling_up_to,
        _state(start),
        seed,
        transient,
        window,
        period,
        callback(progress),
    )
    return Continuation(
        parameter=d["parameter"],
        start=d["start"],
        modes=d["modes"],
        branches=[_branch(b) for b in d["branches"]],
        document=d,
    )


def continue_curve(
    model: Model,
    kind: Literal["fold", "period_doubling", "grazing", "neimark_sacker"],
    parameter: Literal["stop_stiffness", "omega", "gap"],
    second: Literal["stop_stiffness", "omega", "gap"],
    range: tuple[float, float],
    second_range: tuple[float, float],
    *,
    max_step: float = 0.05,
    max_points: int = 400,
    start: Optional[ArrayLike] = None,
    seed: Optional[int] = None,
    transient: int = 1000,
    window: int = 65,
    period: Optional[int] = None,
    progress: Progress = None,
    threads: Optional[int] = None,
) -> Curve:
    """The curve of folds (a multiplier at +1), period doublings (at −1), grazings (the
    tip's extremum nearest the stop touches it) or Neimark–Sacker points (a complex pair of
    multipliers on the unit circle) of the model's orbit, in two of k/k₁
    (``"stop_stiffness"``), ω/(β₁⁻)² (``"omega"``) and d₀ (``"gap"``): pseudo-arclength on
    the shooting problem closed by the point's test function, with the points where it
    meets other curves — ``cantilever continue2``, to the bit.

    Args:
        model: a compliant cantilever model; its values of the two parameters are the start.
        kind: what the curve follows.
        parameter: p, solved for at the start; ``second``: q, held while the first point is
            found.
        range, second_range: the rectangle the curve is traced in, (from, to) with
            0 < from < to, containing the start's values.
        max_step: largest arclength step (1e-4 to 0.2); max_points: each way (2 to 20 000).
        start, seed, transient, window, period: the start orbit, as in :func:`find_orbit`.
        progress: ``progress("curve: orbits", models built, 0)``.
        threads: threads for the curve's two directions (1 to 1024; default one per core).

    Raises:
        NotConvergedError: no point of the curve near the start orbit. UnsupportedError: the
            rigid-impact model or the oscillator. ParameterError: bad input.
    """
    if not (isinstance(range, tuple) and len(range) == 2):
        raise ParameterError(f"invalid range: got {range!r}; allowed: a pair (from, to)")
    if not (isinstance(second_range, tuple) and len(second_range) == 2):
        raise ParameterError(
            f"invalid second_range: got {second_range!r}; allowed: a pair (from, to)"
        )
    d = _core.continue_curve(
        model,
        kind,
        parameter,
        second,
        (float(range[0]), float(range[1])),
        (float(second_range[0]), float(second_range[1])),
        max_step,
        max_points,
        _state(start),
        seed,
        transient,
        window,
        period,
        callback(progress),
        threads,
    )
    return _curve(d)


def _coefficient(c: Any) -> Optional[float]:
    return c["Value"] if isinstance(c, dict) and "Value" in c else None


def energetic_restitution(
    model: Model,
    start: Optional[ArrayLike] = None,
    *,
    seed: Optional[int] = None,
    transient: int = 1000,
    window: int = 40,
    raise_on_failure: bool = True,
) -> Union[EnergeticRestitution, Failure]:
    """The energetic coefficient of restitution r_E (eq 39) of the orbit the compliant model
    settles on: ``transient`` periods, the orbit labelled over ``window`` periods (2 to
    10 000), and the work of the contact force on mode 1 over one period of it (the
    Figure 6 computation).

    Raises:
        NoPeriodError: the motion has no period of at most 32 forcing periods in the window
            (r_E is defined on a periodic orbit) — returned as a :class:`Failure` instead
            with ``raise_on_failure=False``, as :func:`find_orbit` does.
        UnsupportedError: the rigid-impact model. ParameterError: bad input.
    """
    try:
        d = _core.energetic_restitution(model, _state(start), seed, transient, window)
    except COMPUTATION_FAILURES as e:
        if raise_on_failure:
            raise
        return _failure(e)
    m, n = d["kind"]["Periodic"]["m"], d["kind"]["Periodic"]["n"]
    return EnergeticRestitution(
        label=f"({m},{n})",
        period_m=m,
        impacts_n=n,
        residual=d["residual"],
        r_E=_coefficient(d["coefficient"]),
        r_E_energy_change=_coefficient(d["energy_change_coefficient"]),
        contacts=d["contacts"],
        state=np.array(d["state"], dtype=np.float64),
        cycle=d["cycle"],
        document=d,
    )


def modes_needed(
    stop_stiffness: float,
    tolerance: float = 1e-3,
    zeta1: float = 0.01,
    *,
    threads: Optional[int] = None,
) -> ModesNeeded:
    """How many Galerkin modes N resolve a stop of stiffness k/k₁ (1e-3 to 1e6) to a relative
    accuracy (1e-9 to 0.5): one contact simulated for N = 1 … 200, each observable (contact
    duration, exit tip velocity, first-mode velocity after) extrapolated to N → ∞ —
    ``cantilever modes-needed``. Takes about a second; ``threads`` (1 to 1024) caps the
    threads of the scan (default one per core)."""
    d = _core.modes_needed(stop_stiffness, tolerance, zeta1, threads)
    needed = d["needed"]
    scanned = needed.get("Scanned") if isinstance(needed, dict) else None
    beyond = needed.get("Beyond") if isinstance(needed, dict) else None
    unconfirmed = needed.get("Unconfirmed") if isinstance(needed, dict) else None
    studies = {
        name: Study(
            sizes=np.array(s["sizes"], dtype=np.int64),
            values=np.array(s["values"], dtype=np.float64),
            limit=s["limit"],
            uncertainty=s["uncertainty"],
            order=s["order"],
            order_change=s["order_change"],
            scale=s["scale"],
        )
        for name, s in d["studies"]
    }
    return ModesNeeded(
        stop_stiffness=d["stop_stiffness_over_k1"],
        tolerance=d["tolerance"],
        needed=scanned,
        estimate=(beyond or unconfirmed or {}).get("estimate"),
        confirmed=unconfirmed is None,
        hardest=d["hardest"],
        studies=studies,
        criterion=d["criterion"],
        largest_scanned=d["largest_scanned"],
        scan_end=d["scan_end"],
        document=d,
    )
