"""Batch ranking throughput: `rank_batch` (vectorised per chunk) against a naive per-line pure-Python ranker.

Both rank the same lines with the shipped tables; the baseline matches each label and multiplies
probabilities in Python loops, as one would without precomputed log tables. Also reports the load time
of the shipped tables (cold parse) and checks that both rankers agree.
"""

from __future__ import annotations

import json
import math
import time

import numpy as np

from wecook_core.knowledge.nouns import match
from wecook_core.knowledge.recognize import KNOWLEDGE_PATH, Knowledge, knowledge_from_json, load_knowledge, rank_batch

LABELS = ("knife", "tomato", "chopping board", "spoon", "pot", "pan", "oil", "salt", "lemon", "dough",
          "rolling pin", "peeler", "potato", "bread", "butter", "bowl_2", "cherry_tomato", "onion", "carrot",
          "spatula", "garlic", "cheese", "egg", "whisk", "plate", "gizmo")


def lines(count: int, seed: int = 0) -> list[list[str]]:
    rng = np.random.default_rng(seed)
    sizes = rng.integers(1, 5, size=count)
    return [[LABELS[i] for i in rng.integers(0, len(LABELS), size=int(n))] for n in sizes]


def naive(knowledge: Knowledge, labels: list[str]) -> list[tuple[str, float]]:
    """Per line: match every label afresh, multiply P(A) by P(O | A) from the counts, normalise."""
    verbs = knowledge.verbs
    total = sum(int(n) for n in knowledge.action_counts)
    scores = []
    for a in range(len(verbs)):
        row_total = int(knowledge.pair_counts[a].sum())
        if knowledge.prior_kind == "uniform":
            score = 1.0 / len(verbs)
        else:
            score = (int(knowledge.action_counts[a]) + knowledge.alpha) / (total + knowledge.alpha * len(verbs))
        for label in labels:
            o = match(label, knowledge.index)
            if o is not None:
                score *= (int(knowledge.pair_counts[a, o]) + knowledge.alpha) / (
                    row_total + knowledge.alpha * len(knowledge.objects))
        scores.append(score)
    norm = sum(scores)
    return sorted(((v, s / norm) for v, s in zip(verbs, scores, strict=True)), key=lambda x: -x[1])


def _json(ranking: list[tuple[str, float]] | tuple[tuple[str, float], ...]) -> str:
    return json.dumps([{"action": v, "p": p} for v, p in ranking])


def run() -> list[dict[str, object]]:
    knowledge = load_knowledge()
    work = lines(20_000)

    started = time.perf_counter()
    fast = [_json(item.ranking) for item in rank_batch(knowledge, work)]
    fast_s = time.perf_counter() - started
    started = time.perf_counter()
    for _ in rank_batch(knowledge, work):
        pass
    rank_s = time.perf_counter() - started

    sample = work[:2_000]
    started = time.perf_counter()
    slow = [_json(naive(knowledge, labels)) for labels in sample]
    slow_s = (time.perf_counter() - started) * len(work) / len(sample)
    started = time.perf_counter()
    for labels in sample:
        naive(knowledge, labels)
    slow_rank_s = (time.perf_counter() - started) * len(work) / len(sample)

    for a, b in zip(fast[:500], slow[:500], strict=True):
        pa = {x["action"]: x["p"] for x in json.loads(a)}
        pb = {x["action"]: x["p"] for x in json.loads(b)}
        assert pa.keys() == pb.keys() and all(math.isclose(pa[v], pb[v], rel_tol=1e-9, abs_tol=1e-12) for v in pa)

    text = KNOWLEDGE_PATH.read_text()
    best = math.inf
    for _ in range(5):
        t = time.perf_counter()
        knowledge_from_json(json.loads(text), KNOWLEDGE_PATH)
        best = min(best, time.perf_counter() - t)

    return [
        {"benchmark": "batch ranking (20k lines, with JSON)", "value": len(work) / fast_s, "unit": "lines/s",
         "ratio_vs_baseline": slow_s / fast_s, "note": "vs naive per-line pure Python on 2k of the lines"},
        {"benchmark": "batch ranking only (20k lines)", "value": len(work) / rank_s, "unit": "lines/s",
         "ratio_vs_baseline": slow_rank_s / rank_s, "note": "vs naive ranking without JSON"},
        {"benchmark": "naive per-line ranking, with JSON", "value": len(work) / slow_s, "unit": "lines/s",
         "ratio_vs_baseline": 1.0, "note": "baseline"},
        {"benchmark": "load shipped tables (cold parse)", "value": best * 1000, "unit": "ms",
         "ratio_vs_baseline": None, "note": f"{len(knowledge.objects)} objects, {len(knowledge.aliases)} aliases; "
                                            "target < 50 ms"},
    ]


if __name__ == "__main__":
    for row in run():
        print(row)
