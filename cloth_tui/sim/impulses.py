"""Impulses applied once per frame: rain. (Built in the physics issue.)"""

from __future__ import annotations


def build_impulses(scene, model) -> list:
    return []
