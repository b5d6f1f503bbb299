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
solved by a dense Cholesky factor.

The whole cycle is one compiled call (`v_cycle`, every grid's arrays end to end) that holds
no GIL: in the app the simulation thread shares the GIL with the UI and the renderer, and
every return to Python between small steps waits for it.
"""

from __future__ import annotations

import math

import numpy as np

from ...jit import kernel

COARSEST = 600  # particles: a grid this small is solved directly


@kernel(inline="always")
def span_times(indices, data, x, t, end):
    """Entries t:end of a CSR matrix's row (P, I or Iᵀ) times x, for the three columns of x.
    Four partial sums: one sum's chain of dependent additions, not the loads, was what
    bounded a sweep."""
    a0 = a1 = a2 = b0 = b1 = b2 = c0 = c1 = c2 = d0 = d1 = d2 = 0.0
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


@kernel(inline="always")
def row_times(indptr, indices, data, x, i):
    """Row i of a CSR matrix times x, for the three columns of x."""
    return span_times(indices, data, x, indptr[i], indptr[i + 1])


@kernel()
def sweep_from_zero(indptr, indices, data, inv_diag, diag_at, x, b):
    """A forward Gauss-Seidel sweep of P x = b from x = 0 (x's rows are written, not
    read, before their turn): row i reads only the entries left of its diagonal (at
    diag_at[i]), the rows before it; the others still hold 0."""
    for i in range(x.shape[0]):
        p0, p1, p2 = span_times(indices, data, x, indptr[i], diag_at[i])
        w = inv_diag[i]
        x[i, 0] = w * (b[i, 0] - p0)
        x[i, 1] = w * (b[i, 1] - p1)
        x[i, 2] = w * (b[i, 2] - p2)


@kernel()
def residual_after_sweep(indptr, indices, data, diag_at, x, out):
    """out = b − P x after sweep_from_zero: row i there met b with the rows before it and
    its own, so what is left is minus the entries right of its diagonal times x (half a
    product of P where b − P x takes a whole one)."""
    for i in range(x.shape[0]):
        p0, p1, p2 = span_times(indices, data, x, diag_at[i] + 1, indptr[i + 1])
        out[i, 0] = -p0
        out[i, 1] = -p1
        out[i, 2] = -p2


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
def interpolate(indptr, indices, data, coarse, out, add):
    """out (+)= I·coarse for I in CSR, three columns: a correction carried to the finer grid
    (`add`), or with Iᵀ's rows a residual carried to the coarser one."""
    for i in range(out.shape[0]):
        p0, p1, p2 = row_times(indptr, indices, data, coarse, i)
        if add:
            out[i, 0] += p0
            out[i, 1] += p1
            out[i, 2] += p2
        else:
            out[i, 0] = p0
            out[i, 1] = p1
            out[i, 2] = p2


@kernel()
def cholesky_factor(a, out):
    """out = L, lower triangular with L Lᵀ = a (dense, symmetric positive definite; a pivot
    that is not positive gives NaN, which the guard sees). Here, not LAPACK's: OpenBLAS's
    worker threads spin on after each call, on the core the renderer needs, and the coarsest
    grid (at most COARSEST rows) is factored again at every new substep length."""
    n = a.shape[0]
    out[:, :] = 0.0
    for j in range(n):
        total = a[j, j]
        for k in range(j):
            total -= out[j, k] * out[j, k]
        pivot = math.sqrt(total) if total > 0.0 else math.nan
        out[j, j] = pivot
        for i in range(j + 1, n):
            total = a[i, j]
            for k in range(j):
                total -= out[i, k] * out[j, k]
            out[i, j] = total / pivot


@kernel()
def cholesky_solve(chol, b, out):
    """out = (L Lᵀ)⁻¹ b with L lower triangular (dense), three columns."""
    n = chol.shape[0]
    for i in range(n):  # L y = b
        for c in range(3):
            total = b[i, c]
            for j in range(i):
                total -= chol[i, j] * out[j, c]
            out[i, c] = total / chol[i, i]
    for i in range(n - 1, -1, -1):  # Lᵀ x = y
        for c in range(3):
            total = out[i, c]
            for j in range(i + 1, n):
                total -= chol[j, i] * out[j, c]
            out[i, c] = total / chol[i, i]


@kernel()
def v_cycle(row_at, ptr, indices, data, inv_diag, diag_at, i_ptr, i_indices, i_data, t_ptr,
            t_indices, t_data, chol, b, x, rhs, correction, rest):
    """x = one V(1,1)-cycle on b (module docstring), every grid in one call. Grid k's rows
    are row_at[k]:row_at[k+1] of the work arrays (rhs, correction, rest) and of inv_diag; its
    row pointers into indices/data start at ptr[row_at[k] + k], and likewise I's (i_ptr from
    row_at[k] + k) and Iᵀ's, whose rows are grid k + 1's (t_ptr from
    row_at[k + 1] − row_at[1] + k)."""
    grids = row_at.shape[0] - 1
    if grids == 1:
        cholesky_solve(chol, b, x)
        return
    for k in range(grids):
        lo, hi = row_at[k], row_at[k + 1]
        if k > 0:
            correction[lo:hi] = 0.0
        if k == grids - 1:
            cholesky_solve(chol, rhs[lo:hi], correction[lo:hi])
            break
        xk = x if k == 0 else correction[lo:hi]
        bk = b if k == 0 else rhs[lo:hi]
        rows = ptr[lo + k:hi + k + 1]
        # (x is 0 here: the fine grid's from solve, a coarse grid's from above)
        sweep_from_zero(rows, indices, data, inv_diag[lo:hi], diag_at[lo:hi], xk, bk)
        residual_after_sweep(rows, indices, data, diag_at[lo:hi], xk, rest[lo:hi])
        below = row_at[k + 2]
        start = hi - row_at[1] + k  # Iᵀ's rows are grid k + 1's
        interpolate(t_ptr[start:start + below - hi + 1], t_indices, t_data, rest[lo:hi],
                    rhs[hi:below], False)
    for k in range(grids - 2, -1, -1):
        lo, hi = row_at[k], row_at[k + 1]
        xk = x if k == 0 else correction[lo:hi]
        bk = b if k == 0 else rhs[lo:hi]
        interpolate(i_ptr[lo + k:hi + k + 1], i_indices, i_data,
                    correction[hi:row_at[k + 2]], xk, True)
        gauss_seidel_sweep(ptr[lo + k:hi + k + 1], indices, data, inv_diag[lo:hi], xk, bk,
                           False)


def interpolation_1d(n: int):
    """(I, coarse count): n points along a line from the coarse ones at the even indices
    (and the last, where its index is odd), linear between two; the identity for n ≤ 3."""
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
        levels = [_Level(k, m, one)]
        interpolations: list = []  # (I, Iᵀ) from each grid to the one below it
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
            interpolations.append((i, it))
            levels.append(_Level(k, m, one))
        self._flatten(levels, interpolations)
        self.h = None

    def _flatten(self, levels: list[_Level], interpolations: list) -> None:
        """Every grid's arrays end to end, for v_cycle (its docstring has the layout)."""
        sizes = [len(level.indptr) - 1 for level in levels]
        self.row_at = np.concatenate([[0], np.cumsum(sizes)]).astype(np.int64)
        self.grids = len(levels)  # the sheet's own first

        def pointers(matrices):  # row pointers into the concatenated entries
            starts = np.concatenate([[0], np.cumsum([len(m[1]) for m in matrices])])
            return np.concatenate([m[0] + start for m, start in zip(matrices, starts)]
                                  or [np.zeros(0)]).astype(np.int64)

        def entries(matrices, which):
            return np.concatenate([m[which] for m in matrices] or [np.zeros(0)])

        grid = [(lv.indptr, lv.indices) for lv in levels]
        self.ptr = pointers(grid)
        self.indices = entries(grid, 1).astype(np.int64)
        nnz_at = np.concatenate([[0], np.cumsum([len(lv.indices) for lv in levels])])
        self.stiffness = np.concatenate([lv.stiffness for lv in levels])
        self.mass = np.concatenate([lv.mass for lv in levels])
        self.identity = np.concatenate([lv.identity for lv in levels])
        self.on_diagonal = np.concatenate([lv.on_diagonal + at
                                           for lv, at in zip(levels, nnz_at)])
        self.data = np.empty_like(self.stiffness)
        self.inv_diag = np.empty(self.row_at[-1])
        down = [(i.indptr, i.indices, i.data) for i, _ in interpolations]
        up = [(it.indptr, it.indices, it.data) for _, it in interpolations]
        self.i_ptr, self.i_indices = pointers(down), entries(down, 1).astype(np.int64)
        self.i_data = entries(down, 2).astype(np.float64)
        self.t_ptr, self.t_indices = pointers(up), entries(up, 1).astype(np.int64)
        self.t_data = entries(up, 2).astype(np.float64)
        self.rhs = np.zeros((self.row_at[-1], 3))
        self.correction = np.zeros((self.row_at[-1], 3))
        self.rest = np.zeros((self.row_at[-1], 3))  # each grid's residual
        self.chol = np.zeros((0, 0))

    def set_step(self, h: float) -> None:
        """P for substeps of length h (cheap: each grid adds its parts again, and the
        coarsest, at most COARSEST particles, is factored anew)."""
        if h == self.h:
            return
        np.add(self.stiffness, self.identity, out=self.data)
        self.data += self.mass / (h * h)
        self.inv_diag[:] = 1.0 / self.data[self.on_diagonal]
        lo, hi = self.row_at[-2], self.row_at[-1]
        start = self.ptr[lo + self.grids - 1]
        rows = self.ptr[lo + self.grids - 1:hi + self.grids] - start
        coarsest = np.zeros((hi - lo, hi - lo))
        for i in range(hi - lo):
            span = slice(start + rows[i], start + rows[i + 1])
            coarsest[i, self.indices[span]] = self.data[span]
        self.chol = np.empty_like(coarsest)
        cholesky_factor(coarsest, self.chol)
        self.h = h

    def solve(self, b: np.ndarray) -> np.ndarray:
        x = np.zeros(b.shape)
        v_cycle(self.row_at, self.ptr, self.indices, self.data, self.inv_diag,
                self.on_diagonal, self.i_ptr, self.i_indices, self.i_data, self.t_ptr,
                self.t_indices, self.t_data, self.chol,
                np.ascontiguousarray(b, dtype=np.float64), x, self.rhs, self.correction,
                self.rest)
        return x
