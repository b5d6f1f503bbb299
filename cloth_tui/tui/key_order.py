"""Keys applied in the order they were typed, whatever has focus.

Textual hands a key to the focused widget through that widget's own message queue; an Input
inserts a character there at once, but an edit key (Backspace, Home, Delete, Enter…) or a
focus key (Tab) is a binding, run only when the key has bubbled up through every container's
queue to the app. A key typed next goes straight to the focused widget and overtakes it:
Backspace then `7` deleted the 7, and Tab then `5` typed the 5 into the field being left
(or, with a container focused, lost it). The more keys one read of the terminal brings (a
busy machine), the more are overtaken.

So the app applies each key itself, from its own queue, before it looks at the next: its
priority bindings, then a character the focused widget types (an Input's text, a dropdown's
type-to-search), then the bindings from the focused widget outwards (the same chain Textual
walks). Only a key none of them takes goes on to the widget as before (a widget's own key
handlers, the app's `on_key`). Enter in a setting goes further: the app decides there whether
the value is taken and where focus goes, through messages, so the keys typed after it wait
until that is settled (see `release_keys`)."""

from __future__ import annotations

from collections import deque
from typing import Callable

from textual import events
from textual.timer import Timer
from textual.widgets import Input

from .setting_field import SettingField

# s: keys typed after Enter wait at most this long for the app to settle the value. It answers
# within a few frames, but 1 s was seen to pass at start-up on a loaded machine (the keys then
# went to the field being left); the bound only keeps a lost answer from holding keys forever.
HOLD_AT_MOST_S = 5.0


class KeyOrder:
    """A mixin of the App (before `App` in the bases): `on_event` routes the keys. Uses the
    app's `debug_line`: each key, as it comes, goes to the debug log."""

    _held_keys: deque[events.Key] | None = None
    _holding = False
    _hold_timer: Timer | None = None
    debug_line: Callable[[str], None]

    async def on_event(self, event: events.Event) -> None:
        if isinstance(event, (events.AppFocus, events.AppBlur, events.Resize)):
            self.debug_line(f"event {type(event).__name__}")
        if isinstance(event, events.Key) and not event.is_forwarded:
            focused = self.focused
            self.debug_line(f"key in {event.key} focused "
                            f"{type(focused).__name__ if focused is not None else None}"
                            f"{' held' if self._holding or self._held_keys else ''}")
            if self._holding or self._held_keys:
                if self._held_keys is None:
                    self._held_keys = deque()
                self._held_keys.append(event)
                return
            await self._apply_key(event)
            return
        await super().on_event(event)

    async def _apply_key(self, event: events.Key) -> None:
        """What Textual does with a key, without the trip up the DOM between a binding and
        the key after it."""
        if await self._check_bindings(event.key, priority=True):
            return
        focused = self.focused
        if focused is not None and focused.check_consume_key(event.key, event.character):
            await focused._on_key(event)  # types it, as the widget does with a forwarded key
            return
        submits_a_setting = event.key == "enter" and isinstance(focused, Input) and \
            isinstance(focused.parent, SettingField)
        if submits_a_setting:
            self.hold_keys()
        if await self._check_bindings(event.key):
            return
        if submits_a_setting:
            self.release_keys()
        await super().on_event(event)  # on to the focused widget (or the screen), as before

    def hold_keys(self) -> None:
        """Keep the next keys until `release_keys` (the app has settled an entered value)."""
        self._holding = True
        if self._hold_timer is not None:
            self._hold_timer.stop()
        self._hold_timer = self.set_timer(HOLD_AT_MOST_S, self.release_keys)

    def release_keys(self) -> None:
        """Apply the keys held since `hold_keys`, in order, after the current message."""
        if not self._holding:
            return
        self._holding = False
        if self._hold_timer is not None:
            self._hold_timer.stop()
            self._hold_timer = None
        self.call_later(self._apply_held_keys)

    async def _apply_held_keys(self) -> None:
        held = self._held_keys
        while held and not self._holding:  # a held Enter holds the rest again
            await self._apply_key(held.popleft())
