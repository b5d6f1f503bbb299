"""The lab's tests by name. Each is loaded when asked for (they import numpy and the
simulator), so listing the names costs nothing."""

from __future__ import annotations

import importlib

from .study import Experiment, LabError

# name → (module, attribute, one line for --help)
TESTS = {
    "catenary": ("hanging", "CATENARY", "a strip between two hooks: sag against the catenary"),
    "swing": ("hanging", "SWING", "a strip hanging from its top edge: period against the "
                                  "hanging chain's"),
    "cantilever": ("clamped", "CANTILEVER", "a strip clamped horizontally: tip drop against "
                                            "the heavy elastica"),
    "peirce": ("clamped", "PEIRCE", "ASTM D1388 done virtually: B from the 41.5° overhang "
                                    "against the material's"),
    "drape": ("drape", "DRAPE", "the Cusick test: drape coefficient and folds of a 30 cm disc "
                                "(a report)"),
}


def experiment(name: str) -> Experiment:
    if name not in TESTS:
        raise LabError(f"{name!r} is not a lab test; the tests are {', '.join(TESTS)}")
    module, attribute, _ = TESTS[name]
    return getattr(importlib.import_module(f"{__package__}.{module}"), attribute)
