"""The package's shape: layers, no import cycles, light imports, kernel caches keyed right.

The import graph is read from the source with ``ast`` (imports inside functions
included, ``if TYPE_CHECKING:`` blocks excluded), so these tests hold the code
to the layering documented in ``docs/architecture.md``. Run this file as a
script to print the graph's figures.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from dataclasses import dataclass, field
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = SRC / "optri"

#: The compiled core, an extension module (src/core): small, imported where it is used.
CORE = "optri._core"
#: Layers, lowest first: a module may import only modules of its own or a lower layer.
LAYERS = [
    ["optri.errors", "optri.config", "optri._version", "optri._optional", CORE],
    ["optri.predicates"],
    ["optri.polygon", "optri.meshdata"],
    ["optri.io", "optri.data"],
    ["optri.weights", "optri.objective"],
    ["optri.drawing"],
    ["optri.result"],
    ["optri.engines"],
    ["optri.simple"],
    ["optri.domains"],
    ["optri.solve", "optri.chain"],
    ["optri.enumeration", "optri.holes", "optri.teaching", "optri.contours"],
    ["optri.batch", "optri.paper", "optri.bench"],
    ["optri.cli", "optri.__main__"],
    ["optri"],
]
#: The algorithms: never import drawing, io or cli.
ALGORITHMS = (
    "optri.predicates",
    "optri.polygon",
    "optri.weights",
    "optri.objective",
    "optri.engines",
    "optri.simple",
    "optri.domains",
    "optri.enumeration",
    "optri.holes",
)
#: Third-party packages too heavy to import when optri is imported (in functions only).
HEAVY = {
    "numba",
    "llvmlite",
    "matplotlib",
    "click",
    "rich",
    "shapely",
    "trimesh",
    "scipy",
    "dask",
    "distributed",
    "pyarrow",
    "geopandas",
    "pyogrio",
    "pyproj",
    "mapbox_earcut",
    "PIL",
    "imageio",
}


@dataclass
class Module:
    name: str
    path: Path
    is_package: bool
    top: set[str] = field(default_factory=set)  # optri modules imported at module level
    inner: set[str] = field(default_factory=set)  # ... inside functions
    third_top: set[str] = field(default_factory=set)  # third-party, module level
    private: list[str] = field(default_factory=list)  # "module._name" imported


def _modules() -> dict[str, Module]:
    mods = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        rel = path.relative_to(SRC).with_suffix("")
        parts = list(rel.parts)
        is_package = parts[-1] == "__init__"
        if is_package:
            parts = parts[:-1]
        name = ".".join(parts)
        mods[name] = Module(name, path, is_package)
    core = mods[CORE] = Module(CORE, PACKAGE / "_core", False)  # compiled: imports no optri
    for mod in mods.values():
        if mod is core:
            continue
        _read_imports(mod, mods)
    return mods


def _resolve(mod: Module, node: ast.ImportFrom) -> str:
    base = mod.name.split(".") if mod.is_package else mod.name.split(".")[:-1]
    if node.level:
        base = base[: len(base) - (node.level - 1)]
        return ".".join(base + ([node.module] if node.module else []))
    return node.module or ""


def _read_imports(mod: Module, mods: dict[str, Module]) -> None:
    tree = ast.parse(mod.path.read_text())

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.If) and "TYPE_CHECKING" in ast.unparse(child.test):
                continue
            inner = in_function or isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef))
            if isinstance(child, ast.Import):
                for alias in child.names:
                    record(alias.name, [], inner)
            elif isinstance(child, ast.ImportFrom):
                record(_resolve(mod, child), [a.name for a in child.names], inner)
            visit(child, inner)

    def record(target: str, names: list[str], inner: bool) -> None:
        if not target.startswith("optri"):
            if target != "__future__" and not inner:
                mod.third_top.add(target.split(".")[0])
            return
        found = set()
        for name in names:
            sub = f"{target}.{name}"
            if sub in mods:
                found.add(sub)
            elif name.startswith("_") and not name.startswith("__") and target != mod.name:
                mod.private.append(f"{target}.{name}")
        if not names or len(found) < len(names):
            found.add(target)
        (mod.inner if inner else mod.top).update(found - {mod.name})

    visit(tree, False)


def _layer(name: str) -> int:
    best = -1, -1
    for level, prefixes in enumerate(LAYERS):
        for p in prefixes:
            if name == p or name.startswith(p + "."):
                best = max(best, (len(p), level))
    assert best[1] >= 0, f"{name} is in no layer; add it to LAYERS"
    return best[1]


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components with more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def strong(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph.get(v, ()):
            if w not in index:
                strong(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            strong(v)
    return out


def _kernel_modules() -> list[str]:
    """Modules that import numba at module level, directly or through another such module."""
    found = {n for n, m in MODS.items() if "numba" in m.third_top}
    while True:
        more = {n for n, m in MODS.items() if m.top & found} - found
        if not more:
            return sorted(found)
        found |= more


MODS = _modules()
KERNEL_MODULES = _kernel_modules()


def test_no_import_cycles_even_through_imports_inside_functions():
    graph = {n: m.top | m.inner for n, m in MODS.items()}
    assert _cycles(graph) == []


def test_imports_flow_down_the_layers():
    bad = [f"{n} -> {t}" for n, m in MODS.items() for t in m.top | m.inner if _layer(t) > _layer(n)]
    assert bad == []


def test_children_never_import_the_root_package():
    assert [n for n, m in MODS.items() if "optri" in m.top | m.inner and n != "optri"] == []


def test_algorithms_never_import_drawing_io_or_cli():
    bad = [
        f"{n} -> {t}"
        for n, m in MODS.items()
        if n.startswith(ALGORITHMS)
        for t in m.top | m.inner
        if t.startswith(("optri.drawing", "optri.io", "optri.cli"))
    ]
    assert bad == []


def test_no_module_imports_another_modules_private_name():
    assert [f"{n}: {p}" for n, m in MODS.items() for p in m.private] == []


def test_imports_inside_functions_are_for_heavy_packages_only():
    # an optri module imported inside a function must be a kernel module (it loads numba)
    # or the compiled core
    bad = [
        f"{n} -> {t}"
        for n, m in MODS.items()
        for t in m.inner
        if t not in KERNEL_MODULES and t not in (CORE, "optri.engines.core")
    ]
    assert bad == []


def test_heavy_packages_load_only_in_kernel_modules_or_on_use():
    bad = {
        n: sorted(m.third_top & HEAVY)
        for n, m in MODS.items()
        if m.third_top & HEAVY and n not in KERNEL_MODULES and not n.startswith("optri.cli")
    }
    assert bad == {}
    # kernel modules are imported at module level by other kernel modules only
    eager = [
        f"{n} -> {t}"
        for n, m in MODS.items()
        for t in m.top & set(KERNEL_MODULES)
        if n not in KERNEL_MODULES
    ]
    assert eager == []


def test_at_most_twelve_modules_at_the_top():
    # the shared foundations (errors, config, predicates, polygon, meshdata, ...) and the
    # facades; anything else belongs in a feature folder
    top = [p.name for p in PACKAGE.glob("*.py") if p.name not in ("__init__.py", "__main__.py")]
    assert len(top) <= 12, sorted(top)


def test_import_optri_stays_light():
    heavy = sorted(HEAVY)
    code = (
        f"import sys, optri; heavy = {heavy!r}; "
        "print(sorted(m for m in sys.modules if m.split('.')[0] in heavy))"
    )
    env = {"PYTHONPATH": str(SRC), "PATH": "/usr/bin:/bin"}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True
    )
    assert out.stdout.strip() == "[]"


@pytest.mark.parametrize("name", sorted(MODS))
def test_every_module_is_in_a_layer(name):
    assert _layer(name) >= 0


if __name__ == "__main__":
    edges = sum(len(m.top | m.inner) for m in MODS.values())
    graph = {n: m.top | m.inner for n, m in MODS.items()}
    print(f"{len(MODS)} modules, {edges} import edges, {len(_cycles(graph))} cycles")
    print(f"kernel modules: {', '.join(KERNEL_MODULES)}")
