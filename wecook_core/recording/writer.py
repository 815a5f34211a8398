"""Recording a run into one MCAP file (JSON messages, Foxglove schemas), readable even if the run is killed.

Topics: ``/tf`` (foxglove.FrameTransforms: every frame's pose in ``world``), ``/robot`` (foxglove.SceneUpdate:
each arm link's meshes from its URDF as embedded GLB models, written once, see :mod:`.meshes`), ``/scene``
(foxglove.SceneUpdate: the table's and the objects' shapes in their colours, and links without meshes; repeated
at every flush so a viewer that seeks still has it), ``/joint_states`` (ROS 2 sensor_msgs/msg/JointState layout:
both arms, names ``<pid>/<joint>``, positions and velocities), ``/plan/events`` (wecook.RunEvent), ``/log``
(foxglove.Log), ``/camera`` (foxglove.CompressedImage: at action boundaries, or at ``--camera-hz``), and
``/camera/calibration`` (foxglove.CameraCalibration, beside each image of a camera the run's metadata describes:
see :class:`~wecook_core.recording.camera.Pinhole`; the camera's optical frame is then in ``/tf``). The plan
goes in as the attachment ``plan.yaml``; versions, seed and the time origin as metadata ``wecook``. A Foxglove
layout (3D, camera, joint plot, events, log: ``assets/foxglove_layout.json``) is written beside the file as
``<name>.layout.json``.

Durability: at most every ``flush_every_s`` seconds of wall time the writer closes the chunk in progress and
flushes the file (mcap 1.6.0 ``Writer.flush``), so a process killed with SIGKILL leaves every message up to the
last flush in complete chunks. The file then lacks its summary and footer: the seeking reader rejects it, a
``NonSeekingReader`` reads it, and :func:`wecook_core.recording.check.recover_recording` rewrites it whole.

States (``/tf`` and ``/joint_states``) are kept at most ``state_hz`` times per simulated second (default 50:
smooth playback; the executor may report every physics step); events, logs and images are all kept.

Log times are ``time_origin_ns + t * 1e9`` where ``t`` is the simulated time the executor reports; the origin is
the wall clock when recording starts unless given (pass 0 for byte-identical recordings of identical runs).
"""

from __future__ import annotations

import contextlib
import json
import platform
import shutil
import threading
import time
from collections.abc import Callable, Mapping, Sequence
from importlib import metadata as importlib_metadata
from pathlib import Path
from typing import IO, Any, Literal

from mcap.well_known import MessageEncoding, SchemaEncoding
from mcap.writer import CompressionType, Writer

from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, Vec3
from wecook_core.recording import foxglove, meshes
from wecook_core.recording.camera import Pinhole
from wecook_core.resources import ASSETS_DIR

LAYOUT = ASSETS_DIR / "foxglove_layout.json"
"""The Foxglove layout shipped with wecook (import it in Foxglove: Layouts > Import from file)."""


def layout_path(recording: str | Path) -> Path:
    """Where the layout of a recording is written: ``<name>.layout.json`` beside it."""
    recording = Path(recording)
    return recording.with_name(recording.stem + ".layout.json")

PACKAGES: tuple[str, ...] = ("wecook", "pybullet", "ompl", "mcap")


def software_versions() -> dict[str, str]:
    """Versions of wecook, the libraries a run depends on, and Python."""
    versions = {}
    for package in PACKAGES:
        try:
            versions[package] = importlib_metadata.version(package)
        except importlib_metadata.PackageNotFoundError:
            versions[package] = "not installed"
    versions["python"] = platform.python_version()
    return versions


def _dumps(message: Mapping[str, Any]) -> bytes:
    return json.dumps(message, separators=(",", ":"), default=str).encode()


class McapRecorder:
    """A :class:`~wecook_core.execution.schedule.observer.RunObserver` writing an MCAP file.

    Use it as a context manager or call :meth:`close` (``on_end`` closes it too): a recorder that is never
    closed leaves a file that only a non-seeking reader (or ``wecook runs recover``) reads.
    """

    def __init__(self, path: str | Path, *, flush_every_s: float = 1.0, time_origin_ns: int | None = None,
                 state_hz: float | None = 50.0, compression: Literal["zstd", "lz4", "none"] = "zstd",
                 on_flush: Callable[[int], None] | None = None, meshes: bool = True,
                 layout: bool = True, scene_every_s: float = 1.0) -> None:
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.meshes = meshes
        """Draw arm links with their URDF meshes (``/robot``); else as the boxes the executor gives."""
        self.layout = layout
        self.flush_every_s = flush_every_s
        """Wall seconds between flushes (what a crash can lose): the only thing in the file the machine's speed
        decides, and it decides where chunks end, never what messages there are."""
        self.scene_every_s = scene_every_s
        """Simulated seconds between repeats of ``/scene`` (a reader that seeks, or the part of a file a crash
        left, can draw the table and objects from the last one). Repeated at flushes (wall time) it made the
        messages depend on the machine's load: the same plan and seed wrote 17 and 32 ``/scene`` messages."""
        self._last_scene: float | None = None
        self.time_origin_ns = time.time_ns() if time_origin_ns is None else int(time_origin_ns)
        self.on_flush = on_flush
        """Called after each flush with :attr:`flushed_messages`."""
        self.message_count = 0
        """Messages handed to the writer so far."""
        self.flushed_messages = 0
        """Messages that were in the file (flushed to the OS) at the last flush."""
        self._stream: IO[bytes] = open(self.path, "wb")  # noqa: SIM115 (closed in close())
        kind = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}[compression]
        self._writer = Writer(self._stream, compression=kind, enable_data_crcs=True)
        self._writer.start(profile="", library="wecook")
        self._channels: dict[str, int] = {}
        schema_ids = {name: self._writer.register_schema(name, SchemaEncoding.JSONSchema,
                                                         json.dumps(schema).encode())
                      for name, schema in foxglove.SCHEMAS.items()}
        for topic, schema_name in foxglove.TOPIC_SCHEMAS.items():
            self._channels[topic] = self._writer.register_channel(topic, MessageEncoding.JSON,
                                                                  schema_ids[schema_name])
        self._frames: tuple[FrameInfo, ...] = ()
        self._last_ns = 0
        self._last_flush = time.monotonic()
        self._state_period = 1.0 / state_hz if state_hz else 0.0
        self._last_state: float | None = None
        self._last_joints: tuple[float, list[float]] | None = None
        self._saw_run_end = False
        self._camera: Pinhole | None = None
        """The camera the run's metadata describes (its images get a calibration)."""
        self._closed = False
        self._lock = threading.Lock()
        if layout and LAYOUT.is_file():
            with contextlib.suppress(OSError):  # the recording matters, the layout is a convenience
                shutil.copyfile(LAYOUT, layout_path(self.path))

    # ------------------------------------------------------------------------------------ writing

    def _ns(self, t: float) -> int:
        ns = self.time_origin_ns + max(round(t * 1e9), 0)
        self._last_ns = max(self._last_ns, ns)
        return ns

    def _write(self, topic: str, ns: int, message: Mapping[str, Any] | bytes) -> None:
        if self._closed:
            return
        data = message if isinstance(message, bytes) else _dumps(message)
        self._writer.add_message(self._channels[topic], log_time=ns, data=data, publish_time=ns)
        self.message_count += 1

    def _maybe_flush(self) -> None:
        if time.monotonic() - self._last_flush >= self.flush_every_s:
            self._flush()

    def _flush(self) -> None:
        if self._closed:
            return
        self._writer.flush()
        self._last_flush = time.monotonic()
        self.flushed_messages = self.message_count
        if self.on_flush is not None:
            self.on_flush(self.flushed_messages)

    def flush(self) -> None:
        """Close the chunk in progress and flush the file now."""
        with self._lock:
            self._flush()

    # ------------------------------------------------------------------------------- RunObserver

    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int,
                 metadata: Mapping[str, str]) -> None:
        with self._lock:
            self._frames, robot = meshes.drawn_frames(frames, plan_yaml, meshes=self.meshes)
            self._camera = Pinhole.from_metadata(metadata)
            ns = self._ns(0.0)
            self._writer.add_attachment(create_time=ns, log_time=ns, name="plan.yaml",
                                        media_type="application/yaml", data=plan_yaml.encode())
            info = {**software_versions(), "seed": str(seed), "time_origin_ns": str(self.time_origin_ns),
                    **{str(k): str(v) for k, v in metadata.items()}}
            self._writer.add_metadata("wecook", info)
            if robot:
                self._write("/robot", ns, foxglove.robot_update(ns, robot))
            self._write("/scene", ns, foxglove.scene_update(ns, self._frames))
            self._last_scene = 0.0
            self._write("/log", ns, foxglove.log(ns, "info", f"run started: seed {seed}, {len(self._frames)} frames, "
                                                 f"wecook {info['wecook']}"))
            self._flush()

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        with self._lock:
            if self._last_state is not None and t - self._last_state < self._state_period - 1e-9:
                return
            self._last_state = t
            ns = self._ns(t)
            self._write("/tf", ns, foxglove.frame_transforms_json(ns, poses))
            if joints:
                self._write("/joint_states", ns, self._joint_state(t, ns, joints))
            if self._frames and self._last_scene is not None and t - self._last_scene >= self.scene_every_s - 1e-9:
                self._last_scene = t  # repeated on simulated time, so the messages are the run's alone
                self._write("/scene", ns, foxglove.scene_update(ns, self._frames))
            self._maybe_flush()

    def _joint_state(self, t: float, ns: int, joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]
                     ) -> dict[str, Any]:
        names = [f"{agent}/{name}" for agent, (arm, _) in joints.items() for name in arm]
        positions = [float(v) for _, values in joints.values() for v in values]
        velocities = [0.0] * len(positions)
        last = self._last_joints
        if last is not None and t > last[0] and len(last[1]) == len(positions):
            dt = t - last[0]
            velocities = [(a - b) / dt for a, b in zip(positions, last[1], strict=True)]
        self._last_joints = (t, positions)
        return foxglove.joint_state(ns, names, positions, velocities)

    def on_event(self, t: float, event: RunEvent) -> None:
        with self._lock:
            ns = self._ns(t)
            self._write("/plan/events", ns, foxglove.run_event(ns, event))
            self._saw_run_end = self._saw_run_end or event.kind == "run_end"
            self._maybe_flush()

    def on_log(self, t: float, level: Literal["debug", "info", "warning", "error"], message: str) -> None:
        with self._lock:
            ns = self._ns(t)
            self._write("/log", ns, foxglove.log(ns, level, message))
            self._maybe_flush()

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        with self._lock:
            ns = self._ns(t)
            self._write("/camera", ns, foxglove.compressed_image(ns, jpeg))
            calibration = self._camera.calibration(ns, width, height) if self._camera is not None else None
            if calibration is not None:
                self._write("/camera/calibration", ns, calibration)
            self._maybe_flush()

    def on_end(self, t: float) -> None:
        with self._lock:
            ns = self._ns(t)
            if not self._closed and not self._saw_run_end:
                self._write("/plan/events", ns, foxglove.run_event(ns, RunEvent("run_end")))
                self._saw_run_end = True
            self._write("/log", ns, foxglove.log(ns, "info", f"run ended at {t:.2f} s simulated"))
        self.close()

    # ------------------------------------------------------------------------------------ closing

    def close(self) -> None:
        """Write the summary and footer and close the file (idempotent)."""
        with self._lock:
            if self._closed:
                return
            self._writer.finish()
            self._stream.close()
            self._closed = True
            self.flushed_messages = self.message_count

    def __enter__(self) -> McapRecorder:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
