"""The app's debug log: timestamped lines of keys, frames and shutdown, to measure latency
by hand. Written only when CLOTH_TUI_DEBUG_LOG names a file; otherwise every line is dropped."""

from __future__ import annotations

import os
import time


class DebugLog:
    def __init__(self, path: str | None) -> None:
        self._file = open(path, "a", buffering=1, encoding="utf-8") if path else None

    @classmethod
    def from_environment(cls) -> "DebugLog":
        return cls(os.environ.get("CLOTH_TUI_DEBUG_LOG"))

    @property
    def writing(self) -> bool:
        return self._file is not None

    def line(self, text: str, at: float | None = None) -> None:
        """`text` after its time (`at`, else now) in perf_counter seconds."""
        if self._file is not None:
            self._file.write(f"{time.perf_counter() if at is None else at:.4f} {text}\n")

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None
