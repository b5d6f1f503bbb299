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


def run_refused(capsys, *args):
    """`args` through main() in this process, for a command that must refuse them before it
    does anything (a process costs a second of imports and kernel loading); the app, which
    would take over the terminal if it did not refuse, in its own process."""
    if args[0] not in ("simulate", "render"):
        return run(*args)
    capsys.readouterr()
    rc = main(list(args))
    out, err = capsys.readouterr()
    return rc, out, err


def test_simulate_default_reports_finite_sheet():
    rc, out, err = run("simulate", "default", "--frames", "120", "--json")
    assert rc == 0, err
    stats = json.loads(out)
    assert stats["finite"] and stats["particles"] == 33 * 33 and stats["frames"] == 120
    for k in ("constraints", "steps", "min_y", "max_speed", "max_stretch", "mean_stretch",
              "energy", "penetration", "effects", "wall_s"):
        assert k in stats
    assert stats["mean_frame_ms"] == pytest.approx(1e3 * stats["wall_s"] / 120)


def test_simulate_json_reports_the_tolerance_and_what_it_took():
    rc, out, err = run("simulate", "original", "--frames", "30", "--json", "--set",
                       "behavior.frame_rate=10", "--set", "behavior.substeps=1", "--set",
                       "behavior.iterations=1", "--set", "behavior.error_tolerance=0.03")
    assert rc == 0, err
    s = json.loads(out)
    assert s["error_tolerance"] == 0.03 and s["tolerance_met"] is True
    assert s["substeps_used"] > 1 and s["max_stretch"] <= 0.03
    # the error bounded and the stretch the fabric shows are reported apart (hpbd: equal)
    assert s["solver"] == "hpbd" and 0.0 <= s["error"] <= 0.03
    assert "numerical_damping" in s and s["energy_tolerance"] is None
    rc, out, err = run("simulate", "original", "--frames", "30", "--json", "--set",
                       "behavior.frame_rate=10", "--set", "behavior.substeps=1", "--set",
                       "behavior.iterations=1", "--set", "behavior.max_substeps=1")
    s = json.loads(out)
    assert rc == 0 and s["substeps_used"] == 1 and s["tolerance_met"] is False


def test_simulate_json_reports_torn_constraints():
    rc, out, err = run("simulate", "tear", "--frames", "120", "--json")
    assert rc == 0, err
    s = json.loads(out)
    assert s["torn"] > 0 and s["finite"] and "tear_constraints" in s["effects"]
    rc, out, err = run("simulate", "tear", "--frames", "120", "--json", "--set",
                       "behavior.tear=false")
    s = json.loads(out)
    assert rc == 0 and s["torn"] == 0 and "tear_constraints" not in s["effects"]
    rc, out, err = run("simulate", "tear", "--set", "behavior.tear_stretch=0")
    assert rc == 2 and "tear_stretch" in err and len(err.strip().splitlines()) == 1


def test_simulate_json_reports_the_material_its_error_damping_and_tears():
    rc, out, err = run("simulate", "tear", "--frames", "30", "--json", "--set",
                       "behavior.solver=xpbd", "--set", "material.preset=denim", "--set",
                       "material.tear_strength=40", "--set", "cloth.resolution=12")
    assert rc == 0, err
    s = json.loads(out)
    assert s["material"] == "denim" and "tear_by_strength" in s["effects"]
    assert s["torn"] > 0 and s["finite"]
    assert 0.0 <= s["error"] and s["error_tolerance"] < 0.05  # tightened for the tearing
    assert "numerical_damping" in s  # (None here: the wind brings energy in)
    rc, out, err = run("simulate", "default", "--frames", "30", "--json", "--set",
                       "behavior.solver=xpbd", "--set", "material.preset=denim", "--set",
                       "cloth.resolution=12")
    s = json.loads(out)
    assert rc == 0 and s["material"] == "denim" and s["torn"] == 0
    assert isinstance(s["numerical_damping"], float) and s["error"] <= s["error_tolerance"]
    rc, out, err = run("simulate", "original", "--frames", "1", "--json")
    assert rc == 0 and json.loads(out)["material"] is None
    rc, out, err = run("simulate", "default", "--frames", "1", "--json")
    assert rc == 0 and json.loads(out)["material"] == "denim"


def test_unpinned_sheet_comes_to_rest_on_floor():
    rc, out, err = run("simulate", "original", "--set", "cloth.pinned=none", "--frames", "300",
                       "--json")
    s = json.loads(out)
    assert s["penetration"] < 0.002 and s["max_speed"] < 0.5
    assert s["min_y"] >= -0.5


def test_dump_writes_positions(tmp_path):
    out = tmp_path / "s.npz"
    assert main(["simulate", "default", "--frames", "2", "--dump", str(out)]) == 0
    d = np.load(out)
    assert d["positions"].shape == (33 * 33, 3) and int(d["resolution"]) == 33
    assert tuple(d["shape"]) == (33, 33)


def test_dump_of_a_rectangle_writes_its_shape_rows_first(tmp_path):
    out = tmp_path / "r.npz"
    assert main(["simulate", "default", "--frames", "2", "--dump", str(out), "--set",
                 "cloth.size=[2, 0.5]", "--set", "cloth.resolution=[21, 6]"]) == 0
    d = np.load(out)
    assert tuple(d["shape"]) == (6, 21) and "resolution" not in d.files
    grid = d["positions"].reshape(6, 21, 3)
    assert grid[0, -1, 0] - grid[0, 0, 0] == pytest.approx(2.0, abs=0.05)  # x along a row
    assert grid[-1, 0, 2] - grid[0, 0, 2] == pytest.approx(0.5, abs=0.05)  # z down a column


@pytest.mark.parametrize("value", ["cloth.size=[1, 0.01]", "cloth.resolution=[4]",
                                   "cloth.size=[1, nan]"])
def test_bad_rectangles_exit_2_with_one_line(value, capsys):
    assert main(["simulate", "default", "--frames", "1", "--set", value]) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "cloth." in err and "Traceback" not in err


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


BAD_SCENES = {
    "syntax": "[cloth\n",
    "unknown_key": "[cloth]\nfoo = 1\n",
    "wrong_type": "[cloth]\nsize = true\n",
    "nan": "[cloth]\nsize = nan\n",
    "infinity": "[forces]\ngravity_strength = inf\n",
    "negative_size": "[cloth]\nsize = -1.0\n",
    "absurd_resolution": "[cloth]\nresolution = 100000\n",
    "zero_direction": "[forces]\nwind_direction = [0, 0, 0]\n",
    "unknown_object": "[[objects]]\ntype = \"teapot\"\n",
    "spindle_torus": "[[objects]]\ntype = \"torus\"\nmajor_radius = 0.1\nminor_radius = 0.2\n",
    "binary": b"\x00\x01\xff\xfe garbage",
}


@pytest.mark.parametrize("command", ["app", "simulate", "render"])
@pytest.mark.parametrize("case", sorted(BAD_SCENES))
def test_every_command_refuses_bad_scenes_with_one_line(tmp_path, capsys, command, case):
    path = tmp_path / "bad.toml"
    data = BAD_SCENES[case]
    path.write_bytes(data if isinstance(data, bytes) else data.encode())
    args = {"app": [str(path)], "simulate": ["simulate", str(path)],
            "render": ["render", str(path), "-o", str(tmp_path / "x.png")]}[command]
    rc, out, err = run_refused(capsys, *args)
    assert rc == 2, (rc, err)
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


@pytest.mark.parametrize("command", ["app", "simulate", "render"])
@pytest.mark.parametrize("override", ["cloth.size", "nosection=1", "cloth.nope=1",
                                      "cloth.resolution=2.5", "forces.wind=maybe"])
def test_every_command_refuses_malformed_set(tmp_path, capsys, command, override):
    args = {"app": ["default"], "simulate": ["simulate", "default"],
            "render": ["render", "default", "-o", str(tmp_path / "x.png")]}[command]
    rc, out, err = run_refused(capsys, *args, "--set", override)
    assert rc == 2 and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_version_comes_from_the_package_metadata():
    from importlib.metadata import version
    rc, out, err = run("--version")
    assert rc == 0, err
    assert out.strip() == f"cloth-tui {version('cloth-tui')}"


def test_plot_and_dump_into_a_folder_that_refuses_files_exit_2():
    for args in (["simulate", "default", "--dump", "/sys/x.npz"],
                 ["accuracy", "--quick", "--plot", "/sys/x.png"]):
        rc, out, err = run(*args)
        assert rc == 2 and "Permission denied" in err and len(err.strip().splitlines()) == 1


def test_the_command_keeps_numpys_blas_on_one_thread():
    # OpenBLAS's second thread busy-waits between calls (40 % of a core in the app at 256²);
    # the command sets its limit before NumPy loads, unless the user chose one.
    import os

    probe = ("import ctypes, sys\n"
             "from cloth_tui.cli import main\n"
             "main(['simulate', 'default', '--frames', '1'])\n"
             "lib = sorted({l.split()[-1] for l in open('/proc/self/maps') if 'openblas' in l})\n"
             "print('THREADS', ctypes.CDLL(lib[0]).scipy_openblas_get_num_threads64_())\n")
    env = {k: v for k, v in os.environ.items() if k != "OPENBLAS_NUM_THREADS"}
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         env=env, timeout=120)
    assert out.returncode == 0, out.stderr
    assert "THREADS 1" in out.stdout
    env["OPENBLAS_NUM_THREADS"] = "2"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         env=env, timeout=120)
    assert "THREADS 2" in out.stdout
