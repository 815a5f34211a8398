"""A Ray cluster of this machine's own, started with the `ray` CLI as Ray's docs start one: a head and, if asked,
more nodes, each `ray start --block` in its own process group with its own --temp-dir and ports, stopped by
signalling those processes only (never `ray stop`, which would stop every Ray on the machine). Used by the
two-node test and by bench.batch (the speed-up on a cluster that is already running, as a lab's is)."""

from __future__ import annotations

import contextlib
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

ROOT = Path(__file__).parents[2]


_TAKEN: set[int] = set()
"""Ports this process has handed out: the OS may offer a port again once its probe socket is closed, and two
of a cluster's components on one port make `ray start` fail."""


def _free_port() -> int:
    """A free port on this machine, never one handed out before by this process."""
    while True:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = int(s.getsockname()[1])
        if port not in _TAKEN:
            _TAKEN.add(port)
            return port


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
def local_cluster(cpus_per_node: int = 1, nodes: int = 2) -> Iterator[tuple[str, str]]:
    """A head and ``nodes - 1`` more nodes on this machine; yields the head's address (HOST:PORT) and its Ray
    Client address (ray://HOST:PORT)."""
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
        for more in range(1, nodes):
            node(f"node{more}", ["--address", f"127.0.0.1:{port}"])
        _wait_for_nodes(ray, f"127.0.0.1:{port}", nodes, env)
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
