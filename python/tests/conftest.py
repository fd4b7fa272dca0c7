"""The reference for every test: the ``cantilever`` command line of the same checkout, whose
``--json`` output the Python results must equal bit for bit.

The binary is ``$CANTILEVER_BIN`` or ``target/release/cantilever`` at the repository root
(``cargo build --release`` makes it; CI has it from the README's test command).
"""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _binary() -> Path:
    path = Path(os.environ.get("CANTILEVER_BIN", ROOT / "target" / "release" / "cantilever"))
    if not path.exists():
        pytest.exit(
            f"the cantilever command line is not at {path}: build it with `cargo build --release` "
            "at the repository root, or set CANTILEVER_BIN",
            returncode=2,
        )
    return path


class Cli:
    """Runs the command line."""

    def __init__(self, path: Path) -> None:
        self.path = path

    def run(self, *args: str, cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
        return subprocess.run(
            [str(self.path), *args], capture_output=True, text=True, timeout=600, cwd=cwd
        )

    def json(self, *args: str) -> dict[str, Any]:
        """The command's --json document, without its header (schema_version, command)."""
        p = self.run(*args, "--json")
        assert p.returncode == 0, p.stderr
        doc = json.loads(p.stdout)
        doc.pop("schema_version", None)
        doc.pop("command", None)
        return doc  # type: ignore[no-any-return]

    def error(self, *args: str) -> str:
        """The one-line message of a command that exits with status 2 (bad input)."""
        p = self.run(*args)
        assert p.returncode == 2, (p.returncode, p.stdout, p.stderr)
        line = p.stderr.strip()
        assert line.startswith("error: ") and "\n" not in line, line
        return line.removeprefix("error: ")


@pytest.fixture(scope="session")
def cli(tmp_path_factory: pytest.TempPathFactory) -> Cli:
    """The command line, checked to come from the same build of the library as the
    extension (the same commit and state of the tree): otherwise the comparisons compare two
    versions of the code."""
    c = Cli(_binary())
    import impacting_cantilever as ic

    out = tmp_path_factory.mktemp("spectrum")
    theirs = c.json("scene", "spectrum", "--out", str(out))["provenance"]
    ours = ic.citation.build()
    if (theirs["commit"], theirs["dirty"]) != (ours["commit"], ours["dirty"]):
        pytest.exit(
            f"the command line ({theirs['commit'][:12]}, dirty: {theirs['dirty']}) and the "
            f"Python extension ({str(ours['commit'])[:12]}, dirty: {ours['dirty']}) come from "
            "different builds: rebuild both from this tree (cargo build --release; "
            "pip install ./python)",
            returncode=2,
        )
    return c


def same_bits(a: Any, b: Any) -> bool:
    """Equal as IEEE doubles, bit for bit (NaN equal to NaN, 0.0 not equal to -0.0)."""
    import numpy as np

    a = np.asarray(a, dtype=np.float64)
    b = np.asarray(b, dtype=np.float64)
    return a.shape == b.shape and bool(np.array_equal(a.view(np.uint64), b.view(np.uint64)))
