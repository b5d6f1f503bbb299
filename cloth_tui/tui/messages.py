"""Messages the simulation and render threads post to the app (thread-safe `post_message`).
Frames and snapshots travel through one-slot mailboxes on the app; these only wake it."""

from typing import Any

from textual.message import Message


class SimUpdated(Message):
    """Posted when the simulation thread has put a new snapshot in the app's mailbox (and
    the mailbox was empty: one message wakes the app for any number of snapshots)."""


class FrameReady(Message):
    """Posted when the render thread has put a new frame in the app's mailbox (and the
    mailbox was empty)."""


class SimDied(Message):
    """Posted when the simulation thread has ended on an exception, `error`."""

    def __init__(self, error: BaseException | None) -> None:
        super().__init__()
        self.error = error


class PinResult(Message):
    """Posted when the simulation thread has pinned a grabbed particle (the Ctrl+drag
    gesture), or refused to: `text` says which and why; `ok`: it was pinned."""

    def __init__(self, text: str, ok: bool) -> None:
        super().__init__()
        self.text, self.ok = text, ok


class Captured(Message):
    """Posted when the render thread has finished, or failed, a screenshot or a video:
    `event` says which, and where it went."""

    def __init__(self, event: Any) -> None:
        super().__init__()
        self.event = event
