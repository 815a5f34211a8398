"""What Foxglove sees of a run: arm meshes from the URDF, the shipped layout, the steady camera, and a real
recording whose every message conforms to its channel's JSON Schema (checked with the jsonschema library)."""

from __future__ import annotations

import base64
import json
from pathlib import Path

import cv2
import jsonschema
import numpy as np
import pytest
from mcap.reader import make_reader

from wecook_core.recording import foxglove, meshes
from wecook_core.recording.camera import CameraObserver
from wecook_core.recording.layout import layout_text
from wecook_core.recording.synthetic_run import synthetic_run
from wecook_core.recording.writer import LAYOUT, McapRecorder, layout_path

PANDA = meshes._robot_path("franka_panda/panda.urdf")


@pytest.fixture(autouse=True)
def mesh_cache(tmp_path_factory: pytest.TempPathFactory, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path_factory.getbasetemp() / "cache"))


class Images:
    """Keeps the images an observer gets (and ignores the rest)."""

    def __init__(self) -> None:
        self.images: list[tuple[float, bytes, int, int]] = []

    def __getattr__(self, name: str) -> object:
        return lambda *args: None

    def on_image(self, t: float, jpeg: bytes, width: int, height: int) -> None:
        self.images.append((t, jpeg, width, height))


@pytest.mark.slow
def test_panda_links_get_their_visual_meshes_decimated_in_the_right_place() -> None:
    import trimesh

    visuals = meshes.robot_visuals(PANDA)
    with_models = [link for link, v in visuals.items() if v.models]
    assert {f"panda_link{k}" for k in range(8)} | {"panda_hand", "panda_leftfinger"} <= set(with_models)
    link6 = visuals["panda_link6"].models[0]
    assert link6.glb[:4] == b"glTF"
    parts = meshes.glb_parts(link6.glb)
    assert len({p[2] for p in parts}) >= 2  # white shell and dark joints keep their own colours
    faces = sum(len(p[1]) for p in parts)
    assert 1000 < faces < 21620 * 0.2  # the visual OBJ has 21620 triangles
    for link in ("panda_link3", "panda_hand"):  # the visual mesh sits where the collision mesh is (Z-up, metres)
        vertices = np.vstack([p[0] for p in meshes.glb_parts(visuals[link].models[0].glb)])
        collision = trimesh.load(str(Path(PANDA).parent / "meshes" / "collision" /
                                     f"{link.removeprefix('panda_')}.obj"), force="mesh")
        assert np.allclose(vertices.min(0), collision.bounds[0], atol=0.006)
        assert np.allclose(vertices.max(0), collision.bounds[1], atol=0.006)
    finger = visuals["panda_rightfinger"].models[0]
    assert abs(abs(finger.pose[1][2]) - 1.0) < 1e-9  # the URDF's rpy="0 0 pi"
    assert meshes.robot_visuals(Path(PANDA).with_name("missing.urdf")) == {}


def test_the_shipped_layout_is_what_the_builder_makes_and_names_recorded_topics(tmp_path: Path) -> None:
    assert LAYOUT.read_text() == layout_text()
    text = LAYOUT.read_text()
    for topic in ("/robot", "/scene", "/camera", "/camera/calibration", "/joint_states.position[0]", "/plan/events",
                  "/log"):
        assert f'"{topic}"' in text
    panels = [item["content"]["panelType"] for column in json.loads(text)["content"]["items"]
              for item in column["content"]["items"]]
    assert sorted(panels) == ["Image", "Log", "Plot", "Table", "ThreeDee"]
    path = tmp_path / "run.mcap"
    synthetic_run(McapRecorder(path), actions=1, seconds_per_action=0.2)
    assert layout_path(path) == tmp_path / "run.layout.json"
    assert layout_path(path).read_text() == text


def test_camera_renders_at_a_steady_rate_of_simulated_time() -> None:
    sink = Images()
    camera = CameraObserver(sink, hz=4.0)  # type: ignore[arg-type]
    stats = synthetic_run(camera, actions=2, seconds_per_action=1.0, jpeg=b"boundary")
    steady = [(t, jpeg) for t, jpeg, w, h in sink.images if jpeg != b"boundary"]
    assert len(steady) == camera.images == pytest.approx(stats.sim_seconds * 4, abs=1)
    gaps = np.diff([t for t, _ in steady])
    assert np.all(np.abs(gaps - 0.25) < 1 / 30 + 1e-9)  # states come at 30 Hz: within one state of the period
    image = cv2.imdecode(np.frombuffer(steady[3][1], np.uint8), cv2.IMREAD_COLOR)
    assert image.shape == (180, 240, 3)
    assert image.std() > 5  # the table and the links are drawn, not a blank frame
    assert len([1 for *_, jpeg in [(0, j) for _, j, _, _ in sink.images] if jpeg == b"boundary"]) == 4
    with pytest.raises(ValueError):
        CameraObserver(sink, hz=0)  # type: ignore[arg-type]


def _validator(schema: dict) -> jsonschema.protocols.Validator:
    cls = jsonschema.validators.validator_for(schema, default=jsonschema.Draft202012Validator)
    cls.check_schema(schema)
    return cls(schema)


@pytest.mark.sim
def test_every_message_of_a_real_run_conforms_to_its_json_schema(one_arm_recording: Path) -> None:
    record = one_arm_recording
    counts: dict[str, int] = {}
    validators: dict[int, jsonschema.protocols.Validator] = {}
    robot: dict = {}
    times: list[int] = []
    with open(record, "rb") as f:
        for schema, channel, message in make_reader(f, validate_crcs=True).iter_messages():
            assert schema is not None and schema.encoding == "jsonschema" and channel.message_encoding == "json"
            assert schema.name == foxglove.TOPIC_SCHEMAS[channel.topic]
            if schema.id not in validators:
                validators[schema.id] = _validator(json.loads(schema.data))
            decoded = json.loads(message.data)
            errors = list(validators[schema.id].iter_errors(decoded))
            assert not errors, (channel.topic, errors[0].message)
            counts[channel.topic] = counts.get(channel.topic, 0) + 1
            times.append(message.log_time)
            if channel.topic == "/robot":
                robot = decoded
    assert set(counts) == set(foxglove.TOPIC_SCHEMAS)
    assert counts["/robot"] == 1  # the meshes once, not per flush
    links = {e["frame_id"] for e in robot["entities"]}
    assert {f"P1/panda_link{k}" for k in range(8)} | {"P1/panda_hand"} <= links
    model = robot["entities"][0]["models"][0]
    assert model["media_type"] == "model/gltf-binary" and base64.b64decode(model["data"])[:4] == b"glTF"
    sim_seconds = (max(times) - min(times)) / 1e9
    assert counts["/camera"] == pytest.approx(sim_seconds * 2, abs=2)
    # the validator does catch what a viewer would trip on
    joint = _validator(foxglove.SCHEMAS[foxglove.JOINT_STATE])
    good = foxglove.joint_state(5, ["P1/j1"], [0.1], [0.0])
    assert not list(joint.iter_errors(good))
    assert list(joint.iter_errors({k: v for k, v in good.items() if k != "velocity"}))
    assert list(joint.iter_errors({**good, "agent": "P1"}))
