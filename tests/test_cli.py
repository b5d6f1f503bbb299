import json
import subprocess
import sys

import numpy as np
import pytest

from cloth_tui.cli import main


def run(*args):
    p = subprocess.run([sys.executable, "-m", "cloth_tui", *args], capture_output=True,
                       text=True, timeout=300)
    return p.returncode, p.stdout, p.stderr


def test_simulate_default_reports_finite_sheet():
    rc, out, err = run("simulate", "default", "--frames", "120", "--json")
    assert rc == 0, err
    stats = json.loads(out)
    assert stats["finite"] and stats["particles"] == 26 * 26 and stats["frames"] == 120
    for k in ("constraints", "steps", "min_y", "max_speed", "max_stretch", "mean_stretch",
              "energy", "penetration", "effects", "wall_s"):
        assert k in stats


def test_unpinned_sheet_comes_to_rest_on_floor():
    rc, out, err = run("simulate", "default", "--set", "cloth.pinned=none", "--frames", "300",
                       "--json")
    s = json.loads(out)
    assert s["penetration"] < 0.002 and s["max_speed"] < 0.5
    assert s["min_y"] >= -0.5


def test_dump_writes_positions(tmp_path):
    out = tmp_path / "s.npz"
    assert main(["simulate", "default", "--frames", "2", "--dump", str(out)]) == 0
    d = np.load(out)
    assert d["positions"].shape == (676, 3) and int(d["resolution"]) == 26


@pytest.mark.parametrize("content, args", [
    ("[cloth\n", []),
    ("[cloth]\nfoo = 1\n", []),
    ("[cloth]\nsize = true\n", []),
    ("[cloth]\nresolution = 100000\n", []),
    (None, []),
    ("", ["--set", "cloth.size"]),
    ("", ["--set", "cloth.size=-2"]),
    ("", ["--frames", "-1"]),
    ("", ["--dump", "/nonexistent-dir/x.npz"]),
])
def test_bad_input_exits_2_with_one_line(tmp_path, content, args):
    path = tmp_path / "s.toml"
    if content is not None:
        path.write_text(content)
    rc, out, err = run("simulate", str(path), *args)
    assert rc == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_scenes_lists_builtins(capsys):
    assert main(["scenes"]) == 0
    assert "default" in capsys.readouterr().out
