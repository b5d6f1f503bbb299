"""The wheel is what users install: it must carry every module and the built-in scenes and
textures, and the installed package must find them without the source checkout."""

import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    """Built from a copy of the sources (an in-tree build would leave build/ behind), with the
    installed setuptools: no build isolation, no download."""
    src = tmp_path_factory.mktemp("src")
    for name in ("pyproject.toml", "README.md"):
        shutil.copy(ROOT / name, src / name)
    for name in ("cloth_tui", "assets"):
        shutil.copytree(ROOT / name, src / name,
                        ignore=shutil.ignore_patterns("__pycache__", "*.nbi", "*.nbc"))
    out = tmp_path_factory.mktemp("wheel")
    p = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps",
                        "--no-build-isolation", "-q", "-w", str(out), str(src)],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    (whl,) = out.glob("*.whl")
    return whl


def test_wheel_carries_the_builtin_scenes_textures_and_meshes(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    for folder, pattern in (("scenes", "*.toml"), ("textures", "*.png"), ("meshes", "*.ply")):
        files = sorted((ROOT / "assets" / folder).glob(pattern))
        assert files
        missing = [f.name for f in files if f"cloth_tui/assets/{folder}/{f.name}" not in names]
        assert not missing, f"wheel lacks assets/{folder}: {missing}"


def test_wheel_carries_every_module(wheel):
    names = set(zipfile.ZipFile(wheel).namelist())
    modules = [p.relative_to(ROOT).as_posix() for p in (ROOT / "cloth_tui").rglob("*.py")]
    missing = [m for m in modules if m not in names]
    assert not missing, f"not in the wheel (add the package to pyproject.toml): {missing}"


def test_installed_wheel_finds_its_scenes_outside_the_checkout(wheel, tmp_path):
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    code = ("import cloth_tui, cloth_tui.resources as r, cloth_tui.scene_files as s; "
            "print(cloth_tui.__file__); print(r.assets_dir()); "
            "print(' '.join(r.builtin_scenes())); "
            "print(s.load('default').cloth.resolution); "
            "import os; print(os.path.isfile(s.load('torus-drape').objects[0].path))")
    env = dict(os.environ, PYTHONPATH=str(site))
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       cwd=tmp_path, env=env, timeout=120)
    assert p.returncode == 0, p.stderr
    module, assets, scenes, resolution, mesh_found = p.stdout.splitlines()
    assert module.startswith(str(site)) and assets == str(site / "cloth_tui" / "assets")
    assert scenes.split() == sorted(f.stem for f in (ROOT / "assets" / "scenes").glob("*.toml"))
    assert int(resolution) > 1
    assert mesh_found == "True"  # the built-in mesh scene's file, relative to the scene


def test_installed_wheel_reads_its_fabric_table(wheel, tmp_path):
    assert "cloth_tui/materials/presets.toml" in zipfile.ZipFile(wheel).namelist()
    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    code = ("import cloth_tui.materials.presets as p; print(p.__file__); "
            "print(p.get_preset('denim').areal_density)")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       cwd=tmp_path, env=dict(os.environ, PYTHONPATH=str(site)), timeout=120)
    assert p.returncode == 0, p.stderr
    module, density = p.stdout.splitlines()
    assert module.startswith(str(site)) and float(density) == 0.324


@pytest.mark.slow
def test_installed_wheel_serves_the_app_outside_the_checkout(wheel, tmp_path):
    """`cloth-tui serve` from the wheel (its extra, textual-serve, is installed here): a
    visitor, as a page connects, gets the wheel's app drawing its status line. Slow: the
    wheel's kernels compile afresh (numba's cache is keyed by the source's path), and
    .ci/run makes the same visit to the same command from a wheel pip installed."""
    import asyncio

    from .serving import free_port, interrupt, start_server

    site = tmp_path / "site"
    zipfile.ZipFile(wheel).extractall(site)
    env = dict(os.environ, PYTHONPATH=str(site))
    code = "import cloth_tui.serve as s; print(s.__file__)"
    where = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                           cwd=tmp_path, env=env, timeout=60)
    assert where.stdout.startswith(str(site)), where.stderr
    port = free_port()

    async def go():
        server, said = await start_server(tmp_path, "--port", str(port), env=env)
        try:
            visit = await asyncio.create_subprocess_exec(
                sys.executable, str(ROOT / "tools" / "serve_visit.py"), str(port),
                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, env=env)
            out, _ = await visit.communicate()
        finally:
            code = await interrupt(server)
        assert visit.returncode == 0, out.decode()
        assert code == 0

    asyncio.run(go())
