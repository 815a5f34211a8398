"""`wecook execute --live`: a Foxglove WebSocket client on loopback receives the run's transforms while it goes."""

from __future__ import annotations

import json
import signal
import struct
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from websockets.exceptions import ConnectionClosed, ConnectionClosedOK
from websockets.sync.client import connect

from wecook_core.execution.plan_samples import ONE_ARM_CUTS
from wecook_core.recording.live import LiveServer
from wecook_core.recording.synthetic_run import synthetic_run

SUBPROTOCOL = "foxglove.sdk.v1"
"""The protocol foxglove-sdk's server speaks (Foxglove's WebSocket protocol, as the app connects)."""


def _subscribe_all(ws: object, deadline: float) -> dict[int, str]:
    """Read until the server advertises its channels, subscribe to each; subscription id -> topic."""
    while time.monotonic() < deadline:
        message = ws.recv(timeout=max(deadline - time.monotonic(), 0.01))  # type: ignore[attr-defined]
        if isinstance(message, str) and json.loads(message)["op"] == "advertise":
            channels = json.loads(message)["channels"]
            subs = {k: c for k, c in enumerate(channels)}
            ws.send(json.dumps({"op": "subscribe",  # type: ignore[attr-defined]
                                "subscriptions": [{"id": k, "channelId": c["id"]} for k, c in subs.items()]}))
            return {k: c["topic"] for k, c in subs.items()}
    raise AssertionError("no advertise from the server")


def _data(message: bytes, subs: dict[int, str]) -> tuple[str, int, dict] | None:
    if message[0] != 1:  # 1: message data; 2: time
        return None
    sub, ns = struct.unpack_from("<IQ", message, 1)
    return subs[sub], ns, json.loads(message[13:])


@pytest.mark.slow
def test_server_sends_every_topic_and_meshes_to_a_late_subscriber() -> None:
    with LiveServer(port=0, live_hz=1000) as server:
        assert server.url == f"ws://127.0.0.1:{server.port}"
        synthetic_run(server, actions=1, seconds_per_action=0.2, end=False)  # before anyone connects
        with connect(server.url, subprotocols=[SUBPROTOCOL]) as ws:
            subs = _subscribe_all(ws, time.monotonic() + 10)
            assert set(subs.values()) >= {"/tf", "/scene", "/joint_states", "/plan/events", "/log", "/camera"}
            got: dict[str, list[dict]] = {}
            deadline = time.monotonic() + 20
            while time.monotonic() < deadline and "/scene" not in got:  # sent again once the client subscribed
                message = ws.recv(timeout=deadline - time.monotonic())
                if isinstance(message, bytes) and (data := _data(message, subs)) is not None:
                    got.setdefault(data[0], []).append(data[2])
            time.sleep(0.2)
            synthetic_run(server, actions=2, seconds_per_action=0.5, wall_per_sim=0.5)
            while time.monotonic() < deadline and not {"/tf", "/scene", "/joint_states", "/plan/events"} <= set(got):
                try:
                    message = ws.recv(timeout=1.0)
                except TimeoutError:
                    continue
                if isinstance(message, bytes) and (data := _data(message, subs)) is not None:
                    got.setdefault(data[0], []).append(data[2])
    assert got["/tf"][0]["transforms"][0]["parent_frame_id"] == "world"
    assert {e["id"] for e in got["/scene"][0]["entities"]} >= {"table", "object/knife"}  # sent again on subscribe
    assert got["/joint_states"][0]["name"][0] == "P1/joint1"


@pytest.mark.sim
@pytest.mark.slow
def test_execute_live_serves_transforms_while_the_run_goes(tmp_path: Path) -> None:
    plan = tmp_path / "plan.yaml"
    plan.write_text(ONE_ARM_CUTS)
    child = subprocess.Popen([sys.executable, "-m", "wecook_tui.cli", "execute", str(plan), "--no-record", "--live",
                              "--port", "0", "--realtime"], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True)
    try:
        assert child.stdout is not None
        url = ""
        for line in child.stdout:
            if line.startswith("live view: "):
                url = line.split()[2]
                break
        assert url.startswith("ws://127.0.0.1:"), url  # loopback only
        transforms, robot = [], []
        with connect(url, subprotocols=[SUBPROTOCOL]) as ws:
            deadline = time.monotonic() + 60
            subs = _subscribe_all(ws, deadline)
            while time.monotonic() < deadline and (len(transforms) < 5 or not robot):
                try:
                    message = ws.recv(timeout=1.0)
                except TimeoutError:
                    continue
                data = _data(message, subs) if isinstance(message, bytes) else None
                if data is not None and data[0] == "/tf":
                    transforms.append(data)
                elif data is not None and data[0] == "/robot":
                    robot.append(data)
            assert child.poll() is None, "the run ended before the client got its transforms"
        assert len(transforms) >= 5
        frames = {t["child_frame_id"] for t in transforms[-1][2]["transforms"]}
        assert {"P1/panda_link0", "P1/panda_hand", "table", "object/knife"} <= frames
        assert transforms[-1][1] > transforms[0][1]  # the clock moves: these are live states
        assert robot and {e["frame_id"] for e in robot[0][2]["entities"]} >= {"P1/panda_link3"}
    finally:
        child.send_signal(signal.SIGTERM)
        child.communicate(timeout=60)
    assert child.returncode == 130


@pytest.mark.slow
def test_a_watched_run_ends_with_everything_delivered_and_a_close_frame() -> None:
    """foxglove-sdk's ``stop`` drops what is still queued for a client. A viewer that is megabytes behind when the
    run ends (large images, read only once the run is over) still gets the run's last event and log line, the end
    status and every image with its calibration, then a close frame (the closing handshake completes)."""
    server = LiveServer(port=0, live_hz=1000)  # with linger_s=0 (stop at once) run_end was lost 4 times in 4
    got: dict[str, list[dict]] = {}
    statuses: list[dict] = []
    over = threading.Event()
    with connect(server.url, subprotocols=[SUBPROTOCOL], max_size=None, max_queue=1) as ws:
        subs = _subscribe_all(ws, time.monotonic() + 10)
        time.sleep(0.3)  # the subscriptions reach the server

        def run() -> None:
            synthetic_run(server, actions=4, seconds_per_action=0.2, jpeg=b"\xff\xd8" + bytes(1_500_000) + b"\xff\xd9")
            over.set()
            server.close()

        runner = threading.Thread(target=run)
        runner.start()
        assert over.wait(60)  # the viewer is behind: it reads only now
        with pytest.raises(ConnectionClosed) as closed:
            while True:
                message = ws.recv(timeout=30)
                if isinstance(message, str) and json.loads(message)["op"] == "status":
                    statuses.append(json.loads(message))
                elif isinstance(message, bytes) and (data := _data(message, subs)) is not None:
                    got.setdefault(data[0], []).append(data[2])
        runner.join()
    assert isinstance(closed.value, ConnectionClosedOK) and closed.value.rcvd is not None  # a close frame came
    assert got["/plan/events"][-1]["kind"] == "run_end"
    assert got["/log"][-1]["message"].startswith("run ended at")
    assert len(got["/camera"]) == len(got["/camera/calibration"]) == 8
    assert got["/camera/calibration"][0]["width"] == 320 and got["/camera/calibration"][0]["frame_id"] == "camera"
    assert [s["message"] for s in statuses] == ["run ended at 0.80 s simulated"]


def test_closing_an_unwatched_server_does_not_wait() -> None:
    server = LiveServer(port=0, linger_s=30.0)
    synthetic_run(server, actions=1, seconds_per_action=0.2)
    clock = time.monotonic()
    server.close()
    assert time.monotonic() - clock < 5.0
