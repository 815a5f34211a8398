"""The workbench and the command line analyse a session along one path (wecook_core.workflows)."""

from __future__ import annotations

from pathlib import Path

from wecook_core.perception.params import Params
from wecook_core.session.corrections import SetVerb
from wecook_core.session.store import create_session, open_session
from wecook_core.workflows import analyse_session
from wecook_tui import review
from wecook_tui.workspace import analyze_workspace, open_workspace


def test_the_workbench_reviews_the_segments_that_are_exported(tmp_path: Path,
                                                              scenario_inputs: tuple[Path, Path, Path]) -> None:
    """A video long for its ``k_max``: the pipeline raises ``k_max`` to ``k_per_minute`` of the video's length;
    the workbench used to segment with the session's ``k_max`` itself (2 segments here, against 5 exported), so a
    correction keyed by a segment's start landed on another segment, or on none."""
    video, objects, hands = scenario_inputs
    path = create_session(tmp_path, "long", video, objects, hands, params=Params(k_max=1, k_per_minute=200))
    exported = analyse_session(path).analysis.segmentation.segments
    assert len(exported) > 2  # more segments than k_max = 1 allows per hand
    opened = open_workspace(path)
    reviewed = analyze_workspace(opened, ()).segmentation.segments
    assert reviewed == exported
    seg = exported[2]
    open_session(path).record(SetVerb(seg.start, "RH_P1", "peel"))
    ops = open_session(path).applied_corrections
    for analysis in (analyze_workspace(opened, ops), analyse_session(path).analysis):
        index = review.segment_index(analysis.segmentation.segments, seg.start)
        assert analysis.segmentation.segments[index] == seg
        action = review.actions_of(analysis, seg, index).get("RH_P1")
        assert action is not None and action.verb == "peel"


def test_the_workbench_analyses_with_the_videos_shot_cuts_as_wecook_analyze_does(
        tmp_path: Path, scenario_inputs: tuple[Path, Path, Path]) -> None:
    """The workbench's analysis used to leave out the video's shot cuts (and the session's category table), so on
    a video with a cut it reviewed other segments than `wecook analyze` exported."""
    import json

    from wecook_core.perception.segmentation.shots import DETECTOR
    from wecook_core.workflows import SHOTS_FILE

    video, objects, hands = scenario_inputs
    path = create_session(tmp_path, "cut", video, objects, hands)
    stat = video.stat()
    cut = 40  # a cut the shots cache says the video has (the cache is keyed by the very file)
    (path / SHOTS_FILE).write_text(json.dumps({"video": str(video.resolve()), "size": stat.st_size,
                                               "mtime_ns": stat.st_mtime_ns, "detector": DETECTOR,
                                               "cuts": [cut]}) + "\n")
    exported = analyse_session(path).analysis
    assert exported.shots == (cut,)
    reviewed = analyze_workspace(open_workspace(path), ())
    assert reviewed.shots == (cut,)
    assert reviewed.segmentation.segments == exported.segmentation.segments
