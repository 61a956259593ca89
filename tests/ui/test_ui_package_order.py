"""The ui packages depend one way (issue 36): a module imports its own package's modules and those of
the packages in the rows below its own in ``zuml_studio.ui.LAYERS``, never a package beside or above
it. Imports inside functions count, as in tests/test_import_graph.py, whose graph this reads."""
from test_import_graph import _graph
from zuml_studio.ui import LAYERS

UI = "zuml_studio.ui"


def _package(module: str) -> str:
    """The ui package a module is in (``app`` for ui/app.py)."""
    return module[len(UI) + 1:].split(".")[0]


def _against_the_order(graph: dict[str, set[str]], layers: tuple[tuple[str, ...], ...]) -> list[str]:
    row = {package: i for i, packages in enumerate(layers) for package in packages}
    found = []
    for module in sorted(m for m in graph if m.startswith(UI + ".")):
        mine = _package(module)
        if mine not in row:
            found.append(f"{module}: ui.{mine} has no row in zuml_studio.ui.LAYERS")
            continue
        for target in sorted(t for t in graph[module] if t.startswith(UI + ".")):
            theirs = _package(target)
            if theirs != mine and row.get(theirs, len(layers)) >= row[mine]:
                found.append(f"{module} imports {target}: ui.{theirs} is not below ui.{mine}")
    return found


def test_every_ui_import_goes_down_the_order():
    found = _against_the_order(_graph(), LAYERS)
    assert not found, "\n".join(found)


def test_the_order_check_sees_an_import_across_up_or_unplaced():
    graph = {f"{UI}.sim.a": {f"{UI}.device.b", f"{UI}.plots.c", f"{UI}.sim.d"},
             f"{UI}.plots.c": {f"{UI}.packs.e", f"{UI}.base.f"},
             f"{UI}.base.f": set(),
             f"{UI}.newcomer": {f"{UI}.base.f"}}
    assert _against_the_order(graph, LAYERS) == [
        f"{UI}.newcomer: ui.newcomer has no row in zuml_studio.ui.LAYERS",
        f"{UI}.plots.c imports {UI}.packs.e: ui.packs is not below ui.plots",
        f"{UI}.sim.a imports {UI}.device.b: ui.device is not below ui.sim",
    ]
