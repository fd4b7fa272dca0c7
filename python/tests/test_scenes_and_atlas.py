"""Scenes, citations and the atlas: the same key numbers and citation as the command line,
and an atlas computed in shards on a process pool identical to the byte to the one a single
process (and the command line) computes."""

from __future__ import annotations

import concurrent.futures as cf
import json
import multiprocessing
from pathlib import Path

import pytest

import impacting_cantilever as ic

from conftest import Cli


def test_scene_document_and_citation(cli: Cli, tmp_path: Path) -> None:
    scene = ic.scenes.run("spectrum", out=tmp_path / "py")
    doc = cli.json("scene", "spectrum", "--out", str(tmp_path / "cli"))
    mine = scene.document()
    for key in ["scene", "paper", "claim", "method", "parameters", "verdict", "key_numbers"]:
        assert mine[key] == doc[key], key
    for key in ["version", "commit", "dirty", "toolchain", "resolution", "fingerprint"]:
        assert mine["provenance"][key] == doc["provenance"][key], key
    # the files the scene writes are the command line's, but for the date of computation
    for name in ["plot.svg", "table.md", "verdict.json"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    k = scene.key_numbers["beta_free_1"]
    assert isinstance(k, ic.scenes.KeyNumber) and k.uncertainty > 0 and k.digits >= 10
    # the citation, line for line, but for the date in the line that says who computed it
    p = cli.run("cite", "spectrum", "beta_free_1", "--recompute")
    assert p.returncode == 0, p.stderr

    def undated(text: str) -> list[str]:
        return [line for line in text.splitlines() if not line.startswith("computed by")]

    assert undated(scene.cite("beta_free_1")) == undated(p.stdout)
    # a published number: the command line's default, the same text
    p = cli.run("cite", "fig6", "b r_E")
    assert p.returncode == 0, p.stderr
    assert ic.citation.number("fig6", "b r_E") == p.stdout
    assert ic.citation.number("fig6", "b r_E").startswith(
        "The energetic coefficient of restitution r_E (Fig 6(b)): 0.7173 ± 0.0002 ("
    )
    assert "@article{melcher2013impacting" in ic.citation.paper_bibtex()
    assert ic.citation.build()["commit"] == doc["provenance"]["commit"]


def test_an_unknown_scene_or_key_is_the_command_lines_message(cli: Cli) -> None:
    with pytest.raises(ValueError) as e:
        ic.scenes.run("fig99")
    assert str(e.value) == cli.error("scene", "fig99")
    scene = ic.scenes.run("spectrum")
    with pytest.raises(ValueError) as e:
        scene.cite("beta free 9")
    assert str(e.value) == cli.error("cite", "spectrum", "beta free 9")
    with pytest.raises(ValueError) as e:
        ic.citation.number("spectrum", "beta free 9")
    assert str(e.value) == cli.error("cite", "spectrum", "beta free 9")


def test_atlas_shards_on_a_process_pool_equal_the_unsharded_atlas(
    cli: Cli, tmp_path: Path
) -> None:
    p = ic.atlas.params("test")
    whole = ic.atlas.compute_shard(p, 0, 1)
    # the command line's unsharded file, byte for byte
    assert cli.run("atlas", "--resolution", "test", "--out", str(tmp_path / "w.json")).returncode == 0
    assert (tmp_path / "w.json").read_text() == whole
    # three shards in three processes (spawned: a forked child would inherit a thread pool
    # without its threads), merged in any order
    spawn = multiprocessing.get_context("spawn")
    with cf.ProcessPoolExecutor(max_workers=2, mp_context=spawn) as pool:
        shards = list(pool.map(ic.atlas.compute_shard, [p] * 3, range(3), [3] * 3))
    merged = ic.atlas.merge(reversed(shards), out=tmp_path / "py")
    single = ic.atlas.merge([whole])
    assert merged.data_json() == single.data_json()
    assert merged.document()["key_numbers"] == single.document()["key_numbers"]
    # the command line merges the Python shards to the same data and files
    for i, text in enumerate(shards):
        (tmp_path / f"part-{i}.json").write_text(text)
    parts = [str(tmp_path / f"part-{i}.json") for i in range(3)]
    assert cli.run("atlas-merge", *parts, "--out", str(tmp_path / "cli")).returncode == 0
    data = json.loads((tmp_path / "cli" / "data.json").read_text())["data"]
    assert data == json.loads(merged.data_json())
    for name in ["plot.svg", "table.md", "verdict.json"]:
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()


def test_merge_refuses_a_missing_row_as_the_command_line_does(cli: Cli, tmp_path: Path) -> None:
    p = ic.atlas.params("test", k_points=3, omega_points=2, check_stride=2)
    shard = ic.atlas.compute_shard(p, 0, 2)
    with pytest.raises(ValueError) as e:
        ic.atlas.merge([shard])
    (tmp_path / "part.json").write_text(shard)
    assert str(e.value) == cli.error("atlas-merge", str(tmp_path / "part.json"), "--out", str(tmp_path / "o"))


def test_a_scene_pickles_without_computing_again(tmp_path: Path) -> None:
    import pickle

    scene = ic.scenes.run("fig4", "test")
    back = pickle.loads(pickle.dumps(scene))
    assert back.document() == scene.document() and back.key_numbers == scene.key_numbers
    assert back.data_json() == scene.data_json() and back.svg == scene.svg
    assert (back.table, back.extra_tables) == (scene.table, scene.extra_tables)
    assert back.cite() == scene.cite()
    scene.write(tmp_path / "a")
    back.write(tmp_path / "b")
    for name in ["plot.svg", "table.md", "data.json", "key_numbers.json", "verdict.json"]:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()
    with pytest.raises(ic.ParameterError, match="invalid pickled scene"):
        ic._core.scene_restore('{"scene": "fig4"}')
