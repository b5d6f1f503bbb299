"""The layers' import rules (tui → render → sim): the physics loads no terminal, GL or image
library, and the renderer no terminal library. Each check runs in a fresh interpreter, so
modules other tests imported cannot hide or fake a violation."""

import ast
import json
import subprocess
import sys
from pathlib import Path

import pytest

import cloth_tui

FORBIDDEN = {
    "cloth_tui.sim": ("textual", "pyvista", "vtk", "vtkmodules", "imageio"),
    "cloth_tui.render": ("textual",),
    # io writes files: no terminal, and GL only when an OBJ/PLY sequence asks for VTK's writers
    "cloth_tui.io": ("textual", "pyvista", "vtk", "vtkmodules", "imageio"),
    # wedges run on Dask and draw with render/: no terminal, and Dask only when a wedge runs
    "cloth_tui.wedge": ("textual", "dask", "distributed"),
    # the terminal-graphics encoders and detection are pure: testable without an app
    "cloth_tui.tui.graphics": ("textual", "pyvista", "vtk", "vtkmodules"),
}

# Imports every module of the package, then lists the loaded top-level names it must not use.
PROBE = """
import importlib, json, pkgutil, sys
package = importlib.import_module(sys.argv[1])
for info in pkgutil.walk_packages(package.__path__, package.__name__ + "."):
    importlib.import_module(info.name)
loaded = {name.split(".")[0] for name in sys.modules}
print(json.dumps(sorted(loaded & set(sys.argv[2:]))))
"""


def loaded_by(package: str, names) -> list[str]:
    out = subprocess.run([sys.executable, "-c", PROBE, package, *names],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_package_imports_nothing_from_the_layers_above(package):
    assert loaded_by(package, FORBIDDEN[package]) == []


def test_the_probe_sees_what_a_package_imports():
    assert loaded_by("cloth_tui.tui", ("textual", "numpy")) == ["numpy", "textual"]


def module_imports(root: Path) -> dict[str, set[str]]:
    """Each module of the package → the package modules it imports at module level."""
    graph = {}
    for path in root.rglob("*.py"):
        parts = path.relative_to(root.parent).with_suffix("").parts
        module = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        package = module if path.name == "__init__.py" else module.rpartition(".")[0]
        deps = set()
        for node in ast.parse(path.read_text()).body:
            if not isinstance(node, ast.ImportFrom):
                continue
            if node.level:
                base = package.split(".")[:len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
                names = [f"{target}.{a.name}" for a in node.names] if not node.module \
                    else [target]
            else:
                names = [node.module or ""]
            deps.update(n for n in names if n.startswith("cloth_tui"))
        graph[module] = deps
    return {m: {d for d in deps if d in graph} for m, deps in graph.items()}


def import_cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    cycles, state = [], {}

    def visit(module, stack):
        state[module] = "open"
        stack.append(module)
        for dep in sorted(graph[module]):
            if state.get(dep) == "open":
                cycles.append(stack[stack.index(dep):] + [dep])
            elif dep not in state:
                visit(dep, stack)
        stack.pop()
        state[module] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module, [])
    return cycles


def test_no_import_circle_inside_the_package():
    graph = module_imports(Path(cloth_tui.__file__).parent)
    assert len(graph) > 40
    assert import_cycles(graph) == []


def test_the_cycle_finder_sees_a_circle():
    assert import_cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == [["a", "b", "c", "a"]]
