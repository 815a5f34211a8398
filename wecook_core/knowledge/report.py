"""SOURCE.md of the shipped tables: where the counts come from, their licences, and how well they do."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from wecook_core.knowledge.archive import ARCHIVE_LICENCE, ARCHIVE_SOURCE
from wecook_core.knowledge.corpus import EPIC_CITATION, EPIC_LICENCE, EPIC_SOURCE, RECIPES_SOURCE, Corpus
from wecook_core.knowledge.evaluation import Evaluation, Metrics
from wecook_core.knowledge.recognize import Knowledge, rank

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
    (("spoon", "rice", "jar", "pot"), "transfer"),
)
"""Object sets a cook would name one action for; SOURCE.md reports what the learned tables answer."""


def _row(name: str, m: Metrics) -> str:
    return f"| {name} | {m.accuracy:.3f} | {m.macro_precision:.3f} | {m.macro_recall:.3f} |"


def verb_table(metrics: Metrics) -> list[str]:
    """Markdown lines: precision and recall per verb."""
    lines = ["| verb | held-out records | predicted | precision | recall |", "| --- | ---: | ---: | ---: | ---: |"]
    lines += [f"| {s.verb} | {s.support} | {s.predicted} | {s.precision:.3f} | {s.recall:.3f} |"
              for s in metrics.per_verb]
    return lines


def metrics_table(evaluation: Evaluation) -> str:
    """Markdown: the model against the majority baseline, per corpus when there are several, then per verb
    (per verb and corpus)."""
    lines = ["| predictor | accuracy | macro precision | macro recall |", "| --- | ---: | ---: | ---: |",
             _row("commonsense model, all held-out records", evaluation.model)]
    lines += [_row(f"commonsense model, held-out `{source}` records", m) for source, m in evaluation.by_source]
    lines += [_row(f"majority class (`{evaluation.majority}`)", evaluation.baseline)]
    if evaluation.ceiling is not None:
        lines += [_row("ceiling: the model learned from the held-out records themselves", evaluation.ceiling)]
        lines += [_row(f"ceiling, held-out `{source}` records", m) for source, m in evaluation.ceiling_by_source]
    if evaluation.oracle is not None:
        lines += [_row("objects oracle: the most frequent verb of each object set among the held-out records",
                       evaluation.oracle)]
        lines += [_row(f"objects oracle, held-out `{source}` records", m) for source, m in evaluation.oracle_by_source]
    for source, m in evaluation.by_source or (("all", evaluation.model),):
        lines += ["", f"Held-out `{source}` records:" if evaluation.by_source else "Per verb:", "", *verb_table(m)]
    return "\n".join(lines)


def _stat(values: Sequence[float]) -> str:
    return f"{np.mean(values):.3f} ± {np.std(values):.3f}"


def seeds_summary(runs: Mapping[str, Sequence[Evaluation]]) -> str:
    """Markdown: mean and spread of the headline figures over several splits, per model (``runs``: a label
    such as ``uniform, per group`` -> its evaluations) and corpus."""
    first = next(iter(runs.values()))[0]
    seeds = ", ".join(str(e.seed) for e in next(iter(runs.values())))
    lines = [f"Over the splits of seeds {seeds} (mean ± standard deviation):", "",
             "| model (prior, counts) | held-out records | accuracy | macro precision | macro recall |",
             "| --- | --- | ---: | ---: | ---: |"]
    for prior, evaluations in runs.items():
        rows: list[tuple[str, list[Metrics]]] = [("all", [e.model for e in evaluations])]
        rows += [(source, [e.by_source[i][1] for e in evaluations]) for i, (source, _) in enumerate(first.by_source)]
        rows.append(("all, majority class", [e.baseline for e in evaluations]))
        ceilings = [e.ceiling for e in evaluations if e.ceiling is not None]
        if len(ceilings) == len(evaluations):
            rows.append(("all, ceiling (learned from the held-out records)", ceilings))
            rows += [(f"{source}, ceiling", [e.ceiling_by_source[i][1] for e in evaluations])
                     for i, (source, _) in enumerate(first.ceiling_by_source)]
        oracles = [e.oracle for e in evaluations if e.oracle is not None]
        if len(oracles) == len(evaluations):
            rows.append(("all, objects oracle (from the held-out records)", oracles))
            rows += [(f"{source}, objects oracle", [e.oracle_by_source[i][1] for e in evaluations])
                     for i, (source, _) in enumerate(first.oracle_by_source)]
        for name, metrics in rows:
            lines.append(f"| {prior} | {name} | {_stat([m.accuracy for m in metrics])} | "
                         f"{_stat([m.macro_precision for m in metrics])} | "
                         f"{_stat([m.macro_recall for m in metrics])} |")
    return "\n".join(lines)


def _files(alpha: float, prior: str, categories: int, recipes: bool, per_group: bool,
           mixed: bool = False) -> list[str]:
    counted = ("groups (EPIC videos, recipes) per action and per action and object: a group that repeats a verb "
               "with an object counts once" if per_group else "records per action, records per action and object")
    if mixed:
        table = ("- `commonsense.json`: per corpus, its own counts (`components`: groups per action and object, "
                 "an object counted where its record names it in the relation of its role, a tool as what the "
                 "action is done with, a container as where, an ingredient as what it is done to; and each "
                 "action's (relation, object) features, `totals`) and the object aliases; "
                 "`wecook_core.knowledge.recognize.load_knowledge` reads it and takes P(O | A) as the mean over the "
                 f"corpora of each one's additively smoothed share (alpha = {alpha:g}, over `features`), every "
                 "corpus one vote (`wecook_core.knowledge.mixture`); P(A) is uniform.")
    else:
        table = (f"- `commonsense.json`: counts learned from the corpora ({counted}) and the object aliases; "
                 "`wecook_core.knowledge.recognize.load_knowledge` reads it and derives "
                 f"P(O | A) with additive smoothing (alpha = {alpha:g}) over the object vocabulary; P(A) is "
                 + ("uniform (`\"prior\": \"uniform\"`)." if prior == "uniform"
                    else "learned from the action counts."))
    parts = [
        table,
        "- `synonyms.yaml`: hand-written, how corpus verbs fold into wecook's actions (input of the learner); "
        "a verb named after its tool (whisk, spoon, ladle) adds the tool to its record's objects "
        "(`wecook_core.knowledge.learning.INSTRUMENTS`).",
    ]
    if recipes:
        parts.append("- `recipes.csv`: the (verb, objects) records extracted from the recipe instructions "
                     "(input of the learner; `wecook knowledge extract` rebuilds it from the recipes).")
    if categories:
        parts.append(f"- `epic_categories.yaml`: {categories} object categories derived from the EPIC-KITCHENS "
                     "noun categories (overridden by `wecook_core/assets/categories.yaml`).")
    return parts


def _licences(corpus: Corpus, context: int, held_s: float) -> list[str]:
    sources = {r.source for r in corpus.records}
    parts: list[str] = []
    if EPIC_LICENCE in corpus.licences:
        parts += ["", f"**EPIC-KITCHENS** annotations, licence **{EPIC_LICENCE}** (non-commercial use only); the "
                      f"counts learned from them carry the same licence. Cite: {EPIC_CITATION}. The annotations "
                      "are not in this repository: they are read in place from `../shared/data/epic-kitchens/`. "
                      "Objects of a record: its `all_nouns` mapped to EPIC-100 noun classes, plus "
                      + (f"the tools (of the shipped category tables) taken in the same video at most {held_s:g} s "
                         "before it and not put down since (the narrations name the tool once: \"take knife\", "
                         "then \"cut courgette\" a dozen times; `wecook_core.knowledge.corpus.HELD_S`)"
                         if held_s > 0 else "no held tool")
                      + (f", and the nouns of the \"take\" records among the {context} records before it"
                         if context else "") + "."]
    if RECIPES_SOURCE in sources:
        parts += ["", "**Recipe instructions**: the recipes of Public Domain Recipes (publicdomainrecipes.com, "
                      "the continuation of based.cooking), released into the **public domain** by their authors "
                      "(the Unlicense: \"This website and all its content is in the public domain\"). Each clause "
                      "of a recipe's directions becomes a record: its imperative verb and the objects it names "
                      "(`wecook_core.knowledge.instructions`: clause-opening verbs, whole-word noun phrases of "
                      "the shipped category tables, \"Peel and cut the apples\" shares the apples, \"Spoon the "
                      "rice into jars\" is done with a spoon, \"Roll the balls in sugar\" is `roll-in`, a coating, "
                      "folded into dip, "
                      "\"Roll out the dough\" is `roll-out`). The extracted records are shipped as "
                      "`recipes.csv`; the recipes themselves are not."]
    if ARCHIVE_SOURCE in sources:
        parts += ["", "**Open Recipe Archive**: public-domain cookbooks (1800s to early 1900s, 31 collections), "
                      "under the **Unlicense** (public domain dedication); read in place from "
                      "`../shared/data/recipes/` (`wecook_core.knowledge.archive`: every clause of every step, "
                      "old spellings joined, a pronoun takes the ingredients of the recipe's list named last; "
                      "each object with its relation to the verb: object, place, means, source). Counts learned "
                      "from it carry no restriction; the recipes themselves are not in this repository."]
    else:
        parts += ["", "**Open Recipe Archive** (`../shared/data/recipes/`, the Unlicense): not learned from by "
                      "these tables. `wecook knowledge extract` reads it in place (54,843 recipes, 440,937 "
                      "clauses, 95,408 records whose verb folds into wecook's actions, each object with its "
                      "relation to the verb: object, place, means, source) and `wecook knowledge "
                      "learn --corpus ../shared/data/recipes` learns from it; pooled with EPIC it outweighs the "
                      "videos, and the tools it rarely names took the tools' verbs over (knife + meat + board "
                      "ranked roll, spoon + pot transfer): the shared scenarios dropped (`bench.quality`: s301 "
                      "0.50, s303 0.71, tasty-a 0.50). Its held-out figures by collection: `python -m "
                      "bench.recognize --held-out` (six collections held out, seed 0: these tables' model learned "
                      "from the others, macro P 0.387 / R 0.532; the role-aware model of "
                      "`wecook_core.knowledge.relations`, not shipped, 0.474 / 0.605, 0.493 / 0.602 with its "
                      "class and role back-off, `wecook_core.knowledge.classes`, and 0.490 / 0.618 mixed with a "
                      "logistic model, `wecook_core.knowledge.ensemble`)."]
    named = {EPIC_LICENCE} | ({ARCHIVE_LICENCE} if ARCHIVE_SOURCE in sources else set())
    other = [lic for lic in corpus.licences if lic not in named]
    if other:
        parts += ["", "Licences declared by the other corpora: " + ", ".join(other) + "."]
    described = {EPIC_SOURCE, RECIPES_SOURCE, ARCHIVE_SOURCE}
    if sources - described:
        parts += ["", "Other corpora (no licence declared unless listed above): "
                      + ", ".join(sorted(sources - described)) + "."]
    return parts


def source_markdown(corpus: Corpus, knowledge: Knowledge, runs: Mapping[str, Sequence[Evaluation]], *,
                    command: str, alpha: float, context: int, categories: int, records: int = 0,
                    per_group: bool = True, held_s: float = 0.0) -> str:
    """The text of SOURCE.md; ``runs``: prior -> evaluations over several seeds (the tables' prior first)."""
    counts = ", ".join(f"{v} {n}" for v, n in zip(knowledge.verbs, knowledge.action_counts.tolist(), strict=True))
    recipes = any(r.source == RECIPES_SOURCE for r in corpus.records)
    parts = ["# Commonsense knowledge tables: source", "",
             f"Generated by `{command}` (do not edit by hand; rebuild). Files:", "",
             *_files(alpha, knowledge.prior_kind, categories, recipes, per_group, bool(knowledge.components)),
             "", "## Sources", ""]
    parts += [f"- {s}" for s in corpus.sources]
    parts += _licences(corpus, context, held_s)
    parts += ["", "## What was learned", "",
              f"Records kept (verb folds into wecook's actions and the record names an object): {records}; "
              f"action counts ({'groups' if per_group else 'records'}): {counts}; object vocabulary: "
              f"{len(knowledge.objects)} nouns, {len(knowledge.aliases)} aliases.", "", "## Held-out evaluation", ""]
    evaluation = next(iter(runs.values()))[0] if runs else None
    if evaluation is None:
        parts.append("Not evaluated: the corpus has too few groups to hold some out.")
    else:
        parts += [f"Split by unit, corpus by corpus (EPIC: video; recipes: recipe; the Open Recipe Archive: "
                  f"collection, a book never both learned from and tested on), seed {evaluation.seed}: "
                  f"{evaluation.test_groups} units ({evaluation.fraction:.0%} of each corpus's) held out, "
                  f"{evaluation.train_records} training records, "
                  f"{evaluation.test_records} held-out records; the tables are learned from the training records "
                  f"of all corpora. Prediction: argmax of P(A | objects), prior `{knowledge.prior_kind}`. Macro "
                  "averages run over the verbs present in the held-out records (a verb never predicted has "
                  "precision 0). "
                  "Held-out EPIC records carry their held tools too, as the pipeline passes the held "
                  "object with the targets. The ceiling row learns the same model from the held-out records "
                  "and scores it on them (resubstitution): records whose objects are the same and whose verbs "
                  "differ cannot all be named right, and the smoothing that lets the model generalise costs it "
                  "some of the records it has seen; a reference for the held-out rows, not a generalisation "
                  "figure. The objects oracle names each held-out record with the verb most held-out records "
                  "of exactly its object set have: no recogniser fed only these objects can name more of them "
                  "(accuracy), whatever its model; what it misses is what the objects cannot tell (the same "
                  "salt over the same pot poured by one cook, sprinkled by another).", "",
                  metrics_table(evaluation), "", seeds_summary(runs)]
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
        f"{command}            # reads ../shared/data/epic-kitchens and recipes.csv, writes assets/knowledge/",
        "wecook knowledge extract public-domain-recipes/content -o wecook_core/assets/knowledge/recipes.csv",
        "wecook knowledge learn --corpus ../shared/data/epic-kitchens --corpus my_records.csv -o DIR",
        "wecook knowledge evaluate --json",
        "```",
        "",
        "`extract` reads a clone of github.com/ronaldl29/public-domain-recipes (its `content/` folder of "
        "Markdown recipes; any folder of such recipes works, and `--corpus FOLDER` learns from one directly). "
        "A CSV corpus has rows `action,objects[,group[,context]]`, objects separated by `;` "
        "(`chop,knife;onion;chopping board`), and may declare `# corpus:`, `# source:` and `# licence:` in "
        "comment lines.",
    ]
    return "\n".join(parts) + "\n"
