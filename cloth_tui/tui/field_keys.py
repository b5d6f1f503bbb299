"""Keys for a focused text field, applied in the order they were typed.

Textual hands a key to the focused Input through the Input's own message queue; the Input
inserts a character at once, but an edit key (Backspace, Home, Delete, Enter…) is a binding,
run only when the key has bubbled up through every container's queue to the app. A character
typed next goes straight to the Input and overtakes it: Backspace then `7` deletes the 7. The
more keys one read of the terminal brings (a busy machine), the more are overtaken.

So the app applies a key for a focused field itself, from its own queue, one key at a time:
a character is inserted, an edit key runs its binding (the same chain Textual walks: the field,
its containers, the screen, the app) before the next key is looked at. Enter in a setting goes
further: the app decides there whether the value is taken and where focus goes, through
messages, so the keys typed after it wait until that is settled (see `release_keys`)."""

from __future__ import annotations

from collections import deque

from textual import events
from textual.timer import Timer
from textual.widgets import Input

from .panels import SettingField

# s: keys typed after Enter wait at most this long for the app to settle the value (it
# answers within a few frames; the bound only keeps a lost answer from holding keys forever).
HOLD_AT_MOST_S = 1.0


class FieldKeys:
    """A mixin of the App (before `App` in the bases): `on_event` routes the keys."""

    _held_keys: deque[events.Key] | None = None
    _holding = False
    _hold_timer: Timer | None = None

    async def on_event(self, event: events.Event) -> None:
        if isinstance(event, events.Key) and not event.is_forwarded:
            if self._holding or self._held_keys:
                if self._held_keys is None:
                    self._held_keys = deque()
                self._held_keys.append(event)
                return
            if isinstance(self.focused, Input):
                await self._key_to_field(event, self.focused)
                return
        await super().on_event(event)

    async def _key_to_field(self, event: events.Key, field: Input) -> None:
        """What Textual does with a key for a focused field, without the trip up the DOM:
        the app's priority bindings first, then the character, then the bindings from the
        field outwards; a key none of them takes goes on to the field as before."""
        if await self._check_bindings(event.key, priority=True):
            return
        if event.is_printable:
            await field._on_key(event)  # inserts it (over a selection), as the Input does
            return
        submits_a_setting = event.key == "enter" and isinstance(field.parent, SettingField)
        if submits_a_setting:
            self.hold_keys()
        if not await self._check_bindings(event.key):
            if submits_a_setting:
                self.release_keys()
            field._forward_event(event)

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
            event = held.popleft()
            if isinstance(self.focused, Input):
                await self._key_to_field(event, self.focused)
            else:
                await super().on_event(event)
