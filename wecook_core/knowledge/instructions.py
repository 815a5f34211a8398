"""(verb, objects) records from recipe instructions: the imperative clauses of a recipe's directions.

Recipe steps name actions the way a cook says them ("Peel and cut the apples", "In a bowl, whisk the eggs",
"Using a spoon, transfer the rice to the jars"). A step is split into sentences; in each sentence a verb is a
word of :data:`VERBS` that opens a clause (first word, or after a comma, "and", "then" or an adverb), or
its gerund after "by", "after", "while", ... ("by cutting the sausages"). A verb's objects are the known
nouns between it and the next verb; nouns in front of the sentence's first verb ("In a bowl, ...",
"Using a knife, ...") belong to that verb; a verb with no noun of its own that is coordinated with the next
("Peel and cut the apples") shares the next one's. Nouns are matched whole-word, longest phrase first,
singular or plural, against a noun table (by default the shipped category tables: every object wecook
categorises).

Words that are nouns as well as verbs ("salt", "pepper", "butter", "spoon") count as verbs only at the
start of a sentence and not before "and" or a comma ("Salt the water", not "Salt and pepper to taste");
the ones that name what the action is done with (:data:`NAMING_VERBS`) add that noun to the objects.
Raw verbs are kept ("chop"); they are folded into wecook's actions when learning
(:mod:`wecook_core.knowledge.synonyms`). A verb whose sense its particle decides (:data:`PARTICLES`) is kept with
the first particle of its clause, the way EPIC writes its verbs: "Roll the balls in sugar" is ``roll-in``
(coating, folded into dip), "Roll out the dough" is ``roll-out`` (rolling, with a pin).

The Markdown recipe format read here is the one of the public-domain recipe sites built with Hugo
(based.cooking, publicdomainrecipes.com): front matter, ``## Ingredients``, then ``## Directions`` with a
numbered or bulleted list.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

from wecook_core.errors import InputError
from wecook_core.knowledge.nouns import normalise, variants
from wecook_core.knowledge.roles import coating, relation

VERBS: frozenset[str] = frozenset({
    "add", "adjust", "allow", "arrange", "bake", "baste", "batter", "beat", "blanch", "blend", "boil", "braise",
    "bring", "broil", "brown", "brush", "butter", "caramelise", "caramelize", "check", "chill", "chop", "clean",
    "coat", "combine", "cook", "cool", "core", "cover", "crack", "cream", "crimp", "crumble", "crush", "cube",
    "cut", "debone", "deglaze", "dice", "dip", "discard", "dissolve", "distribute", "divide", "drain", "drizzle",
    "dredge", "drop", "dry", "dunk", "dust", "empty", "fill", "fillet", "finish", "flatten", "flip", "fluff", "fold",
    "form", "freeze", "fry", "garnish", "glaze", "grate", "grease", "grill", "grind", "halve", "heat", "immerse",
    "insert", "juice", "julienne", "knead", "ladle", "layer", "leave", "let", "line", "marinate", "mash", "measure",
    "melt",
    "microwave", "mince", "mix", "moisten", "move", "pare", "pat", "peel", "pepper", "pierce", "pinch", "place",
    "plunge", "poach", "pound", "pour", "preheat", "prepare", "press", "pull", "puree", "put", "quarter", "reduce",
    "refrigerate", "remove", "repeat", "reserve", "rest", "return", "rinse", "roast", "roll", "rub", "salt",
    "saute", "scatter", "scoop", "scramble", "scrape", "sear", "season", "separate", "serve", "set", "shake",
    "shape", "shred", "sieve", "sift", "simmer", "skewer", "skim", "skin", "slice", "smash", "smear", "smooth",
    "soak", "spoon", "spray", "spread", "sprinkle", "squeeze", "squish", "stack", "steam", "steep", "stir",
    "strain", "strew", "stuff", "sweeten", "take", "tear", "thread", "tie", "toast", "top", "toss", "transfer", "trim",
    "tuck", "turn", "twist", "unroll", "unwrap", "use", "warm", "wash", "whip", "whisk", "wipe", "wrap", "zest"
})
"""Imperative cooking verbs that open a clause. Only the ones that fold into wecook's actions become
records that count; the others end the clause of the verb before them."""

NOUN_VERBS: frozenset[str] = frozenset({
    "butter", "core", "cream", "dust", "juice", "ladle", "line", "measure", "pepper", "pinch", "quarter", "salt",
    "scoop", "skewer", "skin", "spoon", "top", "zest"
})
"""Verbs that are nouns too: verbs only at a sentence's start, and not before "and" or a comma."""

NAMING_VERBS: frozenset[str] = frozenset(["spoon", "ladle", "scoop", "butter", "salt", "pepper", "skewer"])
"""Verbs that name the tool or ingredient they act with ("Spoon the rice into jars" is done with a spoon,
"Salt the water" with salt): the noun is one of the clause's objects."""

PARTICLES: Mapping[str, frozenset[str]] = {
    "roll": frozenset({"in", "into", "out", "up"}),
}
"""Verb -> the particles that decide its sense ("roll in flour": coat; "roll out": roll; "roll up": wrap
up), recorded as ``verb-particle`` when one of them follows the verb in its clause, before any comma."""

_ADVERBS = frozenset({
    "afterwards", "again", "also", "briefly", "carefully", "constantly", "continuously", "evenly", "finally",
    "finely", "first", "further", "generously", "gently", "immediately", "just", "lightly", "meanwhile", "next",
    "now", "occasionally", "once", "optionally", "quickly", "roughly", "simply", "slowly", "then", "thinly",
    "thoroughly", "well"
})
_BOUNDARIES = frozenset({",", "and", "then", "or", "&", "to"})
_GERUND_OPENERS = frozenset({"by", "after", "before", "while", "when", "start", "begin", "continue", "keep",
                             "finish", "without", "try", "for"})
_TOKEN = re.compile(r"[a-z]+(?:'[a-z]+)?|,")
_SENTENCE = re.compile(r"[.!?;:]+(?:\s+|$)|\s+-\s+|\n")
_MARKUP = re.compile(r"!\[[^\]]*\]\([^)]*\)|\[([^\]]*)\]\([^)]*\)|<[^>]+>|[*_`#>]")
_PARENS = re.compile(r"\([^)]*\)")
_LIST_ITEM = re.compile(r"^\s*(?:\d+[.)]|[-*+])\s+")


def _gerunds(verbs: Iterable[str]) -> dict[str, str]:
    """Gerund -> verb: cut -> cutting, slice -> slicing, stir -> stirring, mix -> mixing."""
    forms: dict[str, str] = {}
    for verb in verbs:
        forms.setdefault(verb + "ing", verb)
        if verb.endswith("e") and not verb.endswith("ee"):
            forms.setdefault(verb[:-1] + "ing", verb)
        if re.search(r"[^aeiou][aeiou][bdgklmnprt]$", verb):
            forms.setdefault(verb + verb[-1] + "ing", verb)
    return forms


_GERUNDS = _gerunds(VERBS)


def tokens(sentence: str) -> list[str]:
    """Lowercase words (apostrophes kept) and commas."""
    return _TOKEN.findall(sentence.lower().replace("’", "'"))


def sentences(text: str) -> list[str]:
    """A step's sentences, markup and parenthesised asides dropped."""
    text = _PARENS.sub(" ", _MARKUP.sub(r"\1", text))
    return [s.strip() for s in _SENTENCE.split(text) if s.strip()]


def _is_verb(words: Sequence[str], i: int, start: int) -> str | None:
    """The verb ``words[i]`` stands for when it opens a clause, else None."""
    word = words[i]
    j = i - 1
    while j >= start and words[j] in _ADVERBS:
        j -= 1
    opens = j < start or words[j] in _BOUNDARIES
    if word in VERBS:
        if word in NOUN_VERBS:
            following = words[i + 1] if i + 1 < len(words) else ""
            return word if j < start and following not in ("and", ",", "or", "to", "") else None
        return word if opens else None
    verb = _GERUNDS.get(word)
    if verb is not None and verb not in NOUN_VERBS and j >= start and words[j] in _GERUND_OPENERS:
        return verb
    return None


_LONGEST: dict[int, tuple[Mapping[str, str], int, dict[tuple[str, ...], str | None]]] = {}


def _table(nouns: Mapping[str, str]) -> tuple[int, dict[tuple[str, ...], str | None]]:
    """The longest phrase of a noun table (in words) and a memo of its phrase lookups, kept per table (a
    recipe corpus asks the same table hundreds of thousands of times)."""
    known = _LONGEST.get(id(nouns))
    if known is None or known[0] is not nouns:
        known = (nouns, max([2, *(k.count("_") + 1 for k in nouns)]), {})  # 2: "sauce-pan" is tried joined
        _LONGEST.clear()
        _LONGEST[id(nouns)] = known
    return known[1], known[2]


def _lookup(words: Sequence[str], nouns: Mapping[str, str]) -> str | None:
    """The noun a phrase of words names: as written (``sauce_pan``), singular or plural, else the words
    joined into one (``saucepan``, ``stewpan``): the old books hyphenate what is now one word ("sauce-pan",
    "stew-pan"), and the tokens split the hyphen."""
    if "," in words:
        return None
    phrase = "_".join(words)
    name = next((nouns[v] for v in variants(phrase) if v in nouns), None)
    if name is None and len(words) > 1:
        joined = "".join(words)
        name = next((nouns[v] for v in variants(joined) if v in nouns), None)
    return name


def _nouns(words: Sequence[str], nouns: Mapping[str, str], longest: int) -> list[str]:
    """Known nouns in ``words``, longest phrase first, whole words only, singular or plural."""
    return [name for name, _ in _spans(words, nouns, longest)]


def _spans(words: Sequence[str], nouns: Mapping[str, str], longest: int) -> list[tuple[str, int]]:
    """(noun, index of its first word) of the known nouns in ``words``, as :func:`_nouns`."""
    found: list[tuple[str, int]] = []
    memo = _table(nouns)[1]
    i = 0
    while i < len(words):
        for n in range(min(longest, len(words) - i), 0, -1):
            phrase = tuple(words[i:i + n])
            if phrase in memo:
                name = memo[phrase]
            else:
                name = memo[phrase] = _lookup(phrase, nouns)
            if name is not None:
                found.append((name, i))
                i += n
                break
        else:
            i += 1
    return found


def _sense(verb: str, clause: Sequence[str]) -> str:
    """``verb-particle`` for a verb of :data:`PARTICLES` followed by one of its particles, else the verb."""
    particles = PARTICLES.get(verb)
    if particles:
        for word in clause:
            if word == ",":
                break
            if word in particles:
                return f"{verb}-{word}"
    return verb


PRONOUNS: frozenset[str] = frozenset({"them", "it", "they", "these", "all", "both", "mixture"})
"""Words by which a clause names ingredients it does not repeat ("add them", "stir it well", "pour the
mixture into a dish"): a clause with one of them after its verb takes the ingredients named last before it
in the recipe (:func:`extract`, with the recipe's ingredient list)."""


def _refers(clause: Sequence[str]) -> int:
    """How a clause's words (after its verb, up to the next verb) name ingredients by a pronoun: 2 when the
    pronoun is the verb's object ("squeeze them over the sugar", "pour the mixture into a dish"), 1 when one
    comes later ("stir until they are soft"), 0 when none does."""
    words = [w for w in clause if w not in _ADVERBS and w != "the"]
    if words and words[0] in PRONOUNS:
        return 2
    return int(any(w in PRONOUNS for w in clause))


def clause_records(sentence: str, nouns: Mapping[str, str]) -> list[tuple[str, tuple[str, ...]]]:
    """The (verb, objects) of a sentence's clauses, in order (see the module docstring)."""
    return [(verb, objects) for verb, objects, _, _ in _clauses(sentence, nouns)]


Clause = tuple[str, tuple[str, ...], int, tuple[str, ...]]
"""(verb, objects, how it names ingredients by a pronoun (:func:`_refers`), relation of each object)."""


def _clauses(sentence: str, nouns: Mapping[str, str]) -> list[Clause]:
    """The clauses of a sentence, in order (see :data:`Clause`)."""
    words = tokens(sentence)
    longest = _table(nouns)[0]
    verbs = [(i, v) for i in range(len(words)) if (v := _is_verb(words, i, 0)) is not None]
    records: list[tuple[str, list[tuple[str, str]]]] = []
    refers: list[int] = []
    for k, (i, verb) in enumerate(verbs):
        end = verbs[k + 1][0] if k + 1 < len(verbs) else len(words)
        clause = words[i + 1:end]
        objects = [(name, relation(clause, at, verb)) for name, at in _spans(clause, nouns, longest)]
        if verb in NAMING_VERBS and verb in nouns:
            objects.insert(0, (nouns[verb], "means"))
        if k == 0:
            objects = [(name, relation(words[:i], at)) for name, at in _spans(words[:i], nouns, longest)] + objects
        records.append((coating(_sense(verb, clause), objects), objects))
        refers.append(_refers(clause))
    for k in range(len(records) - 2, -1, -1):  # "peel and cut the apples": peel shares cut's objects
        i, next_i = verbs[k][0], verbs[k + 1][0]
        if not records[k][1] and all(w in _BOUNDARIES or w in _ADVERBS for w in words[i + 1:next_i]):
            records[k] = (records[k][0], list(records[k + 1][1]))
    found: list[Clause] = []
    for (verb, objects), r in zip(records, refers, strict=True):
        first = dict(reversed(objects))  # each noun once, with the relation of its first mention
        names = tuple(dict.fromkeys(name for name, _ in objects))
        found.append((verb, names, r, tuple(first[n] for n in names)))
    return found


def extract(steps: Iterable[str], nouns: Mapping[str, str],
            ingredients: Sequence[str] = ()) -> list[tuple[str, tuple[str, ...]]]:
    """(verb, objects) of every clause of the steps, in order (:func:`extract_relations` without the
    relations)."""
    return [(verb, objects) for verb, objects, _ in extract_relations(steps, nouns, ingredients)]


def extract_relations(steps: Iterable[str], nouns: Mapping[str, str],
                      ingredients: Sequence[str] = ()) -> list[tuple[str, tuple[str, ...], tuple[str, ...]]]:
    """(verb, objects, relation of each object, :data:`RELATIONS`) of every clause of the steps, in order.

    ``ingredients``: the lines of the recipe's ingredient list. When given, a clause whose verb's object is a
    pronoun ("add them", "squeeze them over the sugar", :data:`PRONOUNS`), or that has one and names no
    ingredient, takes the ingredients of the list that the clauses before it named last (in this step or an
    earlier one): "Put the gooseberries into a saucepan. When they are soft, pulp them through a sieve."
    Ingredients taken so are the clause's objects.
    """
    listed = set(_nouns([w for line in ingredients for w in (*tokens(line), ",")], nouns,
                        _table(nouns)[0])) if ingredients else set()
    found: list[tuple[str, tuple[str, ...], tuple[str, ...]]] = []
    last: list[str] = []
    for step in steps:
        for sentence in sentences(step):
            for verb, objects, refers, relations in _clauses(sentence, nouns):
                named = [o for o in objects if o in listed]
                if last and (refers == 2 or (refers and not named)):
                    of = dict(zip(objects, relations, strict=True))
                    objects = tuple(dict.fromkeys((*last, *objects)))
                    relations = tuple(of.get(o, "object") for o in objects)
                if named:
                    last = named
                found.append((verb, objects, relations))
    return found


# -------------------------------------------------------------------------------------- Markdown recipes

_DIRECTIONS = re.compile(r"^(?:directions|instructions|steps|method|preparation|procedure)\b", re.I)


def directions(text: str) -> list[str]:
    """The steps of a Markdown recipe: the list items (or paragraphs) under its Directions heading."""
    steps: list[str] = []
    inside = False
    for line in text.splitlines():
        heading = re.match(r"^\s*#{1,4}\s*(.*)$", line)
        if heading:
            inside = bool(_DIRECTIONS.match(heading.group(1).strip()))
            continue
        if not inside or not line.strip():
            continue
        if _LIST_ITEM.match(line) or not steps:
            steps.append(_LIST_ITEM.sub("", line).strip())
        else:
            steps[-1] += " " + line.strip()
    return steps


def recipe_files(root: Path) -> list[Path]:
    """The Markdown recipes of a folder (or of its ``content/`` folder), sorted; Hugo ``_index.md`` left out."""
    folder = root / "content" if (root / "content").is_dir() else root
    return sorted(p for p in folder.glob("*.md") if not p.name.startswith("_"))


def is_recipe_folder(root: Path) -> bool:
    return root.is_dir() and any(directions(_read(p)) for p in recipe_files(root)[:20])


def _read(path: Path) -> str:
    try:
        return path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise InputError(path, f"cannot read the recipe: {error}") from None


def recipe_records(root: Path, nouns: Mapping[str, str]) -> list[tuple[str, str, tuple[str, ...]]]:
    """(recipe name, verb, objects) of every clause of every recipe in ``root``, recipes in name order."""
    found = []
    for path in recipe_files(root):
        for verb, objects in extract(directions(_read(path)), nouns):
            found.append((path.stem, verb, objects))
    return found


def noun_table(names: Iterable[str]) -> dict[str, str]:
    """Normalised phrase -> object name, for :func:`extract`, from object names or labels."""
    table: dict[str, str] = {}
    for name in names:
        key = normalise(name)
        if key:
            table.setdefault(key, key)
    return table
