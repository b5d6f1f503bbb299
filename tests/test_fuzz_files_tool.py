"""tools/fuzz_files.py: its cases are reproducible from the seed, mutate what they say, and a
few of them, run for real, end in exit 0 or a one-line refusal."""

import importlib.util
import random
from pathlib import Path

import pytest

spec = importlib.util.spec_from_file_location(
    "fuzz_files", Path(__file__).resolve().parent.parent / "tools" / "fuzz_files.py")
fuzz_files = importlib.util.module_from_spec(spec)
spec.loader.exec_module(fuzz_files)

pytest.importorskip("pyvista")


def test_cases_are_seeded_and_mutate_the_file(tmp_path):
    base = fuzz_files.base_mesh("ply_ascii", tmp_path)
    a = fuzz_files.mutate_mesh(random.Random("1-5"), "ply_ascii", base)
    assert a == fuzz_files.mutate_mesh(random.Random("1-5"), "ply_ascii", base)
    changed = sum(fuzz_files.mutate_mesh(random.Random(f"1-{i}"), "ply_ascii", base)[0] != base
                  for i in range(40))
    assert changed >= 30  # a mutation that finds nothing to replace leaves the file as it was
    assert {fuzz_files.case_kind(1, i) for i in range(200)} == \
        set(fuzz_files.MESH_KINDS) | set(fuzz_files.BAKE_KINDS)


def test_the_classes_name_what_passes():
    assert fuzz_files.classify(0, "") == "ok"
    assert fuzz_files.classify(2, "cloth-tui: error: x\n") == "refused"
    assert fuzz_files.classify(2, "Warning: a\nb\ncloth-tui: error: x\n") == "bad_message"
    # the compile notice of a cold cache is not a warning (seed 40, case 152)
    notice = ("cloth-tui: compiling kernels (first run only)…\n"
              "cloth-tui: 1 kernels compiled in 108 s; later runs load them from numba's cache\n")
    assert fuzz_files.classify(0, notice) == "ok"
    assert fuzz_files.classify(2, notice + "cloth-tui: error: x\n") == "refused"
    assert fuzz_files.classify(0, notice + "RuntimeWarning: x\n") == "stderr"
    assert fuzz_files.classify(-11, "") == "exit_-11" and fuzz_files.classify(None, "") == \
        "timeout"


# seed 1: a PLY refused and one passed, a .usda and a .usdc bake refused, and two of what its
# first run of 300 found: an OBJ index of 10²⁰ (OverflowError), a .usdc whose scene text is
# not UTF-8 (UnicodeDecodeError)
@pytest.mark.parametrize("index", [0, 10, 17, 12, 185, 124])
def test_a_few_cases_end_in_exit_0_or_a_one_line_refusal(tmp_path, index):
    kind = fuzz_files.case_kind(1, index)
    bases = fuzz_files.make_bases(tmp_path, {kind})
    result = fuzz_files.run_one(1, index, bases, timeout=120, keep=None)
    assert result["kind"] == kind
    assert result["class"] in ("ok", "refused"), result
