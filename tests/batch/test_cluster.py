"""`wecook batch --address` on a two-node Ray cluster started here with the `ray` CLI, as Ray's docs start one:
the same trees, graphs and plans as one session at a time, with videos run on both nodes.

The cluster is this test's own: its own --temp-dir and ports, each `ray start --block` in its own process
group, stopped by signalling those processes only (never `ray stop`, which would stop every Ray on the
machine)."""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from tests.batch.one_by_one import one_session_at_a_time
from wecook_core.resources import shared_dir

SCENARIOS = shared_dir() / "data" / "scenarios"
NAMES = ("s301", "s303", "s304")
ROOT = Path(__file__).parents[2]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _wait_for(path: Path, text: str, process: subprocess.Popen[bytes], timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if path.exists() and text in path.read_text(errors="replace"):
            return
        if process.poll() is not None:
            break
        time.sleep(0.2)
    raise AssertionError(f"ray start did not come up:\n{path.read_text(errors='replace')[-3000:]}")


def _wait_for_nodes(ray: str, address: str, count: int, env: dict[str, str], timeout: float = 120.0) -> None:
    """Until `ray status` lists ``count`` active nodes (a node is up before the head counts it)."""
    deadline = time.monotonic() + timeout
    status = ""
    while time.monotonic() < deadline:
        status = subprocess.run([ray, "status", "--address", address], capture_output=True, text=True, env=env,
                                timeout=60).stdout
        active = status.split("Active:", 1)[-1].split("Pending:", 1)[0] if "Active:" in status else ""
        if active.count("node_") >= count:
            return
        time.sleep(1.0)
    raise AssertionError(f"the cluster did not reach {count} nodes:\n{status[-2000:]}")


def _wait_for_port(port: int, timeout: float = 120.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        with socket.socket() as s:
            if s.connect_ex(("127.0.0.1", port)) == 0:
                return
        time.sleep(0.5)
    raise AssertionError(f"nothing listens on port {port}")


def _stop(processes: list[subprocess.Popen[bytes]]) -> None:
    for process in reversed(processes):  # the second node, then the head
        with contextlib.suppress(ProcessLookupError):
            process.send_signal(signal.SIGTERM)  # `ray start --block` shuts its node down on SIGTERM
    for process in reversed(processes):
        with contextlib.suppress(subprocess.TimeoutExpired):
            process.wait(60)
        with contextlib.suppress(ProcessLookupError):  # whatever of its own group is left
            os.killpg(process.pid, signal.SIGKILL)


def _processes_using(folder: Path) -> list[int]:
    found = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            with contextlib.suppress(OSError):
                if str(folder).encode() in (entry / "cmdline").read_bytes():
                    found.append(int(entry.name))
    return found


@contextlib.contextmanager
def local_cluster(cpus_per_node: int = 1) -> Iterator[tuple[str, str]]:
    """A head and a second node on this machine; yields the head's address (HOST:PORT) and its Ray Client
    address (ray://HOST:PORT)."""
    ray = str(Path(sys.executable).parent / "ray")
    temp = Path(tempfile.mkdtemp(prefix="wrc", dir="/tmp"))  # short: Ray's socket paths must fit 107 bytes
    # every node runs this checkout's wecook, as a cluster runs the wecook installed on each node
    path = os.pathsep.join(p for p in (str(ROOT), os.environ.get("PYTHONPATH", "")) if p)
    env = {**os.environ, "RAY_AUTH_MODE": os.environ.get("RAY_AUTH_MODE", "token"), "PYTHONPATH": path}
    port, client = _free_port(), _free_port()
    common = ["--num-cpus", str(cpus_per_node), "--memory", str(2 << 30), "--object-store-memory", str(80 << 20),
              "--temp-dir", str(temp), "--node-ip-address", "127.0.0.1", "--disable-usage-stats", "--block"]
    processes: list[subprocess.Popen[bytes]] = []

    def node(name: str, extra: list[str]) -> None:
        own = ["--dashboard-agent-listen-port", str(_free_port()), "--dashboard-agent-grpc-port", str(_free_port()),
               "--metrics-export-port", str(_free_port()), "--runtime-env-agent-port", str(_free_port()),
               "--node-manager-port", str(_free_port()), "--object-manager-port", str(_free_port())]
        log = temp / f"{name}.log"
        with log.open("wb") as out:
            processes.append(subprocess.Popen([ray, "start", *extra, *common, *own], stdout=out,
                                              stderr=subprocess.STDOUT, env=env, start_new_session=True))
        _wait_for(log, "Ray runtime started", processes[-1])

    try:
        node("head", ["--head", "--port", str(port), "--ray-client-server-port", str(client),
                      "--include-dashboard", "false"])
        node("second", ["--address", f"127.0.0.1:{port}"])
        _wait_for_nodes(ray, f"127.0.0.1:{port}", 2, env)
        _wait_for_port(client)  # the head's Ray Client server comes up on its own time
        yield f"127.0.0.1:{port}", f"ray://127.0.0.1:{client}"
    finally:
        _stop(processes)
        time.sleep(1)
        left = _processes_using(temp)
        for pid in left:  # a Ray process of this cluster that outlived its node: ours, by its temp dir
            with contextlib.suppress(ProcessLookupError):
                os.kill(pid, signal.SIGKILL)
        shutil.rmtree(temp, ignore_errors=True)
        assert not left, f"Ray processes of the test cluster left running: {left}"


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
