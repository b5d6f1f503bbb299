"""The layers' import rules (tui → render → sim): the physics loads no terminal, GL or image
library, and the renderer no terminal library. Each check runs in a fresh interpreter, so
modules other tests imported cannot hide or fake a violation."""

import json
import subprocess
import sys

import pytest

FORBIDDEN = {
    "cloth_tui.sim": ("textual", "pyvista", "vtk", "vtkmodules", "imageio"),
    "cloth_tui.render": ("textual",),
    # io writes files: no terminal, and GL only when an OBJ/PLY sequence asks for VTK's writers
    "cloth_tui.io": ("textual", "pyvista", "vtk", "vtkmodules", "imageio"),
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
