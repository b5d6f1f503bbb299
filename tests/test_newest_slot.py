"""NewestSlot: the newest value wins, each put that finds the slot empty asks for one wake-up,
and a take empties it."""

import threading

from cloth_tui.newest_slot import NewestSlot


def test_the_newest_value_wins_and_a_take_empties_the_slot():
    slot: NewestSlot[int] = NewestSlot()
    assert slot.take() is None and slot.newest is None
    assert slot.put(1) is True      # nothing waited: wake the reader
    assert slot.put(2) is False     # one wake-up is on its way already
    assert slot.dropped == 1
    assert slot.take() == 2 and slot.take() is None
    assert slot.newest == 2         # still readable by whoever only looks
    assert slot.put(3) is True


def test_a_slot_may_start_with_a_value_that_does_not_wait():
    slot = NewestSlot("first")
    assert slot.newest == "first" and slot.take() is None


def test_no_value_is_lost_between_a_put_and_its_wake_up():
    """A reader that takes once per wake-up sees the last value put, from any thread."""
    slot: NewestSlot[int] = NewestSlot()
    wakeups = []

    def writer(base):
        for k in range(2000):
            if slot.put(base + k):
                wakeups.append(1)
    threads = [threading.Thread(target=writer, args=(b,)) for b in (0, 10_000)]
    for t in threads:
        t.start()
    seen = []
    while any(t.is_alive() for t in threads) or wakeups:
        if wakeups:
            wakeups.pop()
            value = slot.take()
            if value is not None:
                seen.append(value)
    for t in threads:
        t.join()
    last = slot.take()
    assert last is None  # every put's wake-up led to a take
    assert slot.newest in (1999, 11_999) and seen[-1] == slot.newest
