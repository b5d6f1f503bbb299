"""`--graphics` on the app command: a forced mode reaches the app; a bad one is exit 2."""

import cloth_tui.tui.app as tui_app
from cloth_tui.cli import main
from cloth_tui.tui.graphics import detect


def test_forced_graphics_mode_reaches_the_app(monkeypatch, tmp_path):
    seen = {}
    monkeypatch.setattr(detect, "query_tty", lambda timeout: (detect.Replies(), (8, 16)))
    monkeypatch.setattr(tui_app, "run_app", lambda scene, captures, **kw: seen.update(kw) or 0)
    assert main(["--graphics", "sixel", "--captures", str(tmp_path)]) == 0
    g = seen["graphics"]
    assert g.mode == "sixel" and g.cell_px == (8, 16)


def test_unknown_graphics_mode_is_one_line_and_exit_2(capsys):
    assert main(["--graphics", "ascii"]) == 2
    err = capsys.readouterr().err.strip()
    assert "--graphics" in err and "ascii" in err and len(err.splitlines()) == 1
