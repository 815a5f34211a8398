"""Writing CVAT for video 1.1 XML: one ``<track>`` per object, a ``<box>`` for every frame it is seen, marked
``keyframe="1"`` where the user set it, and an ``outside="1"`` box on the frame after each run of frames, so
that CVAT (and :func:`wecook_core.formats.cvat.read_cvat`) read back exactly the frames written."""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from pathlib import Path
from xml.sax.saxutils import quoteattr

from wecook_core.model import ObjectTrack


def _number(value: float) -> str:
    return f"{value:.2f}"


def cvat_xml(tracks: Sequence[ObjectTrack], *, size: tuple[int, int] | None = None,
             keyframes: dict[int, Iterable[int]] | None = None) -> str:
    """The XML text; ``keyframes`` maps a track id to its keyframe frames (default: every box is one)."""
    lines = ['<?xml version="1.0" encoding="utf-8"?>', "<annotations>", "  <version>1.1</version>"]
    if size is not None:
        lines += ["  <meta>", "    <task>", "      <original_size>", f"        <width>{size[0]}</width>",
                  f"        <height>{size[1]}</height>", "      </original_size>", "    </task>", "  </meta>"]
    for track in tracks:
        keys = set(keyframes.get(track.track_id, ())) if keyframes is not None else None
        lines.append(f'  <track id="{track.track_id}" label={quoteattr(track.label)} source="manual">')
        frames = track.frames.tolist()
        boxes = track.boxes.tolist()
        for i, (frame, box) in enumerate(zip(frames, boxes, strict=True)):
            key = keys is None or frame in keys or i == 0 or frames[i - 1] != frame - 1
            lines.append(_box(frame, box, outside=False, keyframe=key))
            if i + 1 == len(frames) or frames[i + 1] != frame + 1:
                lines.append(_box(frame + 1, box, outside=True, keyframe=True))
        lines.append("  </track>")
    lines.append("</annotations>")
    return "\n".join(lines) + "\n"


def _box(frame: int, box: Sequence[float], *, outside: bool, keyframe: bool) -> str:
    x1, y1, x2, y2 = (_number(v) for v in box)
    return (f'    <box frame="{frame}" keyframe="{int(keyframe)}" outside="{int(outside)}" occluded="0" '
            f'xtl="{x1}" ytl="{y1}" xbr="{x2}" ybr="{y2}" z_order="0"></box>')


def write_cvat(path: str | Path, tracks: Sequence[ObjectTrack], **options: object) -> None:
    Path(path).write_text(cvat_xml(tracks, **options), encoding="utf-8")  # type: ignore[arg-type]
