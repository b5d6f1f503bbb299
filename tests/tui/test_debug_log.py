from cloth_tui.tui.debug_log import DebugLog


def test_lines_are_written_with_their_time_only_when_a_file_is_named(tmp_path, monkeypatch):
    path = tmp_path / "debug.log"
    monkeypatch.setenv("CLOTH_TUI_DEBUG_LOG", str(path))
    log = DebugLog.from_environment()
    assert log.writing
    log.line("key pause", at=12.5)
    log.line("frame 3")
    log.close()
    log.line("after close")  # dropped, not an error
    first, second = path.read_text(encoding="utf-8").splitlines()
    assert first == "12.5000 key pause"
    stamp, text = second.split(" ", 1)
    assert float(stamp) > 0 and text == "frame 3"

    monkeypatch.delenv("CLOTH_TUI_DEBUG_LOG")
    silent = DebugLog.from_environment()
    assert not silent.writing
    silent.line("nothing")  # no file, no error
