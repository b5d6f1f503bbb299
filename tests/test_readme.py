"""The README is a front door: every `cloth-tui` command in its code blocks runs as written,
every TOML block in it is a scene that loads, it stays short, and neither it nor docs/ carries
history (commit hashes, "the round before")."""

from __future__ import annotations

import functools
import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
README = ROOT / "README.md"
DOCS = sorted((ROOT / "docs").glob("**/*.md"))
CLI = [sys.executable, "-m", "cloth_tui"]

# Commands that open the app or a server run until a person stops them: they are checked
# another way (see _runnable), never skipped silently.
APP_OPTIONS = {"--set", "--captures", "--graphics"}
SLOW = {"accuracy", "wedge"}  # a Dask cluster's start-up, a work-precision study


def code_blocks(text: str, lang: str) -> list[str]:
    return re.findall(rf"^```{lang}\n(.*?)^```", text, flags=re.S | re.M)


def readme_commands() -> list[str]:
    """Every line of the README's sh blocks that runs cloth-tui, continuations joined."""
    out = []
    for block in code_blocks(README.read_text(encoding="utf-8"), "sh"):
        for line in block.replace("\\\n", " ").splitlines():
            line = line.split(" #", 1)[0].strip()
            if line.startswith("cloth-tui"):
                out.append(line)
    return out


@functools.cache
def _subcommands() -> set[str]:
    """The commands `cloth-tui --help` names ("Commands: render, simulate, …")."""
    out = subprocess.run(CLI + ["--help"], capture_output=True, text=True, timeout=60).stdout
    listed = re.search(r"Commands:(.*?)\(", out, flags=re.S)
    assert listed, out
    return {w for w in re.split(r"[,\s]+", listed.group(1)) if w}


def _runnable(argv: list[str]) -> tuple[list[str], str | None]:
    """The command to run for the README's argv, and why it differs from the README's, if it
    does. The app runs until quit: its scene and --set are checked by simulating the same
    scene for two frames, which refuses what the app would refuse."""
    subs = _subcommands()
    if argv and argv[0] in subs:
        if argv[0] == "serve":
            return argv + ["--help"], "serve listens until stopped: its options are parsed"
        return argv, None
    if argv and argv[0].lower().endswith((".usd", ".usdc", ".usda")):
        return [], "opens the app on a bake, which plays until quit"
    scene = argv[0] if argv and not argv[0].startswith("-") else "default"
    rest = argv[1:] if argv and not argv[0].startswith("-") else argv
    return ["simulate", scene, *rest, "--frames", "2"], "the app: its scene simulated"


@pytest.fixture(scope="module")
def workdir(tmp_path_factory) -> Path:
    """One folder for the README's commands of this worker; a command that reads another's
    output has it made first (`_make_inputs`)."""
    return tmp_path_factory.mktemp("readme")


def test_the_readme_shows_commands_of_every_kind():
    commands = readme_commands()
    assert len(commands) >= 10
    assert any(c.startswith("cloth-tui render") for c in commands)
    assert any("material.preset=" in c for c in commands)


@pytest.mark.parametrize("command", [
    pytest.param(c, marks=[pytest.mark.slow] if shlex.split(c)[1:2] and
                 shlex.split(c)[1] in SLOW else [])
    for c in readme_commands()])
def test_every_readme_command_runs_as_written(command, workdir):
    argv = shlex.split(command)[1:]
    if argv and argv[0] in _maybe_commands() - _subcommands():
        pytest.skip(f"`cloth-tui {argv[0]}` is not a command of this build yet")
    run, why = _runnable(argv)
    if not run:
        pytest.skip(f"{command!r}: {why}")
    _make_inputs(argv, workdir)
    p = subprocess.run(CLI + run, cwd=workdir, capture_output=True, text=True, timeout=180,
                       stdin=subprocess.DEVNULL)
    assert p.returncode == 0, f"{command!r} (run as {run}, {why}) exited {p.returncode}: " \
                              f"{p.stderr[-2000:]}"
    assert "Traceback" not in p.stderr


def _output(argv: list[str]) -> str | None:
    for flag in ("-o", "--output"):
        if flag in argv[:-1]:
            return argv[argv.index(flag) + 1]
    return None


def _make_inputs(argv: list[str], workdir: Path) -> None:
    """A command that reads what an earlier README command writes (`render sphere.usdc` the
    bake) gets it made first when missing: with pytest-xdist the two may run on different
    workers, each with its own folder."""
    producers = {_output(shlex.split(c)[1:]): shlex.split(c)[1:] for c in readme_commands()}
    for word in argv:
        maker = producers.get(word)
        if maker is not None and word != _output(argv) and not (workdir / word).exists():
            p = subprocess.run(CLI + maker, cwd=workdir, capture_output=True, text=True,
                               timeout=180, stdin=subprocess.DEVNULL)
            assert p.returncode == 0, f"making {word} for {argv}: {p.stderr[-2000:]}"


def _maybe_commands() -> set[str]:
    """Words the README uses as commands in its table; one the parser does not know yet is a
    command another change adds (the README names it ahead of it)."""
    text = README.read_text(encoding="utf-8")
    return set(re.findall(r"^\| `cloth-tui ([a-z]+)", text, flags=re.M))


def test_every_toml_block_in_the_readme_is_a_scene_that_loads():
    from cloth_tui import scene_files as sf
    blocks = code_blocks(README.read_text(encoding="utf-8"), "toml")
    assert blocks
    for block in blocks:
        sf.loads(block, "README")


def test_the_readme_is_a_front_door():
    text = README.read_text(encoding="utf-8")
    assert len(text.splitlines()) <= 250
    assert text.lstrip().splitlines()[2].startswith("![")  # a picture first, under the title
    picture = re.search(r"!\[[^\]]*\]\(([^)]+)\)", text).group(1)
    assert (ROOT / picture).is_file()


def _anchors(page: Path) -> set[str]:
    """GitHub's anchors of a page's headings: lower case, punctuation out, spaces to hyphens."""
    text = re.sub(r"^```.*?^```", "", page.read_text(encoding="utf-8"), flags=re.S | re.M)
    return {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-")
            for h in re.findall(r"^#+ (.*)$", text, flags=re.M)}


def test_links_from_the_readme_and_docs_reach_files_and_sections_that_exist():
    for page in [README, *DOCS]:
        text = page.read_text(encoding="utf-8")
        for target, anchor in re.findall(r"\]\(([^)#\s]*)(?:#([^)\s]*))?\)", text):
            if "://" in target:
                continue
            linked = page.parent / target if target else page
            assert linked.exists(), f"{page.name} links to missing {target}"
            if anchor and linked.suffix == ".md":
                assert anchor in _anchors(linked), f"{page.name} links to {target}#{anchor}"


def test_the_materials_link_reaches_its_section():
    physics = (ROOT / "docs" / "physics.md").read_text(encoding="utf-8")
    assert "## Materials in SI units — `[material]`" in physics
    assert "docs/physics.md#materials-in-si-units--material" in README.read_text(encoding="utf-8")


HEX = re.compile(r"(?<![0-9A-Za-z_])[0-9a-f]{7,40}(?![0-9A-Za-z_])")


def _commits_named(text: str) -> list[str]:
    found = []
    for word in set(HEX.findall(text)):
        p = subprocess.run(["git", "cat-file", "-e", f"{word}^{{commit}}"], cwd=ROOT,
                           capture_output=True)
        if p.returncode == 0:
            found.append(word)
    return found


def test_no_history_in_the_readme_or_docs():
    if subprocess.run(["git", "rev-parse", "--git-dir"], cwd=ROOT,
                      capture_output=True).returncode != 0:
        pytest.skip("not a git checkout: commit hashes cannot be told from other hex")
    for page in [README, *DOCS]:
        text = page.read_text(encoding="utf-8")
        assert not _commits_named(text), f"{page.name} names commits {_commits_named(text)}"
        for phrase in ("round before", "previous round", "this round"):
            assert phrase not in text.lower(), f"{page.name} says {phrase!r}"
