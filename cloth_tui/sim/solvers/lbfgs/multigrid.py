"""P⁻¹ by one multigrid V-cycle on the sheet's grid: where L-BFGS starts each direction.

P = M/h² + K (step_matrix.py) is one scalar matrix on a regular grid of nz rows of nx
particles. A V(1,1)-cycle (a forward Gauss-Seidel sweep, the residual restricted to a grid of
half the particles a side, the same cycle there, its correction interpolated back, a backward
sweep) is a fixed symmetric positive definite operator, as L-BFGS's H₀ must be. One cycle is
within a few per cent of P⁻¹ (tests/sim/solvers/test_lbfgs_multigrid.py), and costs a few
reads of P where a back-substitution reads its factor, whose fill grows as N log N.

The coarse matrices are Galerkin's, Iᵀ P I with bilinear interpolation I. They are linear
in 1/h², so each level keeps its stiffness and mass parts on one sparsity pattern and a new
substep length only adds them again (`set_step`): the accuracy control changes h often. A
held particle takes no correction from a coarse grid (its row of I is zero) and its row of
P is the identity, so it never moves. The coarsest grid, at most COARSEST particles, is
solved by a sparse LU factor.
"""

from __future__ import annotations

import numpy as np

from ...jit import kernel

COARSEST = 600  # particles: a grid this small is solved directly


@kernel(inline="always")
def row_times(indptr, indices, data, x, i):
    """Row i of P times x, for the three columns of x. Four partial sums: one sum's chain of
    dependent additions, not the loads, was what bounded a sweep."""
    a0 = a1 = a2 = b0 = b1 = b2 = c0 = c1 = c2 = d0 = d1 = d2 = 0.0
    t, end = indptr[i], indptr[i + 1]
    while t + 3 < end:
        j, w = indices[t], data[t]
        a0 += w * x[j, 0]
        a1 += w * x[j, 1]
        a2 += w * x[j, 2]
        j, w = indices[t + 1], data[t + 1]
        b0 += w * x[j, 0]
        b1 += w * x[j, 1]
        b2 += w * x[j, 2]
        j, w = indices[t + 2], data[t + 2]
        c0 += w * x[j, 0]
        c1 += w * x[j, 1]
        c2 += w * x[j, 2]
        j, w = indices[t + 3], data[t + 3]
        d0 += w * x[j, 0]
        d1 += w * x[j, 1]
        d2 += w * x[j, 2]
        t += 4
    while t < end:
        j, w = indices[t], data[t]
        a0 += w * x[j, 0]
        a1 += w * x[j, 1]
        a2 += w * x[j, 2]
        t += 1
    return (a0 + b0) + (c0 + d0), (a1 + b1) + (c1 + d1), (a2 + b2) + (c2 + d2)


@kernel()
def gauss_seidel_sweep(indptr, indices, data, inv_diag, x, b, forward):
    """One Gauss-Seidel sweep of P x = b over the rows, first to last or last to first, for
    the three right-hand sides at once."""
    n = x.shape[0]
    for step in range(n):
        i = step if forward else n - 1 - step
        p0, p1, p2 = row_times(indptr, indices, data, x, i)
        w = inv_diag[i]
        x[i, 0] += w * (b[i, 0] - p0)
        x[i, 1] += w * (b[i, 1] - p1)
        x[i, 2] += w * (b[i, 2] - p2)


@kernel()
def residual(indptr, indices, data, x, b, out):
    """out = b − P x."""
    for i in range(x.shape[0]):
        p0, p1, p2 = row_times(indptr, indices, data, x, i)
        out[i, 0] = b[i, 0] - p0
        out[i, 1] = b[i, 1] - p1
        out[i, 2] = b[i, 2] - p2


def interpolation_1d(n: int):
    """(I, coarse count): n points along a line from the coarse ones at the even indices
    (and the last, where it is odd), linear between two; the identity for n ≤ 3."""
    import scipy.sparse as sp

    if n <= 3:
        return sp.identity(n, format="csr"), n
    coarse = np.arange(0, n, 2)
    if coarse[-1] != n - 1:
        coarse = np.append(coarse, n - 1)
    of_coarse = np.full(n, -1)
    of_coarse[coarse] = np.arange(len(coarse))
    between = np.flatnonzero(of_coarse < 0)  # odd points, each midway between two coarse
    rows = np.concatenate([coarse, between, between])
    cols = np.concatenate([np.arange(len(coarse)), of_coarse[between - 1],
                           of_coarse[between + 1]])
    vals = np.concatenate([np.ones(len(coarse)), np.full(2 * len(between), 0.5)])
    return sp.csr_matrix((vals, (rows, cols)), shape=(n, len(coarse))), len(coarse)


class _Level:
    """One grid's P on a fixed pattern: stiffness + mass/h² + identity (held or empty rows)."""

    def __init__(self, stiffness, mass, identity):
        pattern = (abs(stiffness) + mass + identity).tocsr()  # no term cancels another
        pattern.sort_indices()
        rows = np.repeat(np.arange(pattern.shape[0]), np.diff(pattern.indptr))
        cols = pattern.indices

        def on_pattern(part):
            return np.asarray(part.tocsr()[rows, cols]).ravel()

        self.indptr = pattern.indptr.astype(np.int64)
        self.indices = cols.astype(np.int64)
        self.stiffness, self.mass = on_pattern(stiffness), on_pattern(mass)
        self.identity = on_pattern(identity)
        self.on_diagonal = np.flatnonzero(rows == cols)
        self.data = np.empty_like(self.stiffness)
        self.inv_diag = np.empty(pattern.shape[0])
        self.correction = np.zeros((pattern.shape[0], 3))
        self.rest = np.zeros((pattern.shape[0], 3))  # the residual

    def set_step(self, h: float) -> None:
        np.add(self.stiffness, self.identity, out=self.data)
        self.data += self.mass / (h * h)
        self.inv_diag[:] = 1.0 / self.data[self.on_diagonal]

    def matrix(self):
        import scipy.sparse as sp
        n = len(self.indptr) - 1
        return sp.csr_matrix((self.data, self.indices, self.indptr), shape=(n, n))


class StepMultigrid:
    """`.solve(b)` ≈ P⁻¹ b by one V(1,1)-cycle (module docstring); `.set_step(h)` first."""

    def __init__(self, stiffness, mass: np.ndarray, held: np.ndarray, nx: int, nz: int):
        """`stiffness`: K with held particles' rows and columns empty (N × N, N = nx·nz);
        `mass` (N,) kg."""
        import scipy.sparse as sp

        free = ~held
        k = sp.csr_matrix(stiffness)
        m = sp.diags(np.where(free, mass, 0.0), format="csr")
        one = sp.diags(held.astype(float), format="csr")
        self.levels = [_Level(k, m, one)]
        self.interpolate: list = []  # (I, Iᵀ) from each level to the one below it
        keep = sp.diags(free.astype(float))  # held particles take no coarse correction
        while k.shape[0] > COARSEST and max(nx, nz) > 3:
            ix, nx = interpolation_1d(nx)
            iz, nz = interpolation_1d(nz)
            i = sp.kron(iz, ix, format="csr")
            if keep is not None:
                i, keep = (keep @ i).tocsr(), None
            it = i.T.tocsr()
            k, m = (it @ k @ i).tocsr(), (it @ m @ i).tocsr()
            empty = m.diagonal() + k.diagonal() <= 0.0  # over held particles only
            one = sp.diags(empty.astype(float), format="csr")
            self.interpolate.append((i, it))
            self.levels.append(_Level(k, m, one))
        self.h = None
        self._direct = None

    def set_step(self, h: float) -> None:
        """P for substeps of length h (cheap: each level adds its parts again)."""
        if h == self.h:
            return
        from scipy.sparse.linalg import splu

        for level in self.levels:
            level.set_step(h)
        self._direct = splu(self.levels[-1].matrix().tocsc())
        self.h = h

    def solve(self, b: np.ndarray) -> np.ndarray:
        x = np.zeros(b.shape)
        self._cycle(0, np.ascontiguousarray(b, dtype=np.float64), x)
        return x

    def _cycle(self, k: int, b: np.ndarray, x: np.ndarray) -> None:
        level = self.levels[k]
        if k == len(self.levels) - 1:
            x[...] = self._direct.solve(b)
            return
        args = (level.indptr, level.indices, level.data)
        gauss_seidel_sweep(*args, level.inv_diag, x, b, True)
        residual(*args, x, b, level.rest)
        i, it = self.interpolate[k]
        below = self.levels[k + 1].correction
        below[...] = 0.0
        self._cycle(k + 1, it @ level.rest, below)
        x += i @ below
        gauss_seidel_sweep(*args, level.inv_diag, x, b, False)
