"""`wecook runs export --ros2`: a run's recording as a ROS 2 bag, read back with rosbags as ROS 2 tools read it."""

from __future__ import annotations

import base64
import itertools
import json
import xml.etree.ElementTree as ET
from collections import Counter
from pathlib import Path

import pytest
from mcap.reader import make_reader
from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_typestore

from wecook_core.errors import InputError
from wecook_core.recording import meshes
from wecook_core.recording.ros2 import export_ros2
from wecook_core.recording.synthetic_run import synthetic_run
from wecook_core.recording.writer import McapRecorder
from wecook_tui.cli import main

PANDA = Path(meshes._robot_path("franka_panda/panda.urdf"))
STORE = get_typestore(Stores.ROS2_JAZZY)


def urdf_arm_joints(urdf: Path) -> list[str]:
    """The revolute joints of a URDF, in its order (the Panda's seven arm joints)."""
    return [j.get("name", "") for j in ET.parse(urdf).getroot().iter("joint") if j.get("type") == "revolute"]


def source(path: Path) -> dict[str, list[tuple[int, dict]]]:
    """Topic -> (log time, decoded JSON) of every message of a wecook recording."""
    out: dict[str, list[tuple[int, dict]]] = {}
    with open(path, "rb") as f:
        for _, channel, message in make_reader(f).iter_messages(log_time_order=True):
            out.setdefault(channel.topic, []).append((message.log_time, json.loads(message.data)))
    return out


def read_bag(path: Path) -> tuple[dict[str, str], dict[str, list[tuple[int, object]]]]:
    """(topic -> message type, topic -> (timestamp, deserialised message)) of a ROS 2 bag, read with rosbags."""
    with Reader(path) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        messages: dict[str, list[tuple[int, object]]] = {}
        for connection, ns, raw in reader.messages():
            messages.setdefault(connection.topic, []).append((ns, STORE.deserialize_cdr(raw, connection.msgtype)))
    return types, messages


def stamp_ns(header: object) -> int:
    return header.stamp.sec * 1_000_000_000 + header.stamp.nanosec  # type: ignore[attr-defined]


@pytest.fixture(scope="module")
def recording(tmp_path_factory: pytest.TempPathFactory) -> Path:
    path = tmp_path_factory.mktemp("run") / "run.mcap"
    synthetic_run(McapRecorder(path, time_origin_ns=1_700_000_000_000_000_000, layout=False), actions=3,
                  seconds_per_action=1.0, joint_names=urdf_arm_joints(PANDA), jpeg=b"\xff\xd8a frame\xff\xd9")
    return path


@pytest.mark.parametrize("storage", ["mcap", "sqlite3"])
def test_a_recording_reads_back_as_a_ros2_bag_with_the_standard_messages(recording: Path, tmp_path: Path,
                                                                         storage: str) -> None:
    bag = tmp_path / "bag"
    done = export_ros2(recording, bag, storage=storage)  # type: ignore[arg-type]
    types, messages = read_bag(bag)
    assert types == {"/tf": "tf2_msgs/msg/TFMessage", "/P1/joint_states": "sensor_msgs/msg/JointState",
                     "/P2/joint_states": "sensor_msgs/msg/JointState",
                     "/camera/image/compressed": "sensor_msgs/msg/CompressedImage",
                     "/camera/camera_info": "sensor_msgs/msg/CameraInfo", "/rosout": "rcl_interfaces/msg/Log",
                     "/plan/events": "std_msgs/msg/String"} == done.types
    src = source(recording)
    counts = {"/tf": len(src["/tf"]), "/P1/joint_states": len(src["/joint_states"]),
              "/P2/joint_states": len(src["/joint_states"]), "/camera/image/compressed": len(src["/camera"]),
              "/camera/camera_info": len(src["/camera/calibration"]), "/rosout": len(src["/log"]),
              "/plan/events": len(src["/plan/events"])}
    assert {t: len(m) for t, m in messages.items()} == counts == done.messages
    assert counts["/tf"] == 90 and counts["/camera/image/compressed"] == 6
    assert done.left_out == {"/scene": len(src["/scene"])}
    for topic, stamped in messages.items():  # receive times are the recording's log times, in order
        times = [ns for ns, _ in stamped]
        assert times == sorted(times), topic
    assert [ns for ns, _ in messages["/tf"]] == [ns for ns, _ in src["/tf"]]

    urdf = urdf_arm_joints(PANDA)
    for pid in ("P1", "P2"):
        states = [m for _, m in messages[f"/{pid}/joint_states"]]
        assert all(list(s.name) == urdf for s in states)  # type: ignore[attr-defined]
        assert {s.header.frame_id for s in states} == {f"{pid}/link0"}  # type: ignore[attr-defined]
        stamps = [stamp_ns(s.header) for s in states]  # type: ignore[attr-defined]
        assert all(b > a for a, b in itertools.pairwise(stamps))
        offset = 0 if pid == "P1" else 7
        for (_, json_state), state in zip(src["/joint_states"], states, strict=True):
            assert list(state.position) == pytest.approx(json_state["position"][offset:offset + 7])  # type: ignore[attr-defined]
            assert list(state.velocity) == pytest.approx(json_state["velocity"][offset:offset + 7])  # type: ignore[attr-defined]

    (_, first_json), (_, first) = src["/tf"][0], messages["/tf"][0]
    by_child = {t.child_frame_id: t for t in first.transforms}  # type: ignore[attr-defined]
    assert set(by_child) == {t["child_frame_id"] for t in first_json["transforms"]}
    for t in first_json["transforms"]:
        ros = by_child[t["child_frame_id"]]
        assert ros.header.frame_id == "world"
        assert [ros.transform.translation.x, ros.transform.translation.y, ros.transform.translation.z] == \
            pytest.approx([t["translation"][k] for k in "xyz"], abs=1e-6)
        assert [getattr(ros.transform.rotation, k) for k in "xyzw"] == pytest.approx(
            [t["rotation"][k] for k in "xyzw"], abs=1e-6)

    images = [m for _, m in messages["/camera/image/compressed"]]
    assert all(bytes(i.data) == b"\xff\xd8a frame\xff\xd9" and i.format == "jpeg" for i in images)  # type: ignore[attr-defined]
    assert [base64.b64decode(m["data"]) for _, m in src["/camera"]] == [bytes(i.data) for i in images]  # type: ignore[attr-defined]
    for (_, calibration), (_, info) in zip(src["/camera/calibration"], messages["/camera/camera_info"], strict=True):
        assert (info.width, info.height) == (calibration["width"], calibration["height"]) == (320, 240)  # type: ignore[attr-defined]
        assert list(info.k) == pytest.approx(calibration["K"]) and list(info.p) == pytest.approx(calibration["P"])  # type: ignore[attr-defined]
        assert list(info.d) == [0.0] * 5 and info.distortion_model == "plumb_bob"  # type: ignore[attr-defined]
        assert info.header.frame_id == images[0].header.frame_id == "camera"  # type: ignore[attr-defined]
    assert [stamp_ns(m.header) for _, m in messages["/camera/camera_info"]] == \
        [stamp_ns(i.header) for i in images]  # type: ignore[attr-defined]
    assert "camera" in by_child  # the camera's optical frame is in /tf
    logs = [m for _, m in messages["/rosout"]]
    assert {log.level for log in logs} == {20} and logs[0].msg.startswith("run started")  # type: ignore[attr-defined]
    events = [json.loads(m.data) for _, m in messages["/plan/events"]]  # type: ignore[attr-defined]
    assert events == [m for _, m in src["/plan/events"]] and events[-1]["kind"] == "run_end"


def test_the_mcap_bag_is_cdr_with_the_ros2_profile(recording: Path, tmp_path: Path) -> None:
    bag = tmp_path / "bag"
    export_ros2(recording, bag)
    files = sorted(p.name for p in bag.iterdir())
    assert files == ["bag.mcap", "metadata.yaml"]
    with open(bag / "bag.mcap", "rb") as f:
        reader = make_reader(f)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
        assert summary is not None
        assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
        assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
        joint_schema = next(s for s in summary.schemas.values() if s.name == "sensor_msgs/msg/JointState")
        assert b"string[] name" in joint_schema.data and b"float64[] position" in joint_schema.data
    metadata = (bag / "metadata.yaml").read_text()
    assert "wecook.seed" in metadata  # the recording's metadata, in the bag's custom_data


def test_an_existing_bag_is_never_overwritten_and_bad_input_exits_2(recording: Path, tmp_path: Path,
                                                                    capsys: pytest.CaptureFixture[str]) -> None:
    bag = tmp_path / "bag"
    bag.mkdir()
    (bag / "mine.txt").write_text("keep me")
    with pytest.raises(InputError, match="exists"):
        export_ros2(recording, bag)
    assert main(["runs", "export", str(recording), "--ros2", str(bag)]) == 2
    assert sorted(p.name for p in bag.iterdir()) == ["mine.txt"]
    not_a_recording = tmp_path / "notes.mcap"
    not_a_recording.write_text("hello")
    assert main(["runs", "export", str(not_a_recording), "--ros2", str(tmp_path / "other")]) == 2
    assert not (tmp_path / "other").exists()  # nothing half-written is left
    err = capsys.readouterr().err
    assert "exists; not overwritten" in err and "notes.mcap" in err


def test_the_cli_writes_the_bag_and_says_what_is_in_it(recording: Path, tmp_path: Path,
                                                       capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["runs", "export", str(recording), "--ros2", str(tmp_path / "bag")]) == 0
    out = capsys.readouterr().out
    assert "/P1/joint_states" in out and "sensor_msgs/msg/JointState" in out and "left out" in out
    types, _ = read_bag(tmp_path / "bag")
    assert Counter(types.values())["sensor_msgs/msg/JointState"] == 2


@pytest.mark.sim
def test_a_real_run_exports_with_the_urdf_joint_names_and_the_camera_placed(tmp_path: Path,
                                                                           one_arm_recording: Path) -> None:
    record = one_arm_recording
    export_ros2(record, tmp_path / "bag")
    types, messages = read_bag(tmp_path / "bag")
    src = source(record)
    urdf_joints = {j.get("name") for j in ET.parse(PANDA).getroot().iter("joint")}
    states = [m for _, m in messages["/P1/joint_states"]]
    assert len(states) == len(src["/joint_states"]) > 10
    names = list(states[0].name)  # type: ignore[attr-defined]
    assert names[:7] == urdf_arm_joints(PANDA) and set(names) <= urdf_joints  # panda_joint1..7, then the fingers
    assert {s.header.frame_id for s in states} == {"P1/panda_link0"}  # type: ignore[attr-defined]
    frames = {t.child_frame_id for t in messages["/tf"][-1][1].transforms}  # type: ignore[attr-defined]
    assert {"P1/panda_link0", "P1/panda_hand", "table", "object/knife", "camera"} <= frames
    assert len(messages["/camera/image/compressed"]) == len(messages["/camera/camera_info"]) == len(src["/camera"])
    info = messages["/camera/camera_info"][0][1]
    assert (info.width, info.height) == (240, 180)  # type: ignore[attr-defined]
    assert types["/camera/camera_info"] == "sensor_msgs/msg/CameraInfo"
