"""The run as a video: a fixed camera rendered at a steady rate of simulated time (``wecook execute --camera-hz``).

:class:`CameraObserver` wraps the run's observer: it forwards every call, and from the states the run reports
(every frame's world pose) it renders a view at ``hz`` images per simulated second into ``on_image`` (JPEG,
foxglove.CompressedImage on ``/camera``). It renders its own light copy of the scene in a separate PyBullet
client (DIRECT, the tiny software renderer, no shadows): the table and the objects from their shapes, the arms
from the link meshes of :mod:`.meshes` decimated once more (about 2 % of the URDF's triangles). The simulation's
own client would render the full visual meshes (about 200 000 triangles for two Pandas): ~90 ms an image at
320x240 (~45 ms without shadows), against ~4-7 ms here at 240x180. ``bench/recording.py`` measures the cost at
the default rate.

So that a 3D view can place the image, the camera is a frame of the run: :data:`FRAME` (its optical frame: z
along the view, x to the right of the image, y down, as ROS and Foxglove want) is added to every state's poses
(so it is in ``/tf``), and the camera's :class:`Pinhole` model goes in the run's metadata, from which the
recorder and the live view write a ``foxglove.CameraCalibration`` beside each image (``/camera/calibration``).
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any, Literal

from wecook_core.execution.schedule.observer import FrameInfo, Quat, RunEvent, RunObserver, Shape, Vec3
from wecook_core.recording import foxglove, meshes

DEFAULT_HZ = 2.0
"""Images per simulated second by default."""
SIZE = (240, 180)
"""Pixels of each image."""
EYE, TARGET, FOV = (0.0, -1.5, 1.0), (0.0, 0.0, 0.15), 55.0
"""Where the camera is and looks, in metres from the table frame's origin (the middle of its top), and its
vertical field of view (degrees)."""
JPEG_QUALITY = 80
KEEP = 0.15
"""Share of the recorded meshes' triangles the camera renders (parts of fewer than 100 are kept whole): the
tiny renderer's time is mostly per triangle, and a 320x240 view needs no finer mesh."""
FRAME = "camera"
"""The camera's optical frame in ``/tf``, and the ``frame_id`` of its images and calibration."""


@dataclass(frozen=True)
class Pinhole:
    """A distortion-free pinhole camera with square pixels, as PyBullet's ``computeProjectionMatrixFOV`` renders:
    pixel coordinates have their origin at the centre of the top-left pixel (OpenCV's and ROS's convention)."""

    width: int
    """Pixels."""
    height: int
    """Pixels."""
    fov_deg: float
    """Vertical field of view, degrees."""

    @property
    def focal(self) -> float:
        """fx = fy, pixels."""
        return self.height / 2 / math.tan(math.radians(self.fov_deg) / 2)

    @property
    def centre(self) -> tuple[float, float]:
        """(cx, cy), pixels: where the view's axis lands. Measured, not ``((w - 1) / 2, (h - 1) / 2)``: PyBullet's
        tiny renderer samples each pixel at a corner and flips the rows, so a point on the axis lands on pixel
        (w / 2, h / 2 - 1) (a sphere at the target of a 240x180 view: mask centroid (120.0, 89.0))."""
        return self.width / 2, self.height / 2 - 1

    def calibration(self, ns: int, width: int, height: int) -> dict[str, Any] | None:
        """The foxglove.CameraCalibration of an image of ``width`` x ``height`` taken at ``ns``, or None when the
        image is not this camera's (another size: the executor's own images at action boundaries)."""
        if (width, height) != (self.width, self.height):
            return None
        return foxglove.camera_calibration(ns, width, height, self.focal, self.centre, FRAME)

    def metadata(self) -> dict[str, str]:
        """The run metadata that tells the recorder and the live view which camera the images come from."""
        return {"camera_size": f"{self.width}x{self.height}", "camera_fov_deg": f"{self.fov_deg:g}"}

    @classmethod
    def from_metadata(cls, metadata: Mapping[str, str]) -> Pinhole | None:
        """The camera of :meth:`metadata`, or None when the run says none (or says it wrong)."""
        try:
            width, height = (int(v) for v in metadata["camera_size"].split("x"))
            fov = float(metadata["camera_fov_deg"])
        except (KeyError, ValueError):
            return None
        return cls(width, height, fov) if width > 0 and height > 0 and 0 < fov < 180 else None


def optical_pose(eye: Vec3, target: Vec3, up: Vec3 = (0.0, 0.0, 1.0)) -> tuple[Vec3, Quat]:
    """The world pose of the optical frame of a camera at ``eye`` looking at ``target`` with ``up`` up in the
    image (``computeViewMatrix``'s arguments): z from eye to target, x to the image's right, y down."""
    import numpy as np
    from scipy.spatial.transform import Rotation

    z = np.subtract(target, eye, dtype=float)
    z /= np.linalg.norm(z)
    x = np.cross(z, up)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    quat = Rotation.from_matrix(np.column_stack([x, y, z])).as_quat()
    return (float(eye[0]), float(eye[1]), float(eye[2])), tuple(float(v) for v in quat)  # type: ignore[return-value]


class CameraObserver:
    """Forwards to ``inner`` and adds ``on_image`` calls at ``hz`` per simulated second (first at t = 0)."""

    def __init__(self, inner: RunObserver, hz: float = DEFAULT_HZ, *, size: tuple[int, int] = SIZE,
                 eye: Vec3 = EYE, target: Vec3 = TARGET, keep: float = KEEP) -> None:
        if hz <= 0:
            raise ValueError("camera rate must be positive")
        self.inner = inner
        self.period = 1.0 / hz
        self.size = size
        self.eye, self.target = eye, target
        self.keep = keep
        self.model = Pinhole(size[0], size[1], FOV)
        self.pose: tuple[Vec3, Quat] | None = None
        """The optical frame's world pose (known from the first state: the camera stands where the table is)."""
        self.images = 0
        self.render_seconds = 0.0
        """CPU seconds spent rendering and encoding (this thread)."""
        self._next = 0.0
        self._client: int | None = None
        self._bodies: list[tuple[str, int, tuple[Vec3, Quat]]] = []
        """(frame, body, pose of the body in the frame) of the render scene."""
        self._view: Any = None
        self._projection: Any = None

    # ----------------------------------------------------------------------------- render scene

    def _build(self, frames: Sequence[FrameInfo], plan_yaml: str) -> None:
        import pybullet as p

        client = p.connect(p.DIRECT)
        self._client = client
        visuals = meshes.arm_visuals(meshes.plan_arm_urdfs(plan_yaml))
        for frame in frames:
            visual = visuals.get(frame.frame_id)
            shapes = frame.shapes if visual is None or not visual.models else visual.shapes
            for shape in shapes:
                self._add(frame.frame_id, _shape_visual(p, client, shape), shape.pose)
            for model in visual.models if visual is not None else ():
                for vertices, faces, rgba in meshes.glb_parts(model.glb):
                    vertices, faces = _coarser(vertices, faces, self.keep)
                    scaled = [[float(v[k]) * model.scale[k] for k in range(3)] for v in vertices]
                    shape_id = p.createVisualShape(p.GEOM_MESH, vertices=scaled,
                                                   indices=[int(i) for i in faces.reshape(-1)], rgbaColor=rgba,
                                                   physicsClientId=client)
                    self._add(frame.frame_id, shape_id, model.pose)
        w, h = self.size
        self._projection = p.computeProjectionMatrixFOV(self.model.fov_deg, w / h, 0.05, 6.0)

    def _add(self, frame_id: str, shape_id: int, pose: tuple[Vec3, Quat]) -> None:
        import pybullet as p

        if shape_id < 0 or self._client is None:
            return
        body = p.createMultiBody(0, -1, shape_id, [0, 0, -10], physicsClientId=self._client)
        self._bodies.append((frame_id, body, pose))

    def _place(self, poses: Mapping[str, tuple[Vec3, Quat]]) -> tuple[Vec3, Vec3]:
        """The camera's eye and target in the world (:attr:`eye` and :attr:`target` from the table's origin in
        ``poses``); sets :attr:`pose` the first time."""
        table = poses.get("table", ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.0)))[0]
        eye = tuple(a + b for a, b in zip(table, self.eye, strict=True))
        target = tuple(a + b for a, b in zip(table, self.target, strict=True))
        if self.pose is None:
            self.pose = optical_pose(eye, target)  # type: ignore[arg-type]
        return eye, target  # type: ignore[return-value]

    def render(self, poses: Mapping[str, tuple[Vec3, Quat]]) -> bytes | None:
        """A JPEG of the scene with every frame at ``poses`` (frames not given stay where they were)."""
        import cv2
        import numpy as np
        import pybullet as p

        if self._client is None:
            return None
        c = self._client
        if self._view is None:
            eye, target = self._place(poses)
            self._view = p.computeViewMatrix(list(eye), list(target), [0, 0, 1])
        for frame_id, body, (lp, lq) in self._bodies:
            pose = poses.get(frame_id)
            if pose is not None:
                pos, orn = p.multiplyTransforms(pose[0], pose[1], lp, lq)
                p.resetBasePositionAndOrientation(body, pos, orn, physicsClientId=c)
        w, h = self.size
        image = p.getCameraImage(w, h, self._view, self._projection, renderer=p.ER_TINY_RENDERER, shadow=0,
                                 flags=p.ER_NO_SEGMENTATION_MASK, physicsClientId=c)
        rgb = np.reshape(np.asarray(image[2], dtype=np.uint8), (h, w, 4))[:, :, :3]
        ok, jpeg = cv2.imencode(".jpg", cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR), [cv2.IMWRITE_JPEG_QUALITY, JPEG_QUALITY])
        return jpeg.tobytes() if ok else None

    def close(self) -> None:
        import pybullet as p

        if self._client is not None and p.isConnected(self._client):
            p.disconnect(self._client)
        self._client = None

    # ------------------------------------------------------------------------------- RunObserver

    def on_start(self, frames: Sequence[FrameInfo], plan_yaml: str, seed: int,
                 metadata: Mapping[str, str]) -> None:
        self.inner.on_start(frames, plan_yaml, seed, {**metadata, "camera_hz": f"{1 / self.period:g}",
                                                      **self.model.metadata()})
        self._build(frames, plan_yaml)

    def on_state(self, t: float, poses: Mapping[str, tuple[Vec3, Quat]],
                 joints: Mapping[str, tuple[Sequence[str], Sequence[float]]]) -> None:
        if self.pose is None:
            self._place(poses)
        assert self.pose is not None
        self.inner.on_state(t, {**poses, FRAME: self.pose}, joints)
        if t + 1e-9 >= self._next:
            while self._next <= t + 1e-9:
                self._next += self.period
            clock = time.thread_time()
            jpeg = self.render(poses)
            self.render_seconds += time.thread_time() - clock
            if jpeg is not None:
                self.images += 1
                self.inner.on_image(t, jpeg, *self.size)

    def on_event(self, t: float, event: RunEvent) -> None:
        self.inner.on_event(t, event)

    def on_log(self, t: float, level: Literal["debug", "info", "warning", "error"], message: str) -> None:
        self.inner.on_log(t, level, message)

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        self.inner.on_image(t, jpeg, width, height)

    def on_end(self, t: float) -> None:
        self.close()
        self.inner.on_end(t)


def _coarser(vertices: Any, faces: Any, keep: float) -> tuple[Any, Any]:
    if keep >= 1.0 or len(faces) < 100:
        return vertices, faces
    import fast_simplification
    import numpy as np

    out_v, out_f = fast_simplification.simplify(np.asarray(vertices, dtype=np.float32),
                                                np.asarray(faces, dtype=np.int64), target_reduction=1.0 - keep)
    return (out_v, out_f) if len(out_f) else (vertices, faces)


def _shape_visual(p: Any, client: int, shape: Shape) -> int:
    sx, sy, sz = shape.size
    if shape.kind == "sphere":
        return int(p.createVisualShape(p.GEOM_SPHERE, radius=sx / 2, rgbaColor=shape.color, physicsClientId=client))
    if shape.kind == "cylinder":
        return int(p.createVisualShape(p.GEOM_CYLINDER, radius=sx / 2, length=sz, rgbaColor=shape.color,
                                       physicsClientId=client))
    return int(p.createVisualShape(p.GEOM_BOX, halfExtents=[sx / 2, sy / 2, sz / 2], rgbaColor=shape.color,
                                   physicsClientId=client))
