"""A measured preset's stretch that stiffens with strain and its bending by direction are what
ARCSim's data-driven model makes of the stored samples; typed numbers keep the linear model."""

import math

import numpy as np
import pytest

from cloth_tui.materials.errors import MaterialError
from cloth_tui.materials.measured import BendingByDirection, StretchCurve
from cloth_tui.materials.presets import load_presets, parse_presets
from cloth_tui.materials.schema import material_from_table

WANG = [p for p in load_presets().values() if p.arcsim_stretching and not p.alias_of]


def arcsim_stiffness(samples, g):
    """ARCSim's evaluate_stretching_sample (dde.cpp, with conf.cpp's table: every angle's
    zero-strain entry is the first sample, the strained entries the five others): the
    doubled stiffness at Green strain g (2×2), interpolated in the largest principal
    stretch's strain (reaching the strained samples at 1/6) and its direction's angle."""
    lam, vecs = np.linalg.eigh(2 * g + np.eye(2))
    top = int(np.argmax(lam))
    w, v = math.sqrt(lam[top]), vecs[:, top]
    if v[0] < 0:  # an eigenvector's sign is arbitrary: the one at 0° to 90° from the warp
        v = -v
    angle = min(abs(math.atan2(v[1], v[0]) / math.pi) * 8, 4 - 1e-6)
    a_id, a_w = int(angle), angle - int(angle)
    s = min(max((w - 1) * 6, 0.0), 1 - 1e-6)
    low = np.asarray(samples[0], float)
    high = np.asarray(samples[1:], float)
    k = (low * (1 - s) * (1 - a_w) + high[a_id] * s * (1 - a_w)
         + low * (1 - s) * a_w + high[a_id + 1] * s * a_w)
    return 2 * np.maximum(k, 0.0)


def arcsim_tension(samples, strain, along):
    """N/m of rest width: the first Piola stress λ·S along `along` (0 warp, 1 weft) of a strip
    stretched by `strain` with its width held, S = k·G without the coupling (C12) the grid's
    membrane has not."""
    g = np.zeros((2, 2))
    g[along, along] = strain + 0.5 * strain ** 2
    k = arcsim_stiffness(samples, g)
    return (1 + strain) * k[0 if along == 0 else 2] * g[along, along]


@pytest.mark.parametrize("preset", WANG, ids=lambda p: p.name)
@pytest.mark.parametrize("strain", [0.01, 0.05, 0.1, 0.3])
def test_the_tension_curves_are_arcsims_model_of_the_stored_samples(preset, strain):
    samples = [preset.arcsim_stretching] + _strained(preset.name)
    warp, weft = preset.stretch_curves
    assert warp.tension(strain) == pytest.approx(arcsim_tension(samples, strain, 0), rel=1e-5)
    assert weft.tension(strain) == pytest.approx(arcsim_tension(samples, strain, 1), rel=1e-5)
    assert warp.low == preset.stretch_warp and weft.low == preset.stretch_weft


def _strained(name):
    """The five strained samples as the table file stores them."""
    import importlib.resources
    import tomllib
    text = importlib.resources.files("cloth_tui.materials").joinpath("presets.toml").read_text()
    return tomllib.loads(text)[name]["arcsim_stretching_strained"]


def test_the_knits_stiffen_many_times_over_and_the_wovens_hardly():
    navy = load_presets()["wang2011-navy-sparkle-sweat"].stretch_curves[1]
    denim = load_presets()["denim"].stretch_curves[0]
    assert navy.tension(0.1) / (navy.low * 0.1) > 40
    assert 1.1 < denim.tension(0.1) / (denim.low * 0.1) < 1.4


@pytest.mark.parametrize("preset", WANG, ids=lambda p: p.name)
def test_the_folds_at_0_45_and_90_degrees_have_the_three_stored_rigidities(preset):
    b = preset.bending_by_direction
    assert b.fold_0 == preset.bending
    assert (b.along(0), b.along(45), b.along(90)) == pytest.approx(
        (b.fold_0, b.fold_45, b.fold_90), rel=1e-12)
    assert min(b.grid_rigidities()) > 0  # a convex energy on the grid


def test_denims_fold_across_the_warp_is_half_as_stiff_again_as_along_it():
    b = load_presets()["denim"].bending_by_direction
    assert b.fold_90 / b.fold_0 == pytest.approx(96.951576 / 64.196457)
    assert b.fold_45 == pytest.approx(73.384567e-6 / 4)


def test_a_preset_brings_its_curves_and_typed_numbers_replace_them_with_the_linear_model():
    plain = material_from_table({"preset": "denim", "damping": 1.0})
    assert plain.stretch_curves is not None and plain.bending_by_direction is not None
    typed = material_from_table({"preset": "denim", "stretch": 300.0})
    assert typed.stretch_curves is None and typed.bending_by_direction is not None
    typed = material_from_table({"preset": "denim", "bending": 1e-5})
    assert typed.stretch_curves is not None and typed.bending_by_direction is None
    custom = material_from_table({"areal_density": 0.2, "stretch": 100.0, "shear": 10.0,
                                  "bending": 1e-5})
    assert custom.stretch_curves is None and custom.bending_by_direction is None
    assert all(p.stretch_curves is None for p in load_presets().values() if p.estimate)


ROW = """[x]
areal_density = 0.2
arcsim_stretching = [10.0, 0.0, 20.0, 5.0]
arcsim_bending = 40e-6
source = "s"
"""


@pytest.mark.parametrize("extra, says", [
    ("arcsim_stretching_strained = [[1, 2, 3, 4]]", r"five \[C11"),
    ("arcsim_stretching_strained = [" + "[1, 2, 3, 4], " * 4 + "[1, 2, 3]]", r"five \[C11"),
    ("arcsim_bending_45 = 40e-6", "both"),
    ("arcsim_bending_45 = 5e-6\narcsim_bending_90 = 40e-6", "convex"),
    ("arcsim_bending_45 = \"a\"\narcsim_bending_90 = 40e-6", "numbers"),
])
def test_a_malformed_measured_row_is_refused_in_one_line(extra, says):
    with pytest.raises(MaterialError, match=says) as e:
        parse_presets(ROW + extra)
    assert "\n" not in str(e.value)


def test_the_measured_keys_need_an_arcsim_row():
    with pytest.raises(MaterialError, match="need arcsim_stretching"):
        parse_presets('[x]\nareal_density = 0.2\nstretch = 1.0\nshear = 1.0\nbending = 1e-6\n'
                      'source = "s"\narcsim_bending_45 = 1e-6\narcsim_bending_90 = 1e-6\n')


def test_a_curve_is_linear_in_compression_and_flat_past_its_reach():
    c = StretchCurve(10.0, 70.0)
    assert c.tension(-0.05) == pytest.approx(-0.5)
    assert c.stiffness(0.5) == c.stiffness(1 / 6) == 70.0
    assert c.stiffness(1 / 12) == pytest.approx(40.0)
    assert BendingByDirection(1.0, 1.0, 1.0).grid_rigidities() == (1.0, 1.0, 1.0)


@pytest.mark.parametrize("name", ["jersey", "denim", "wang2011-white-swim-solid"])
def test_a_curves_tangent_and_inverse_are_its_tensions(name):
    for c in load_presets()[name].stretch_curves:
        for strain in (0.01, 0.1, 0.2, 0.6):
            d = 1e-7
            assert c.tangent(strain) == pytest.approx(
                (c.tension(strain + d) - c.tension(strain - d)) / (2 * d), rel=1e-5)
            assert c.strain_at(c.tension(strain)) == pytest.approx(strain, rel=1e-9)


def test_the_stiffness_where_a_fabric_pulls_with_a_tension():
    from cloth_tui.materials.schema import stiffness_at_tension
    linear = material_from_table({"preset": "jersey", "stretch": [30.0, 70.0]})
    assert stiffness_at_tension(linear, 100.0) == 70.0
    jersey = material_from_table({"preset": "jersey"})
    warp, weft = jersey.stretch_curves
    assert stiffness_at_tension(jersey, 100.0) == max(
        warp.tangent(warp.strain_at(100.0)), weft.tangent(weft.strain_at(100.0)))
    assert stiffness_at_tension(jersey, 100.0) > 10 * max(warp.low, weft.low)
