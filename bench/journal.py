"""Journal appends (issue 28): appends per second on an empty journal and on one of 5,000 entries, measured in
the same run; the ratio (late / early) should stay near 1, since an append no longer replays the journal (it was
about 0.2: 500 appends/s at the start, 100/s at 5,000 entries). The fsync of each append is left out (os.fsync
does nothing while it runs): it is the disk's time, the same for every append, and its noise on a shared machine
hid the ratio; with it, about 450 appends/s either way here (75/s at 5,000 entries before)."""

from __future__ import annotations

import os
import tempfile
import time
from pathlib import Path

from wecook_core.session.journal import Journal

ENTRIES = 5000
MEASURED = 200


def _rate(journal: Journal, start: int) -> float:
    began = time.perf_counter()
    for i in range(MEASURED):
        journal.record({"op": "split", "frame": start + i})
    return MEASURED / (time.perf_counter() - began)


def run() -> list[dict[str, object]]:
    real = os.fsync
    os.fsync = lambda fd: None
    try:
        return _run()
    finally:
        os.fsync = real


def _run() -> list[dict[str, object]]:
    with tempfile.TemporaryDirectory() as folder:
        journal = Journal(Path(folder) / "journal.jsonl")
        early = _rate(journal, 10)
        journal.close()
        with (Path(folder) / "journal.jsonl").open("a") as handle:  # grown without an fsync per line
            for seq in range(MEASURED + 1, ENTRIES + 1):
                handle.write(f'{{"seq":{seq},"time":"","op":"split","frame":{10 + seq}}}\n')
        journal = Journal(Path(folder) / "journal.jsonl")
        late = _rate(journal, 10 + ENTRIES + 1)
        journal.close()
    return [
        {"benchmark": "appends, empty journal", "value": early, "unit": "appends/s"},
        {"benchmark": f"appends, {ENTRIES} entries", "value": late, "unit": "appends/s",
         "ratio_vs_baseline": late / early, "note": "baseline: the empty journal; about 1 when appends are O(1)"},
    ]
