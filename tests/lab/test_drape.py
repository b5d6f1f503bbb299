"""The Cusick test's measures on shapes whose answers are known: the disc and its support on
the grid, the shadow of a polygon, the folds of a rim, the drape coefficient."""

import math

import numpy as np
import pytest

from cloth_tui.lab import drape


def test_the_disc_and_its_support_on_the_grid():
    n = 61
    inside, held, hem, h = drape.disc_masks(n)
    assert h == pytest.approx(0.3 / 60)
    assert inside.sum() * h * h == pytest.approx(math.pi * 0.15 ** 2, rel=0.01)
    assert held.sum() * h * h == pytest.approx(math.pi * 0.09 ** 2, rel=0.02)
    assert not (held & ~inside).any() and not (hem & held).any()
    ring = drape.hem_order(n, hem)
    assert len(ring) == hem.sum()


def rim(radius, folds, depth, points=360):
    t = np.linspace(0, 2 * np.pi, points, endpoint=False)
    r = radius * (1 + depth * np.cos(folds * t))
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def test_the_shadow_of_a_circle_and_of_a_folded_rim():
    assert drape.shadow_area(rim(0.15, 0, 0)) == pytest.approx(math.pi * 0.15 ** 2, rel=1e-4)
    # r = R(1 + d cos kt): area π R² (1 + d²/2)
    assert drape.shadow_area(rim(0.12, 6, 0.2, points=3600)) == pytest.approx(
        math.pi * 0.12 ** 2 * (1 + 0.02), rel=1e-4)


@pytest.mark.parametrize("folds", [4, 6, 9])
def test_the_folds_of_a_rim_are_counted(folds):
    assert drape.fold_count(rim(0.12, folds, 0.15)) == folds


def test_the_drape_coefficient_runs_from_the_support_to_the_flat_disc():
    assert drape.drape_coefficient(math.pi * 0.15 ** 2) == pytest.approx(1.0)
    assert drape.drape_coefficient(math.pi * 0.09 ** 2) == pytest.approx(0.0)


def test_a_disc_cut_from_the_sheet_drapes_and_the_rest_falls_away():
    """On today's solver (pbd and its distance 'bending', not a material: no number here is
    a fabric's), the specimen's mechanics: the corners cut loose fall freely, the support
    stays where it is held, and the hem hangs below it (undamped, it swings: measured where
    it is)."""
    n = 21
    scene = drape.strip_scene(size=[0.3, 0.3], resolution=[n, n], pins=drape.specimen_pins(n),
                              behavior={"solver": "pbd", "substeps": 8, "damping": 0.0})
    r = drape.settle_disc(scene, n)
    inside, held, hem, _ = drape.disc_masks(n)
    x = r["state"].x
    y0 = scene.cloth.height
    t = r["state"].t
    corners = ~inside
    assert np.allclose(y0 - x[corners, 1], 0.5 * 9.81 * t * t, rtol=0.02)  # free fall
    assert np.allclose(x[held, 1], y0)
    assert (x[hem, 1] < y0 - 0.005).all()  # the rim fell (pbd's distance "bending" is stiff)
    assert (x[inside & ~held, 1] < y0).all()
    assert 0.0 < r["drape_coefficient"] < 1.0 and r["folds"] >= 0
