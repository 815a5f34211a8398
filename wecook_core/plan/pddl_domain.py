"""The schemas of the PDDL domain ``wecook`` (see :mod:`wecook_core.plan.pddl`): one per form of a verb, each with
the precondition that says what the verb needs.

Types: ``arm``, ``task`` (one part of a plan action), ``gate`` (orders tasks), ``thing`` with ``tool``,
``container`` and ``ingredient``.
Parameters are named by role, the same in every schema: ``?k`` the task, ``?a`` the arm that acts, ``?t`` what it
holds to act (a tool, the bottle it pours, the container it tips), ``?x`` what it acts on, ``?from`` and ``?to``
where a transfer takes ``?x`` from and to, ``?h`` the arm that holds ``?held`` still meanwhile, ``?r`` the arm a
handover gives ``?x`` to. A task fact (``task-cut ?k ?a ?t ?x``) says which arm does the task, with what and on
what, as the plan has it; the schema says what that needs (a cut: the arm holds ``?t``, and ``?t`` is fit to cut).
"""

from __future__ import annotations

from dataclasses import dataclass

from wecook_core.model import VERBS

HELD_VERBS: tuple[str, ...] = ("pour", "sprinkle", "dip")
"""Verbs done with the held object itself onto ``?x`` (the oil poured into the pot): the task names the held
object, and the arm must hold it."""
TOOL_VERBS: tuple[str, ...] = tuple(v for v in VERBS if v not in (*HELD_VERBS, "transfer"))
"""Verbs done with a held tool on ``?x``: the arm must hold a tool fit for the verb (``fits-cut``: the plan's
knife), none other."""

_TYPES = {"?k": "task", "?a": "arm", "?h": "arm", "?r": "arm", "?t": "thing", "?x": "thing", "?from": "thing",
          "?to": "thing", "?held": "thing"}


@dataclass(frozen=True)
class Schema:
    name: str
    params: tuple[str, ...]
    """Parameter names (``?a``), typed by role (:data:`_TYPES`)."""
    task: tuple[str, ...]
    """Parameters of its task fact ``(task-<name> ?k ...)``, after ``?k``."""
    pre: tuple[str, ...]
    """Preconditions besides ``(ready ?k)`` and the task fact."""
    eff: tuple[str, ...] = ()
    """Effects besides ``(done ?k)`` and ``(not (ready ?k))``."""

    def text(self) -> str:
        params = " ".join(f"{p} - {_TYPES[p]}" for p in self.params)
        pre = ("(ready ?k)", f"(task-{self.name} ?k {' '.join(self.task)})", *self.pre)
        eff = ("(done ?k)", "(not (ready ?k))", *self.eff)
        return "\n".join([f"  (:action {self.name}", f"    :parameters ({params})",
                          f"    :precondition (and {' '.join(pre)})", f"    :effect (and {' '.join(eff)}))"])

    def task_predicate(self) -> str:
        return f"(task-{self.name} ?k - task {' '.join(f'{p} - {_TYPES[p]}' for p in self.task)})"

    def held(self) -> Schema:
        """The same done while another arm ``?h`` holds ``?held`` (two different things: ``?t`` is held by ``?a``,
        and each thing by one arm at most, so ``?h`` is another arm)."""
        return Schema(f"{self.name}-held", (*self.params, "?h", "?held"), (*self.task, "?h", "?held"),
                      (*self.pre, "(holding ?h ?held)"), self.eff)


def schema(verb: str, form: str) -> Schema:
    """The schema of ``verb`` in ``form``: ``tool`` (a held tool), ``held`` (the held object itself), ``hand`` (by
    the hand itself), ``tipping`` (a transfer by tipping the held container the ingredient is in)."""
    if verb == "transfer":
        moves = ("(not (in ?x ?from))", "(in ?x ?to)")
        if form == "tool":
            return Schema("transfer", ("?k", "?a", "?t", "?x", "?from", "?to"), ("?a", "?t", "?x", "?to"),
                          ("(holding ?a ?t)", "(fits-transfer ?t)", "(in ?x ?from)", "(reaches ?a ?from)",
                           "(reaches ?a ?to)"), moves)
        if form == "tipping":
            return Schema("transfer-tipping", ("?k", "?a", "?t", "?x", "?to"), ("?a", "?t", "?x", "?to"),
                          ("(holding ?a ?t)", "(in ?x ?t)", "(reaches ?a ?to)"), ("(not (in ?x ?t))", "(in ?x ?to)"))
        return Schema("transfer-by-hand", ("?k", "?a", "?x", "?from", "?to"), ("?a", "?x", "?to"),
                      ("(free ?a)", "(loose ?x)", "(in ?x ?from)", "(reaches ?a ?x)", "(reaches ?a ?to)"), moves)
    if form == "tool":
        return Schema(verb, ("?k", "?a", "?t", "?x"), ("?a", "?t", "?x"),
                      ("(holding ?a ?t)", f"(fits-{verb} ?t)", "(reaches ?a ?x)"))
    if form == "held":
        return Schema(verb, ("?k", "?a", "?t", "?x"), ("?a", "?t", "?x"), ("(holding ?a ?t)", "(reaches ?a ?x)"))
    return Schema(f"{verb}-by-hand", ("?k", "?a", "?x"), ("?a", "?x"), ("(free ?a)", "(reaches ?a ?x)"))


HANDOVER = Schema("handover", ("?k", "?a", "?r", "?x"), ("?a", "?r", "?x"), ("(holding ?a ?x)", "(free ?r)"),
                  ("(holding ?r ?x)", "(free ?a)", "(not (holding ?a ?x))", "(not (free ?r))"))


def domain_text(schemas: tuple[Schema, ...], fits: tuple[str, ...], name: str) -> str:
    """The domain ``name`` with grasp, release, ``schemas``, the ``fits-<verb>`` predicates of ``fits``, and the
    gates that order tasks: a task that waits for others is ready once its gate chain is passed, one ``pass``
    per task waited for (``(needs ?g ?j ?n)``: gate ``?g`` opens ``?n`` once ``?j`` is done), then ``start``."""
    predicates = ["(free ?a - arm)", "(holding ?a - arm ?x - thing)", "(loose ?x - thing)",
                  "(in ?x - thing ?c - thing)", "(reaches ?a - arm ?x - thing)", "(ready ?k - task)",
                  "(done ?k - task)", "(open ?g - gate)", "(needs ?g - gate ?j - task ?n - gate)",
                  "(unlocks ?g - gate ?k - task)", *(f"(fits-{verb} ?t - thing)" for verb in fits),
                  *(s.task_predicate() for s in schemas)]
    lines = [f"(define (domain {name})",
             "  (:requirements :strips :typing)",
             "  (:types arm task gate thing - object",
             "          tool container ingredient - thing)",
             "  (:predicates", *(f"    {p}" for p in predicates), "  )",
             "  (:action grasp",
             "    :parameters (?a - arm ?x - thing)",
             "    :precondition (and (free ?a) (loose ?x) (reaches ?a ?x))",
             "    :effect (and (holding ?a ?x) (not (free ?a)) (not (loose ?x))))",
             "  (:action release",
             "    :parameters (?a - arm ?x - thing)",
             "    :precondition (holding ?a ?x)",
             "    :effect (and (free ?a) (loose ?x) (not (holding ?a ?x))))",
             "  (:action pass",
             "    :parameters (?g - gate ?j - task ?n - gate)",
             "    :precondition (and (open ?g) (needs ?g ?j ?n) (done ?j))",
             "    :effect (open ?n))",
             "  (:action start",
             "    :parameters (?g - gate ?k - task)",
             "    :precondition (and (open ?g) (unlocks ?g ?k))",
             "    :effect (ready ?k))",
             *(s.text() for s in schemas)]
    return "\n".join([*lines, ")", ""])
