"""Rebuilding the shipped tables: read corpora, learn, derive categories, evaluate, write SOURCE.md."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from wecook_core.files import write_atomic
from wecook_core.knowledge.archive import ARCHIVE_LICENCE, ARCHIVE_SOURCE, is_archive, read_archive
from wecook_core.knowledge.categories import (
    CATEGORIES_PATH,
    DERIVED_PATH,
    derive_categories,
    format_categories,
    read_categories,
)
from wecook_core.knowledge.corpus import (
    EPIC_LICENCE,
    HELD_S,
    RECIPES_SOURCE,
    Corpus,
    merge,
    read_corpus,
    read_csv,
    read_epic,
    read_recipes,
)
from wecook_core.knowledge.evaluation import Evaluation, evaluate
from wecook_core.knowledge.instructions import is_recipe_folder, noun_table
from wecook_core.knowledge.learning import fold, learn
from wecook_core.knowledge.recognize import PRIORS, Knowledge, save_knowledge
from wecook_core.knowledge.report import EXPECTED, source_markdown
from wecook_core.knowledge.synonyms import load_synonyms
from wecook_core.model import Category
from wecook_core.resources import ASSETS_DIR, shared_dir

KNOWLEDGE_DIR = ASSETS_DIR / "knowledge"
__all__ = ["ARCHIVE_LICENCE", "ARCHIVE_PATH", "EXPECTED", "KNOWLEDGE_DIR", "RECIPES_PATH", "Built", "build",
           "default_archive", "default_corpora", "default_corpus", "extract_archive", "extract_recipes",
           "read_corpora", "recipe_nouns"]

RECIPES_PATH = KNOWLEDGE_DIR / "recipes.csv"
"""The (verb, objects) records extracted from the public-domain recipes (``wecook knowledge extract``)."""
ARCHIVE_PATH = Path("open-recipe-archive.csv")
"""Where ``wecook knowledge extract`` writes the records of the Open Recipe Archive by default (the current
folder: the shipped tables do not learn from them, see :func:`default_corpora`): the records whose verb folds
into wecook's actions and that name an object (re-extract after changing the synonyms)."""
ARCHIVE_ORIGIN = ("Open Recipe Archive (github.com/AdamBouhmad/open-recipe-archive, commit ae3bd2c, "
                  "collections/*/recipes/*.md; ../shared/data/recipes/open-recipe-archive.jsonl.gz)")
RECIPES_LICENCE = "Unlicense (public domain dedication)"
RECIPES_ORIGIN = ("Public Domain Recipes (publicdomainrecipes.com; github.com/ronaldl29/public-domain-recipes, "
                  "content/, commit 61b488e of 2026-03-02), the continuation of based.cooking")


def default_corpus() -> Path:
    """The team's copy of the EPIC-KITCHENS annotations, read in place."""
    return shared_dir() / "data" / "epic-kitchens"


def default_archive() -> Path:
    """The team's copy of the Open Recipe Archive, read in place."""
    return shared_dir() / "data" / "recipes"


def default_corpora() -> list[Path]:
    """What `wecook knowledge learn` reads by default: the EPIC-KITCHENS annotations, the shipped records of
    the recipe instructions (Public Domain Recipes) and the Open Recipe Archive (:func:`default_archive`, read
    in place), each its own table (:mod:`~wecook_core.knowledge.mixture`: pooled, the archive outweighed the
    videos ten to one and the shared scenarios dropped)."""
    return [default_corpus(), RECIPES_PATH, default_archive()]


def recipe_nouns() -> dict[str, str]:
    """The nouns looked for in recipe instructions: every object of the shipped category tables."""
    return noun_table([*read_categories(DERIVED_PATH).entries, *read_categories(CATEGORIES_PATH).entries])


def tool_names() -> Callable[[str], bool]:
    """Whether an object name is a tool in the shipped category tables (the hand-written over the derived)."""
    table = read_categories(DERIVED_PATH).merged(read_categories(CATEGORIES_PATH))
    return lambda name: table.categorize(name) is Category.TOOL


def read_corpora(paths: Sequence[Path], *, context: int = 0, held_s: float = HELD_S) -> Corpus:
    """One corpus from EPIC folders, folders of Markdown recipes and CSV files (see
    :func:`~wecook_core.knowledge.corpus.read_corpus`); EPIC's held tools are the tools of the shipped
    category tables (:func:`tool_names`)."""
    corpora = []
    for path in paths:
        if path.is_dir():
            if _is_epic(path):
                corpora.append(read_epic(path, context=context, held_s=held_s, is_tool=tool_names()))
            elif is_archive(path):
                corpora.append(read_archive(path, recipe_nouns()))
            elif is_recipe_folder(path):
                corpora.append(read_recipes(path, recipe_nouns()))
            else:
                corpora.append(read_corpus(path))
        else:
            if is_archive(path):
                corpora.append(read_archive(path, recipe_nouns()))
            else:
                corpora.append(read_csv(path) if path.is_file() else read_corpus(path))
    return merge(corpora)


def extract_recipes(root: Path, out: Path, *, origin: str = "", licence: str = "") -> int:
    """Write the (verb, objects) records of a folder of Markdown recipes as a CSV corpus (``action,objects,
    group`` with ``# corpus/source/licence`` lines), the form the shipped ``recipes.csv`` has; returns the
    number of records."""
    corpus = read_recipes(root, recipe_nouns())
    lines = [f"# corpus: {RECIPES_SOURCE}",
             f"# source: {origin or root}; (verb, objects) of each clause of the recipes' directions, extracted by "
             "`wecook knowledge extract` (wecook_core.knowledge.instructions)"]
    if licence:
        lines.append(f"# licence: {licence}")
    lines.append("action,objects,group")
    for record in corpus.records:
        lines.append(f"{record.action},{';'.join(record.objects)},{record.group}")
    write_atomic(out, "\n".join(lines) + "\n", replace=True, what="corpus")
    return len(corpus.records)


def extract_archive(path: Path, out: Path, *, origin: str = ARCHIVE_ORIGIN, licence: str = ARCHIVE_LICENCE) -> int:
    """Write the records of the Open Recipe Archive whose verb folds into wecook's actions and that name an
    object, as a CSV corpus (``action,objects,group,context,relations``, group ``collection/recipe``, no context,
    the relation of each object to its verb); returns their number."""
    corpus = read_archive(path, recipe_nouns())
    folder = load_synonyms()
    kept = [r for r in corpus.records if r.objects and folder.fold(r.action) is not None]
    lines = [f"# corpus: {ARCHIVE_SOURCE}",
             f"# source: {origin}; (verb, objects) of each clause of the recipes' steps whose verb folds into "
             f"wecook's actions, of {len(corpus.records)} clauses, extracted by `wecook knowledge extract` "
             "(wecook_core.knowledge.archive)",
             f"# licence: {licence}", "action,objects,group,context,relations"]
    lines += [f"{r.action},{';'.join(r.objects)},{r.group},,{';'.join(r.relations)}" for r in kept]
    write_atomic(out, "\n".join(lines) + "\n", replace=True, what="corpus")
    return len(kept)


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
    evaluations: tuple[Evaluation, ...] = ()
    """The held-out evaluations of seeds ``seed .. seed + 4`` with the tables' prior and counting (the first is
    :attr:`evaluation`)."""


def build(paths: Sequence[Path], out: Path = KNOWLEDGE_DIR, *, alpha: float | None = None, context: int = 0,
          held_s: float = HELD_S, seed: int = 0, fraction: float = 0.2, prior: str = "uniform", per_group: bool = True,
          mixed: bool = True, command: str = "wecook knowledge learn") -> Built:
    """Learn the tables from ``paths`` into ``out``: ``commonsense.json``, ``epic_categories.yaml`` (when
    the corpus has noun categories) and ``SOURCE.md`` (sources, licences, counts, held-out evaluation over
    five seeds). ``mixed`` (the default): one table per corpus, mixed (:mod:`~wecook_core.knowledge.mixture`;
    ``alpha`` default its :data:`~wecook_core.knowledge.mixture.ALPHA`), evaluated beside the pooled tables;
    else the corpora's counts pooled (``alpha`` default 1) with ``prior`` and ``per_group``, evaluated beside
    the other prior and the other way of counting (:func:`~wecook_core.knowledge.learning.count`)."""
    from wecook_core.knowledge.mixture import ALPHA, learn_mixed

    corpus = read_corpora(paths, context=context, held_s=held_s)
    seeds = range(seed, seed + 5)
    if mixed:
        alpha = ALPHA if alpha is None else alpha
        knowledge = learn_mixed(corpus, alpha=alpha, source="; ".join(corpus.sources))
        settings: dict[str, dict[str, Any]] = {
            "mixed by corpus, objects in their roles": dict(alpha=alpha, mixed=True),
            "pooled, uniform, per group": dict(alpha=1.0, prior="uniform")}
    else:
        alpha = 1.0 if alpha is None else alpha
        knowledge = learn(corpus, alpha=alpha, source="; ".join(corpus.sources), prior=prior, per_group=per_group)
        variants = dict.fromkeys([(prior, per_group), *((p, per_group) for p in PRIORS), (prior, not per_group)])
        settings = {f"{p}, {'per group' if g else 'per record'}": dict(alpha=alpha, prior=p, per_group=g)
                    for p, g in variants}
    try:
        runs = {name: tuple(evaluate(corpus, seed=s, fraction=fraction, **kind) for s in seeds)
                for name, kind in settings.items()}
    except ValueError:
        runs = {}
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
        write_atomic(files[-1], format_categories(derived, header), replace=True, what="category table")
    files.append(out / "SOURCE.md")
    write_atomic(files[-1], source_markdown(corpus, knowledge, runs, command=command, alpha=alpha, context=context,
                                            held_s=held_s, records=len(fold(corpus)[0]), per_group=per_group,
                                            categories=categories), replace=True, what="source notes")
    ours = next(iter(runs.values()), ())
    return Built(knowledge, ours[0] if ours else None, categories, tuple(files), ours)
