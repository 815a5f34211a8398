"""Layouts from 80x24 to 300x80: the footer keeps help and quit, the side panel grows, the actions show."""

from __future__ import annotations

from pathlib import Path

import pytest
from tui_driving import pilot_test, settle
from tui_fake import fake_workspace

from wecook_tui.app import WecookApp
from wecook_tui.widgets.inspector import Inspector


def screen_text(app: WecookApp) -> list[str]:
    return ["".join(segment.text for segment in strip) for strip in app.screen._compositor.render_strips()]


@pytest.mark.parametrize("size", [(80, 24), (200, 55), (300, 80)])
@pilot_test
@pytest.mark.slow
async def test_nothing_needed_is_off_screen(tmp_path: Path, size: tuple[int, int]) -> None:
    opener, analyzer = fake_workspace(tmp_path)
    app = WecookApp(tmp_path / "kitchen", opener=opener, analyzer=analyzer)
    async with app.run_test(size=size) as pilot:
        await settle(pilot, app)
        lines = screen_text(app)
        assert len(lines) == size[1]
        assert "? Help" in lines[-1] and "q Quit" in lines[-1]
        inspector = app.main.query_one(Inspector)
        assert inspector.size.width >= min(30, size[0] // 3)
        if size[0] >= 200:
            assert inspector.size.width > 56  # grows with the terminal
        panel = [line[inspector.region.x:] for line in lines[inspector.region.y:inspector.region.bottom]]
        assert any("Actions" in line for line in panel) and any("RH_P1: cut" in line for line in panel)
        assert any("segment 1/3" in line for line in lines)
