"""Which frame a per-frame file stands for: the number in its name, or its place in the sorted set.

Tools that write one file per frame (OpenPose's JSON, YouTube-VIS and OVIS ``file_names``) name them two
ways, and only the set of names tells which:

- **a counter of the video's frames, from 0.** OpenPose run on a video writes ``NAME_000000000012_keypoints.json``
  for frame 12 (a 12-digit counter from 0, a file for every frame); YouTube-VIS lists ``00000.jpg, 00005.jpg,
  ...``, every fifth frame of the 30 fps video, numbered by that video's frames. The number is the frame:
  when the smallest number is 0, or every number has OpenPose's 12 zero-padded digits (its counter, which
  ``--frame_first`` starts later);
- **the names of images** (OpenPose run on a folder of images names each file after its image: ``im1010.jpg``
  gives ``im1010_keypoints.json``; OVIS counts ``img_0000001.jpg`` from 1). The numbers are the user's own,
  with an arbitrary start and perhaps gaps, and the video made of those images shows them in order: the
  frame is the file's place among the names sorted by their number (a warning says so).

A set where no name has a number is taken in sorted order of the names; one where some names have a number
and others not, or two names the same number, mixes files of different runs: :class:`NumberingError`. When
the video is known and numbers from 0 (not OpenPose's counter, which is the frame whatever the video says)
run past its end while the files alone fit it, the video was made of the files: sorted order too. Whichever
way is taken, a warning names it unless the numbers were plainly the frames (from 0, no gaps).
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from pathlib import PurePath

_LAST_NUMBER = re.compile(r"(\d+)(?!.*\d)")
_OPENPOSE_COUNTER = re.compile(r"(?<!\d)\d{12}$")


class NumberingError(ValueError):
    """The names do not number frames one each: ``index`` is the name at fault."""

    def __init__(self, message: str, index: int) -> None:
        super().__init__(message)
        self.index = index


def name_number(name: str) -> str | None:
    """The digits of the last number in a file name's stem (``_keypoints`` removed), or None."""
    stem = PurePath(name).name
    stem = stem[: -len("_keypoints.json")] if stem.endswith("_keypoints.json") else PurePath(stem).stem
    match = _LAST_NUMBER.search(stem)
    return match.group(1) if match else None


def name_frames(names: Sequence[str], frame_count: int | None = None) -> tuple[list[int], str | None]:
    """The 0-based frame of each name (in the order given), and a note on how they were read (None when the
    numbers were plainly the frames). See the module docstring."""
    digits = [name_number(name) for name in names]
    numbers = [int(d) if d is not None and len(d) <= 12 else None for d in digits]
    if not names:
        return [], None
    if all(d is None for d in digits):
        order = sorted(range(len(names)), key=lambda i: _natural(names[i]))
        return _ranks(order), "the file names hold no frame numbers: frames taken in sorted order of the names"
    seen: dict[int, int] = {}
    for i, number in enumerate(numbers):
        if digits[i] is None:
            raise NumberingError(f"no frame number in the file name, unlike {PurePath(names[0 if i else 1]).name}",
                                 i)
        if number is None:
            raise NumberingError(f"frame {digits[i][:20]}... in the file name is too large", i)  # type: ignore[index]
        if number in seen:
            raise NumberingError(f"frame {number} again (also {PurePath(names[seen[number]]).name})", i)
        seen[number] = i
    values = [n for n in numbers if n is not None]
    low, high = min(values), max(values)
    openpose_counter = all(d is not None and _OPENPOSE_COUNTER.search(d) for d in digits)
    fits_as_files = frame_count is not None and high >= frame_count and len(values) <= frame_count
    if openpose_counter or (low == 0 and not fits_as_files):
        gaps = high - low + 1 != len(values)
        note = None if low == 0 and not gaps else (
            f"the file names number frames {low}-{high}" + (" with gaps" if gaps else "") + ": taken as the "
            "video's frames")
        return values, note
    order = sorted(range(len(names)), key=lambda i: values[i])
    why = (f"numbered {low}-{high}, past the video's {frame_count} frames" if fits_as_files
           else f"numbered from {low}, not 0")
    first = names[order[0]]
    return _ranks(order), (f"the files are {why}: frames taken in the order of those numbers ({PurePath(first).name} "
                           "is frame 0)")


def _ranks(order: list[int]) -> list[int]:
    frames = [0] * len(order)
    for rank, i in enumerate(order):
        frames[i] = rank
    return frames


def _natural(name: str) -> list[tuple[int, str]]:
    return [(int(part), "") if part.isdigit() else (0, part) for part in re.split(r"(\d+)", name)]
