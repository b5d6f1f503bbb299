"""NewestSlot: one value handed from a thread that makes them to one that uses them, where
only the newest matters (a snapshot, a drawn frame, a frame to encode). A put replaces a
value still waiting, so a slow reader skips values instead of queueing them."""

from __future__ import annotations

import threading
from typing import Generic, TypeVar

T = TypeVar("T")


class NewestSlot(Generic[T]):
    def __init__(self, value: T | None = None):
        self._lock = threading.Lock()
        self._newest = value
        self._waiting = False
        self.dropped = 0  # values replaced before anyone took them

    def put(self, value: T) -> bool:
        """Hold `value`, replacing any waiting one. True when nothing was waiting: the
        reader has no wake-up on the way for this one and must be sent one."""
        with self._lock:
            first = not self._waiting
            if not first:
                self.dropped += 1
            self._newest, self._waiting = value, True
        return first

    def take(self) -> T | None:
        """The waiting value, which then no longer waits; None when none waits."""
        with self._lock:
            if not self._waiting:
                return None
            self._waiting = False
            return self._newest

    @property
    def newest(self) -> T | None:
        """The last value put, taken or not (None before the first)."""
        with self._lock:
            return self._newest
