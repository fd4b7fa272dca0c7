"""How to cite: the software (with the version and commit of this build) and the paper it
reproduces, as plain text and BibTeX (the same data as ``CITATION.cff``), and one published
number of the book (:func:`number`; a number of a run of your own:
:meth:`impacting_cantilever.scenes.Scene.cite`)."""

from __future__ import annotations

from typing import Optional

from . import _core

__all__ = ["number", "software", "software_bibtex", "paper", "paper_bibtex", "build"]


def number(scene: str, key: Optional[str] = None) -> str:
    """The citation of a key number the book publishes (all of the scene's when None), as
    ``cantilever cite SCENE [KEY]`` prints it (KEY: the key, or the number's name in words):
    a sentence to paste, the value ± uncertainty
    with its basis and unit, the parameters, the method, the build, the reproduce command,
    and the software and the paper as plain text and BibTeX. Instant: the numbers are the
    ones committed with this build (checked against a recomputation by its test suite).
    An unknown scene or key raises ValueError naming the keys that share its words."""
    return _core.cite(scene, key)  # type: ignore[no-any-return]


def software() -> str:
    """The software, as plain text, for this build."""
    return _core.citations()["software_plain"]  # type: ignore[no-any-return]


def software_bibtex() -> str:
    """The software, as BibTeX, for this build."""
    return _core.citations()["software_bibtex"]  # type: ignore[no-any-return]


def paper() -> str:
    """Melcher, Champneys & Wagg (2013), as plain text."""
    return _core.citations()["paper_plain"]  # type: ignore[no-any-return]


def paper_bibtex() -> str:
    """Melcher, Champneys & Wagg (2013), as BibTeX."""
    return _core.citations()["paper_bibtex"]  # type: ignore[no-any-return]


def build() -> dict[str, object]:
    """This build: version, commit, whether the tree had uncommitted changes, compiler."""
    c = _core.citations()
    return {k: c[k] for k in ("version", "commit", "dirty", "toolchain")}
