"""A USD bake's file system: a disk that fills says so and keeps the saved frames; the
temp files of killed bakes go at the next bake into that folder."""

import os
import subprocess
import sys

import pytest

from cloth_tui.io.part_files import remove_stale_parts

from ..small_disk import small_tmpfs

pxr = pytest.importorskip("pxr")
from pxr import Sdf, Usd, UsdGeom  # noqa: E402


def _bake(out, frames, *overrides):
    return subprocess.run([sys.executable, "-m", "cloth_tui", "bake", "default", "-o", str(out),
                           "--frames", str(frames), *overrides],
                          capture_output=True, text=True, timeout=600, check=False)


def test_a_full_disk_is_named_and_the_saved_frames_stay_readable(tmp_path):
    with small_tmpfs(tmp_path / "disk", "2M") as disk:
        p = _bake(disk / "b.usdc", 400)
        assert p.returncode == 2, p.stderr
        line = p.stderr.strip()
        assert "\n" not in line and "the disk is full" in line, line
        assert "Corrupt" not in line
        stage = Usd.Stage.Open(Sdf.Layer.OpenAsAnonymous(str(disk / "b.usdc")))
        samples = UsdGeom.Mesh.Get(stage, "/World/Cloth").GetPointsAttr().GetTimeSamples()
        saved = len(samples)  # ~20 fit beside the last periodic save (a frame or two)
        assert saved >= 10 and f"keeps the first {saved} frames" in line
        assert samples == [float(k) for k in range(1, saved + 1)]
        assert stage.GetEndTimeCode() == saved
        assert [f.name for f in disk.iterdir()] == ["b.usdc"]  # no temp left


def _dead_pid() -> int:
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def test_a_bake_removes_the_temp_files_killed_bakes_left_and_only_those(tmp_path):
    dead = _dead_pid()
    stale = tmp_path / f".b.{dead}.0a1b2c3d.part.usdc"
    running = tmp_path / f".b.{os.getpid()}.0a1b2c3d.part.usdc"  # a live bake's
    others = [tmp_path / f".c.{dead}.0a1b2c3d.part.usdc",  # another bake's name
              tmp_path / f".b.{dead}.0a1b2c3d.part.usda",  # another kind
              tmp_path / ".b.0a1b2c3d.part.usdc",  # no owner named: cannot tell
              tmp_path / "b.usdc.keep"]
    for f in (stale, running, *others):
        f.write_bytes(b"x" * 1000)
    p = _bake(tmp_path / "b.usdc", 2, "--set", "cloth.resolution=8")
    assert p.returncode == 0, p.stderr
    assert not stale.exists()
    assert running.exists() and all(f.exists() for f in others)


def test_remove_stale_parts_leaves_a_folder_it_cannot_read_alone(tmp_path):
    assert remove_stale_parts(tmp_path / "missing" / "b.usdc") == []
