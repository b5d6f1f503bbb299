"""Every compiled kernel leaves divergence to the guard: no kernel raises on a zero divisor."""

import importlib
import pkgutil

import numpy as np
from numba.core.registry import CPUDispatcher

import cloth_tui.sim
from cloth_tui.sim.collision import selfcollision


def sim_kernels():
    """Every kernel of every module under cloth_tui.sim, its subpackages' (solvers/...) too."""
    prefix = "cloth_tui.sim."
    for info in pkgutil.walk_packages(cloth_tui.sim.__path__, prefix):
        module = importlib.import_module(info.name)
        for name, obj in vars(module).items():
            if isinstance(obj, CPUDispatcher) and obj.__module__ == module.__name__:
                yield f"{info.name[len(prefix):]}.{name}", obj


def test_every_sim_kernel_uses_the_numpy_error_model_and_releases_the_gil():
    kernels = dict(sim_kernels())
    assert len(kernels) > 30, sorted(kernels)
    wrong = {name: k.targetoptions for name, k in kernels.items()
             if k.targetoptions.get("error_model") != "numpy" or not k.targetoptions.get("nogil")}
    assert not wrong, wrong


def test_a_divisor_driven_to_zero_gives_a_non_finite_state_not_an_exception():
    # Subnormal inverse masses times a small distance underflow to exactly 0.0: the Python
    # error model raised ZeroDivisionError here and killed the simulation thread.
    x = np.array([[0.0, 0.0, 0.0], [1e-3, 0.0, 0.0]])
    inv_mass = np.array([5e-324, 0.0])
    pairs = np.array([[0, 1]], dtype=np.int64)
    selfcollision.resolve_pairs(x, inv_mass, pairs, 1, 0.01)
    assert not np.isfinite(x).all()
