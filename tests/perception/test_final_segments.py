"""Corrections are folded against the segments the analysis really has: every cut (GGS's, the user's splits and
merges, shot cuts, the edges of holds by unseen hands) made once, by :func:`final_segments`."""

from __future__ import annotations

from functools import cache

from wecook_core.knowledge.recognize import load_knowledge
from wecook_core.model import Observations, Segment, Segmentation
from wecook_core.observations.importer import load_observations
from wecook_core.perception.association.frame_links import UnseenHold
from wecook_core.perception.params import Params
from wecook_core.perception.pipeline import final_segments
from wecook_core.session.corrections import Merge, SetVerb, Split, fold
from wecook_core.synth import demo_dir
from wecook_core.workflows import analyse

SHOT = 870
"""A shot cut inside the demo's cutting (GGS has no breakpoint there)."""


@cache
def _demo() -> Observations:
    folder = demo_dir()
    return load_observations(folder / "video.mp4", folder / "objects.csv", folder / "hands.csv")


def test_a_verb_set_over_a_span_reaches_the_segment_a_shot_cut_made() -> None:
    obs = _demo()
    correction = SetVerb(segment=785, hand="RH_P1", verb="peel", end=1019)
    analysis = analyse(obs, load_knowledge(), Params(), [correction], shots=(SHOT,))
    starts = [s.start for s in analysis.segmentation.segments]
    assert SHOT in starts, "the shot cut makes a segment"
    verbs = {sa.segment.start: a.verb for sa in analysis.segment_actions for a in sa.actions
             if a.hand == "RH_P1" and a.verb is not None and 785 <= sa.segment.start < 1019}
    assert verbs, "the knife hand acts in the span"
    assert set(verbs.values()) == {"peel"}, verbs


def test_final_segments_makes_every_cut_once() -> None:
    ggs = Segmentation({}, (Segment(0, 100), Segment(100, 200)), {})
    unseen = (UnseenHold("RH_P1", "spoon", 130, 170),)
    params = Params(min_segment_s=0.1)  # 3 frames at 30 fps
    corrections = fold([Split(40), Merge(100)])
    cut = final_segments(ggs, (60, 198), unseen, params, 30.0, corrections)
    # GGS's 100 merged away; the user's 40; the shot 60; the hold's edges 130 and 170; 198 too near the end
    assert [(s.start, s.end) for s in cut.segments] == [(0, 40), (40, 60), (60, 130), (130, 170), (170, 200)]


def test_an_analysis_converts_its_durations_to_frames_once(monkeypatch) -> None:  # type: ignore[no-untyped-def]
    """Every stage gets the frame counts the pipeline worked out (``rate=``); none converts seconds again."""
    from wecook_core.perception.pipeline import analyze

    calls: list[float] = []
    real = Params.at

    def counted(self: Params, fps: float):  # type: ignore[no-untyped-def]
        calls.append(fps)
        return real(self, fps)

    monkeypatch.setattr(Params, "at", counted)
    analyze(_demo(), load_knowledge(), Params(), shots=(SHOT,))
    assert calls == [_demo().video.fps]
