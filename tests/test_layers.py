"""The package's rooms match its layers: every import (module level or inside a function, walked with
``ast``) points down the layer order below or stays in its own layer, and no two modules import each
other, directly or through a longer circle."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "cof_gym"

# The layer order, lowest first: the one place it is written (README "Layout" describes it).
LAYERS: tuple[str, ...] = (
    "validation",  # strict argument checks every layer shares: no cof_gym imports
    "measurement",  # sine fit from lock-in sums, comfort filters: only the checks below
    "physics",  # creep laws, contact, vehicle models, the native callback
    "analysis",  # small-signal theory of the physics (Eq. 3/4, the paper's schedule), plotting
    "task",  # scenarios, ground truth, action/observation types, reward, creep-curve identification
    "envs",  # the Gymnasium env and its vector twin
    "agents",  # policies behind the Agent interface, their registry and adapters
    "commands",  # evaluate, train, bench, reproduce-paper and their reports
    "cli",  # the cof-gym command line
)
TOP = "__init__"  # cof_gym/__init__.py registers the envs by entry-point strings only


def _module_name(path: Path) -> str:
    rel = path.relative_to(PACKAGE.parent).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def _layer(module: str) -> str:
    parts = module.split(".")
    return TOP if len(parts) == 1 else parts[1]


def _imports(path: Path) -> set[str]:
    """The cof_gym modules ``path`` imports (``from cof_gym.x import y`` counts y when it is a module)."""
    tree = ast.parse(path.read_text(), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(a.name for a in node.names if a.name.startswith("cof_gym"))
        elif isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("cof_gym") and node.level == 0:
            found.add(node.module)
            for alias in node.names:
                sub = f"{node.module}.{alias.name}"
                if (PACKAGE.parent / sub.replace(".", "/")).with_suffix(".py").exists() or \
                        (PACKAGE.parent / sub.replace(".", "/") / "__init__.py").exists():
                    found.add(sub)
    return found - {"cof_gym"}


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}
GRAPH = {name: {m for m in _imports(path) if m in MODULES and m != name} for name, path in MODULES.items()}


def test_every_package_folder_has_a_layer():
    folders = {p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    modules = {p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__"}
    assert folders | modules <= set(LAYERS), f"unlayered: {sorted((folders | modules) - set(LAYERS))}"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_point_down(module):
    if _layer(module) == TOP:
        assert not GRAPH[module], f"cof_gym/__init__.py imports {sorted(GRAPH[module])}: register by strings"
        return
    rank = LAYERS.index(_layer(module))
    upward = sorted(m for m in GRAPH[module] if _layer(m) != TOP and LAYERS.index(_layer(m)) > rank)
    assert not upward, f"{module} ({_layer(module)}) imports higher layers: {upward}"


def test_no_import_circle():
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(GRAPH[node]):
            if state.get(nxt) == 1:
                cycle = stack[stack.index(nxt):] + [nxt]
                pytest.fail("import circle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for module in sorted(GRAPH):
        if module not in state:
            visit(module)


def test_the_walker_sees_an_upward_import(tmp_path):
    """The check itself can fail: a physics module importing an agent is caught."""
    bad = tmp_path / "bad.py"
    bad.write_text("def f():\n    from cof_gym.agents.registry import make_agent\n")
    assert "cof_gym.agents.registry" in _imports(bad)


# The learned interrogator's package has layers of its own, lowest first (its docstring names them): a module
# imports only those before it; the package's __init__ re-exports the first six, which training reads through it.
INTERROGATOR = "cof_gym.agents.interrogator"
INTERROGATOR_ORDER = ("readings", "features", "networks", "interval", "climb", "caution", "agent", "training")


def test_the_interrogators_modules_cover_its_order_and_import_only_those_before_them():
    inside = {m for m in MODULES if m.startswith(INTERROGATOR + ".")}
    assert inside == {f"{INTERROGATOR}.{name}" for name in INTERROGATOR_ORDER}
    for rank, name in enumerate(INTERROGATOR_ORDER):
        module = f"{INTERROGATOR}.{name}"
        allowed = {f"{INTERROGATOR}.{below}" for below in INTERROGATOR_ORDER[:rank]}
        if name == INTERROGATOR_ORDER[-1]:
            allowed.add(INTERROGATOR)
        reached = {m for m in GRAPH[module] if m == INTERROGATOR or m.startswith(INTERROGATOR + ".")}
        assert reached <= allowed, f"{module} imports {sorted(reached - allowed)}"
    assert GRAPH[INTERROGATOR] == {f"{INTERROGATOR}.{name}" for name in INTERROGATOR_ORDER[:-1]}
