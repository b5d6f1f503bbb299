"""Whole frames: the simulation and its divergence guard, the accuracy control, the
simulation thread, what is measured and reported."""
