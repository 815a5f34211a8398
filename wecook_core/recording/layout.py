"""The Foxglove layout for a run: 3D view (meshes, scene, transforms, the camera's image where the camera stands),
camera, joint positions, events and log.

Built with foxglove-sdk's layout types (``foxglove.layouts``, the ``live`` extra) and shipped as
``wecook_core/assets/foxglove_layout.json`` so that recording needs no SDK; ``python -m
wecook_core.recording.layout`` rewrites the asset, and a test checks the asset is what this module builds.
"""

from __future__ import annotations

import json
import sys
from typing import Any

JOINT_PLOT = [f"/joint_states.position[{k}]" for k in range(7)]
"""P1's seven arm joints (names P1/panda_joint1..7 come first in every message)."""


def build_layout() -> dict[str, Any]:
    import foxglove.layouts as fl

    three_d = fl.ThreeDeePanel(title="arms and table", config=fl.ThreeDeeConfig(
        follow_tf="world", fixed_frame="world",
        topics={"/robot": fl.BaseRendererSceneUpdateTopicSettings(visible=True),
                "/scene": fl.BaseRendererSceneUpdateTopicSettings(visible=True),
                # the camera's image where the camera stands (its frame in /tf, its calibration)
                "/camera": fl.BaseRendererImageTopicSettings(visible=True, camera_info_topic="/camera/calibration",
                                                             distance=0.4),
                "/camera/calibration": fl.BaseRendererCameraTopicSettings(visible=True, distance=0.4)},
        camera_state=fl.ThreeDeeCameraState(distance=2.4, phi=55.0, theta_offset=35.0, target_offset=(0, 0, 0.7),
                                            perspective=True)))
    camera = fl.ImagePanel(title="camera", config=fl.ImageConfig(image_mode=fl.ImageModeConfig(
        image_topic="/camera", calibration_topic="/camera/calibration")))
    plot = fl.PlotPanel(title="P1 joint positions (rad)", config=fl.PlotConfig(
        paths=[fl.PlotSeries(value=path, label=f"P1 joint {k + 1}", timestamp_method="receiveTime")
               for k, path in enumerate(JOINT_PLOT)], show_legend=True))
    events = fl.TablePanel(title="plan events", config=fl.TableConfig(topic_path="/plan/events"))
    log = fl.LogPanel(title="log", config=fl.LogConfig(topic_to_render="/log"))
    left = fl.SplitContainer(direction="column", items=[fl.SplitItem(proportion=2.0, content=three_d),
                                                        fl.SplitItem(proportion=1.0, content=plot)])
    right = fl.SplitContainer(direction="column", items=[fl.SplitItem(proportion=1.0, content=camera),
                                                         fl.SplitItem(proportion=1.0, content=events),
                                                         fl.SplitItem(proportion=1.0, content=log)])
    layout = fl.Layout(content=fl.SplitContainer(direction="row", items=[fl.SplitItem(proportion=2.0, content=left),
                                                                         fl.SplitItem(proportion=1.0, content=right)]))
    data: dict[str, Any] = json.loads(layout.to_json())
    return data


def layout_text() -> str:
    return json.dumps(build_layout(), indent=1, sort_keys=True) + "\n"


if __name__ == "__main__":
    from wecook_core.recording.writer import LAYOUT

    LAYOUT.write_text(layout_text())
    print(f"wrote {LAYOUT}", file=sys.stderr)
