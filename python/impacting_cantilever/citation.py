"""How to cite: the software (with the version and commit of this build) and the paper it
reproduces, as plain text and BibTeX (the same data as ``CITATION.cff``). To cite one
number, use :meth:`impacting_cantilever.scenes.Scene.cite`."""

from __future__ import annotations

from . import _core

__all__ = ["software", "software_bibtex", "paper", "paper_bibtex", "build"]


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
