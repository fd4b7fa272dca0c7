"""The book's chapter *From Python* prints what this build prints: each of its scripts is
run again and its output compared, line for line, with the committed one the chapter
includes (regenerate them with ``python python/bench/chapter.py``)."""

from __future__ import annotations

import importlib.util
import os
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


def test_the_book_build_can_run_the_chapter_into_a_folder(tmp_path: Path) -> None:
    """``cantilever book`` runs ``chapter.py --out DIR`` when the package of its own build is
    installed (src/results/book/python.rs): the script must write every file the book
    takes from it (that module's FILES), into DIR and nowhere else."""
    import re
    import subprocess
    import sys

    rust = (ROOT / "src" / "results" / "book" / "python.rs").read_text()
    listed = re.search(r"pub const FILES: \[&str; \d+\] = \[(.*?)\];", rust, re.S)
    assert listed is not None, "FILES in src/results/book/python.rs"
    files = set(re.findall(r'"([^"]+)"', listed.group(1)))
    committed = {p: p.stat().st_mtime_ns for p in chapter.OUT.iterdir()}
    subprocess.run(
        [sys.executable, str(ROOT / "python" / "bench" / "chapter.py"), "--out", str(tmp_path)],
        check=True,
        cwd=ROOT,
        # the package this test imports, whatever the working folder
        env={**os.environ, "MPLBACKEND": "Agg", "PYTHONPATH": os.pathsep.join(sys.path)},
        stdout=subprocess.DEVNULL,
    )
    # the figure needs matplotlib (the book runs the script only where it is installed)
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        files.discard("bifurcation.png")
    assert files <= {p.name for p in tmp_path.iterdir()}
    assert {p: p.stat().st_mtime_ns for p in chapter.OUT.iterdir()} == committed
    for name in chapter.SCRIPTS:
        assert (tmp_path / f"{name}-output.txt").read_text() == (
            chapter.OUT / f"{name}-output.txt"
        ).read_text()
