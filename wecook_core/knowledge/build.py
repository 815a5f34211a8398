"""Rebuilding the shipped tables: read corpora, learn, derive categories, evaluate, write SOURCE.md."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wecook_core.knowledge.categories import CATEGORIES_PATH, derive_categories, format_categories, read_categories
from wecook_core.knowledge.corpus import EPIC_CITATION, EPIC_LICENCE, Corpus, merge, read_corpus, read_csv, read_epic
from wecook_core.knowledge.evaluation import Evaluation, Metrics, evaluate
from wecook_core.knowledge.learning import learn
from wecook_core.knowledge.recognize import Knowledge, rank, save_knowledge
from wecook_core.resources import ASSETS_DIR, shared_dir

KNOWLEDGE_DIR = ASSETS_DIR / "knowledge"

EXPECTED: tuple[tuple[tuple[str, ...], str], ...] = (
    (("knife", "tomato"), "cut"),
    (("spoon", "pot"), "stir"),
    (("rolling pin", "dough"), "roll"),
    (("peeler", "potato"), "peel"),
    (("lemon",), "squeeze"),
    (("hand", "lemon"), "squeeze"),
    (("oil", "pan"), "pour"),
    (("salt", "pot"), "sprinkle"),
    (("butter knife", "bread"), "spread"),
    (("butter", "knife", "bread"), "spread"),
    (("foil",), "wrap"),
    (("plastic wrap", "bowl"), "wrap"),
    (("bread", "sauce"), "dip"),
)
"""Object sets a cook would name one action for; SOURCE.md reports what the learned tables answer."""


def default_corpus() -> Path:
    """The team's copy of the EPIC-KITCHENS annotations, read in place."""
    return shared_dir() / "data" / "epic-kitchens"


def read_corpora(paths: Sequence[Path], *, context: int = 2) -> Corpus:
    """One corpus from EPIC folders and CSV files (see :func:`~wecook_core.knowledge.corpus.read_corpus`)."""
    corpora = []
    for path in paths:
        if path.is_dir():
            corpora.append(read_epic(path, context=context) if _is_epic(path) else read_corpus(path))
        else:
            corpora.append(read_csv(path) if path.is_file() else read_corpus(path))
    return merge(corpora)


def _is_epic(path: Path) -> bool:
    return (path / "epic55").is_dir() or (path / "epic100").is_dir()


@dataclass(frozen=True)
class Built:
    knowledge: Knowledge
    evaluation: Evaluation | None
    """None when the corpus has too few groups to hold some out."""
    categories: int
    """Entries written to the derived category table (0: the corpus has no noun categories)."""
    files: tuple[Path, ...]


def build(paths: Sequence[Path], out: Path = KNOWLEDGE_DIR, *, alpha: float = 1.0, context: int = 2,
          seed: int = 0, fraction: float = 0.2, command: str = "wecook knowledge learn") -> Built:
    """Learn the tables from ``paths`` into ``out``: ``commonsense.json``, ``epic_categories.yaml`` (when
    the corpus has noun categories) and ``SOURCE.md`` (sources, licences, counts, held-out evaluation)."""
    corpus = read_corpora(paths, context=context)
    knowledge = learn(corpus, alpha=alpha, source="; ".join(corpus.sources))
    try:
        evaluation: Evaluation | None = evaluate(corpus, seed=seed, fraction=fraction, alpha=alpha)
        others = tuple(evaluate(corpus, seed=s, fraction=fraction, alpha=alpha) for s in range(seed + 1, seed + 5))
    except ValueError:
        evaluation, others = None, ()
    out.mkdir(parents=True, exist_ok=True)
    files = [out / "commonsense.json"]
    save_knowledge(knowledge, files[0])
    categories = 0
    if corpus.noun_categories:
        overrides = read_categories(CATEGORIES_PATH).entries if CATEGORIES_PATH.is_file() else {}
        derived = derive_categories(corpus.noun_categories, corpus.nouns, overrides)
        categories = len(derived)
        header = (f"Derived by `{command}` from the EPIC-KITCHENS noun classes' `category` column\n"
                  f"(licence {EPIC_LICENCE}); assets/categories.yaml overrides these. Do not edit: rebuild.")
        files.append(out / "epic_categories.yaml")
        files[-1].write_text(format_categories(derived, header), encoding="utf-8")
    files.append(out / "SOURCE.md")
    files[-1].write_text(source_markdown(corpus, knowledge, evaluation, command=command, alpha=alpha,
                                         context=context, categories=categories, others=others),
                         encoding="utf-8")
    return Built(knowledge, evaluation, categories, tuple(files))


def metrics_table(evaluation: Evaluation) -> str:
    """Markdown: the model against the majority baseline, then per verb."""
    def row(name: str, m: Metrics) -> str:
        return f"| {name} | {m.accuracy:.3f} | {m.macro_precision:.3f} | {m.macro_recall:.3f} |"

    lines = ["| predictor | accuracy | macro precision | macro recall |", "| --- | ---: | ---: | ---: |",
             row("commonsense model", evaluation.model), row(f"majority class (`{evaluation.majority}`)",
                                                             evaluation.baseline),
             "", "| verb | held-out records | predicted | precision | recall |", "| --- | ---: | ---: | ---: | ---: |"]
    lines += [f"| {s.verb} | {s.support} | {s.predicted} | {s.precision:.3f} | {s.recall:.3f} |"
              for s in evaluation.model.per_verb]
    return "\n".join(lines)


def seeds_summary(evaluations: Sequence[Evaluation]) -> str:
    """Markdown: mean and spread of the headline numbers over several splits."""
    def stat(values: list[float]) -> str:
        return f"{np.mean(values):.3f} ± {np.std(values):.3f}"

    seeds = ", ".join(str(e.seed) for e in evaluations)
    lines = [f"Over the splits of seeds {seeds} (mean ± standard deviation):", "",
             "| predictor | accuracy | macro precision | macro recall |", "| --- | ---: | ---: | ---: |"]
    for name, pick in (("commonsense model", lambda e: e.model), ("majority class", lambda e: e.baseline)):
        metrics = [pick(e) for e in evaluations]
        lines.append(f"| {name} | {stat([m.accuracy for m in metrics])} | "
                     f"{stat([m.macro_precision for m in metrics])} | {stat([m.macro_recall for m in metrics])} |")
    return "\n".join(lines)


def source_markdown(corpus: Corpus, knowledge: Knowledge, evaluation: Evaluation | None, *, command: str,
                    alpha: float, context: int, categories: int, others: Sequence[Evaluation] = ()) -> str:
    epic = EPIC_LICENCE in corpus.licences
    counts = ", ".join(f"{v} {n}" for v, n in zip(knowledge.verbs, knowledge.action_counts.tolist(), strict=True))
    parts = [
        "# Commonsense knowledge tables: source",
        "",
        "Generated by `wecook knowledge learn` (do not edit by hand; rebuild). Files:",
        "",
        "- `commonsense.json`: counts learned from the corpus (records per action, records per action and "
        "object) and the object aliases; `wecook_core.recognize.load_knowledge` reads it and derives "
        f"P(A) and P(O | A) with additive smoothing (alpha = {alpha:g}) over the object vocabulary.",
        "- `synonyms.yaml`: hand-written, how corpus verbs fold into wecook's actions (input of the learner).",
    ]
    if categories:
        parts.append(f"- `epic_categories.yaml`: {categories} object categories derived from the corpus's noun "
                     "categories (overridden by `wecook_core/assets/categories.yaml`).")
    parts += ["", "## Source", ""]
    parts += [f"- {s}" for s in corpus.sources]
    if epic:
        parts += ["", f"EPIC-KITCHENS annotations, licence **{EPIC_LICENCE}** (non-commercial use only); the "
                      f"tables here are derived from them and carry the same licence. Cite: {EPIC_CITATION}. "
                      "The annotations themselves are not in this repository: they are read in place from "
                      "`../shared/data/epic-kitchens/`."]
    other = [lic for lic in corpus.licences if lic != EPIC_LICENCE]
    if other:
        parts += ["", "Other licences: " + ", ".join(other)]
    parts += [
        "", "## What was learned", "",
        f"Records kept (verb folds into wecook's actions): {int(knowledge.action_counts.sum())} "
        f"({counts}); object vocabulary: {len(knowledge.objects)} nouns, {len(knowledge.aliases)} aliases.",
    ]
    if epic:
        parts += ["", "Objects of a record: its `all_nouns` mapped to EPIC-100 noun classes, plus the nouns "
                      f"of the \"take\" records among the {context} records before it in the same video (the "
                      "narrations rarely name the tool: \"take knife\", then \"cut tomato\"). "
                      + ("Context is off." if context == 0 else "")]
    parts += ["", "## Held-out evaluation", ""]
    if evaluation is None:
        parts.append("Not evaluated: the corpus has too few groups to hold some out.")
    else:
        parts += [f"Split by group (EPIC: video), seed {evaluation.seed}: {evaluation.test_groups} groups "
                  f"({evaluation.fraction:.0%}) held out, {evaluation.train_records} training records, "
                  f"{evaluation.test_records} held-out records. Prediction: argmax of P(A | objects). Macro "
                  "averages run over the verbs present in the held-out records (a verb never predicted "
                  "has precision 0). Held-out records carry their take-context objects too, as the pipeline "
                  "passes the held tool with the targets.", "", metrics_table(evaluation)]
        if others:
            parts += ["", seeds_summary([evaluation, *others])]
    parts += ["", "## Common cases", "",
              "What a cook would answer, and the learned tables' top-1 (computed at build time):", "",
              "| objects | expected | top-1 (p) | |", "| --- | --- | --- | --- |"]
    for objects, expected in EXPECTED:
        ranking = rank(knowledge, objects)
        verb, p = ranking[0] if ranking else ("-", 0.0)
        parts.append(f"| {' + '.join(objects)} | {expected} | {verb} ({p:.2f}) | "
                     f"{'ok' if verb == expected else 'wrong'} |")
    parts += [
        "", "## Rebuild", "",
        "```",
        f"{command}            # reads ../shared/data/epic-kitchens, writes assets/knowledge/",
        "wecook knowledge learn --corpus ../shared/data/epic-kitchens --corpus my_records.csv -o DIR",
        "wecook knowledge evaluate --json",
        "```",
        "",
        "A CSV corpus has rows `action,objects[,group]`, objects separated by `;` "
        "(`chop,knife;onion;chopping board`).",
    ]
    return "\n".join(parts) + "\n"
