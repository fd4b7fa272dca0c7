"""The results of the paper as scenes (the library's registry, ``results::scenes``): run one
at the book's resolution (the numbers the book publishes) or the tests' reduced one, read
its key numbers with their uncertainties, and cite them as ``cantilever cite`` does.

>>> import impacting_cantilever as ic
>>> fig4 = ic.scenes.run("fig4")                          # about 2 s
>>> fig4.key_numbers["N=3 impact_velocity_1"]              # value ± uncertainty unit
>>> print(fig4.cite("N=3 impact_velocity_1"))              # with BibTeX of both works
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any, Literal, Optional, Union

from . import _core
from ._progress import Progress, callback

__all__ = ["SceneInfo", "KeyNumber", "Scene", "available", "names", "info", "run"]


@dataclass(frozen=True)
class SceneInfo:
    """One result of the paper, as the registry lists it."""

    name: str
    #: Where in the paper ("§5.3, Fig 4").
    paper: str
    summary: str
    #: The paper's claim (markdown), "—" for a methods result.
    claim: str
    #: How the numbers are computed and verified.
    method: str
    #: Its chapter in the book (a file under book/src/).
    chapter: str
    #: The key numbers shown on the book's landing page, as (label, key).
    headline: list[tuple[str, str]]
    #: Whether the tests' resolution is reduced from the book's.
    reduced_for_tests: bool


@dataclass(frozen=True)
class KeyNumber:
    """A cited float: the value to the significant figures its uncertainty supports."""

    #: The value, rounded to ``digits`` significant figures.
    value: float
    #: An absolute bound or estimate of its error, in ``unit``.
    uncertainty: float
    #: How the uncertainty was obtained (a round-off bound, a refinement study, …).
    basis: str
    #: The unit ("" for a pure number); ``unit_meaning`` says what it is.
    unit: str
    unit_meaning: Optional[str]
    digits: int

    def __str__(self) -> str:
        u = f" ± {self.uncertainty:.1g}" if self.uncertainty > 0 else " (exact)"
        unit = f" {self.unit}" if self.unit else ""
        return f"{self.value:.{max(self.digits - 1, 0)}e}{u}{unit}"


KeyValue = Union[KeyNumber, int, str, list[KeyNumber]]


def _key_value(v: dict[str, Any]) -> KeyValue:
    if "values" in v:
        return [
            KeyNumber(x, u, v["uncertainty_basis"] or "", v["unit"] or "", v["unit_meaning"], d)
            for x, u, d in zip(v["values"], v["uncertainties"], v["digits"])
        ]
    if "uncertainty" in v:
        return KeyNumber(
            v["value"],
            v["uncertainty"],
            v["uncertainty_basis"],
            v["unit"],
            v["unit_meaning"],
            v["digits"],
        )
    return v["value"]  # type: ignore[no-any-return]


class Scene:
    """A computed scene: key numbers, verdict, provenance, data, plot and tables."""

    def __init__(self, run: Any) -> None:
        self._run = run
        doc = run.document()
        #: The key numbers, in the scene's order: a :class:`KeyNumber`, an exact integer, a
        #: label, or a list of key numbers.
        self.key_numbers: dict[str, KeyValue] = {
            k: _key_value(v) for k, v in doc["key_numbers"].items()
        }
        #: Each key number's name in words ("the first impact velocity of the periodic orbit
        #: (N = 3)"), by its key: how a citation or a diff refers to it.
        self.names: dict[str, str] = {
            k: v.get("name", k) for k, v in doc["key_numbers"].items()
        }
        #: {"outcome": "Reproduced" | …, "evidence": one line with our numbers}.
        self.verdict: dict[str, str] = doc["verdict"]
        #: version, commit, dirty, toolchain, date, resolution, fingerprint.
        self.provenance: dict[str, Any] = doc["provenance"]
        #: The parameters the data were computed with.
        self.parameters: dict[str, Any] = doc["parameters"]
        self.name: str = doc["scene"]
        self.paper: str = doc["paper"]
        self.claim: str = doc["claim"]
        self.method: str = doc["method"]

    def document(self) -> dict[str, Any]:
        """The key numbers as a citable document: the ``key_numbers.json`` the scene writes
        (and ``cantilever scene NAME --json`` prints)."""
        return self._run.document()  # type: ignore[no-any-return]

    def data(self) -> Any:
        """All computed data (the ``data`` member of ``data.json``)."""
        return self._run.data()

    def data_json(self) -> str:
        """The computed data as compact JSON text, exactly as the library serialises it."""
        return self._run.data_json()  # type: ignore[no-any-return]

    @property
    def svg(self) -> str:
        """The scene's plot, SVG text."""
        return self._run.svg  # type: ignore[no-any-return]

    @property
    def table(self) -> str:
        """The main markdown table."""
        return self._run.tables()[0]  # type: ignore[no-any-return]

    @property
    def extra_tables(self) -> dict[str, str]:
        """Further markdown tables, by name."""
        return dict(self._run.tables()[1])

    def write(self, directory: Union[str, os.PathLike[str]]) -> None:
        """Writes plot.svg, table.md, data.json, key_numbers.json and verdict.json into
        ``directory``, as ``cantilever scene NAME --out DIR`` does."""
        self._run.write(os.fspath(directory))

    def cite(self, key: Optional[str] = None) -> str:
        """The citation of one key number of this run (all when None), as ``cantilever cite
        --recompute`` prints it:
        value ± uncertainty with its basis and unit, the parameters, the method, the build
        that computed it, and the software and the paper as plain text and BibTeX."""
        return self._run.cite(key)  # type: ignore[no-any-return]

    def __repr__(self) -> str:
        return (
            f"Scene({self.name} ({self.paper}): {self.verdict['outcome']}, "
            f"{len(self.key_numbers)} key numbers, resolution {self.provenance['resolution']})"
        )


def available() -> list[SceneInfo]:
    """Every scene, in the book's order."""
    return [
        SceneInfo(**{**d, "headline": [tuple(h) for h in d["headline"]]})
        for d in _core.scene_list()
    ]


def names() -> list[str]:
    """The scenes' names."""
    return [s.name for s in available()]


def info(name: str) -> SceneInfo:
    """One scene's entry in the registry."""
    for s in available():
        if s.name == name:
            return s
    _core.scene_run(name, "book")  # raises the library's message for an unknown name
    raise AssertionError("unreachable")


def run(
    name: str,
    resolution: Literal["book", "test"] = "book",
    *,
    out: Union[str, os.PathLike[str], None] = None,
    progress: Progress = None,
    threads: Optional[int] = None,
) -> Scene:
    """Runs one scene (``cantilever scene NAME``): at the book's resolution its key numbers
    are the ones the book publishes; the README lists each scene's time (the atlas about two
    minutes on two cores). Writes its files into ``out`` if given. ``progress``: a callback
    or a tqdm bar; ``threads`` (1 to 1024) caps its threads (default one per core)."""
    path = None if out is None else os.fspath(out)
    return Scene(_core.scene_run(name, resolution, path, callback(progress), threads))
