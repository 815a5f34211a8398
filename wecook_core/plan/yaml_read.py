"""Reading plan YAML fast and bounded: the data of a plan file, in time linear in its size.

Two paths, one result (the data ``yaml.safe_load`` gives):

- the fast path, where PyYAML has libyaml (``yaml.CSafeLoader``): libyaml's parser makes the events and this
  module builds the lists, dicts and scalars from them directly, with the safe loader's resolver and
  constructors for plain scalars (ints, floats, bools, nulls, timestamps; each distinct one built once). It skips
  the node graph the composer would make and PyYAML's constructor machinery: a 10,000-action plan (2 MiB) reads
  in about a tenth of ``yaml.load(text, CSafeLoader)``'s time. It bounds the nesting and the number of values as
  it goes. A document with what plans never need (anchors and aliases, explicit tags, merge keys, a collection
  as a mapping key) goes the general way instead;
- the general path: the safe loader (libyaml's where present, else PyYAML's own) composes the node graph, which is
  bounded (nesting, values once aliases are expanded) before anything is constructed from it.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml
from yaml import events

from wecook_core.errors import InputError

MAX_PLAN_BYTES = 64 << 20
"""The largest plan file read (64 MiB; a plan of 10,000 actions is about 3 MiB)."""
MAX_PLAN_DEPTH = 64
"""The deepest nesting of YAML collections in a plan (a plan needs 6)."""
MAX_PLAN_NODES = 2_000_000
"""The most YAML values a plan may hold once its aliases are expanded (an alias bomb of a few KB expands
to billions)."""

CLoader: type | None = getattr(yaml, "CSafeLoader", None)
"""libyaml's safe loader, where PyYAML was built with it."""

_STR = "tag:yaml.org,2002:str"
_BUILT = frozenset({"tag:yaml.org,2002:null", "tag:yaml.org,2002:bool", "tag:yaml.org,2002:int",
                    "tag:yaml.org,2002:float", "tag:yaml.org,2002:timestamp"})
"""Tags of plain scalars the fast path builds (with the safe constructor's own functions)."""


def _too_deep(mark: Any) -> yaml.MarkedYAMLError:
    return yaml.MarkedYAMLError(problem=f"nested deeper than {MAX_PLAN_DEPTH} levels", problem_mark=mark)


def _too_many(path: str | Path | None, mark: Any) -> InputError:
    return InputError(path, f"more than {MAX_PLAN_NODES} values once its aliases are expanded (an alias bomb?)",
                      place=f"line {mark.line + 1}")


class _PlanLoader(yaml.SafeLoader):
    """PyYAML's own safe loader with the nesting bounded by :data:`MAX_PLAN_DEPTH` while composing (libyaml's
    composer cannot be bounded this way; where it is used, :func:`_bounded` checks the nesting after it)."""

    depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        self.depth += 1
        try:
            if self.depth > MAX_PLAN_DEPTH:
                raise _too_deep(self.peek_event().start_mark)
            return super().compose_node(parent, index)
        finally:
            self.depth -= 1


def _bounded(node: yaml.Node, path: str | Path | None) -> int:
    """Values in ``node`` counting every alias as a copy; an :class:`InputError` past :data:`MAX_PLAN_NODES`, a
    YAML error past :data:`MAX_PLAN_DEPTH` levels of nesting. Linear in the number of distinct nodes."""
    sizes: dict[int, int] = {}
    order: list[yaml.Node] = []
    stack = [(node, 1)]
    while stack:  # post-order without recursion; shared (aliased) nodes are sized once
        current, depth = stack.pop()
        if depth > MAX_PLAN_DEPTH:
            raise _too_deep(current.start_mark)
        if id(current) in sizes:
            continue
        sizes[id(current)] = -1
        order.append(current)
        if isinstance(current, yaml.SequenceNode):
            stack.extend((child, depth + 1) for child in current.value)
        elif isinstance(current, yaml.MappingNode):
            stack.extend((item, depth + 1) for pair in current.value for item in pair)
    for current in reversed(order):
        if isinstance(current, yaml.SequenceNode):
            children = current.value
        elif isinstance(current, yaml.MappingNode):
            children = [item for pair in current.value for item in pair]
        else:
            children = []
        total = 1 + sum(max(sizes[id(child)], 1) for child in children)
        if total > MAX_PLAN_NODES:
            raise _too_many(path, current.start_mark)
        sizes[id(current)] = total
    return sizes[id(node)]


class _General(Exception):
    """The document needs the general path."""


class _Scalars:
    """Plain scalars to values, as the safe loader resolves and constructs them, each distinct one once."""

    def __init__(self) -> None:
        self.loader = yaml.SafeLoader("")
        self.values: dict[tuple[str, tuple[bool, bool]], Any] = {}

    def value(self, text: str, implicit: tuple[bool, bool]) -> Any:
        key = (text, implicit)
        try:
            return self.values[key]
        except KeyError:
            pass
        tag = self.loader.resolve(yaml.ScalarNode, text, implicit)
        if tag == _STR:
            value: Any = text
        elif tag in _BUILT:
            value = self.loader.yaml_constructors[tag](self.loader, yaml.ScalarNode(tag, text))
        else:
            raise _General
        self.values[key] = value
        return value


def _from_events(text: str, path: str | Path | None) -> Any:
    """The document's data built from libyaml's events (see the module's docstring); :class:`_General` when it
    needs the general path."""
    assert CLoader is not None
    scalars = _Scalars()
    stack: list[Any] = []
    keys: list[Any] = []  # per open mapping: the pending key as a 1-tuple, or None
    root: Any = None
    documents = 0
    count = 0
    first_mark: Any = None
    scalar, seq_start, seq_end, map_start, map_end = (events.ScalarEvent, events.SequenceStartEvent,
                                                      events.SequenceEndEvent, events.MappingStartEvent,
                                                      events.MappingEndEvent)
    try:
        event: Any
        for event in yaml.parse(text, Loader=CLoader):
            kind = event.__class__
            if kind is scalar:
                if event.anchor is not None or event.tag not in (None, "!"):
                    raise _General
                value = scalars.value(event.value, event.implicit) if event.style == "" or event.style is None \
                    else event.value
            elif kind is seq_start or kind is map_start:
                if event.anchor is not None or event.tag not in (None, "!"):
                    raise _General
                if len(stack) >= MAX_PLAN_DEPTH:
                    raise _too_deep(event.start_mark)
                count += 1
                if count > MAX_PLAN_NODES:
                    raise _too_many(path, event.start_mark)
                stack.append([] if kind is seq_start else {})
                if kind is map_start:
                    keys.append(None)
                continue
            elif kind is seq_end:
                value = stack.pop()
            elif kind is map_end:
                value = stack.pop()
                keys.pop()
            elif kind is events.DocumentStartEvent:
                documents += 1
                if documents == 1:
                    first_mark = event.start_mark
                else:
                    raise yaml.composer.ComposerError("expected a single document in the stream", first_mark,
                                                      "but found another document", event.start_mark)
                continue
            elif kind is events.AliasEvent:
                raise _General
            else:
                continue
            if kind is scalar:
                if len(stack) >= MAX_PLAN_DEPTH:
                    raise _too_deep(event.start_mark)
                count += 1
                if count > MAX_PLAN_NODES:
                    raise _too_many(path, event.start_mark)
            if not stack:
                root = value
                continue
            top = stack[-1]
            if top.__class__ is list:
                top.append(value)
            elif keys[-1] is None:
                if isinstance(value, list | dict):
                    raise _General  # a collection as a key: the safe constructor says what is wrong
                keys[-1] = (value,)
            else:
                top[keys[-1][0]] = value
                keys[-1] = None
    finally:
        scalars.loader.dispose()
    return root


def _general(text: str, path: str | Path | None) -> Any:
    loader = CLoader(text) if CLoader is not None else _PlanLoader(text)
    try:
        node = loader.get_single_node()
        if node is None:
            return None
        _bounded(node, path)
        return loader.construct_document(node)
    finally:
        loader.dispose()


def parse_plan_yaml(text: str, path: str | Path | None) -> Any:
    """The data of plan YAML text (as ``yaml.safe_load`` reads it), with nesting and values bounded: a YAML
    error (``yaml.YAMLError``) or an :class:`InputError` naming ``path``."""
    try:
        if CLoader is not None:
            try:
                return _from_events(text, path)
            except _General:
                pass
        return _general(text, path)
    except yaml.MarkedYAMLError as error:
        if "maximum nesting depth" in str(error.problem):  # libyaml's own bound (1000 levels), met while scanning
            raise _too_deep(error.problem_mark) from None
        raise
    except RecursionError:
        raise InputError(path, f"not valid YAML (nested deeper than {MAX_PLAN_DEPTH} levels)") from None
    except (ValueError, OverflowError) as error:  # an integer of more than 4300 digits, a date out of range
        raise InputError(path, f"not valid YAML ({str(error)[:100]})") from None
