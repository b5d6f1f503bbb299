"""Pin groups on a grid of rows × cols particles: which particles each [[pins]] table holds,
where (its offset, or its keys over time), and how (exactly, or by a soft pin).

Hard pins (stiffness 1) join the model's `pinned` particles (inverse mass 0), held at their
anchors: the rest place plus the offset, moved each substep along the keys (`MovePins`).
Soft pins keep their mass and are pulled towards their target once per substep, after the
constraints, by an XPBD zero-length constraint of compliance α = 1/k (`SoftPins`): with λ
started at 0 each substep its correction is Δx = (a − x)·w/(w + α/h²), the implicit-Euler
step of a spring k between the particle and its target, so the hold settles where k·|x − a|
balances the load whatever the substeps or iterations.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ...pin_groups import SOFT_PIN_SCALE, PinGroup, block, cells
from ...scene_keys import SceneError
from ..jit import kernel

EXACT = PinGroup(at=[[0, 0]])  # how cloth.pinned and the wave hold: in place, exactly


def grid_shape(model) -> tuple[int, int]:
    """(rows, cols) of the model's particle grid; particle (row, col) is row*cols + col."""
    return model.shape


@dataclass(frozen=True)
class Track:
    """An offset over time: linear between keys, held before the first and after the last."""
    times: np.ndarray    # (T,) s, increasing
    offsets: np.ndarray  # (T, 3) m

    def at(self, t: float) -> np.ndarray:
        return np.array([np.interp(t, self.times, self.offsets[:, d]) for d in range(3)])


@dataclass(frozen=True)
class Hold:
    """Particles held at their rest place plus an offset; some slots follow tracks."""
    index: np.ndarray   # (K,) particle indices
    rest: np.ndarray    # (K, 3) their places on the flat sheet, m
    offset: np.ndarray  # (K, 3) static offsets, m (unused in moving slots: their track says)
    moving: tuple = ()  # ((slots (k,), Track), ...)

    def at(self, t: float) -> np.ndarray:
        """Where each particle is held at time t (s)."""
        out = self.rest + self.offset
        for slots, track in self.moving:
            out[slots] = self.rest[slots] + track.at(t)
        return out

    def key_times(self) -> np.ndarray:
        return np.unique(np.concatenate([[0.0]] + [tr.times for _, tr in self.moving]))


@dataclass(frozen=True)
class PinLayout:
    hard: Hold              # aligned with the model's `pinned`
    soft: Hold
    soft_compliance: np.ndarray  # (S,) m/N: 1/k of each soft-pinned particle's spring
    soft_label: tuple = ()       # (S,) which group holds each soft-pinned particle


def empty_hold() -> Hold:
    return Hold(np.zeros(0, np.int64), np.zeros((0, 3)), np.zeros((0, 3)))


def group_particles(group: PinGroup, rows: int, cols: int, where: str) -> np.ndarray:
    """Sorted particle indices a group chooses (its ranges checked against the grid)."""
    listed = cells(group, rows, cols, where)
    if listed is not None:
        return np.unique(np.array([r * cols + c for r, c in listed], np.int64))
    rr, cc = block(group, rows, cols, where)
    return (np.asarray(rr)[:, None] * cols + np.asarray(cc)[None, :]).ravel().astype(np.int64)


def layout(fixed: list[tuple[str, np.ndarray]], groups: list[PinGroup], rest: np.ndarray,
           rows: int, cols: int) -> tuple[np.ndarray, PinLayout]:
    """Combine the particles cloth.pinned and the wave hold in place (`fixed`: (key, indices)
    each) with the groups. Returns the hard-pinned particles (sorted) and the layout. A
    particle two sources hold differently (offset, keys or stiffness) is a SceneError naming
    both."""
    owner = np.full(rows * cols, -1, np.int64)  # which source holds each particle
    sources: list[tuple[str, PinGroup]] = []

    def claim(index: np.ndarray, where: str, group: PinGroup) -> np.ndarray:
        taken = owner[index]
        for k in np.flatnonzero(taken >= 0):
            other, held = sources[taken[k]]
            if not held.holds_the_same_as(group):
                r, c = divmod(int(index[k]), cols)
                raise SceneError(f"{where} and {other} both hold particle [{r}, {c}] but "
                                 "differently (offset, keys or stiffness); a particle may be "
                                 "in two groups only if both hold it the same way"
                                 + ("; set cloth.pinned = \"none\" to leave its pattern out"
                                    if other.startswith("cloth.pinned") else "")
                                 + ("; the wave holds both its edges in place"
                                    if other == "behavior.wave" else ""))
        new = index[taken < 0]
        owner[new] = len(sources)
        sources.append((where, group))
        return new

    in_place = [np.zeros(0, np.int64)]
    for where, index in fixed:
        in_place.append(claim(np.unique(np.asarray(index, np.int64)), where, EXACT))
    hard_parts, soft_parts = [np.concatenate(in_place)], []
    for i, g in enumerate(groups):
        new = claim(group_particles(g, rows, cols, f"pins[{i}]"), f"pins[{i}]", g)
        (hard_parts if g.stiffness == 1.0 else soft_parts).append((i, g, new))
    hard = np.unique(np.concatenate([hard_parts[0]] + [p[2] for p in hard_parts[1:]]))
    return hard, PinLayout(_hold(hard, hard_parts[1:], rest), *_soft(soft_parts, rest))


def _track(g: PinGroup) -> Track | None:
    if not g.keys:
        return None
    k = np.array(g.keys, np.float64)
    return Track(k[:, 0].copy(), k[:, 1:].copy())


def _hold(index: np.ndarray, parts: list, rest: np.ndarray) -> Hold:
    offset = np.zeros((len(index), 3))
    moving = []
    for _, g, particles in parts:
        slots = np.searchsorted(index, particles)
        track = _track(g)
        if track is None:
            offset[slots] = g.offset
        else:
            moving.append((slots, track))
    return Hold(index, rest[index].copy(), offset, tuple(moving))


def _soft(parts: list, rest: np.ndarray) -> tuple[Hold, np.ndarray, tuple]:
    if not parts:
        return empty_hold(), np.zeros(0), ()
    index = np.concatenate([p[2] for p in parts])
    order = np.argsort(index, kind="stable")
    index = index[order]
    compliance = np.concatenate([np.full(len(p[2]), _compliance(p[1], len(p[2])))
                                 for p in parts])[order]
    labels = np.concatenate([np.full(len(p[2]), p[0]) for p in parts])[order]
    hold = _hold(index, [(i, g, index[labels == i]) for i, g, _ in parts], rest)
    return hold, compliance, tuple(int(v) for v in labels)


def _compliance(g: PinGroup, count: int) -> float:
    """1/k of one particle's spring: the group's SOFT_PIN_SCALE·s/(1−s) N/m shared evenly.
    A particle claimed by an earlier group too counts in that group only."""
    s = g.stiffness
    total = SOFT_PIN_SCALE * s / (1.0 - s)
    return count / total if count else 0.0


def hard_anchors(model, t: float) -> np.ndarray:
    """Where the model's pinned particles are held at time t."""
    if model.pin_layout is None:
        return model.rest_positions[model.pinned].copy()
    return model.pin_layout.hard.at(t)


def start_positions(model) -> np.ndarray:
    """The sheet at t = 0: flat, with held particles at their t = 0 places."""
    x = np.array(model.rest_positions, dtype=np.float64)
    x[model.pinned] = hard_anchors(model, 0.0)
    if model.pin_layout is not None and len(model.pin_layout.soft.index):
        x[model.pin_layout.soft.index] = model.pin_layout.soft.at(0.0)
    return x


class MovePins:
    """Moves the anchors of hard groups with keys to where they are at the substep's end."""
    name = "move_pins"

    def __init__(self, model):
        self.hard = model.pin_layout.hard

    def apply(self, state, h):
        t = state.t + h
        for slots, track in self.hard.moving:
            state.anchors[slots] = self.hard.rest[slots] + track.at(t)


@kernel()
def pull_soft_pins(x, index, targets, inv_mass, compliance, h):
    inv_h2 = 1.0 / (h * h)
    for k in range(index.shape[0]):
        i = index[k]
        w = inv_mass[i]
        f = w / (w + compliance[k] * inv_h2)
        x[i, 0] += f * (targets[k, 0] - x[i, 0])
        x[i, 1] += f * (targets[k, 1] - x[i, 1])
        x[i, 2] += f * (targets[k, 2] - x[i, 2])


class SoftPins:
    """The soft pins' zero-length XPBD constraints, once per substep (see the docstring)."""
    name = "soft_pins"

    def __init__(self, model):
        lay = model.pin_layout
        self.soft, self.compliance, self.inv_mass = lay.soft, lay.soft_compliance, model.inv_mass
        self._static = None if lay.soft.moving else lay.soft.at(0.0)

    def apply(self, state, h):
        targets = self._static if self._static is not None else self.soft.at(state.t + h)
        pull_soft_pins(state.x, self.soft.index, targets, self.inv_mass, self.compliance, h)


def pin_effects(model) -> tuple[list, list]:
    """(effects first in a substep, effects after the hard pins) the layout needs."""
    lay = model.pin_layout
    if lay is None:
        return [], []
    first = [MovePins(model)] if lay.hard.moving else []
    last = [SoftPins(model)] if len(lay.soft.index) else []
    return first, last


def with_user_pin(model, particle: int, position) -> tuple:
    """A model that also holds `particle` exactly at `position` (the app's pin gesture),
    and the pinned slot it has. A particle already held in place moves to `position`; one a
    soft or moving group holds is refused (SceneError), since that group decides where it is."""
    lay = model.pin_layout or PinLayout(
        Hold(model.pinned, model.rest_positions[model.pinned].copy(),
             np.zeros((len(model.pinned), 3))), empty_hold(), np.zeros(0))
    rows, cols = grid_shape(model)
    r, c = divmod(int(particle), cols)
    if particle in set(lay.soft.index.tolist()) or any(
            particle in set(model.pinned[s].tolist()) for s, _ in lay.hard.moving):
        raise SceneError(f"particle [{r}, {c}] follows a soft or moving pin group, which "
                         "decides where it is held")
    p = np.asarray(position, np.float64)
    if not np.isfinite(p).all():
        raise SceneError("the pin's place is not a finite position")
    slots = np.flatnonzero(model.pinned == particle)
    rest = model.rest_positions[particle]
    if len(slots):
        offset = lay.hard.offset.copy()
        offset[slots[0]] = p - rest
        hard = replace(lay.hard, offset=offset)
        return replace(model, pin_layout=replace(lay, hard=hard)), int(slots[0])
    # appended, so the slots tethers and the wave refer to stay where they are
    pinned = np.append(model.pinned, particle).astype(np.int64)
    inv_mass = model.inv_mass.copy()
    inv_mass[particle] = 0.0
    hard = Hold(pinned, np.vstack([lay.hard.rest, rest]), np.vstack([lay.hard.offset, p - rest]),
                lay.hard.moving)
    tether_pin = None if model.tether_pin is None else model.tether_pin.copy()
    if tether_pin is not None:
        tether_pin[particle] = -1
    for arr in (pinned, inv_mass):
        arr.setflags(write=False)
    new = replace(model, pinned=pinned, inv_mass=inv_mass, tether_pin=tether_pin,
                  pin_layout=replace(lay, hard=hard))
    return new, len(pinned) - 1


def track_times(hold: Hold, spacing: float = 0.01, most: int = 64) -> np.ndarray:
    """Times at which to check where a hold's moving particles are: every key, and between
    keys often enough that no particle moves more than `spacing` (m) from one to the next,
    `most` in all (then farther apart)."""
    keys = hold.key_times()
    if not hold.moving or len(keys) < 2:
        return keys[:1] if not hold.moving else keys
    moves = [max(float(np.linalg.norm(tr.at(b) - tr.at(a))) for _, tr in hold.moving)
             for a, b in zip(keys, keys[1:])]
    total = sum(moves)
    budget = max(0, most - len(keys))
    step = max(spacing, total / budget if budget else math.inf)
    out = [keys[0]]
    for (a, b), d in zip(zip(keys, keys[1:]), moves):
        k = max(1, math.ceil(d / step)) if math.isfinite(step) else 1
        out += list(np.linspace(a, b, k + 1)[1:])
    return np.array(out)
