"""Type stubs of the Rust extension ``impacting_cantilever._core``. Use the package's own
functions (``impacting_cantilever.simulate`` etc.), which shape these results; the units are
those of :mod:`impacting_cantilever._models`."""

from typing import Any, Callable, Optional, Union

import numpy as np
from numpy.typing import NDArray

__version__: str
DEFAULT_STOP_STIFFNESS: float
DEFAULT_RESTITUTION: float

_Progress = Optional[Callable[[str, int, int], object]]

class Model:
    """A validated model: the compliant cantilever, the oscillator, or either against a
    rigid stop with a law."""

    def __eq__(self, other: object) -> bool: ...
    def __hash__(self) -> int: ...

    @property
    def kind(self) -> str:
        """"compliant" or "rigid"."""
    @property
    def modes(self) -> int:
        """N, the number of modes (1 for the oscillator)."""
    @property
    def period(self) -> float:
        """T = 2π/ω, the forcing period (non-dimensional beam time)."""
    @property
    def angular_frequency(self) -> float:
        """ω in the model's time unit (not in units of (β₁⁻)²)."""
    @property
    def gap_length(self) -> float:
        """d₀ in the model's length unit (the free tip amplitude at resonance)."""
    @property
    def free_tip_amplitude(self) -> tuple[float, float]:
        """(A_free, ωA_free) at the forcing frequency, without the stop."""
    @property
    def condition(self) -> float:
        """The larger eigenvector condition of the region flows."""
    def parameters(self) -> dict[str, Any]:
        """The parameters as given (constructor keywords), with "model"."""
    def law_matrix(self) -> Optional[NDArray[np.float64]]:
        """The rigid model's law [R] (N × N), or None."""
    def rest(self) -> NDArray[np.float64]:
        """zeros(2N)."""
    def random_state(self, seed: int) -> NDArray[np.float64]:
        """The random start of a seed (η_j in ±2A_free/N, η̇_j in ±2ωA_free/N)."""
    def modal_state(
        self, s: Any, w: Any, w_t: Any
    ) -> NDArray[np.float64]:
        """[η; η̇] of profiles w(s), w_t(s) sampled at increasing s from ≤ 0 to ≥ 1."""
    def matrices(self) -> dict[str, NDArray[np.float64]]:
        """stiffness_free (K⁻), stiffness_contact (K⁺), damping (C), forcing (f_j), tip (φ(1))."""

class SceneRun:
    @property
    def name(self) -> str: ...
    @property
    def svg(self) -> str: ...
    def document(self) -> dict[str, Any]: ...
    def data(self) -> Any: ...
    def data_json(self) -> str: ...
    def tables(self) -> tuple[str, list[tuple[str, str]]]: ...
    def write(self, dir: str) -> None: ...
    def cite(self, key: Optional[str] = None) -> str: ...
    def __reduce__(self) -> tuple[Any, tuple[str]]: ...

def compliant(
    modes: int,
    stop_stiffness: float,
    gap: float,
    zeta1: float,
    omega: float,
    gap_unit: str,
    damping_reading: str,
    viscous: float,
    forcing: Union[str, float],
) -> Model: ...
def rigid(base: Model, law: str, restitution: float) -> Model: ...
def oscillator(
    stiffness: float,
    damping: float,
    forcing: float,
    omega: float,
    tip_gain: float,
    gap: float,
    stop_stiffness: float,
) -> Model: ...
def problem(
    name: str,
    modes: int,
    gap: Optional[float] = None,
    zeta1: Optional[float] = None,
    omega: Optional[float] = None,
) -> Model: ...
def units() -> tuple[float, float]:
    """((β₁⁻)², k₁ = (β₁⁻)⁴)."""

def simulate(
    model: Model,
    periods: int,
    record: int,
    start: Optional[NDArray[np.float64]],
    seed: Optional[int],
    dense_per_period: Optional[int],
    periodicity_tolerance: float,
    max_period: int,
    progress: _Progress,
    energy: bool = ...,
) -> dict[str, Any]: ...
def find_orbit(
    model: Model,
    start: Optional[NDArray[np.float64]],
    seed: Optional[int],
    transient: int,
    window: int,
    period: Optional[int],
    period_tolerance: float,
    max_iterations: int,
    restitution: bool,
) -> dict[str, Any]: ...
def find_orbits(
    models: list[Model],
    start: Optional[NDArray[np.float64]],
    seed: Optional[int],
    transient: int,
    window: int,
    period: Optional[int],
    period_tolerance: float,
    max_iterations: int,
    restitution: bool,
    progress: _Progress,
    threads: Optional[int],
) -> list[Union[dict[str, Any], tuple[str, str, Optional[float]]]]: ...
def motion(
    model: Model,
    start: Optional[NDArray[np.float64]],
    seed: Optional[int],
    transient: int,
    segments: Optional[int],
    segment_periods: Optional[int],
    iterates: Optional[int],
    longest_period: Optional[int],
    resolution: Optional[float],
    progress: _Progress,
) -> dict[str, Any]: ...
def continue_branch(
    model: Model,
    parameter: str,
    to: float,
    one_way: bool,
    max_step: float,
    doubling_up_to: int,
    start: Optional[NDArray[np.float64]],
    seed: Optional[int],
    transient: int,
    window: int,
    period: Optional[int],
    progress: _Progress,
) -> dict[str, Any]: ...
def continue_curve(
    model: Model,
    kind: str,
    parameter: str,
    second: str,
    range: tuple[float, float],
    second_range: tuple[float, float],
    max_step: float,
    max_points: int,
    start: Optional[NDArray[np.float64]],
    seed: Optional[int],
    transient: int,
    window: int,
    period: Optional[int],
    progress: _Progress,
    threads: Optional[int] = None,
) -> dict[str, Any]: ...
def energetic_restitution(
    model: Model,
    start: Optional[NDArray[np.float64]],
    seed: Optional[int],
    transient: int,
    window: int,
) -> dict[str, Any]: ...
def modes_needed(
    stop_stiffness: float, tolerance: float, zeta1: float, threads: Optional[int] = None
) -> dict[str, Any]: ...
def time_rust(
    model: Model,
    what: str,
    repeats: int,
    periods: int = 0,
    record: int = 1,
    dense_per_period: Optional[int] = None,
) -> list[tuple[float, float]]:
    """(wall, thread processor) seconds of pure-Rust calls (no Python in the loop)."""

def scene_list() -> list[dict[str, Any]]: ...
def scene_run(
    name: str,
    resolution: str = "book",
    out: Optional[str] = None,
    progress: _Progress = None,
    threads: Optional[int] = None,
) -> SceneRun: ...
def scene_restore(payload: str) -> SceneRun: ...
def citations() -> dict[str, Any]: ...
def cite(scene: str, key: Optional[str] = None) -> str: ...
def atlas_params(resolution: str) -> str: ...
def atlas_shard(
    params: str,
    index: int,
    count: int,
    progress: _Progress = None,
    threads: Optional[int] = None,
) -> str: ...
def atlas_merge(
    shards: list[str],
    out: Optional[str] = None,
    progress: _Progress = None,
    threads: Optional[int] = None,
) -> SceneRun: ...
def atlas_build() -> str: ...
