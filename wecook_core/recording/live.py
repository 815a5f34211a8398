"""Serving a run live over Foxglove's WebSocket protocol (foxglove-sdk), so Foxglove can connect and watch.

:class:`LiveServer` is a :class:`~wecook_core.execution.schedule.observer.RunObserver`: it publishes the same topics,
schemas and JSON messages as the recording (:mod:`.recorder`), from a server the SDK runs on its own threads,
bound to ``127.0.0.1`` only. Its cost to the run is kept small:

- states (``/tf``, ``/joint_states``) are sent at most :data:`LIVE_HZ` times per *wall* second (a viewer draws no
  faster; the simulation usually runs many times faster than real time), and not built at all while no client
  subscribes to them;
- the SDK queues each client's messages and drops the oldest when a client is slow (``message_backlog_size``):
  a slow viewer never blocks the run;
- ``/robot`` (the link meshes, about 1 MB) and ``/scene`` are sent again to each client that subscribes to
  them, since a client that connects mid-run would otherwise never get them.

The server advertises the ``time`` capability and broadcasts the simulated clock, so Foxglove's time follows
the run. Needs the ``live`` extra (``pip install 'wecook[live]'``).

The end of a run, as a viewer sees it (foxglove-sdk 0.30.3, measured with the ``websockets`` client): ``on_end``
publishes a status ("run ended at ... s"); :meth:`LiveServer.close` then waits :data:`LINGER_S` while a client is
subscribed (the SDK tells nothing of its queues; the wait ends early when every client has left), so that what was
queued reaches the viewer, and stops the server, which sends each client a close frame and completes the closing
handshake. Without the wait the SDK's ``stop`` drops what is still queued: the viewer of a short run missed its
``run_end`` in 4 of 20 trials, and always when it was a few megabytes behind. Not in our hands: the close frame
carries no status code (clients report 1005, "no status"), ``stop`` takes none; and the SDK accepts only the
``foxglove.sdk.v1`` subprotocol (a client offering only ``foxglove.websocket.v1``, as older Foxglove Studio and
Lichtblick do, gets HTTP 400), a constant of its handshake that ``start_server`` has no option for.
"""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Mapping, Sequence
from typing import Any, Literal

from wecook_core.errors import InputError
from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, Vec3
from wecook_core.recording import foxglove, meshes
from wecook_core.recording.camera import Pinhole

LIVE_HZ = 30.0
"""States sent per wall-clock second at most."""
LINGER_S = 1.0
"""Wall seconds :meth:`LiveServer.close` waits, while a client is subscribed, before stopping the server (loopback
delivers megabytes in milliseconds; a second covers a viewer that is behind)."""
DEFAULT_PORT = 8765
HOST = "127.0.0.1"


def _sdk() -> Any:
    try:
        import foxglove as sdk
    except ImportError:
        raise InputError(None, "--live needs foxglove-sdk: pip install 'wecook[live]'") from None
    return sdk


class LiveServer:
    """Serves a run on ``ws://127.0.0.1:<port>`` while it goes (``port=0``: any free port, see :attr:`port`).

    The server starts in the constructor (so the address can be shown before the run) and stops in
    :meth:`close` (``on_end`` does not stop it: call :meth:`close`, or use it as a context manager)."""

    def __init__(self, port: int = DEFAULT_PORT, *, time_origin_ns: int | None = None, live_hz: float = LIVE_HZ,
                 meshes: bool = True, linger_s: float = LINGER_S) -> None:
        sdk = _sdk()
        self._sdk = sdk
        self.linger_s = linger_s
        self.time_origin_ns = time.time_ns() if time_origin_ns is None else int(time_origin_ns)
        self.meshes = meshes
        self._period = 1.0 / live_hz if live_hz else 0.0
        self._last_wall = -1e9
        self._latched: dict[str, bytes] = {}
        self._latched_ns: dict[str, int] = {}
        self._lock = threading.Lock()
        self._last_joints: tuple[float, list[float]] | None = None
        self._camera: Pinhole | None = None
        self.sent = 0
        """Messages handed to the server so far."""
        self._context = sdk.Context()
        self._channels: dict[str, Any] = {}
        for topic, schema_name in foxglove.TOPIC_SCHEMAS.items():
            schema = sdk.Schema(name=schema_name, encoding="jsonschema",
                                data=json.dumps(foxglove.SCHEMAS[schema_name]).encode())
            self._channels[topic] = sdk.Channel(topic, schema=schema, message_encoding="json",
                                                context=self._context)
        listener = _resend_listener(self)
        try:
            self._server: Any = sdk.start_server(
                name="wecook", host=HOST, port=port, context=self._context, server_listener=listener,
                capabilities=[sdk.Capability.Time], message_backlog_size=4096)
        except Exception as error:  # the SDK raises RuntimeError for a port in use
            raise InputError(None, f"cannot serve on {HOST}:{port}: {error}") from None
        self.port = int(self._server.port)
        self.url = f"ws://{HOST}:{self.port}"
        self._closed = False

    # ------------------------------------------------------------------------------------ sending

    def _ns(self, t: float) -> int:
        return self.time_origin_ns + max(round(t * 1e9), 0)

    def _send(self, topic: str, ns: int, message: Mapping[str, Any] | bytes) -> None:
        if self._closed:
            return
        data = message if isinstance(message, bytes) else json.dumps(message, separators=(",", ":")).encode()
        self._channels[topic].log(data, log_time=ns)
        self.sent += 1

    def resend(self, topic: str) -> None:
        """Send a latched topic's message again (a client subscribed to it)."""
        with self._lock:
            if topic in self._latched:
                self._send(topic, self._latched_ns[topic], self._latched[topic])

    # ------------------------------------------------------------------------------- RunObserver

    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int,
                 metadata: Mapping[str, str]) -> None:
        scene_frames, robot = meshes.drawn_frames(frames, plan_yaml, meshes=self.meshes)
        self._camera = Pinhole.from_metadata(metadata)
        ns = self._ns(0.0)
        with self._lock:
            if robot:
                self._latched["/robot"] = json.dumps(foxglove.robot_update(ns, robot)).encode()
            self._latched["/scene"] = json.dumps(foxglove.scene_update(ns, scene_frames)).encode()
            for topic, data in self._latched.items():
                self._latched_ns[topic] = ns
                self._send(topic, ns, data)
            self._send("/log", ns, foxglove.log(ns, "info", f"run started: seed {seed}"))

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        wall = time.monotonic()
        if wall - self._last_wall < self._period:
            return
        self._last_wall = wall
        ns = self._ns(t)
        with self._lock:
            self._server.broadcast_time(ns)
            if self._channels["/tf"].has_sinks():
                self._send("/tf", ns, foxglove.frame_transforms_json(ns, poses))
            if joints and self._channels["/joint_states"].has_sinks():
                names = [f"{agent}/{name}" for agent, (arm, _) in joints.items() for name in arm]
                positions = [float(v) for _, values in joints.values() for v in values]
                last, velocities = self._last_joints, [0.0] * len(positions)
                if last is not None and t > last[0] and len(last[1]) == len(positions):
                    velocities = [(a - b) / (t - last[0]) for a, b in zip(positions, last[1], strict=True)]
                self._last_joints = (t, positions)
                self._send("/joint_states", ns, foxglove.joint_state(ns, names, positions, velocities))

    def on_event(self, t: float, event: RunEvent) -> None:
        ns = self._ns(t)
        with self._lock:
            self._send("/plan/events", ns, foxglove.run_event(ns, event))

    def on_log(self, t: float, level: Literal["debug", "info", "warning", "error"], message: str) -> None:
        ns = self._ns(t)
        with self._lock:
            self._send("/log", ns, foxglove.log(ns, level, message))

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        ns = self._ns(t)
        with self._lock:
            if self._channels["/camera"].has_sinks():
                self._send("/camera", ns, foxglove.compressed_image(ns, jpeg))
            calibration = self._camera.calibration(ns, width, height) if self._camera is not None else None
            if calibration is not None and self._channels["/camera/calibration"].has_sinks():
                self._send("/camera/calibration", ns, calibration)

    def on_end(self, t: float) -> None:
        ns = self._ns(t)
        with self._lock:
            self._server.broadcast_time(ns)
            self._send("/log", ns, foxglove.log(ns, "info", f"run ended at {t:.2f} s simulated"))
            if not self._closed:
                self._server.publish_status(f"run ended at {t:.2f} s simulated", self._sdk.StatusLevel.Info, id="run")

    # ------------------------------------------------------------------------------------ closing

    def watched(self) -> bool:
        """A client is subscribed to some topic."""
        return any(channel.has_sinks() for channel in self._channels.values())

    def close(self) -> None:
        """Stop the server (idempotent), after :attr:`linger_s` wall seconds while a client is subscribed (so it gets
        what is still queued for it; no wait when nobody watches)."""
        with self._lock:
            if self._closed:
                return
            self._closed = True
        deadline = time.monotonic() + self.linger_s
        while self.watched() and time.monotonic() < deadline:
            time.sleep(0.05)
        self._server.stop()

    def __enter__(self) -> LiveServer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _resend_listener(server: LiveServer) -> Any:
    """The SDK's ServerListener: a client subscribing to ``/robot`` or ``/scene`` gets its message again."""
    listener: Any = _sdk().ServerListener

    class Resend(listener):
        def on_subscribe(self, client: Any, channel: Any) -> None:
            if channel.topic in ("/robot", "/scene"):
                threading.Thread(target=server.resend, args=(channel.topic,), daemon=True).start()

    return Resend()
