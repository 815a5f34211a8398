"""Tree files: YAML, a list of ``{start: frame, end: frame, tree: "..."}`` (end exclusive)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import yaml

from wecook_core.errors import InputError, read_input_text, yaml_error
from wecook_core.files import write_atomic
from wecook_core.model import TreeSpan
from wecook_core.trees.notation import TreeSyntaxError, format_tree, parse_tree


def dump_tree_spans(spans: Sequence[TreeSpan]) -> str:
    lines = []
    for span in spans:
        tree = format_tree(span.tree).replace('"', '\\"')
        lines.append(f'- {{start: {span.start}, end: {span.end}, tree: "{tree}"}}')
    return "\n".join(lines) + "\n" if lines else "[]\n"


def write_tree_file(path: str | Path, spans: Sequence[TreeSpan]) -> None:
    """Write the tree file atomically (a reader sees the old file or the new one, never a torn one)."""
    write_atomic(path, dump_tree_spans(spans), replace=True, what="tree file")


def read_tree_file(path: str | Path) -> tuple[TreeSpan, ...]:
    path = Path(path)
    text = read_input_text(path)
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as error:
        raise yaml_error(path, error, "not YAML") from None
    if data is None:
        raise InputError(path, "empty file; expected a list of {start, end, tree}")
    if not isinstance(data, list):
        raise InputError(path, "expected a list of {start, end, tree}")
    spans = []
    for i, item in enumerate(data):
        place = f"entry {i + 1}"
        if not isinstance(item, dict) or not {"start", "end", "tree"} <= set(item):
            raise InputError(path, "expected a mapping with start, end and tree", place=place)
        start, end, tree = item["start"], item["end"], item["tree"]
        if not (isinstance(start, int) and isinstance(end, int)) or not 0 <= start < end:
            raise InputError(path, f"start and end must be frames with 0 <= start < end, found {start!r}, {end!r}",
                             place=place)
        if not isinstance(tree, str):
            raise InputError(path, "tree must be a string in bracket notation", place=place)
        try:
            node = parse_tree(tree)
        except TreeSyntaxError as error:
            raise InputError(path, f"tree {error}", place=place) from None
        spans.append(TreeSpan(start, end, node))
    return tuple(spans)
