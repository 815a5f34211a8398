"""The layout is the architecture: layers import only downwards, and no module imports itself round a cycle.

Every import statement counts, wherever it stands: at the top, inside a function or under ``TYPE_CHECKING``.
The layers, top to bottom (a layer may import any layer below it, never one above or a sibling):

    wecook_tui                       the command line and the workbench
    wecook_core.batch                many videos: one task per video and stage, resumable
    wecook_core.workflows            use cases: analyse a session, export its plan, the demo
    wecook_core.session              a session on disk: inputs, journal, typed corrections
    wecook_core.recording            a run recorded as MCAP: writer, Foxglove schemas, live view, check, recovery
    wecook_core.execution            the plan acted out: execute_plan (run) over the PyBullet adapter (bullet),
      .bullet                          which implements the simulator-free world (primitives and roles),
      .world                           written over skills (verbs' motions, TSRs) and motion planning,
      .skills | .planning              all driven by the scheduler (executor, programs, the run's observer)
      .schedule
    wecook_core.plan | .synth        the robot plan (model, checks, YAML, layout) | synthetic scenarios
    wecook_core.perception           the pipeline and evaluation, over
      .recognition                     actions: individual, transfer, collaborative; motion cues
      .repairs                         objects hidden in hands, holds by unseen hands
      .association                     per-frame links, what each hand holds, per-segment summaries
      .segmentation                    GGS on each hand, shot cuts
      .params, .label_runs, .geometry  the tunables; runs in per-frame labels; box geometry
    wecook_core.trees                the grammar, trees in bracket notation, tree files, the action graph
    wecook_core.observations         boxes and hands imported (or detected) into one checked value
    wecook_core.knowledge            the commonsense tables, object categories, learning them from corpora
    wecook_core.formats              one module per outside format
    wecook_core.files                reading the user's files safely, writing ours atomically
    wecook_core.model, .errors, .resources   shared frozen dataclasses, errors, where data lives
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("wecook_core", "wecook_tui")

LAYERS: tuple[tuple[str, ...], ...] = (
    ("wecook_tui",),
    ("wecook_core.batch",),
    ("wecook_core.workflows",),
    ("wecook_core.session",),
    ("wecook_core.recording",),
    ("wecook_core.execution",),
    ("wecook_core.execution.bullet",),
    ("wecook_core.execution.world",),
    ("wecook_core.execution.skills", "wecook_core.execution.planning"),
    ("wecook_core.execution.schedule",),
    ("wecook_core.plan", "wecook_core.synth"),
    ("wecook_core.perception",),
    ("wecook_core.perception.recognition",),
    ("wecook_core.perception.repairs",),
    ("wecook_core.perception.association",),
    ("wecook_core.perception.segmentation",),
    ("wecook_core.perception.params", "wecook_core.perception.label_runs", "wecook_core.perception.geometry",
     "wecook_core.perception.filters"),
    ("wecook_core.trees",),
    ("wecook_core.observations",),
    ("wecook_core.knowledge",),
    ("wecook_core.formats",),
    ("wecook_core.files",),
    ("wecook_core.model", "wecook_core.errors", "wecook_core.resources", "wecook_core"),
)


def _modules() -> dict[str, Path]:
    found: dict[str, Path] = {}
    for package in PACKAGES:
        for path in (ROOT / package).rglob("*.py"):
            parts = path.relative_to(ROOT).with_suffix("").parts
            name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
            found[name] = path
    return found


MODULES = _modules()


def _imports(name: str, path: Path) -> set[str]:
    """The project modules ``name`` imports (``from a import b`` counts ``a.b`` when that is a module, else ``a``)."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                module = ".".join([*base, node.module] if node.module else base)
            else:
                module = node.module or ""
            subs = [f"{module}.{alias.name}" for alias in node.names if f"{module}.{alias.name}" in MODULES]
            targets = subs if len(subs) == len(node.names) else [module, *subs]
        else:
            continue
        for target in targets:
            while target and target not in MODULES:
                target = target.rpartition(".")[0]
            if target and target != name:
                out.add(target)
    return out


GRAPH = {name: _imports(name, path) for name, path in MODULES.items()}


def _layer(module: str) -> tuple[int, str]:
    """(rank, layer) of the most specific layer holding ``module``; rank 0 is the top."""
    best: tuple[int, str, int] | None = None
    for rank, layer in enumerate(LAYERS):
        for prefix in layer:
            if (module == prefix or module.startswith(prefix + ".")) and (best is None or len(prefix) > best[2]):
                best = (rank, prefix, len(prefix))
    assert best is not None, f"{module} is in no layer"
    return best[0], best[1]


def test_every_module_is_in_a_layer() -> None:
    for module in MODULES:
        _layer(module)


def test_layers_import_only_downwards() -> None:
    wrong = []
    for module, targets in sorted(GRAPH.items()):
        rank, layer = _layer(module)
        for target in sorted(targets):
            target_rank, target_layer = _layer(target)
            if target_layer == layer or (layer != "wecook_core" and target_layer == "wecook_core"):
                continue
            if target_rank <= rank:
                wrong.append(f"{module} ({layer}) imports {target} ({target_layer})")
    assert wrong == []


def _cycles() -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for nxt in GRAPH[node]:
            if nxt not in index:
                visit(nxt)
                low[node] = min(low[node], low[nxt])
            elif nxt in on_stack:
                low[node] = min(low[node], index[nxt])
        if low[node] == index[node]:
            component = []
            while True:
                top = stack.pop()
                on_stack.discard(top)
                component.append(top)
                if top == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(GRAPH):
        if node not in index:
            visit(node)
    return found


def test_no_import_cycles() -> None:
    assert _cycles() == []


def test_the_checks_can_fail() -> None:
    """The two checks above see a planted upward import and a planted cycle."""
    saved = {k: set(v) for k, v in GRAPH.items()}
    try:
        GRAPH["wecook_core.model"].add("wecook_core.perception.pipeline")
        assert _cycles(), "a cycle through model and the pipeline should be found"
        with pytest.raises(AssertionError):
            test_layers_import_only_downwards()
    finally:
        GRAPH.clear()
        GRAPH.update(saved)


@pytest.mark.parametrize("package", PACKAGES)
def test_no_source_file_over_500_lines(package: str) -> None:
    long = {str(p.relative_to(ROOT)): n for p in (ROOT / package).rglob("*.py")
            if (n := len(p.read_text().splitlines())) > 500}
    assert long == {}
