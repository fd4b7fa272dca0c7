"""The book's chapter *From Python* prints what this build prints: each of its scripts is
run again and its output compared, line for line, with the committed one the chapter
includes (regenerate them with ``python python/bench/chapter.py``)."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
_spec = importlib.util.spec_from_file_location("chapter", ROOT / "python" / "bench" / "chapter.py")
assert _spec is not None and _spec.loader is not None
chapter = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(chapter)


@pytest.mark.parametrize("name", chapter.SCRIPTS)
def test_each_scripts_output_is_this_builds(name: str, tmp_path: Path) -> None:
    committed = (chapter.OUT / f"{name}-output.txt").read_text()
    assert chapter.script_output(name, tmp_path) == committed, (
        f"book/src/python/{name}-output.txt is not what this build prints: "
        "run python python/bench/chapter.py"
    )


def test_the_error_example_is_this_builds() -> None:
    assert chapter.error_text() == (chapter.OUT / "error-example.txt").read_text()
