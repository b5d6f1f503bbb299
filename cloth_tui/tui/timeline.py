"""The timeline of a bake: one row, the played part of the bar, the playhead and the rest.
It owns no playback: keys and the mouse become messages, and the app tells it what to show
(`show`) once the player has moved."""

from __future__ import annotations

from rich.text import Text
from textual import events
from textual.binding import Binding
from textual.message import Message
from textual.widget import Widget

PLAYED, HEAD, AHEAD = "━", "●", "─"
BIG_STEP = 10  # frames a shift+arrow steps


class Timeline(Widget, can_focus=True):
    DEFAULT_CSS = """
    Timeline { height: 1; width: 1fr; }
    """

    BINDINGS = [
        Binding("space", "play_pause", "Play/Pause"),
        Binding("right", "step(1)", "Frame", key_display="←→"),
        Binding("left", "step(-1)", "Frame back", show=False),
        Binding("shift+right", f"step({BIG_STEP})", f"{BIG_STEP} frames", show=False),
        Binding("shift+left", f"step(-{BIG_STEP})", f"{BIG_STEP} frames back", show=False),
        Binding("home", "seek_end(0)", "First/last", key_display="Home End"),
        Binding("end", "seek_end(1)", "Last frame", show=False),
    ]

    class Seek(Message):
        """Posted when the user picks a frame: a click or a drag on the bar, or Home/End.
        `index` is 0..count-1."""

        def __init__(self, index: int) -> None:
            super().__init__()
            self.index = index

    class Step(Message):
        """Posted when the user steps by `delta` frames with the arrow keys (shift: BIG_STEP)."""

        def __init__(self, delta: int) -> None:
            super().__init__()
            self.delta = delta

    class PlayPause(Message):
        """Posted when the user presses space on the timeline."""

    def __init__(self, count: int, *, id: str | None = None) -> None:
        super().__init__(id=id)
        self.count = max(int(count), 1)
        self.position = 0
        self._dragging = False

    def show(self, position: int) -> None:
        """Draw the playhead at frame index `position`."""
        if position != self.position:
            self.position = position
            self.refresh()

    # -- geometry: one cell per 1/(width-1) of the bake, both ends inclusive --------------
    def index_at(self, x: int) -> int:
        last = max(self.size.width - 1, 1)
        x = min(max(x, 0), last)
        return round(x / last * (self.count - 1))

    def column_of(self, index: int) -> int:
        if self.count == 1:
            return 0
        return round(index / (self.count - 1) * max(self.size.width - 1, 0))

    def render(self) -> Text:
        width = self.size.width
        if width <= 0:
            return Text("")
        head = self.column_of(self.position)
        text = Text(no_wrap=True, overflow="crop")
        text.append(PLAYED * head, style="bold #e0a030")
        text.append(HEAD, style="bold #ffffff")
        text.append(AHEAD * (width - head - 1), style="#707070")
        return text

    # -- keys -----------------------------------------------------------------------------
    def action_play_pause(self) -> None:
        self.post_message(self.PlayPause())

    def action_step(self, delta: int) -> None:
        self.post_message(self.Step(int(delta)))

    def action_seek_end(self, end: int) -> None:
        self.post_message(self.Seek(self.count - 1 if end else 0))

    # -- mouse: a click seeks, a drag scrubs ----------------------------------------------
    def on_mouse_down(self, event: events.MouseDown) -> None:
        self._dragging = True
        self.capture_mouse()
        self.post_message(self.Seek(self.index_at(event.x)))

    def on_mouse_move(self, event: events.MouseMove) -> None:
        if self._dragging:
            index = self.index_at(event.x)
            if index != self.position:
                self.post_message(self.Seek(index))

    def on_mouse_up(self, event: events.MouseUp) -> None:
        if self._dragging:
            self._dragging = False
            self.release_mouse()
