"""Shared by the physics tests: scenes from keyword overrides, and running frames."""

from __future__ import annotations

from cloth_tui.scene import Scene


def scene(**overrides) -> Scene:
    """`scene(cloth__resolution=8)` is the schema's defaults (the original scene) with
    cloth.resolution = 8."""
    return Scene().with_values({k.replace("__", "."): v for k, v in overrides.items()})


def run(sim, frames: int):
    for _ in range(frames):
        sim.advance_frame()
    return sim
