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


# Imports the module, then lists the loaded package modules whose names start with the prefix.
LOADS = """
import importlib, json, pkgutil, sys
module = importlib.import_module(sys.argv[1])
if hasattr(module, "__path__"):
    for info in pkgutil.walk_packages(module.__path__, module.__name__ + "."):
        importlib.import_module(info.name)
print(json.dumps(sorted(n for n in sys.modules if n == sys.argv[2] or
                        n.startswith(sys.argv[2] + "."))))
"""


def modules_loaded_by(module: str, prefix: str) -> list[str]:
    out = subprocess.run([sys.executable, "-c", LOADS, module, prefix],
                         capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout)


def test_the_scene_schema_imports_no_simulation_code():
    """The schema reads the solvers' and shapes' declarations (solver_specs, object_shapes),
    never the physics."""
    assert modules_loaded_by("cloth_tui.scene", "cloth_tui.sim") == []


def test_the_simulation_imports_the_scene_schema_only_for_type_hints():
    assert modules_loaded_by("cloth_tui.sim", "cloth_tui.scene") == []
    assert run_time_imports(Path(cloth_tui.__file__).parent / "sim", "cloth_tui.scene") == []


def run_time_imports(root: Path, target: str) -> list[str]:
    """Where a module under `root` imports `target` anywhere (in a function too), outside
    an `if TYPE_CHECKING:` block."""
    found = []
    for path in sorted(root.rglob("*.py")):
        parts = path.relative_to(root.parent.parent).with_suffix("").parts
        package = ".".join(parts[:-1])
        hints = set()
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.If) and getattr(node.test, "id", "") == "TYPE_CHECKING":
                hints.update(id(n) for b in node.body for n in ast.walk(b))
        for node in ast.walk(tree):
            if id(node) in hints:
                continue
            if isinstance(node, ast.ImportFrom):
                base = package.split(".")[:len(package.split(".")) - node.level + 1] \
                    if node.level else []
                modules = [".".join(base + ([node.module] if node.module else []))]
                if not node.module:
                    modules = [f"{modules[0]}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                modules = [a.name for a in node.names]
            else:
                continue
            if any(m == target or m.startswith(target + ".") for m in modules):
                found.append(f"{path.relative_to(root.parent)}:{node.lineno}")
    return found


def test_the_run_time_import_finder_sees_one(tmp_path):
    sim = tmp_path / "cloth_tui" / "sim"
    (sim / "run").mkdir(parents=True)
    (sim / "run" / "late.py").write_text(
        "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    from ...scene import Scene\n"
        "def f():\n    from ...scene import SceneError\n")
    assert run_time_imports(sim, "cloth_tui.scene") == ["sim/run/late.py:5"]
