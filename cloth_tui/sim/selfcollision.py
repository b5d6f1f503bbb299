"""Self-collision: keeps particles of the sheet apart. (Built in the physics issue.)"""

from __future__ import annotations


def build_self_collision(scene, model) -> list:
    return []
