"""Writing a synthetic scenario to disk: the video, the native CSVs, an OpenPose folder and the true trees."""

from __future__ import annotations

from pathlib import Path

from wecook_core.formats.native import write_hands_csv, write_objects_csv
from wecook_core.synth.openpose import write_openpose
from wecook_core.synth.render import write_video
from wecook_core.synth.scenario import VIDEO_NAME, Scenario
from wecook_core.trees.treefile import write_tree_file

SCENARIO_FILES: tuple[str, ...] = ("objects.csv", "hands.csv", "truth.yaml", "openpose", VIDEO_NAME)
"""What :func:`write_scenario` writes into its folder."""


def check_scenario_folder(out_dir: str | Path, *, replace: bool = False) -> Path:
    """``out_dir`` when a scenario may be written there: a folder (or nothing yet) holding none of
    :data:`SCENARIO_FILES`, unless ``replace``; else an :class:`InputError`."""
    from wecook_core.errors import InputError
    from wecook_core.files import check_output

    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(out, "is not a folder; a scenario is written into a folder")
    check_output(out / "objects.csv", replace=True, what="scenario")  # its parents are folders
    taken = [name for name in SCENARIO_FILES if (out / name).exists()]
    if taken and not replace:
        raise InputError(out, f"already holds {', '.join(taken)}; not overwritten (pass --force to replace them)")
    return out


def write_scenario(scenario: Scenario, out_dir: str | Path, *, video: bool = True, openpose: bool = True) -> Path:
    """Write ``video.mp4`` (unless ``video=False``), ``objects.csv``, ``hands.csv``, ``openpose/`` and
    ``truth.yaml`` into ``out_dir`` (created); returns it."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    write_objects_csv(out / "objects.csv", scenario.observations.objects)
    write_hands_csv(out / "hands.csv", scenario.observations.hands)
    write_tree_file(out / "truth.yaml", scenario.truth)
    if openpose:
        write_openpose(scenario, out / "openpose")
    if video:
        write_video(scenario, out / VIDEO_NAME)
    return out
