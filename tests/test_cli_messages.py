"""Bad input on the command line gives exit 2 and exactly one line on stderr, with control
characters from keys, values and file names escaped (issue 19)."""

import contextlib
import io
import json
import unicodedata

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cloth_tui.cli import main

UNSAFE = {"Cc", "Cf", "Zl", "Zp", "Cs"}
hostile = st.lists(st.one_of(st.characters(codec="utf-8", exclude_characters="\x00"),
                             st.sampled_from(["\x1b]0;x\x07", "\x1b[31m", "\n", "\r", "\x9b",
                                              "\u202e", "\u2028"])),
                   min_size=1, max_size=10).map("".join)


def run_cli(argv) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def assert_one_safe_line(err: str) -> None:
    assert err.endswith("\n") and err.count("\n") == 1, repr(err)
    assert not any(unicodedata.category(c) in UNSAFE for c in err[:-1]), repr(err)


@settings(max_examples=40, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(hostile, st.sampled_from(["set_key", "set_value", "scene_name", "toml_key", "size"]))
def test_bad_input_is_one_escaped_line_with_exit_2(tmp_path, text, where):
    scene_file = tmp_path / "s.toml"
    key = '"' + "".join(f"\\U{ord(c):08x}" for c in text) + '"'
    scene_file.write_text(f"[cloth]\n{key} = 1\n", encoding="utf-8")
    argv = {"set_key": ["simulate", "default", "--set", f"cloth.{text}=1"],
            "set_value": ["simulate", "default", "--set", f"cloth.pinned={text}x"],
            "scene_name": ["simulate", f"{tmp_path}/{text}.toml"],
            "toml_key": ["simulate", str(scene_file)],
            "size": ["render", "default", "-o", str(tmp_path / "o.png"), "--size", text]}[where]
    code, _, err = run_cli(argv)
    assert code == 2
    assert_one_safe_line(err)


def test_huge_integers_and_deep_nesting_exit_2_in_one_line():
    for override in ["cloth.mass=" + "9" * 400, "forces.wind_direction=[0, 1, " + "9" * 400 + "]",
                     "cloth.mass=" + "[" * 5000 + "]" * 5000, "cloth.mass=" + "7" * 5000,
                     "forces.wind_direction=[0, 1e-200, 0]", "cloth.mass=5e-324",
                     "behavior.frame_rate=1e-12"]:
        code, _, err = run_cli(["simulate", "default", "--set", override])
        assert code == 2, override
        assert_one_safe_line(err)


def test_a_scene_file_named_with_a_newline_runs(tmp_path):
    path = tmp_path / "two\nlines.toml"
    path.write_text("[cloth]\nresolution = 4\n", encoding="utf-8")
    code, out, _ = run_cli(["simulate", str(path), "--frames", "1", "--json"])
    assert code == 0 and json.loads(out)["particles"] == 16


def test_paths_longer_than_the_file_system_allows_exit_2(tmp_path):
    for argv in (["simulate", "a" * 300 + ".toml"],
                 ["simulate", "default", "--set", "appearance.cloth_texture=" + "b" * 300 + ".png"],
                 ["simulate", "default", "--set", "appearance.ground_texture=~nosuchuser/a.png"]):
        code, _, err = run_cli(argv)
        assert code == 2, argv
        assert_one_safe_line(err)


@pytest.mark.parametrize("name", ["out.png", "out.mp4", "out.gif"])
def test_render_to_an_existing_folder_with_a_file_name_exits_2(tmp_path, name):
    (tmp_path / name).mkdir()
    code, _, err = run_cli(["render", "default", "-o", str(tmp_path / name), "--size", "64x48",
                            "--frames", "2"])
    assert code == 2 and (tmp_path / name).is_dir()
    assert_one_safe_line(err)


def test_the_reported_divergence_inside_a_frame_halts_with_a_reason_not_a_crash():
    # issue 19's example: a ZeroDivisionError in the black hole's kernel before the guard ran
    code, out, err = run_cli(["simulate", "original", "--set", "behavior.solver=springs",
                              "--set", "behavior.integrator=verlet", "--set",
                              "behavior.stiffness=1e9", "--set", "forces.custom=black_hole",
                              "--frames", "10", "--json"])
    stats = json.loads(out)
    assert code == 0 and err == "" and stats["finite"] and "diverges" in stats["halted"]
