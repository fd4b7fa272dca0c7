"""The multi-tap atlas (stable periodic orbits (m, n) over k/k₁ × ω/(β₁⁻)², N = 10) in
shards: shard I of N takes the rows i with i mod N = I, each row depends only on the
parameters and its index, so the merged atlas is identical — to the byte — to the one a
single process computes, whatever the number of shards, processes or machines.

A shard is JSON text, the same file ``cantilever atlas --shard I/N --out FILE`` writes (so
shards from Python and from the command line merge together when they come from the same
build). Fan them out with any executor::

    import concurrent.futures as cf
    import impacting_cantilever as ic

    p = ic.atlas.params("test")                       # 9 × 9; "book" is 128 × 128
    with cf.ProcessPoolExecutor() as pool:            # any start method, fork included
        shards = list(pool.map(ic.atlas.compute_shard, [p] * 4, range(4), [4] * 4))
    atlas = ic.atlas.merge(shards, out="out/atlas")   # the scene's files, as atlas-merge

with Dask (``client.map(ic.atlas.compute_shard, [p] * n, range(n), [n] * n)`` then
``ic.atlas.merge(client.gather(futures))``), or as a SLURM job array, one shard per task::

    # shard.py — sbatch --array=0-63 --wrap "python shard.py"
    import os, impacting_cantilever as ic
    i, n = int(os.environ["SLURM_ARRAY_TASK_ID"]), 64
    text = ic.atlas.compute_shard(ic.atlas.params("book"), i, n)
    open(f"part-{i}.json", "w").write(text)

    # merge.py — after the array (sbatch --dependency=afterok:<job id>)
    import glob, impacting_cantilever as ic
    ic.atlas.merge([open(f).read() for f in glob.glob("part-*.json")], out="out/atlas")

Each shard uses every core it is given (the rows run in parallel threads, with the
interpreter released), or ``threads`` of them. Worker processes may be started by any
method, "fork" included: each process builds its own thread pool (a forked child does not
use its parent's, whose threads it has not inherited).
"""

from __future__ import annotations

import json
import os
from concurrent.futures import Executor
from typing import Any, Iterable, Literal, Optional, Union

from . import _core
from ._progress import Progress, callback
from .scenes import Scene

__all__ = ["params", "compute_shard", "merge", "compute", "compute_sharded", "build"]

Params = dict[str, Any]


def params(resolution: Literal["book", "test"] = "book", **changes: Any) -> Params:
    """The atlas parameters: the book's (128 × 128 cells) or the tests' (9 × 9), with any
    field changed, e.g. ``params("book", k_points=512, omega_points=512)``. Fields: modes,
    k_over_k1_range, k_points, omega_range, omega_points, zeta1, gap, starts, transient,
    max_period, seed, check_modes, check_stride, check_starts, curves (a dict: max_curves,
    max_seeds, max_points, round, edge_sample: the edges the curves leave checked one by one,
    0 to 4096)."""
    p: Params = json.loads(_core.atlas_params(resolution))
    unknown = set(changes) - set(p)
    if unknown:
        raise ValueError(
            f"invalid atlas parameter {sorted(unknown)[0]}: got a value; "
            f"allowed: one of {', '.join(p)}"
        )
    p.update(changes)
    return p


def compute_shard(
    params: Params,
    index: int,
    count: int,
    progress: Progress = None,
    threads: Optional[int] = None,
) -> str:
    """Shard ``index`` of ``count`` (0 ≤ index < count), as JSON text: picklable, and the
    file format of ``cantilever atlas`` (write it with ``open(path, "w").write(text)``).
    ``threads`` (1 to 1024) caps the threads its rows run on (default one per core: give
    ``threads=1`` to each of as many worker processes as cores)."""
    return _core.atlas_shard(json.dumps(params), index, count, callback(progress), threads)


def merge(
    shards: Iterable[str],
    out: Union[str, os.PathLike[str], None] = None,
    progress: Progress = None,
    threads: Optional[int] = None,
) -> Scene:
    """Merges the shards (JSON texts, in any order) into the atlas scene's result — key
    numbers, verdict, data, plot — tracing its boundary curves (``params["curves"]``), and
    writes its files into ``out`` if given, as ``cantilever atlas-merge`` does. Refuses
    shards of different parameters or builds, a row given twice, or a missing row."""
    path = None if out is None else os.fspath(out)
    return Scene(_core.atlas_merge(list(shards), path, callback(progress), threads))


def compute(
    params: Params, progress: Progress = None, threads: Optional[int] = None
) -> Scene:
    """The whole atlas in this process (one shard)."""
    return merge(
        [compute_shard(params, 0, 1, progress, threads)], progress=progress, threads=threads
    )


def compute_sharded(
    params: Params, count: int, executor: Executor, threads: Optional[int] = None
) -> Scene:
    """The atlas in ``count`` shards on an executor (a ``ProcessPoolExecutor``, a Dask
    client's ``get_executor()``, …), each shard on ``threads`` threads, merged."""
    futures = [
        executor.submit(compute_shard, params, i, count, None, threads) for i in range(count)
    ]
    return merge((f.result() for f in futures), threads=threads)


def build() -> str:
    """This build (version and commit): shards of different builds are not merged."""
    return _core.atlas_build()
