"""The MCAP recorder: topics, Foxglove schemas, attachment, metadata, and files readable while unfinished."""

from __future__ import annotations

import base64
import json
from pathlib import Path

import pytest
from mcap.exceptions import EndOfFile
from mcap.reader import NonSeekingReader, make_reader

from wecook_core.execution.schedule.observer import FrameInfo, RunEvent, Shape
from wecook_core.recording import foxglove
from wecook_core.recording.check import schema_problems
from wecook_core.recording.synthetic_run import synthetic_run
from wecook_core.recording.writer import McapRecorder


def read_all(path: Path) -> list[tuple[str, str, dict]]:
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        return [(c.topic, s.name if s else "", json.loads(m.data)) for s, c, m in reader.iter_messages()]


def test_a_recorded_run_has_every_topic_with_its_schema(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    stats = synthetic_run(McapRecorder(path, time_origin_ns=0), actions=3, seconds_per_action=1.0,
                          fail=("a2",), plan_yaml="wecook_plan: 1\nactions: []\n", seed=7)
    messages = read_all(path)
    topics = {topic: schema for topic, schema, _ in messages}
    assert topics == {t: s for t, s in foxglove.TOPIC_SCHEMAS.items() if t != "/robot"}  # no URDF: no meshes
    tf = [m for t, _, m in messages if t == "/tf"]
    assert len(tf) == stats.states
    first = tf[0]["transforms"][0]
    assert set(first) == {"timestamp", "parent_frame_id", "child_frame_id", "translation", "rotation"}
    assert first["parent_frame_id"] == "world" and set(first["rotation"]) == {"x", "y", "z", "w"}
    assert set(first["timestamp"]) == {"sec", "nsec"}
    joints = [m for t, _, m in messages if t == "/joint_states"]  # ROS 2 sensor_msgs/msg/JointState, both arms
    assert len(joints) == stats.states and topics["/joint_states"] == "sensor_msgs/msg/JointState"
    names = joints[0]["name"]
    assert len(names) == len(joints[0]["position"]) == len(joints[0]["velocity"]) == 14
    assert names[:2] == ["P1/joint1", "P1/joint2"] and names[7] == "P2/joint1"
    assert set(joints[0]["header"]) == {"stamp", "frame_id"} and set(joints[0]["header"]["stamp"]) == {"sec", "nanosec"}
    assert joints[0]["velocity"] == [0.0] * 14 and any(v != 0.0 for v in joints[5]["velocity"])
    dt = (joints[6]["header"]["stamp"]["nanosec"] - joints[5]["header"]["stamp"]["nanosec"]) / 1e9
    assert joints[6]["velocity"][0] == pytest.approx((joints[6]["position"][0] - joints[5]["position"][0]) / dt)
    events = [m for t, _, m in messages if t == "/plan/events"]
    kinds = [(e["kind"], e["action_id"]) for e in events if e["kind"].startswith("action")]
    assert kinds == [("action_start", "a1"), ("action_end", "a1"), ("action_start", "a2"),
                     ("action_failed", "a2"), ("action_start", "a3"), ("action_end", "a3")]
    assert events[-1]["kind"] == "run_end"
    failed = next(e for e in events if e["kind"] == "action_failed")
    assert failed["detail"] == "synthetic failure" and failed["agent"] == "P2"
    logs = [m for t, _, m in messages if t == "/log"]
    assert logs and all(m["level"] == 2 for m in logs)
    image = next(m for t, _, m in messages if t == "/camera")
    assert base64.b64decode(image["data"]) == b"\xff\xd8synthetic\xff\xd9" and image["format"] == "jpeg"
    with open(path, "rb") as f:
        reader = make_reader(f)
        attachments = {a.name: a.data for a in reader.iter_attachments()}
    with open(path, "rb") as f:
        meta = {m.name: m.metadata for m in make_reader(f).iter_metadata()}
    assert attachments == {"plan.yaml": b"wecook_plan: 1\nactions: []\n"}
    assert meta["wecook"]["seed"] == "7"
    assert {"wecook", "pybullet", "ompl", "mcap", "python"} <= set(meta["wecook"])


def test_scene_entities_draw_shapes_in_their_frames(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    frames = (FrameInfo("table", (Shape("box", (1.0, 0.8, 0.04)),)),
              FrameInfo("P1/link3", (Shape("cylinder", (0.1, 0.1, 0.2)), Shape("sphere", (0.05, 0.05, 0.05)))),
              FrameInfo("P1/link4"))
    with McapRecorder(path, time_origin_ns=1_500_000_000) as rec:
        rec.on_start(frames, "wecook_plan: 1\n", 0, {})
        rec.on_state(0.25, {"table": ((0, 0, 0), (0, 0, 0, 1))}, {})
        rec.on_event(0.25, RunEvent("run_end"))
    scene = next(m for t, _, m in read_all(path) if t == "/scene")
    entities = {e["id"]: e for e in scene["entities"]}
    assert set(entities) == {"table", "P1/link3"}           # a frame without shapes has no entity
    link = entities["P1/link3"]
    assert link["frame_id"] == "P1/link3" and link["frame_locked"] is True
    assert link["cylinders"][0]["size"] == {"x": 0.1, "y": 0.1, "z": 0.2}
    assert len(link["spheres"]) == 1 and link["cubes"] == []
    assert entities["table"]["cubes"][0]["size"] == {"x": 1.0, "y": 0.8, "z": 0.04}
    tf = next(m for t, _, m in read_all(path) if t == "/tf")
    assert tf["transforms"][0]["timestamp"] == {"sec": 1, "nsec": 750_000_000}


def test_schemas_are_json_schemas_naming_foxglove_fields() -> None:
    scene = foxglove.SCHEMAS["foxglove.SceneUpdate"]
    entity = scene["properties"]["entities"]["items"]["properties"]
    assert {"frame_id", "id", "timestamp", "cubes", "cylinders", "spheres", "frame_locked"} <= set(entity)
    tf = foxglove.SCHEMAS["foxglove.FrameTransforms"]["properties"]["transforms"]["items"]["properties"]
    assert set(tf) == {"timestamp", "parent_frame_id", "child_frame_id", "translation", "rotation"}
    assert foxglove.SCHEMAS["foxglove.CompressedImage"]["properties"]["data"]["contentEncoding"] == "base64"
    for name, schema in foxglove.SCHEMAS.items():
        assert schema["title"] == name and schema["type"] == "object"


def test_unfinished_file_reads_back_up_to_the_last_flush(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    rec = McapRecorder(path, flush_every_s=3600)
    synthetic_run(rec, actions=2, seconds_per_action=0.5, end=False)
    rec.flush()
    flushed = rec.flushed_messages
    rec.on_log(99.0, "info", "after the flush")  # buffered in the open chunk, never flushed
    got = 0
    with open(path, "rb") as f, pytest.raises(EndOfFile):  # no footer: reading ends at the end of the data
        for _ in NonSeekingReader(f).iter_messages(log_time_order=False):
            got += 1
    assert got == flushed == rec.message_count - 1
    rec.close()


def test_flushes_about_every_interval(tmp_path: Path) -> None:
    import time

    flushes: list[int] = []
    rec = McapRecorder(tmp_path / "run.mcap", flush_every_s=0.05, on_flush=flushes.append)
    clock = time.monotonic()
    synthetic_run(rec, actions=2, seconds_per_action=0.5, state_hz=20, wall_per_sim=0.5)  # ~0.5 s wall
    periods = (time.monotonic() - clock) / 0.05
    # one at the start, then about one per period (a flush waits for the next call after its period is over)
    assert periods / 2 <= len(flushes) <= periods + 2, (len(flushes), periods)
    assert flushes == sorted(flushes)


def test_fast_transforms_json_matches_the_plain_encoding() -> None:
    import numpy as np

    poses = {"P1/link0": ((0.1, -0.2, 0.3), (0.0, 0.0, 0.0, 1.0)),
             'odd "name"': ((np.float64(1 / 3), 2.0, -5e-7), (0.5, 0.5, -0.5, 0.5)),
             "bad": ((float("nan"), 0.0, 0.0), (0.0, 0.0, 0.0, 1.0))}
    fast = json.loads(foxglove.frame_transforms_json(3_000_000_007, poses))
    plain = foxglove.frame_transforms(3_000_000_007, poses)
    assert len(fast["transforms"]) == 3
    for got, want in zip(fast["transforms"], plain["transforms"], strict=True):
        assert got["timestamp"] == want["timestamp"] == {"sec": 3, "nsec": 7}
        assert got["child_frame_id"] == want["child_frame_id"]
        for key in ("translation", "rotation"):
            for axis, value in want[key].items():
                if value != value:  # NaN is written as null
                    assert got[key][axis] is None
                else:
                    assert abs(got[key][axis] - value) <= 5e-7


def test_states_are_kept_at_most_state_hz(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    with McapRecorder(path, state_hz=10) as rec:
        rec.on_start((), "wecook_plan: 1\n", 0, {})
        for k in range(100):  # 240 Hz for 100 steps: 0.41 s
            rec.on_state(k / 240, {"table": ((0, 0, 0), (0, 0, 0, 1))}, {})
        rec.on_event(1.0, RunEvent("run_end"))
    times = [m["transforms"][0]["timestamp"]["nsec"] for t, _, m in read_all(path) if t == "/tf"]
    assert len(times) == 5  # t = 0, 0.1, 0.2, 0.3, 0.4 (to the nearest step)


def test_every_message_conforms_to_its_channel_schema(tmp_path: Path) -> None:
    path = tmp_path / "run.mcap"
    synthetic_run(McapRecorder(path), actions=2, seconds_per_action=0.5, fail=("a2",))
    with open(path, "rb") as f:
        reader = make_reader(f)
        seen = set()
        for schema, channel, message in reader.iter_messages():
            assert schema is not None and schema.encoding == "jsonschema" and channel.message_encoding == "json"
            problems = schema_problems(json.loads(message.data), json.loads(schema.data), channel.topic)
            assert problems == [], problems[:5]
            seen.add(channel.topic)
    assert seen == set(foxglove.TOPIC_SCHEMAS) - {"/robot"}
    tf = foxglove.SCHEMAS["foxglove.FrameTransforms"]
    assert schema_problems({"transforms": [{"timestamp": {"sec": -1, "nsec": 0}}]}, tf, "/tf") == \
        ["/tf.transforms[0].timestamp.sec: -1 < 0"]
    assert schema_problems({"transforms": [{"translation": {"x": "1"}, "frame": "a"}]}, tf, "/tf") == \
        ["/tf.transforms[0].translation.x: '1' is not number", "/tf.transforms[0].frame: not in the schema"]


def test_what_is_recorded_depends_on_the_run_not_on_the_machines_speed(tmp_path: Path) -> None:
    """Issue 28: the same plan and seed under load wrote 17 and 32 ``/scene`` messages, the scene being repeated
    at every (wall-clock) flush. The same run recorded as fast as possible and paced at half real time, with
    flushes every 20 ms of wall time, gives the same messages on every channel, in the same order; only where
    the chunks end may differ. The scene still comes back about once a simulated second."""

    def messages(name: str, wall_per_sim: float) -> list[tuple[str, int, bytes]]:
        path = tmp_path / name
        with McapRecorder(path, flush_every_s=0.02, time_origin_ns=0) as rec:
            synthetic_run(rec, actions=2, seconds_per_action=0.6, state_hz=20, wall_per_sim=wall_per_sim)
        with open(path, "rb") as f:
            return [(c.topic, m.log_time, m.data) for _, c, m in make_reader(f).iter_messages()]

    fast, paced = messages("fast.mcap", 0.0), messages("paced.mcap", 0.5)
    assert fast == paced
    scenes = [t for topic, t, _ in fast if topic == "/scene"]
    assert len(scenes) == 2 and scenes[0] == 0 and 0.95e9 <= scenes[1] <= 1.05e9, scenes
