"""How a recipe clause names each of its nouns: the verb's object, where it goes, what it is done with.

Read from the nearest preposition before the noun (:func:`relation`), except when the preposition is the verb's
particle: "stir in the flour", "pour in the batter", "roll out the paste", "cut off the roots" name the verb's
object after a word that elsewhere says where ("into the pan", "out of the oven", "off the fire").
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

PLACES: frozenset[str] = frozenset({"in", "into", "to", "onto", "on", "over", "upon", "inside", "through",
                                    "under", "round", "around", "across", "between", "among", "within"})
"""Prepositions after which a noun is where the action goes or happens ("into the pan", "over the fish")."""
MEANS: frozenset[str] = frozenset({"with", "using", "by"})
"""Prepositions after which a noun is what the action is done with ("with a fork", "using a brush", "dust
the board with flour")."""
SOURCES: frozenset[str] = frozenset({"from", "off", "out"})
"""Prepositions after which a noun is where something comes from ("out of the pan")."""
SUBORDINATE: frozenset[str] = frozenset({"until", "till", "when", "while", "if", "unless", "so", "as", "than",
                                         "because", "whilst"})
"""Words that open a subordinate clause: a noun after one is not what the verb acts on ("stir until the sugar
is dissolved")."""

RELATIONS: tuple[str, ...] = ("object", "place", "means", "source", "aside")
"""How a clause names each of its nouns (:func:`relation`): the verb's object (none of the prepositions
below), after a preposition of :data:`PLACES`, of :data:`MEANS` or of :data:`SOURCES`, or in a subordinate
clause (:data:`SUBORDINATE`). Measured on the held-out archive collections (:mod:`wecook_core.knowledge.
relations`, seed 0): giving the subordinate clause's nouns a relation of their own rather than ``object`` raised
macro P / R from 0.463 / 0.591 to 0.468 / 0.594; dropping them, 0.467 / 0.596."""

VIDEO_RELATIONS: Mapping[str, str] = {"tool": "means", "ingredient": "object", "container": "place"}
"""The role an object has in a video segment (a held tool, an ingredient worked or held, the container) -> the
relation a sentence gives it."""


def role_relation(role: str) -> str:
    """The relation an object of ``role`` (tool, container, ingredient; anything else an ingredient) has in
    what a video shows: a tool is what the action is done with, a container where it happens, an ingredient
    what it is done to."""
    return VIDEO_RELATIONS.get(role, "object")

_MIXING = frozenset({"stir", "mix", "beat", "whisk", "whip", "blend", "fold", "cream", "pour", "drizzle",
                     "sprinkle", "scatter", "strew", "squeeze", "add", "work", "rub"})
_TRIMMING = frozenset({"cut", "chop", "slice", "trim", "snip", "peel", "pare", "skin", "pour", "skim", "drain",
                       "scrape", "pull", "pinch", "squeeze"})
PARTICLES: Mapping[str, frozenset[str] | None] = {
    "in": _MIXING,
    "out": None,
    "up": None,
    "off": _TRIMMING,
}
"""Particle -> the verbs it is a particle of right after them (None: every verb): the noun phrase after it is
the verb's object. "in" is one after the verbs that add what they name ("stir in the flour"); after the others
it is where ("roll in flour", "put in a pan", "dip in egg"). "out" and "up" are particles after any verb
("roll out the paste", "cut up the fowl") unless "of" follows ("out of the pan" is where from); "off" after the
verbs that take a part away ("cut off the roots", "pour off the fat"), where after the others ("take off the
fire"). Measured on the held-out archive collections (``bench/recognize.py --held-out``, seed 0): the
role-aware model of :mod:`wecook_core.knowledge.relations` 0.469 / 0.601 -> 0.474 / 0.605 (macro P / R)."""


COATINGS: frozenset[str] = frozenset({"egg", "batter", "breadcrumb", "flour"})
"""What a thing is coated with, not wrapped in: "wrap them in beaten egg" (the old books, translated, wrap in
egg, in batter, in crumbs before frying) is a coating, a dip; "wrap the fish in paper" is wrapping. A clause of
"wrap" whose place is one of these is ``wrap-coat`` (folded into dip in ``synonyms.yaml``)."""


def coating(verb: str, objects: Sequence[tuple[str, str]]) -> str:
    """``wrap-coat`` for a ``wrap`` whose place (``objects``: (noun, relation)) is a :data:`COATINGS`, else the
    verb."""
    if verb == "wrap" and any(rel == "place" and name in COATINGS for name, rel in objects):
        return "wrap-coat"
    return verb


def particle(words: Sequence[str], k: int, verb: str) -> bool:
    """Whether ``words[k]`` is the particle of ``verb`` (the clause's verb, ``words`` the clause after it):
    the clause's first word, a particle of :data:`PARTICLES` for this verb, not followed by "of"."""
    if k != 0 or not verb:
        return False
    word = words[0]
    if word not in PARTICLES:
        return False
    verbs = PARTICLES[word]
    following = words[1] if len(words) > 1 else ""
    return (verbs is None or verb in verbs) and following not in ("of", ",", "")


def relation(words: Sequence[str], at: int, verb: str = "") -> str:
    """How the noun starting at ``words[at]`` is named (:data:`RELATIONS`): by the nearest preposition (or
    subordinating word) before it in its clause, up to a comma or the clause's start; "a pinch of salt over the
    fish" names the salt as the object, the fish as the place. With the clause's ``verb`` (``words`` then being
    the clause after it), a preposition that is the verb's particle (:func:`particle`) names the object."""
    for k in range(at - 1, -1, -1):
        word = words[k]
        if word == ",":
            break
        if word in SUBORDINATE:
            return "aside"
        if particle(words, k, verb):
            return "object"
        if word in PLACES:
            return "place"
        if word in MEANS:
            return "means"
        if word in SOURCES:
            return "source"
    return "object"
