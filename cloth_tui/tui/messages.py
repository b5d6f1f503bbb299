"""Messages the simulation and render threads post to the app (thread-safe `post_message`).
Frames and snapshots travel through one-slot mailboxes on the app; these only wake it."""

from typing import Any

from textual.message import Message


class SimUpdated(Message):
    """A new snapshot waits in the app's mailbox."""


class FrameReady(Message):
    """A new rendered frame waits in the app's mailbox."""


class SimDied(Message):
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
    def __init__(self, event: Any) -> None:
        super().__init__()
        self.event = event
