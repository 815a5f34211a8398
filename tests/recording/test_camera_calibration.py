"""The camera in /tf with its calibration: a 3D view projects a point of the world where the image shows it."""

from __future__ import annotations

import base64
import json
from pathlib import Path

import cv2
import numpy as np
import pytest
from mcap.reader import make_reader
from scipy.spatial.transform import Rotation

from wecook_core.execution.schedule.observer import FrameInfo, Shape
from wecook_core.recording import foxglove
from wecook_core.recording.camera import FRAME, CameraObserver, Pinhole, optical_pose
from wecook_core.recording.check import check_recording
from wecook_core.recording.writer import McapRecorder

IDENTITY = (0.0, 0.0, 0.0, 1.0)
TABLE = ((0.1, 0.05, 0.7), IDENTITY)
"""Not at the origin: the camera stands where the table is."""
BALLS = [(0.35, 0.15, 0.78), (-0.25, -0.2, 0.95), (0.05, 0.3, 0.8)]
"""World positions of a small red ball (clear of the table top at 0.7 m), one per image: right and far, left and
high, middle and far."""


def topics(path: Path) -> dict[str, list[dict]]:
    out: dict[str, list[dict]] = {}
    with open(path, "rb") as f:
        for _, channel, message in make_reader(f).iter_messages(log_time_order=True):
            out.setdefault(channel.topic, []).append(json.loads(message.data))
    return out


def red_centroid(jpeg: bytes) -> tuple[np.ndarray, tuple[int, int]]:
    """(u, v) of the red pixels' centroid (u to the right, v down, pixel centres at integers), image (h, w)."""
    image = cv2.imdecode(np.frombuffer(jpeg, np.uint8), cv2.IMREAD_COLOR)
    b, g, r = (image[:, :, k].astype(int) for k in range(3))
    ys, xs = np.nonzero((r > 30) & (r > 2 * g) & (r > 2 * b))
    assert len(xs) > 10, "the ball is in view"
    return np.array([xs.mean(), ys.mean()]), image.shape[:2]


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("camera") / "run.mcap"
    grey = (0.6, 0.6, 0.6, 1.0)
    frames = (FrameInfo("table", (Shape("box", (1.0, 0.8, 0.04), ((0.0, 0.0, -0.02), IDENTITY), grey),)),
              FrameInfo("object/ball", (Shape("sphere", (0.08, 0.08, 0.08), color=(1.0, 0.0, 0.0, 1.0)),)))
    camera = CameraObserver(McapRecorder(path, time_origin_ns=0, layout=False), hz=1.0)
    camera.on_start(frames, "wecook_plan: 1\n", 0, {})
    for k, ball in enumerate(BALLS):
        camera.on_state(float(k), {"table": TABLE, "object/ball": (ball, IDENTITY)}, {"P1": (["j1"], [0.0])})
    camera.on_end(float(len(BALLS) - 1))
    return path


def test_the_camera_frame_and_calibration_project_the_world_where_the_image_shows_it(recording: Path) -> None:
    recorded = topics(recording)
    assert check_recording(recording).ok  # the calibration conforms to its schema
    images, calibrations = recorded["/camera"], recorded["/camera/calibration"]
    assert len(images) == len(calibrations) == len(BALLS)
    for image, calibration, tf, ball in zip(images, calibrations, recorded["/tf"], BALLS, strict=True):
        assert calibration["timestamp"] == image["timestamp"] and calibration["frame_id"] == image["frame_id"] == FRAME
        camera = next(t for t in tf["transforms"] if t["child_frame_id"] == FRAME)
        assert camera["parent_frame_id"] == "world"
        centroid, (h, w) = red_centroid(base64.b64decode(image["data"]))
        assert (calibration["width"], calibration["height"]) == (w, h) == (240, 180)
        rotation = Rotation.from_quat([camera["rotation"][k] for k in "xyzw"])
        origin = np.array([camera["translation"][k] for k in "xyz"])
        x, y, z = rotation.inv().apply(np.subtract(ball, origin))  # the ball in the optical frame
        assert z > 0  # in front of the camera
        projected = np.reshape(calibration["P"], (3, 4)) @ [x, y, z, 1.0]
        uv = projected[:2] / projected[2]
        k = np.reshape(calibration["K"], (3, 3))
        assert uv == pytest.approx((k @ [x / z, y / z, 1.0])[:2])
        assert np.linalg.norm(uv - centroid) < 0.5, (uv, centroid)  # within half a pixel of where the image shows it


def test_the_camera_stands_where_the_table_is_and_looks_at_it() -> None:
    position, quat = optical_pose((0.0, -1.5, 1.0), (0.0, 0.0, 0.15))
    axes = Rotation.from_quat(quat).as_matrix()
    assert position == (0.0, -1.5, 1.0)
    forward = np.array([0.0, 1.5, -0.85]) / np.linalg.norm([0.0, 1.5, -0.85])
    assert axes[:, 2] == pytest.approx(forward)  # z: along the view
    assert axes[:, 0] == pytest.approx([1.0, 0.0, 0.0])  # x: the image's right (+x of the world, seen from -y)
    assert axes[:, 1][2] < 0  # y: down in the image
    pinhole = Pinhole(240, 180, 55.0)
    assert pinhole.focal == pytest.approx(90 / np.tan(np.radians(27.5)))
    assert Pinhole.from_metadata(pinhole.metadata()) == pinhole
    assert Pinhole.from_metadata({}) is None
    assert Pinhole.from_metadata({"camera_size": "wide", "camera_fov_deg": "55"}) is None
    assert pinhole.calibration(0, 320, 240) is None  # another camera's image gets no calibration
    message = pinhole.calibration(5, 240, 180)
    assert message is not None and not foxglove.SCHEMAS["foxglove.CameraCalibration"]["additionalProperties"]
