from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

import pytest
import yaml
from session_inputs import FPS, FRAMES, W, make_inputs

from wecook_core import __version__
from wecook_core.errors import InputError
from wecook_core.perception.params import Params
from wecook_core.session.store import (
    JOURNAL_FILE,
    SESSION_FILE,
    check_name,
    content_hash,
    create_session,
    list_sessions,
    open_session,
    sessions_root,
)


@pytest.fixture
def inputs(tmp_path: Path) -> dict[str, Path]:
    return make_inputs(tmp_path / "inputs")


def create(root: Path, inputs: dict[str, Path], name: str = "take1", **kwargs: object) -> Path:
    return create_session(root, name, inputs["video"], inputs["objects"], inputs["hands"],
                          categories=inputs["categories"], **kwargs)  # type: ignore[arg-type]


def test_create_records_inputs_hashes_video_and_params(tmp_path: Path, inputs: dict[str, Path]) -> None:
    path = create(tmp_path / "sessions", inputs, params=Params(min_link_s=0.1))
    assert path == tmp_path / "sessions" / "take1"
    meta = yaml.safe_load((path / SESSION_FILE).read_text())
    assert meta["wecook_version"] == __version__ and meta["name"] == "take1"
    assert meta["inputs"]["objects"]["sha256"] == hashlib.sha256(inputs["objects"].read_bytes()).hexdigest()
    assert meta["inputs"]["objects"]["format"] == "csv" and meta["inputs"]["hands"]["format"] == "openpose"
    assert meta["inputs"]["video"]["path"] == str(inputs["video"].resolve())
    assert meta["video"]["fps"] == FPS and meta["video"]["frame_count"] == FRAMES
    assert meta["params"]["min_link_s"] == 0.1
    assert (path / JOURNAL_FILE).read_bytes() == b""
    assert (path / "plans").is_dir() and (path / "runs").is_dir()
    session = open_session(path)
    assert session.warnings == []
    assert session.params == Params(min_link_s=0.1)
    assert session.video is not None and session.video.width == W
    assert session.inputs["hands"].sha256 == content_hash(inputs["hands"])
    assert session.trees_path == path / "trees.yaml" and session.graph_path == path / "graph.yaml"
    assert session.plans_dir == path / "plans" and session.runs_dir == path / "runs"
    obs = session.load_observations()
    assert [t.name for t in obs.objects] == ["whisk", "pan"]
    assert [t.hand for t in obs.hands] == ["LH_P1", "RH_P1"]


def test_folder_hash_covers_names_and_contents(tmp_path: Path, inputs: dict[str, Path]) -> None:
    before = content_hash(inputs["hands"])
    first = inputs["hands"] / "take_000000000000_keypoints.json"
    first.rename(inputs["hands"] / "renamed_000000000000_keypoints.json")
    renamed = content_hash(inputs["hands"])
    assert renamed != before
    (inputs["hands"] / "renamed_000000000000_keypoints.json").rename(first)
    assert content_hash(inputs["hands"]) == before
    first.write_text('{"people": []}')
    assert content_hash(inputs["hands"]) != before


def test_bad_input_leaves_no_session_behind(tmp_path: Path, inputs: dict[str, Path]) -> None:
    root = tmp_path / "sessions"
    inputs["objects"].write_text("frame,track_id,label,x1,y1,x2,y2\n999,1,whisk,10,10,20,20\n")
    with pytest.raises(InputError, match=r"objects\.csv:frame 999: track 1 \(whisk\)"):
        create(root, inputs)
    assert not root.exists() or list(root.iterdir()) == []


def test_a_failure_while_writing_removes_the_half_made_folder(tmp_path: Path, inputs: dict[str, Path],
                                                              monkeypatch: pytest.MonkeyPatch) -> None:
    root = tmp_path / "sessions"
    real_rename = os.rename

    def rename(src: str | Path, dst: str | Path) -> None:
        if Path(dst).parent == root:
            raise OSError(28, "No space left on device")
        real_rename(src, dst)

    monkeypatch.setattr(os, "rename", rename)
    with pytest.raises(OSError, match="No space"):
        create(root, inputs)
    assert list(root.iterdir()) == []


@pytest.mark.parametrize("name", ["", "a/b", "..", ".hidden", "-x", "a b", "x" * 65, "a..b"])
def test_bad_names(name: str) -> None:
    with pytest.raises(InputError, match="bad session name"):
        check_name(name)


def test_good_names_and_an_existing_name(tmp_path: Path, inputs: dict[str, Path]) -> None:
    for name in ("take1", "Take_2.v3", "a-b"):
        assert check_name(name) == name
    create(tmp_path, inputs)
    with pytest.raises(InputError, match="already exists"):
        create(tmp_path, inputs)


def test_corrections_undo_and_redo_survive_reopening(tmp_path: Path, inputs: dict[str, Path]) -> None:
    session = open_session(create(tmp_path, inputs))
    session.record({"op": "set_verb", "segment": 0, "hand": "RH_P1", "verb": "stir"})
    session.record({"op": "set_hand_object", "segment": 0, "hand": "RH_P1", "object": "whisk"})
    session.record({"op": "split", "frame": 8})
    assert session.undo()
    again = open_session(session.path)
    assert again.corrections.verbs == {(0, "RH_P1"): "stir"}
    assert again.corrections.hand_object == {(0, "RH_P1"): "whisk"}
    assert again.corrections.splits == frozenset()
    assert again.can_redo and again.redo()
    assert open_session(session.path).corrections.splits == frozenset({8})
    assert [e.seq for e in open_session(session.path).entries] == [1, 2, 3, 4, 5]


def test_changed_and_missing_inputs_are_warnings(tmp_path: Path, inputs: dict[str, Path]) -> None:
    path = create(tmp_path / "s", inputs)
    stat = inputs["objects"].stat()
    os.utime(inputs["objects"], ns=(stat.st_atime_ns, stat.st_mtime_ns + 5_000_000_000))  # touched, same bytes
    assert open_session(path).warnings == []
    inputs["objects"].write_text("frame,track_id,label,x1,y1,x2,y2\n0,1,whisk,10,10,20,21\n")
    (inputs["hands"] / "take_000000000003_keypoints.json").write_text('{"people": []}')
    warnings = open_session(path).warnings
    assert any("objects input changed" in w and "sha256" in w for w in warnings)
    assert any("hands input changed" in w for w in warnings)
    inputs["video"].unlink()
    session = open_session(path)
    assert any(w.startswith("video input is missing") for w in session.warnings)
    with pytest.raises(InputError, match=r"take\.avi"):
        session.load_observations()


def test_video_optional_imports_against_the_recorded_video_facts(tmp_path: Path, inputs: dict[str, Path]) -> None:
    path = create(tmp_path / "s", inputs)
    whole = open_session(path).import_observations(video_optional=True)
    assert whole.video_problem is None and whole.observations.video.frame_count == FRAMES
    inputs["video"].write_bytes(b"\x00garbage" * 100)
    session = open_session(path)
    with pytest.raises(InputError, match=r"take\.avi"):
        session.load_observations()
    imported = session.import_observations(video_optional=True)
    assert imported.video_problem is not None and "take.avi" in imported.video_problem
    assert imported.observations.video == session.video
    assert [t.name for t in imported.observations.objects] == ["whisk", "pan"]
    assert set(imported.observations.categories) == {"whisk", "pan"}
    with pytest.raises(InputError, match=r"take\.avi"):
        session.load_observations()  # the stand-in is not cached as the real import


def test_video_optional_when_the_video_was_cut_short(tmp_path: Path, inputs: dict[str, Path]) -> None:
    path = create(tmp_path / "s", inputs)
    data = inputs["video"].read_bytes()
    inputs["video"].write_bytes(data[: len(data) * 4 // 5])  # still opens, but the hands run past its end
    session = open_session(path)
    with pytest.raises(InputError, match="frame"):
        session.load_observations()
    imported = session.import_observations(video_optional=True)
    assert imported.video_problem is not None and "frame" in imported.video_problem
    assert imported.observations.video == session.video
    assert [t.hand for t in imported.observations.hands] == ["LH_P1", "RH_P1"]


def test_a_torn_journal_line_is_a_warning_when_opening(tmp_path: Path, inputs: dict[str, Path]) -> None:
    session = open_session(create(tmp_path, inputs))
    session.record({"op": "set_status", "segment": 0, "status": "accepted"})
    with session.journal_path.open("ab") as handle:
        handle.write(b'{"seq":2,"op":"set_st')
    reopened = open_session(session.path)
    assert len(reopened.warnings) == 1 and "torn" in reopened.warnings[0]
    assert len(reopened.entries) == 1


def test_params_can_be_changed(tmp_path: Path, inputs: dict[str, Path]) -> None:
    session = open_session(create(tmp_path, inputs))
    session.set_params(Params(k={"RH_P1": 4}))
    assert open_session(session.path).params == Params(k={"RH_P1": 4})
    meta = yaml.safe_load((session.path / SESSION_FILE).read_text())
    meta["params"]["from_the_future"] = 1
    (session.path / SESSION_FILE).write_text(yaml.safe_dump(meta))
    reopened = open_session(session.path)
    assert reopened.params == Params(k={"RH_P1": 4})
    assert any("from_the_future" in w for w in reopened.warnings)


def test_open_refuses_what_is_not_a_session(tmp_path: Path) -> None:
    with pytest.raises(InputError, match="no such session"):
        open_session(tmp_path / "nope")
    with pytest.raises(InputError, match="not a session"):
        open_session(tmp_path)
    (tmp_path / SESSION_FILE).write_text("inputs: [\n")
    with pytest.raises(InputError, match="malformed YAML"):
        open_session(tmp_path)


def test_sessions_root_and_listing(tmp_path: Path, inputs: dict[str, Path], monkeypatch: pytest.MonkeyPatch
                                   ) -> None:
    monkeypatch.delenv("WECOOK_SESSIONS", raising=False)
    monkeypatch.chdir(tmp_path)
    assert sessions_root() == tmp_path / "sessions"
    monkeypatch.setenv("WECOOK_SESSIONS", str(tmp_path / "env"))
    assert sessions_root() == tmp_path / "env"
    assert sessions_root(tmp_path / "given") == tmp_path / "given"
    root = tmp_path / "env"
    assert list_sessions(root) == []
    second = open_session(create(root, inputs, "b"))
    create(root, inputs, "a")
    second.record({"op": "split", "frame": 4})
    second.record({"op": "split", "frame": 9})
    second.undo()
    (root / "notes").mkdir()
    (root / "broken").mkdir()
    (root / "broken" / SESSION_FILE).write_text(": :\n")
    rows = list_sessions(root)
    assert [(r.name, r.corrections) for r in rows] == [("a", 0), ("b", 1), ("broken", 0)]
    assert rows[0].video == str(inputs["video"].resolve()) and rows[0].created.endswith("Z")
    assert rows[2].problem is not None and rows[0].problem is None


def test_a_cocovid_video_choice_is_recorded_and_used(tmp_path: Path, inputs: dict[str, Path]) -> None:
    data = {
        "videos": [{"id": 1, "name": "other"}, {"id": 2, "name": "second"}],
        "images": [{"id": 1, "video_id": 1, "frame_id": 0}, {"id": 2, "video_id": 2, "frame_id": 3}],
        "annotations": [{"image_id": 1, "category_id": 1, "instance_id": 1, "bbox": [0, 0, 5, 5]},
                        {"image_id": 2, "category_id": 2, "instance_id": 4, "bbox": [1, 1, 5, 5]}],
        "categories": [{"id": 1, "name": "whisk"}, {"id": 2, "name": "pan"}],
    }
    inputs["objects"] = tmp_path / "coco.json"
    inputs["objects"].write_text(json.dumps(data))
    with pytest.raises(InputError, match="2 videos in the file"):
        create(tmp_path / "s", inputs)
    session = open_session(create(tmp_path / "s", inputs, select="second"))
    assert session.inputs["objects"].select == "second" and session.inputs["objects"].format == "cocovid"
    (track,) = session.load_observations().objects
    assert (track.name, track.frames.tolist()) == ("pan", [3])


def test_opening_reads_the_cached_import_until_an_input_or_the_import_code_changes(
        tmp_path: Path, inputs: dict[str, Path], monkeypatch: pytest.MonkeyPatch) -> None:
    import numpy as np

    from wecook_core.session import store

    path = create(tmp_path, inputs)
    cache = path / "cache" / "observations.npz"
    assert cache.is_file()  # made with the session
    fresh = store.import_observations  # what a real import gives
    calls = []
    monkeypatch.setattr(store, "import_observations", lambda *a, **k: calls.append(1) or fresh(*a, **k))
    cached = open_session(path).import_observations()
    assert calls == []  # no import: the cache was read
    again = open_session(path)
    again._imported = None
    cache.rename(cache.with_suffix(".off"))
    imported = again.import_observations()
    assert calls == [1]
    for a, b in zip(cached.observations.objects, imported.observations.objects, strict=True):
        assert (a.name, a.label, a.track_id) == (b.name, b.label, b.track_id)
        assert np.array_equal(a.frames, b.frames) and np.array_equal(a.boxes, b.boxes)
    for a, b in zip(cached.observations.hands, imported.observations.hands, strict=True):
        assert a.hand == b.hand and np.array_equal(a.xy, b.xy) and np.array_equal(a.frames, b.frames)
    assert cached.observations.video == imported.observations.video
    assert cached.observations.categories == imported.observations.categories
    assert cached.warnings == imported.warnings and cached.missing == imported.missing
    assert cache.is_file()  # written again by that import
    os.utime(inputs["objects"], ns=(1, 1))  # an input touched: the cache is stale
    open_session(path).import_observations()
    assert calls == [1, 1]
    cache.write_bytes(b"not a cache")  # unreadable: imported again, never an error
    open_session(path).import_observations()
    assert calls == [1, 1, 1]
