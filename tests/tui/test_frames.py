"""Frame decoding (cache, prefetch, damaged files), overlays, half-block rendering; and that a slow decode never
holds up the keys."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import numpy as np
import pytest
from rich.segment import Segment
from tui_driving import pilot_test, wait_for
from tui_fake import fake_workspace, make_video

from wecook_tui.app import WecookApp
from wecook_tui.frames import (
    HALF_BLOCK,
    BoxMark,
    Canvas,
    FrameSource,
    HandMark,
    Label,
    LinkMark,
    Overlay,
    draw,
    fit,
    to_strips,
)
from wecook_tui.widgets.frame_view import FrameView


def test_decode_caches_resizes_and_evicts(tmp_path: Path) -> None:
    source = FrameSource(make_video(tmp_path / "v.avi", frames=30), cache_size=8)
    assert source.ok and source.facts.frame_count == 30 and (source.facts.width, source.facts.height) == (320, 180)
    source.set_size(64, 36)
    frame = source.decode(5)
    assert frame is not None and frame.shape == (36, 64, 3)
    assert source.cached(5) is frame
    assert source.prefetch(6, 20) == 14
    assert source.cached(5) is None and source.cached(19) is not None  # least recently used went first
    assert source.decode(30) is None and source.decode(-1) is None
    source.set_size(32, 18)
    assert source.cached(6) is None  # a new size drops the cache but for the last few frames, resized again
    again = source.cached(19)
    assert again is not None and again.shape == (18, 32, 3)


def test_frames_match_a_sequential_read(tmp_path: Path) -> None:
    """Seeks, backward reads and forward skips give the same pixels as reading the file in order."""
    import cv2

    path = make_video(tmp_path / "v.avi", frames=40)
    capture = cv2.VideoCapture(str(path))
    truth = [capture.read()[1] for _ in range(40)]
    source = FrameSource(path)
    for index in (0, 1, 2, 30, 10, 11, 39, 5, 25):
        got = source.decode(index)
        assert got is not None and np.array_equal(got, truth[index]), index


def test_prefetch_stops_when_cancelled(tmp_path: Path) -> None:
    source = FrameSource(make_video(tmp_path / "v.avi", frames=30))
    calls = []
    assert source.prefetch(0, 30, cancelled=lambda: len(calls.append(1) or calls) > 3) == 3


def test_missing_and_corrupt_videos_say_why(tmp_path: Path) -> None:
    missing = FrameSource(tmp_path / "nope.mp4")
    assert not missing.ok and "missing" in (missing.facts.error or "")
    assert missing.decode(0) is None
    broken = tmp_path / "broken.mp4"
    broken.write_bytes(b"\x00not a video" * 100)
    corrupt = FrameSource(broken)
    assert not corrupt.ok and "broken.mp4" in (corrupt.facts.error or "")


def test_fit_keeps_the_aspect_and_an_even_height() -> None:
    assert fit((1280, 720), (160, 45)) == (160, 90)
    assert fit((1280, 720), (100, 45)) == (100, 56)
    width, height = fit((640, 480), (80, 10))
    assert height == 20 and width == 26 and height % 2 == 0


def test_half_blocks_pair_rows_and_join_runs() -> None:
    image = np.zeros((4, 6, 3), np.uint8)
    image[0] = (0, 0, 255)  # BGR red on the top row
    image[1] = (255, 0, 0)
    image[2:, 3:] = (0, 255, 0)
    strips = to_strips(Canvas(image))
    assert len(strips) == 2 and all(strip.cell_length == 6 for strip in strips)
    first: list[Segment] = list(strips[0])
    assert len(first) == 1 and first[0].text == HALF_BLOCK * 6
    assert first[0].style.color.triplet == (248, 0, 0)  # 5-bit quantised red on top
    assert first[0].style.bgcolor.triplet == (0, 0, 248)
    assert [len(s.text) for s in strips[1]] == [3, 3]


def test_labels_overwrite_cells_with_text() -> None:
    strips = to_strips(Canvas(np.zeros((4, 10, 3), np.uint8), [Label(2, 1, "knife", (255, 255, 255))]))
    text = "".join(segment.text for segment in strips[1])
    assert text == HALF_BLOCK * 2 + "knife" + HALF_BLOCK * 3
    assert "".join(segment.text for segment in strips[0]) == HALF_BLOCK * 10


def test_overlay_draws_scaled_boxes_links_and_hands() -> None:
    image = np.zeros((18, 32, 3), np.uint8)
    overlay = Overlay(boxes=(BoxMark("bowl", (100, 40, 200, 140), (0, 255, 0)),),
                      hands=(HandMark("RH_P1", (300, 150), (255, 0, 0), selected=True),),
                      links=(LinkMark((150, 90), (300, 150), (255, 255, 255)),))
    canvas = draw(image, overlay, (320, 180))
    assert not image.any()  # drawn on a copy
    assert tuple(canvas.image[4, 15]) == (0, 255, 0)  # the box's top edge, scaled by 1/10
    assert canvas.image[15, 30].any()  # the hand marker
    assert {label.text for label in canvas.labels} == {"bowl", "RH_P1"}


@pilot_test
@pytest.mark.slow
async def test_a_slow_decode_never_holds_up_the_keys(tmp_path: Path) -> None:
    opener, analyzer = fake_workspace(tmp_path)
    gate = threading.Event()

    def slow_opener(path: Path):  # type: ignore[no-untyped-def]
        opened = opener(path)
        original = opened.frames.decode

        def decode(index: int):  # type: ignore[no-untyped-def]
            if index > 0:
                gate.wait(5)  # a decoder stuck on a damaged file
            return original(index)

        opened.frames.decode = decode
        opened.frames.prefetch = lambda *args, **kwargs: 0
        return opened

    app = WecookApp(tmp_path / "kitchen", opener=slow_opener, analyzer=analyzer)
    async with app.run_test(size=(120, 40)) as pilot:
        while app.analysis is None:
            await pilot.pause(0.02)
        view = app.main.query_one(FrameView)
        started = time.perf_counter()
        await pilot.press("L", "L", "n", "a")
        assert time.perf_counter() - started < 2.0
        assert app.main.frame == 40 and view.index == 40 and view.shown == 0  # old picture while decoding
        assert app.corrections.status  # and the accept went through
        gate.set()
        await wait_for(pilot, lambda: view.shown == 40, 200)
        assert view.shown == 40


def test_overlapping_labels_move_to_a_free_row() -> None:
    image = np.zeros((20, 40, 3), np.uint8)
    overlay = Overlay(boxes=(BoxMark("bowl", (20, 40, 100, 100), (0, 255, 0)),
                             BoxMark("board", (30, 40, 200, 100), (0, 255, 0))),
                      hands=(HandMark("RH_P1", (0, 50), (255, 0, 0)),))
    labels = draw(image, overlay, (400, 200)).labels
    rows = {label.text: (label.x, label.y) for label in labels}
    assert rows["bowl"][1] != rows["board"][1] or abs(rows["bowl"][0] - rows["board"][0]) > 5
    cells = [(label.y, x) for label in labels for x in range(label.x, label.x + len(label.text))]
    assert len(cells) == len(set(cells))  # no two labels share a cell


def test_box_labels_sit_outside_the_box_in_a_contrasting_colour() -> None:
    from wecook_tui.frames import contrasting

    image = np.zeros((40, 80, 3), np.uint8)
    overlay = Overlay(boxes=(BoxMark("onion", (100, 100, 300, 300), (240, 240, 90)),
                             BoxMark("jar", (400, 0, 600, 150), (40, 40, 160))))
    labels = {label.text: label for label in draw(image, overlay, (800, 400)).labels}
    onion, jar = labels["onion"], labels["jar"]
    assert onion.y < 100 / 10 // 2 and onion.background == (240, 240, 90) and onion.colour == (0, 0, 0)
    assert jar.y > 150 / 10 // 2 and jar.colour == (255, 255, 255)  # at the frame's top edge: below the box
    assert contrasting((255, 255, 255)) == (0, 0, 0) and contrasting((0, 0, 80)) == (255, 255, 255)
    strips = to_strips(draw(image, overlay, (800, 400)))
    cell = next(seg for seg in strips[onion.y] if seg.text == "o")
    assert cell.style.bgcolor.triplet == (240 & 0xF8, 240 & 0xF8, 90 & 0xF8)  # the tag, not the picture


def test_action_colours_are_distinct() -> None:
    import itertools

    from wecook_tui.review import ACTION_COLOURS

    rgb = {verb: tuple(int(code[i:i + 2], 16) for i in (1, 3, 5)) for verb, code in ACTION_COLOURS.items()}
    for (a, ca), (b, cb) in itertools.combinations(rgb.items(), 2):
        assert sum((x - y) ** 2 for x, y in zip(ca, cb, strict=True)) ** 0.5 > 60, (a, b)


def _cells(strip) -> list[tuple[str, tuple[int, int, int], tuple[int, int, int]]]:  # type: ignore[no-untyped-def]
    return [(char, segment.style.color.triplet, segment.style.bgcolor.triplet)
            for segment in strip for char in segment.text]


def test_half_blocks_show_each_cell_s_two_pixels_frame_after_frame() -> None:
    """Every cell is ``▀`` with its top pixel as foreground and its bottom pixel as background (5 bits a
    channel), on pictures with long runs and on noise, one after the other (runs are reused between frames)."""
    rng = np.random.default_rng(3)
    blocky = np.repeat(np.repeat(rng.integers(0, 256, (5, 8, 3), dtype=np.uint8), 7, axis=0), 9, axis=1)
    noise = rng.integers(0, 256, (35, 72, 3), dtype=np.uint8)  # an odd number of rows: the last is doubled
    for image in (blocky, noise, blocky[::-1].copy()):
        strips = to_strips(Canvas(image))
        padded = np.vstack([image, image[-1:]]) if image.shape[0] % 2 else image
        assert len(strips) == padded.shape[0] // 2
        for row, strip in enumerate(strips):
            expected = [(HALF_BLOCK, tuple(int(v) & 0xF8 for v in padded[2 * row, x, ::-1]),
                         tuple(int(v) & 0xF8 for v in padded[2 * row + 1, x, ::-1])) for x in range(image.shape[1])]
            assert _cells(strip) == expected, row
            assert strip.cell_length == image.shape[1]
    labelled = to_strips(Canvas(blocky, [Label(3, 2, "bowl", (0, 0, 0), (240, 240, 90))]))
    assert "".join(char for char, _, _ in _cells(labelled[2]))[3:7] == "bowl"
    assert _cells(labelled[3]) == _cells(to_strips(Canvas(blocky))[3])  # only the label's row changes


def test_a_selected_box_is_drawn_white_and_thicker() -> None:
    image = np.zeros((18, 32, 3), np.uint8)
    plain = draw(image, Overlay(boxes=(BoxMark("bowl", (100, 40, 200, 140), (0, 255, 0)),)), (320, 180))
    chosen = draw(image, Overlay(boxes=(BoxMark("bowl", (100, 40, 200, 140), (0, 255, 0), selected=True),)),
                  (320, 180))
    assert tuple(plain.image[4, 15]) == (0, 255, 0) and not plain.image[5, 15].any()
    assert tuple(chosen.image[4, 15]) == (255, 255, 255) and chosen.image[5, 15].all()
    assert chosen.labels[0].background == (255, 255, 255) and chosen.labels[0].colour == (0, 0, 0)


def test_prefetch_with_a_step_keeps_every_step_th_frame_with_the_right_pixels(tmp_path: Path) -> None:
    import cv2

    path = make_video(tmp_path / "v.avi", frames=30)
    capture = cv2.VideoCapture(str(path))
    truth = [capture.read()[1] for _ in range(30)]
    source = FrameSource(path)
    assert source.prefetch(2, 20, step=3) == 6  # 2, 5, 8, 11, 14, 17
    for index in range(2, 20):
        frame = source.cached(index)
        assert (frame is not None) == ((index - 2) % 3 == 0), index
        if frame is not None:
            assert np.array_equal(frame, truth[index]), index


@pilot_test
@pytest.mark.slow
async def test_playback_that_lags_keeps_every_few_frames_and_shows_the_latest_kept(tmp_path: Path) -> None:
    opener, analyzer = fake_workspace(tmp_path)
    app = WecookApp(tmp_path / "kitchen", opener=opener, analyzer=analyzer)
    async with app.run_test(size=(120, 40)) as pilot:
        while app.analysis is None:
            await pilot.pause(0.02)
        view = app.main.query_one(FrameView)
        await app.workers.wait_for_complete()
        source = view.source
        assert source is not None
        source.forget()  # an empty cache
        calls: list[tuple[int, int, int]] = []
        prefetch = source.prefetch

        def recorded(start: int, stop: int, cancelled, step: int = 1) -> int:  # type: ignore[no-untyped-def]
            calls.append((start, stop, step))
            return prefetch(start, stop, cancelled, step) if step > 1 else 0  # only the strided one decodes

        source.prefetch = recorded  # type: ignore[method-assign]
        for frame in (3, 6, 9, 12):  # the clock moved three frames between paints, four times
            app.main.frame = frame
            await pilot.pause()
        assert view.stride == 3
        await app.workers.wait_for_complete()
        assert calls[0][2] == 1 and calls[-1] == (13, 132, 3)
        ahead = [i for i in range(13, 60) if source.cached(i) is not None]
        assert ahead == list(range(13, 60, 3))  # every third frame decoded ahead
        app.main.frame = 14  # not kept: the latest kept before it is shown, nothing decoded
        await pilot.pause()
        assert view.index == 14 and view.shown == 13 and source.cached(14) is None
        app.main.frame = 15
        await pilot.pause()
        assert view.stride == 1  # a one-frame step: every frame again


@pytest.mark.slow
def test_prefetch_behind_the_cursor_decodes_the_nearest_frames_first(tmp_path: Path) -> None:
    """Stepping back wants the frame just below the cursor next: the first block read is the one below it."""
    source = FrameSource(make_video(tmp_path / "v.avi", frames=60))
    source.set_size(64, 36)
    calls: list[int] = []
    done = source.prefetch_back(50, 40, cancelled=lambda: len(calls.append(1) or calls) > FrameSource.BACK_BLOCK + 1)
    assert done == FrameSource.BACK_BLOCK
    assert all(source.cached(i) is not None for i in range(50 - FrameSource.BACK_BLOCK, 50))
    assert source.cached(50) is None and source.cached(10) is None
    assert source.prefetch_back(50, 40) == 40 - FrameSource.BACK_BLOCK
    assert all(source.cached(i) is not None for i in range(10, 50))


def test_a_new_size_resizes_the_last_frames_again_instead_of_decoding(tmp_path: Path) -> None:
    """The layout settling a column smaller keeps the frames just shown, with the pixels a decode would give."""
    path = make_video(tmp_path / "v.avi", frames=30)
    source = FrameSource(path)
    source.set_size(64, 36)
    for index in range(20):
        source.decode(index)
    source.set_size(62, 34)
    kept = [i for i in range(30) if source.cached(i) is not None]
    assert kept == [0, *range(20 - FrameSource.RAW_KEPT, 20)]
    fresh = FrameSource(path)
    fresh.set_size(62, 34)
    for index in kept:
        frame, truth = source.cached(index), fresh.decode(index)
        assert frame is not None and truth is not None and frame.shape == (34, 62, 3)
        assert np.array_equal(frame, truth), index
