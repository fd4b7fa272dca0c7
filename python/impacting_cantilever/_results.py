"""The results of the computations: plain numpy arrays in small frozen dataclasses.

Units as in :mod:`impacting_cantilever._models`: time of the non-dimensional beam, lengths
in units of the free tip amplitude at resonance, velocities in those lengths per unit time,
stop stiffness in units of k₁ = (β₁⁻)⁴ and frequencies in units of (β₁⁻)².
"""

from __future__ import annotations

import inspect
import re
import textwrap
from dataclasses import dataclass, field, fields
from typing import Any, ClassVar, Optional

import numpy as np
from numpy.typing import NDArray

from ._tables import Table, split


def _opt(x: Optional[float], fmt: str) -> str:
    return "—" if x is None else format(x, fmt)


def _same(a: Any, b: Any) -> bool:
    """Equal values: arrays by shape and every element (NaN equal to NaN), floats with NaN
    equal to NaN, anything else by ``==``."""
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        if not (isinstance(a, np.ndarray) and isinstance(b, np.ndarray)):
            return False
        if a.shape != b.shape or a.dtype != b.dtype:
            return False
        nan_aware = np.issubdtype(a.dtype, np.floating) or np.issubdtype(a.dtype, np.complexfloating)
        return bool(np.array_equal(a, b, equal_nan=nan_aware))
    if isinstance(a, float) and isinstance(b, float) and a != a and b != b:
        return True
    if isinstance(a, (list, tuple)) and isinstance(b, (list, tuple)):
        return type(a) is type(b) and len(a) == len(b) and all(map(_same, a, b))
    return bool(a == b)


#: The units of every result, as ``help()`` shows them under each result's fields.
UNITS = textwrap.fill(
    "Units: time of the non-dimensional beam (EI = ρA = L = 1; the forcing period is "
    "T = 2π/ω); lengths (tip, d₀, modal coordinates) in units of the free tip amplitude at "
    "resonance, velocities in those lengths per unit time — to compare with the book's key "
    "numbers, which are in units of A_free(ω), the free tip amplitude at the forcing "
    "frequency, use in_free_units(); k in units of k₁ = (β₁⁻)⁴, ω in units of (β₁⁻)². "
    "The oscillator's results are in its own units.",
    88,
)


def _field_docs(cls: type) -> list[tuple[str, str]]:
    """The ``#:`` comment above each field of a class's body (the form Sphinx reads), as
    (name, text): what ``help()`` shows once they are in the docstring."""
    try:
        lines, _ = inspect.getsourcelines(cls)
    except (OSError, TypeError):  # no source (a frozen build): the docstring stays as it is
        return []
    docs, comment = [], []
    for line in lines[1:]:
        text = line.strip()
        if text.startswith("#:"):
            comment.append(text[2:].strip())
            continue
        m = re.match(r"([A-Za-z_]\w*)\s*:", text)
        if m and comment and line.startswith("    ") and not line.startswith("     "):
            docs.append((m.group(1), " ".join(comment)))
        comment = []
    return docs


class _Result:
    """A result's common behaviour: its arrays are read-only (a frozen result cannot be
    changed through them), and two results are equal when every field is, arrays compared
    element by element (the generated ``==`` of a dataclass would compare arrays to an
    array of truth values and raise); a measurement such as the wall time is not compared.
    Each field's ``#:`` comment (its meaning and unit) is appended to the class's docstring
    under "Attributes", so that ``help()`` shows it."""

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        docs = _field_docs(cls)
        if docs:
            wrap = lambda t: textwrap.fill(  # noqa: E731
                t, 88, initial_indent="        ", subsequent_indent="        "
            )
            body = "\n".join(f"    {name}:\n{wrap(text)}" for name, text in docs)
            cls.__doc__ = (
                f"{inspect.cleandoc(cls.__doc__ or '')}\n\nAttributes:\n{body}\n\n{UNITS}\n"
            )

    #: True: a result is a success (a :class:`~impacting_cantilever.Failure` is not).
    success: ClassVar[bool] = True

    def __post_init__(self) -> None:
        for f in fields(self):  # type: ignore[arg-type]
            v = getattr(self, f.name)
            if isinstance(v, np.ndarray):
                v.flags.writeable = False

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        return all(
            _same(getattr(self, f.name), getattr(other, f.name))
            for f in fields(self)  # type: ignore[arg-type]
            if f.compare
        )

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, repr=False, eq=False)
class Events(_Result, Table):
    """The contact events of a recorded window (impacts, for the rigid model), in order;
    ``to_pandas()`` gives them as a table."""

    #: t, the time of each event (non-dimensional beam time).
    time: NDArray[np.float64]
    #: The forcing cycle it falls in (t = (cycle + phase)·T).
    cycle: NDArray[np.int64]
    #: Its forcing phase, as a fraction of the period T in [0, 1).
    phase: NDArray[np.float64]
    #: Entering contact (True) or leaving it; every rigid impact is an entry.
    entering: NDArray[np.bool_]
    #: A touch with zero normal velocity to round-off (compliant): recorded, no switch.
    grazing: NDArray[np.bool_]
    #: The tip velocity φ(1)ᵀη̇ at the event (rigid: before the impact).
    tip_velocity: NDArray[np.float64]
    #: The modal velocities η̇ at each event, shape (events, N) (rigid: before the impact).
    modal_velocities: NDArray[np.float64]
    #: Rigid model: the tip velocity after each impact (None for the compliant model).
    outgoing_tip_velocity: Optional[NDArray[np.float64]]
    #: Rigid model: η̇ after each impact, shape (events, N) (None for the compliant model).
    modal_velocities_after: Optional[NDArray[np.float64]]

    def __len__(self) -> int:
        return len(self.time)

    def _columns(self) -> dict[str, Any]:
        c = {f: getattr(self, f) for f in ["time", "cycle", "phase", "entering", "grazing"]}
        c["tip_velocity"] = self.tip_velocity
        if self.outgoing_tip_velocity is not None:
            c["outgoing_tip_velocity"] = self.outgoing_tip_velocity
        return {**c, **split("modal_velocity", self.modal_velocities)}

    def __repr__(self) -> str:
        entries = int(np.count_nonzero(self.entering & ~self.grazing))
        return f"Events({len(self)} events, {entries} entries into contact)"


@dataclass(frozen=True, repr=False, eq=False)
class Dense(_Result):
    """Dense output of a recorded window on the grid t = cycle·T + j·T/per_period."""

    #: t of each sample.
    t: NDArray[np.float64]
    #: In contact with the stop (rigid: resting on it).
    in_contact: NDArray[np.bool_]
    #: The tip displacement d = φ(1)ᵀη.
    tip: NDArray[np.float64]
    #: The tip velocity ḋ.
    tip_velocity: NDArray[np.float64]
    #: The modal state [η; η̇] of each sample, shape (samples, 2N).
    state: NDArray[np.float64]

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return f"Dense({len(self)} samples of t, in_contact, tip, tip_velocity, state)"


@dataclass(frozen=True, repr=False, eq=False)
class Simulation(_Result):
    """What :func:`~impacting_cantilever.simulate` gives: a transient discarded, then a
    recorded window."""

    events: Events
    #: Dense output of the window (None unless ``dense_per_period`` was given).
    dense: Optional[Dense]
    #: The smallest period m ≤ ``max_period_searched`` whose stroboscopic samples repeat to
    #: ``periodicity_tolerance`` (relative) at the end of the window, else None.
    period_m: Optional[int]
    #: n: entries into contact (rigid: impacts) per period m, None when not periodic.
    impacts_n: Optional[int]
    #: (fewest, most) entries in the window's blocks of m periods, None when not periodic:
    #: apart where round-off decides an event, so that n is not exact.
    impacts_n_range: Optional[tuple[int, int]]
    #: The smallest strobe residual found (None with fewer than 2 recorded periods).
    periodicity_residual: Optional[float]
    periodicity_tolerance: float
    #: min(max_period, record/2), the largest period tested.
    max_period_searched: int
    #: Entries into contact (impacts) in the whole recorded window.
    contacts_in_window: int
    #: Flights between two contacts that rise less than ``flight_resolution`` from the stop:
    #: where there are any, round-off decides the counts above (they are not exact).
    shallow_flights: int
    #: The tip displacement the flow resolves (κε × the larger of the window's largest tip
    #: displacement and A_free(ω); 0 without a window or for the rigid model).
    flight_resolution: float
    #: The certified largest tip displacement of the window (compliant), with when and to
    #: what tolerance: no value of d in the window exceeds it by more.
    max_tip: Optional[float]
    max_tip_time: Optional[float]
    max_tip_tolerance: Optional[float]
    #: The unaccounted part of the exact energy budget of the whole run, relative (compliant,
    #: with ``energy=True``).
    energy_imbalance: Optional[float]
    #: What round-off explains of it: κε√(segments + 1).
    energy_imbalance_bound: Optional[float]
    #: The eigenvector condition of the flows the model uses (accurate to ~ this × 2.2e-16).
    eigenvector_condition: float
    #: "completed", or why a rigid run stopped early.
    outcome: str
    #: Where the run ended: t, its cycle and phase, and the state [η; η̇] (to chain runs).
    final_time: float
    final_cycle: int
    final_phase: float
    final_state: NDArray[np.float64]
    #: Where it started ("rest", "state given", "random state, seed …").
    start: str
    periods: int
    record: int
    #: Wall time of the computation (the interpreter released), seconds (a measurement, not
    #: part of the result: two equal runs compare equal whatever it is).
    wall_seconds: float = field(compare=False)

    def __repr__(self) -> str:
        orbit = (
            f"({self.period_m}, {self.impacts_n}) orbit"
            if self.period_m is not None
            else "no period found"
        )
        tip = "" if self.max_tip is None else f", max tip {self.max_tip:.6g}"
        energy = (
            "" if self.energy_imbalance is None else f", energy imbalance {self.energy_imbalance:.1e}"
        )
        return (
            f"Simulation({self.periods} + {self.record} periods from {self.start}: {orbit}, "
            f"{len(self.events)} events{tip}{energy}, {self.outcome})"
        )


@dataclass(frozen=True, repr=False, eq=False)
class Orbit(_Result):
    """A periodic orbit by Newton shooting on the stroboscopic map, with its Floquet
    multipliers (the eigenvalues of the exact monodromy matrix)."""

    #: The state [η; η̇] at the start of a forcing period on the orbit.
    state: NDArray[np.float64]
    #: m: forcing periods per orbit period (the least).
    period_m: int
    #: n: entries into contact (rigid: impacts) per orbit period.
    impacts_n: int
    #: (fewest, most) entries per orbit period over four periods run on from the orbit:
    #: apart where round-off decides an event, so that n is not exact.
    impacts_n_range: tuple[int, int]
    #: The Floquet multipliers, largest modulus first (complex).
    multipliers: NDArray[np.complex128]
    #: All multipliers inside the unit circle.
    stable: bool
    #: ‖P^m(x) − x‖∞/‖x‖∞ (at most 1e-12).
    residual: float
    #: Newton steps taken.
    iterations: int
    #: r_E (eq 39) over one period, when asked for (None: no real root, or not asked).
    energetic_restitution: Optional[float]
    #: The largest multiplier modulus.
    spectral_radius: float
    #: Where the transient started.
    start: str

    def __repr__(self) -> str:
        rE = "" if self.energetic_restitution is None else f", r_E = {self.energetic_restitution:.6g}"
        return (
            f"Orbit(({self.period_m}, {self.impacts_n}), "
            f"{'stable' if self.stable else 'unstable'}, spectral radius "
            f"{self.spectral_radius:.6f}, residual {self.residual:.1e}, "
            f"{self.iterations} Newton steps{rE})"
        )


@dataclass(frozen=True, eq=False)
class Bifurcation(_Result):
    """A bifurcation between two points of a branch."""

    #: "Fold", "PeriodDoubling", "NeimarkSacker", "BranchPoint" or "Grazing".
    kind: str
    #: Where, in the continuation parameter (interpolated).
    parameter: float
    #: The parameters of the two points it lies between.
    between: tuple[float, float]
    #: The first of the two points.
    index: int
    #: Contacts per period before and after.
    impacts: tuple[int, int]
    #: Stable before and after.
    stable: tuple[bool, bool]


@dataclass(frozen=True, repr=False, eq=False)
class Branch(_Result, Table):
    """A traced branch of period-m orbits, one entry per point (arclength order)."""

    period_m: int
    #: The continuation parameter p of each point (k/k₁ or ω/(β₁⁻)²).
    parameter: NDArray[np.float64]
    #: The orbit's state [η; η̇] at the start of a forcing period, shape (points, 2N).
    state: NDArray[np.float64]
    #: n, contacts per orbit period.
    impacts_n: NDArray[np.int64]
    #: Floquet multipliers, largest modulus first, shape (points, 2N).
    multipliers: NDArray[np.complex128]
    stable: NDArray[np.bool_]
    residual: NDArray[np.float64]
    #: The largest multiplier modulus.
    spectral_radius: NDArray[np.float64]
    #: The largest tip displacement over the orbit.
    max_tip: NDArray[np.float64]
    #: The smallest |d_ext − d₀| over free-flight extrema (NaN where there is none).
    grazing_distance: NDArray[np.float64]
    #: Tip velocity at each entry into contact, per point.
    impact_velocities: list[NDArray[np.float64]]
    bifurcations: list[Bifurcation]
    #: Why the branch ends.
    end: str
    #: The branch it doubled from, if born at a period doubling.
    parent: Optional[int]

    def _columns(self) -> dict[str, Any]:
        names = ["parameter", "impacts_n", "stable", "spectral_radius", "residual", "max_tip"]
        return {**{f: getattr(self, f) for f in names}, "grazing_distance": self.grazing_distance}

    def __len__(self) -> int:
        return len(self.parameter)

    def __repr__(self) -> str:
        kinds = ", ".join(f"{b.kind} at {b.parameter:.6g}" for b in self.bifurcations)
        return (
            f"Branch(period {self.period_m}, {len(self)} points, p = {self.parameter[0]:.6g} → "
            f"{self.parameter[-1]:.6g}, bifurcations: [{kinds}], {self.end})"
        )


def _branch(b: dict[str, Any]) -> Branch:
    pts = b["points"]
    mult = np.array(
        [[complex(re, im) for re, im in p["multipliers"]] for p in pts], dtype=np.complex128
    )
    gd = [p["shape"]["grazing_distance"] for p in pts]
    return Branch(
        period_m=b["period_m"],
        parameter=np.array([p["parameter"] for p in pts], dtype=np.float64),
        state=np.array([p["state"] for p in pts], dtype=np.float64),
        impacts_n=np.array([p["impacts_n"] for p in pts], dtype=np.int64),
        multipliers=mult,
        stable=np.array([p["stable"] for p in pts], dtype=np.bool_),
        residual=np.array([p["residual"] for p in pts], dtype=np.float64),
        spectral_radius=np.abs(mult).max(axis=1) if len(pts) else np.zeros(0),
        max_tip=np.array([p["shape"]["max_tip"] for p in pts], dtype=np.float64),
        grazing_distance=np.array([np.nan if g is None else g for g in gd], dtype=np.float64),
        impact_velocities=[
            np.array(p["shape"]["impact_velocities"], dtype=np.float64) for p in pts
        ],
        bifurcations=[
            Bifurcation(
                kind=f["kind"],
                parameter=f["parameter"],
                between=tuple(f["between"]),
                index=f["index"],
                impacts=tuple(f["impacts"]),
                stable=tuple(f["stable"]),
            )
            for f in b["bifurcations"]
        ],
        end=b["end"],
        parent=b["parent"],
    )


@dataclass(frozen=True, repr=False, eq=False)
class Continuation(_Result):
    """The branches of a continuation: branch 0 runs towards ``to``, branch 1 (unless
    one-way) the other way, then the branches born at period doublings."""

    #: "k/k₁" or "ω/(β₁⁻)²".
    parameter: str
    #: The starting orbit's parameter value.
    start: float
    modes: int
    branches: list[Branch]
    #: The whole result as ``cantilever continue --json`` prints it (without its header).
    document: dict[str, Any] = field(compare=False)

    def __repr__(self) -> str:
        lines = [f"Continuation in {self.parameter} from {self.start}, N = {self.modes}:"]
        lines += [f"  {i}: {b!r}" for i, b in enumerate(self.branches)]
        return "\n".join(lines)


@dataclass(frozen=True, repr=False, eq=False)
class CodimTwo(_Result):
    """A point where a curve meets another curve (between two of its points)."""

    #: What it meets: "fold", "period_doubling", "neimark_sacker", "grazing" or "cusp".
    meets: str
    #: Where, in the curve's two parameters (interpolated).
    p: float
    q: float
    #: The first of the two points it lies between.
    index: int


@dataclass(frozen=True, repr=False, eq=False)
class Curve(_Result):
    """A curve of folds, period doublings, Neimark–Sacker points or grazings of period-m
    orbits in two parameters (p, q), one entry per point in arclength order — ``cantilever
    continue2``, to the bit."""

    #: "fold", "period_doubling", "grazing" or "neimark_sacker".
    kind: str
    period_m: int
    modes: int
    #: The symbols of p and q, e.g. ("k/k₁", "ω/(β₁⁻)²").
    parameters: tuple[str, str]
    #: The start orbit's (p, q) as the model gives them.
    start: tuple[float, float]
    p: NDArray[np.float64]
    q: NDArray[np.float64]
    #: The orbit's state [η; η̇] at the start of a forcing period, shape (points, 2N).
    state: NDArray[np.float64]
    #: n, contacts per orbit period.
    impacts_n: NDArray[np.int64]
    #: Floquet multipliers, largest modulus first, shape (points, 2N).
    multipliers: NDArray[np.complex128]
    #: ‖P^m(x) − x‖∞/‖x‖∞ of each polished orbit.
    orbit_residual: NDArray[np.float64]
    #: How far each is from the condition: |μ ∓ 1| of the nearest multiplier, ||μ| − 1| of
    #: the complex pair nearest the unit circle, or |d_ext − d₀|/A_free.
    test_residual: NDArray[np.float64]
    codim_two: list[CodimTwo]
    #: Why each end ends (the first point's, the last point's).
    ends: tuple[str, str]
    #: The whole result as ``cantilever continue2 --json`` prints it (without its header).
    document: dict[str, Any] = field(compare=False)

    def __len__(self) -> int:
        return len(self.p)

    def __repr__(self) -> str:
        meets = ", ".join(f"{c.meets} at ({c.p:.6g}, {c.q:.6g})" for c in self.codim_two)
        return (
            f"Curve({self.kind}, period {self.period_m}, N = {self.modes}, {len(self)} points in "
            f"{self.parameters}, meets: [{meets}], ends: {self.ends})"
        )


def _curve(d: dict[str, Any]) -> Curve:
    c = d["curve"]
    pts = c["points"]
    n = 2 * d["modes"]
    mult = np.array(
        [[complex(re, im) for re, im in p["multipliers"]] for p in pts], dtype=np.complex128
    ).reshape(len(pts), n)
    return Curve(
        kind=c["kind"],
        period_m=c["period_m"],
        modes=d["modes"],
        parameters=tuple(c["parameters"]),
        start=tuple(d["start"]),
        p=np.array([p["p"] for p in pts], dtype=np.float64),
        q=np.array([p["q"] for p in pts], dtype=np.float64),
        state=np.array([p["state"] for p in pts], dtype=np.float64).reshape(len(pts), n),
        impacts_n=np.array([p["impacts_n"] for p in pts], dtype=np.int64),
        multipliers=mult,
        orbit_residual=np.array([p["orbit_residual"] for p in pts], dtype=np.float64),
        test_residual=np.array([p["test_residual"] for p in pts], dtype=np.float64),
        codim_two=[
            CodimTwo(meets=x["meets"], p=x["p"], q=x["q"], index=x["index"])
            for x in c["codim_two"]
        ],
        ends=tuple(c["ends"]),
        document=d,
    )


@dataclass(frozen=True, repr=False, eq=False)
class EnergeticRestitution(_Result):
    """r_E (eq 39) of the orbit a run settles on, with each contact's r̃_E (eq 38)."""

    #: The orbit's (m, n) label.
    label: str
    period_m: Optional[int]
    impacts_n: Optional[int]
    #: Its stroboscopic residual.
    residual: float
    #: Eq (39) over one period of the orbit (None if not periodic or no real root).
    r_E: Optional[float]
    #: The variant with mode 1's whole energy change during the contacts.
    r_E_energy_change: Optional[float]
    #: The contacts of that period: entry, exit, v1 (η̇₁ at entry), tip_velocity, work.
    contacts: list[dict[str, Any]]
    #: The state on the orbit at the start of that period, and its cycle.
    state: NDArray[np.float64]
    cycle: int
    document: dict[str, Any] = field(compare=False)

    def __repr__(self) -> str:
        return (
            f"EnergeticRestitution({self.label}: r_E = {_opt(self.r_E, '.6g')}, "
            f"{len(self.contacts)} contacts per period, residual {self.residual:.1e})"
        )


@dataclass(frozen=True, eq=False)
class Study(_Result):
    """A refinement study of one observable over N (Richardson limit, GCI uncertainty)."""

    sizes: NDArray[np.int64]
    values: NDArray[np.float64]
    limit: float
    uncertainty: float
    order: Optional[float]
    order_change: Optional[float]
    scale: float


@dataclass(frozen=True, repr=False, eq=False)
class ModesNeeded(_Result):
    """How many Galerkin modes resolve a stop of stiffness k to a relative accuracy."""

    stop_stiffness: float
    tolerance: float
    #: N* found in the scan (every scanned N from it on meets the tolerance), else None.
    needed: Optional[int]
    #: The power-law estimate of N* from the observed order when the scan does not settle
    #: N* (beyond the scan, or inside it but unconfirmed), else None.
    estimate: Optional[float]
    #: False when the estimate lies inside the scan but the N → ∞ limit is too uncertain to
    #: confirm it against the scanned values.
    confirmed: bool
    #: The observable that needs the most modes.
    hardest: str
    studies: dict[str, Study]
    #: The smallest N with (β_N⁻)³ ≥ k, for comparison.
    criterion: int
    #: The largest N scanned (200, or less when the scan had to end early).
    largest_scanned: int
    #: Why the scan ended before N = 200 (None: it did not).
    scan_end: Optional[str]
    document: dict[str, Any] = field(compare=False)

    def __repr__(self) -> str:
        n = (
            str(self.needed)
            if self.needed is not None
            else (
                (
                    f"≈ {self.estimate:.3g} (beyond the scan)"
                    if self.confirmed
                    else f"≈ {self.estimate:.3g} (estimated, unconfirmed by the scan)"
                )
                if self.estimate
                else "unresolved"
            )
        )
        return (
            f"ModesNeeded(N* = {n} for {self.tolerance:g} at k = {self.stop_stiffness:g}k₁, "
            f"set by the {self.hardest}; criterion (β_N)³ = k gives {self.criterion})"
        )
