"""`wecook batch --address` on a two-node Ray cluster started here with the `ray` CLI, as Ray's docs start one
(:func:`tests.batch.cluster.local_cluster`): the same trees, graphs and plans as one session at a time, with
videos run on both nodes."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from tests.batch.cluster import local_cluster
from tests.batch.one_by_one import one_session_at_a_time
from wecook_core.resources import shared_dir

SCENARIOS = shared_dir() / "data" / "scenarios"
NAMES = ("s301", "s303", "s304")
ROOT = Path(__file__).parents[2]


@pytest.mark.slow
@pytest.mark.skipif(not (SCENARIOS / "s301").is_dir(), reason="../shared/data/scenarios is missing")
def test_a_two_node_cluster_gives_the_trees_of_one_session_at_a_time(tmp_path: Path) -> None:
    pytest.importorskip("ray")
    one_by_one = one_session_at_a_time(tmp_path / "one", list(NAMES))
    manifest = tmp_path / "videos.yaml"  # the shared scenarios, in place (the "shared storage")
    manifest.write_text("videos:\n" + "".join(
        f"  - {{name: {n}, video: {SCENARIOS / n / 'video.mp4'}, objects: {SCENARIOS / n / 'objects.xml'}, "
        f"hands: {SCENARIOS / n / 'openpose'}, truth: {SCENARIOS / n / 'truth.yaml'}}}\n" for n in NAMES))
    batch_root, client_root = tmp_path / "batch", tmp_path / "client"

    def batch(manifest: Path, root: Path, address: str, tries: int = 1) -> None:
        for attempt in range(tries):
            done = subprocess.run(
                [sys.executable, "-m", "wecook_tui.cli", "batch", str(manifest), "--root", str(root),
                 "--address", address, "--stages", "import,analyze,export"],
                cwd=ROOT, capture_output=True, text=True, timeout=900,
                env={**os.environ, "RAY_AUTH_MODE": os.environ.get("RAY_AUTH_MODE", "token")})
            if done.returncode == 0 or "Starting Ray client server failed" not in done.stderr \
                    or attempt == tries - 1:
                break
            shutil.rmtree(root, ignore_errors=True)  # Ray's own start of its per-client server failed: again
        assert done.returncode == 0, done.stderr[-3000:]

    one = tmp_path / "one.yaml"
    one.write_text("videos:\n" + manifest.read_text().splitlines()[2] + "\n")  # s303
    with local_cluster() as (address, client):
        batch(manifest, batch_root, address)
        # through Ray Client; its proxy starts a server process per client, which on a loaded machine (load 6-10
        # here) failed to come up in 1 of 2 runs before any wecook code ran: one more try then
        batch(one, client_root, client, tries=2)
    report = json.loads((batch_root / "batch.json").read_text())
    assert report["workers"] == 2 and [v["status"] for v in report["videos"]] == ["done"] * 3, report
    nodes = {s["node"] for v in report["videos"] for s in v["stages"]}
    assert len(nodes) == 2 and None not in nodes, f"videos ran on both nodes: {nodes}"
    for name in NAMES:
        for file in ("trees.yaml", "graph.yaml", "plans/plan.yaml"):
            assert (batch_root / name / file).read_text() == (one_by_one / name / file).read_text(), (name, file)
    assert (client_root / "s303" / "trees.yaml").read_text() == (one_by_one / "s303" / "trees.yaml").read_text()
