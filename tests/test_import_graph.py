"""The package's modules import each other without a circle (issue 25): a reader can follow any
module's imports down to the leaves; and its packages import each other one way only, in the order
``LAYERS`` below writes down (issue 36, docs/architecture.md). Imports inside functions count too,
since a lazy import only hides a circle; those under ``if TYPE_CHECKING:`` do not run, and do not count."""
import ast
from pathlib import Path

import zuml_studio

PACKAGE = Path(zuml_studio.__file__).parent


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, name: str, modules: set[str]) -> set[str]:
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    found = set()
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for_type_checkers = {id(inner) for node in ast.walk(tree)
                         if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING"
                         for stmt in node.body for inner in ast.walk(stmt)}
    for node in ast.walk(tree):
        if id(node) in for_type_checkers:
            continue
        if isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")[: len(package.split(".")) - node.level + 1]
                base = ".".join(anchor + ([base] if base else []))
            # `from . import x` and `from .pkg import mod` name modules; `from .mod import f` a module.
            targets = [f"{base}.{alias.name}" for alias in node.names] + [base]
        else:
            continue
        for target in targets:
            while target and target not in modules:
                target = target.rpartition(".")[0]
            if target and target != name:
                found.add(target)
    return found


def _graph() -> dict[str, set[str]]:
    paths = {_module_name(p): p for p in PACKAGE.rglob("*.py")}
    modules = set(paths)
    # A package's __init__ runs before any of its modules: importing pkg.mod imports pkg, which is not
    # a circle of the code's making, so the edge a module has to its own parent packages is left out.
    return {name: {t for t in _imports(path, name, modules) if not name.startswith(t + ".")}
            for name, path in paths.items()}


def _cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan, iterative)."""
    index, low, on_stack, stack, found, counter = {}, {}, set(), [], [], [0]
    for root in sorted(graph):
        if root in index:
            continue
        work = [(root, iter(sorted(graph[root])))]
        index[root] = low[root] = counter[0]; counter[0] += 1
        stack.append(root); on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = counter[0]; counter[0] += 1
                    stack.append(child); on_stack.add(child)
                    work.append((child, iter(sorted(graph[child]))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop(); on_stack.discard(member); component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def test_no_module_imports_itself_through_others():
    assert _cycles(_graph()) == []


def test_the_graph_sees_a_circle():
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


# The package order (issue 36, docs/architecture.md), bottom first: a module may import modules of
# its own unit and of the units of the layers below; the units of one layer do not import each other.
# A unit is a package or a top-level module of zuml_studio; zuml_studio.ui is one top unit here (the
# order of its own packages is tested on its own).
LAYERS = [
    ("errors",),
    ("data_error",),
    ("i18n",),
    ("file_errors", "user_dirs", "error_words"),
    ("recovery",),
    ("macro_file",),
    ("data",),
    ("domain",),
    ("lang",),
    ("protocol", "wizard"),
    ("streams",),
    ("logs",),
    ("sim",),
    ("safety",),
    ("device", "packs"),
    ("virtual",),
    ("cli", "ui"),
]
_LAYER_OF = {unit: level for level, units in enumerate(LAYERS) for unit in units}


def _unit(module: str) -> str | None:
    """The unit of a module below zuml_studio; None for the package's own __init__."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else None


def _against_the_order(graph: dict[str, set[str]]) -> list[str]:
    found = []
    for module, targets in sorted(graph.items()):
        unit = _unit(module)
        if unit is None:
            continue
        for target in sorted(targets):
            other = _unit(target)
            if other is None or other == unit:
                continue
            if _LAYER_OF[other] >= _LAYER_OF[unit]:
                found.append(f"{module} imports {target}: {unit} (layer {_LAYER_OF[unit]}) may not import "
                             f"{other} (layer {_LAYER_OF[other]})")
    return found


def test_every_package_and_top_level_module_has_a_place_in_the_order():
    units = {_unit(name) for name in _graph()} - {None}
    assert sorted(units - set(_LAYER_OF)) == [], "add them to LAYERS (and to docs/architecture.md)"
    assert sorted(set(_LAYER_OF) - units) == [], "LAYERS names a unit that is not there"


def test_every_import_goes_down_the_package_order():
    assert _against_the_order(_graph()) == []


def test_the_order_sees_an_import_upwards_and_sideways():
    graph = {"zuml_studio.sim.engine": {"zuml_studio.protocol.messages", "zuml_studio.sim.battery"},
             "zuml_studio.lang.lint": {"zuml_studio.sim.interpreter"},
             "zuml_studio.device.zuml.client": {"zuml_studio.packs.db"}}
    device, lang, sim = _LAYER_OF["device"], _LAYER_OF["lang"], _LAYER_OF["sim"]
    assert _against_the_order(graph) == [
        f"zuml_studio.device.zuml.client imports zuml_studio.packs.db: device (layer {device}) may not import packs "
        f"(layer {device})",
        f"zuml_studio.lang.lint imports zuml_studio.sim.interpreter: lang (layer {lang}) may not import sim "
        f"(layer {sim})"]
