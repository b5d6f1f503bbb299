"""hpbd with a material: the fabric's XPBD passes (xpbd/fabric_constraints.py) with coarse
corrections of the structural edges' multipliers between them, so that a large sheet's
tension settles in a few passes and the sheet still stretches as the material says.

Why not hpbd's coarse levels of positions: rigid and one-sided, they take a fabric's stretch
out (a denim sheet held by two clips sagged 0.500 m under them against 0.520 with converged
xpbd). Nor compliant ones: XPBD's state is its multipliers λ, the positions follow from
them, x = x̃ + M⁻¹∇Cᵀλ; a correction of the positions alone is read by the next passes as
where the inertia wants the sheet, and they relax the stretch it made. So the correction
here is of λ, and the positions move by exactly what the changed λ say.

Each pass of Gauss-Seidel solves, for the λ of the structural edges, the linear system of
XPBD's step (Macklin et al. 2016, linearised at the positions now)

    A Δλ = r,   A = J M⁻¹ Jᵀ + α̃,   r = −C − α̃λ,

one edge at a time, which takes an error in the tension along a sheet of n edges ~n² passes
to remove: the smooth errors, which a hanging sheet's are. A coarse correction solves the
same system on a subspace where the tension is the same over 2 × 2 blocks of edges of one
direction (an aggregate; each coarser level joins 2 × 2 aggregates of the one below, and a
strip's short axis, once one block wide, stays so while its length goes on halving):
Δλ = P Δλ_c with
(PᵀAP) Δλ_c = Pᵀr, by a V-cycle of Gauss-Seidel sweeps over the levels (Galerkin
aggregation multigrid). Since it is a correction of the same system on a subspace, the
passes' fixed point (converged xpbd) is unchanged: a step that XPBD would leave as it is,
it leaves as it is too. The shear cells and bending stencils are not coarsened (bending's
λ is warm-started across substeps already, xpbd/fabric_constraints.py). The corrections follow the
first half of a substep's passes; the rest smooth the steps the blocks leave at their
borders (docs/physics.md, "hpbd with a material", has what that and the cost measured).

A is assembled anew for a substep's first correction (its J is the edges' directions then;
the later ones of the substep reuse it): each edge adds w_a + w_b + α̃ to its aggregate's
diagonal, and each pair of edges sharing a particle w_p (±n_i)·(±n_j) to the two entries of
their aggregates; the sparsity pattern, and where each term goes, is made once.
"""

from __future__ import annotations

import numpy as np

from ...jit import kernel

MIN_AGGREGATES = 4   # a level with fewer is not split again
PRE_SWEEPS = 2       # Gauss-Seidel sweeps on a level before handing its residual down
POST_SWEEPS = 2      # … and after taking the coarser correction
COARSEST_SWEEPS = 24  # on the coarsest level (a few dozen aggregates: all but solved)


@kernel(inline="always")
def edge_normals(x, edges, alive, out):
    """Unit vectors along each live edge, a → b (0 for a dead or coincident one)."""
    for e in range(edges.shape[0]):
        a, b = edges[e, 0], edges[e, 1]
        dx = x[b, 0] - x[a, 0]
        dy = x[b, 1] - x[a, 1]
        dz = x[b, 2] - x[a, 2]
        d = np.sqrt(dx * dx + dy * dy + dz * dz)
        inv = 1.0 / d if alive[e] and d > 0.0 else 0.0
        out[e, 0], out[e, 1], out[e, 2] = dx * inv, dy * inv, dz * inv


@kernel(inline="always")
def assemble_first_level(normals, inv_mass, edges, alive, alpha_t, term_particle, term_i,
                         term_j, term_sign, term_entry, term_entry_t, diag_entry, values):
    """values ← PᵀAP of the first level: each live edge's A_ee = w_a + w_b + α̃ onto its
    aggregate's diagonal, and each pair i < j of edges sharing a particle p its
    A_ij = A_ji = w_p·s·(n_i·n_j) onto the entries (i's, j's aggregate) and (j's, i's)."""
    values[:] = 0.0
    for e in range(alpha_t.shape[0]):
        if alive[e]:
            values[diag_entry[e]] += inv_mass[edges[e, 0]] + inv_mass[edges[e, 1]] + alpha_t[e]
    for k in range(term_particle.shape[0]):
        i, j = term_i[k], term_j[k]
        if not (alive[i] and alive[j]):
            continue
        dot = (normals[i, 0] * normals[j, 0] + normals[i, 1] * normals[j, 1]
               + normals[i, 2] * normals[j, 2])
        v = inv_mass[term_particle[k]] * term_sign[k] * dot
        values[term_entry[k]] += v
        values[term_entry_t[k]] += v


@kernel(inline="always")
def coarsen_values(fine_values, entry_map, coarse_values):
    """A coarser level's PᵀAP from the level below's entries."""
    coarse_values[:] = 0.0
    for k in range(fine_values.shape[0]):
        coarse_values[entry_map[k]] += fine_values[k]


@kernel(inline="always")
def edge_residual(x, edges, rest, alive, alpha_t, lam, edge_slot, aggregate, out):
    """out[aggregate] ← Σ over its live edges of r = −C − α̃λ (C = |x_b − x_a| − L0; λ in the
    sweeps' slot order)."""
    out[:] = 0.0
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        a, b = edges[e, 0], edges[e, 1]
        d = np.sqrt((x[b, 0] - x[a, 0]) ** 2 + (x[b, 1] - x[a, 1]) ** 2
                    + (x[b, 2] - x[a, 2]) ** 2)
        out[aggregate[e]] += rest[e] - d - alpha_t[e] * lam[edge_slot[e]]


@kernel(inline="always")
def gauss_seidel(ptr, col, val, diag, rhs, sol, sweeps):
    """`sweeps` forward sweeps of Gauss-Seidel on val·sol = rhs (CSR; diag the index of each
    row's diagonal entry; a row without one, all its edges torn, stays 0)."""
    for _ in range(sweeps):
        for i in range(ptr.shape[0] - 1):
            d = val[diag[i]] if diag[i] >= 0 else 0.0
            if d <= 0.0:
                continue
            s = rhs[i]
            for q in range(ptr[i], ptr[i + 1]):
                s -= val[q] * sol[col[q]]
            sol[i] += s / d


@kernel(inline="always")
def restrict_residual(ptr, col, val, rhs, sol, parent, out):
    """out[parent] ← Σ of the level's residual rhs − val·sol."""
    out[:] = 0.0
    for i in range(ptr.shape[0] - 1):
        s = rhs[i]
        for q in range(ptr[i], ptr[i + 1]):
            s -= val[q] * sol[col[q]]
        out[parent[i]] += s


@kernel(inline="always")
def prolong(coarse, parent, sol):
    for i in range(parent.shape[0]):
        sol[i] += coarse[parent[i]]


@kernel(inline="always")
def apply_correction(x, inv_mass, edges, alive, normals, aggregate, delta, lam, edge_slot):
    """λ_e += Δλ of its aggregate, and the positions by what that says, x += M⁻¹JᵀΔλ."""
    for e in range(edges.shape[0]):
        if not alive[e]:
            continue
        dl = delta[aggregate[e]]
        lam[edge_slot[e]] += dl
        a, b = edges[e, 0], edges[e, 1]
        wa, wb = inv_mass[a], inv_mass[b]
        for c in range(3):
            x[a, c] -= wa * dl * normals[e, c]
            x[b, c] += wb * dl * normals[e, c]


@kernel()
def coarse_correction(x, inv_mass, edges, rest, alive, alpha_t, lam, edge_slot, normals,
                      aggregate, term_particle, term_i, term_j, term_sign, term_entry,
                      term_entry_t, diag_entry, assemble, row_off, ptr_off, entry_off, ptr,
                      col, val, diag, rhs, sol, parent, entry_map, pre, post, coarsest):
    """One correction, all in one call (the levels' arrays concatenated, level k's rows [row_off[k],
    row_off[k+1]), its CSR row pointers [ptr_off[k], ptr_off[k+1]) and entries [entry_off[k],
    entry_off[k+1]), indices local to the level; `parent` and `entry_map` give a row's and an
    entry's place on the next level): with `assemble`, PᵀAP at the positions now (else the last
    one's); restrict r, a V-cycle from 0 (`pre` and `post` sweeps a level, `coarsest` on the last),
    then λ and x. One kernel call for the whole cycle, not one a level and sweep."""
    levels = row_off.shape[0] - 1
    edge_normals(x, edges, alive, normals)
    if assemble:
        e0, e1 = entry_off[0], entry_off[1]
        assemble_first_level(normals, inv_mass, edges, alive, alpha_t, term_particle, term_i,
                             term_j, term_sign, term_entry, term_entry_t, diag_entry,
                             val[e0:e1])
        for k in range(levels - 1):
            coarsen_values(val[entry_off[k]:entry_off[k + 1]],
                           entry_map[entry_off[k]:entry_off[k + 1]],
                           val[entry_off[k + 1]:entry_off[k + 2]])
    r0, r1 = row_off[0], row_off[1]
    edge_residual(x, edges, rest, alive, alpha_t, lam, edge_slot, aggregate, rhs[r0:r1])
    sol[:] = 0.0
    for k in range(levels):  # down: smooth, hand the residual on
        r0, r1 = row_off[k], row_off[k + 1]
        p, e = ptr[ptr_off[k]:ptr_off[k + 1]], entry_off[k]
        c, v, dg = col[e:entry_off[k + 1]], val[e:entry_off[k + 1]], diag[r0:r1]
        if k == levels - 1:
            gauss_seidel(p, c, v, dg, rhs[r0:r1], sol[r0:r1], coarsest)
        else:
            gauss_seidel(p, c, v, dg, rhs[r0:r1], sol[r0:r1], pre)
            n0, n1 = row_off[k + 1], row_off[k + 2]
            restrict_residual(p, c, v, rhs[r0:r1], sol[r0:r1], parent[r0:r1], rhs[n0:n1])
    for k in range(levels - 2, -1, -1):  # up: take the coarser correction, smooth
        r0, r1 = row_off[k], row_off[k + 1]
        n0, n1 = row_off[k + 1], row_off[k + 2]
        prolong(sol[n0:n1], parent[r0:r1], sol[r0:r1])
        p, e = ptr[ptr_off[k]:ptr_off[k + 1]], entry_off[k]
        gauss_seidel(p, col[e:entry_off[k + 1]], val[e:entry_off[k + 1]], diag[r0:r1],
                     rhs[r0:r1], sol[r0:r1], post)
    r0, r1 = row_off[0], row_off[1]
    apply_correction(x, inv_mass, edges, alive, normals, aggregate, sol[r0:r1], lam,
                     edge_slot)


class AggregateLevel:
    """One level's aggregates: the sparsity of its PᵀAP (CSR; the values are
    DualHierarchy's, filled per correction) and where each aggregate goes on the next
    coarser level (`parent`)."""

    def __init__(self, rows: np.ndarray, cols: np.ndarray, count: int):
        order = np.lexsort((cols, rows))
        rows, cols = rows[order], cols[order]
        ptr = np.zeros(count + 1, np.int64)
        np.add.at(ptr, rows + 1, 1)
        self.ptr = np.cumsum(ptr).astype(np.int64)
        self.col = np.ascontiguousarray(cols, np.int64)
        self.diag = np.full(count, -1, np.int64)
        on_diag = rows == cols
        self.diag[rows[on_diag]] = np.nonzero(on_diag)[0]
        self._keys = rows * count + cols  # sorted: entry index of (row, col) by searchsorted
        self.count = count
        self.parent = np.zeros(count, np.int64)

    def entry(self, rows: np.ndarray, cols: np.ndarray) -> np.ndarray:
        return np.searchsorted(self._keys, rows * self.count + cols).astype(np.int64)


def edge_aggregates(model) -> list[np.ndarray]:
    """For each level, the aggregate of every structural edge (model.edges order): 2 × 2
    blocks of edges of one direction, 2 × 2 blocks of those on the next level, and so on
    while a level has at least MIN_AGGREGATES and is smaller than the one below."""
    e = model.edges
    kind = (e[:, 1] - e[:, 0] != 1).astype(np.int64)  # 0 along a row, 1 along a column
    r, c = np.divmod(e[:, 0], model.nx)
    out, last = [], len(e)
    for lvl in range(1, 32):
        _, agg = np.unique(np.stack([kind, r >> lvl, c >> lvl], axis=1), axis=0,
                           return_inverse=True)
        agg = agg.ravel().astype(np.int64)
        count = int(agg.max()) + 1 if len(agg) else 0
        if count < MIN_AGGREGATES or count >= last:
            break
        out.append(agg)
        last = count
    return out


class DualHierarchy:
    """The coarse corrections of the module docstring for one model's structural edges."""

    def __init__(self, model):
        self.model = model
        edges = model.edges
        self.aggregates = edge_aggregates(model)
        self.levels: list[AggregateLevel] = []
        self.normals = np.zeros((len(edges), 3))
        if not self.aggregates:
            return
        # every ordered pair of structural edges that share a particle: a term of A
        ends = np.concatenate([edges[:, 0], edges[:, 1]])
        which = np.concatenate([np.arange(len(edges))] * 2)
        sign = np.concatenate([-np.ones(len(edges)), np.ones(len(edges))])
        order = np.argsort(ends, kind="stable")
        ends, which, sign = ends[order], which[order], sign[order]
        starts = np.searchsorted(ends, np.arange(model.num_particles + 1))
        p_list, i_list, j_list, s_list = [], [], [], []
        degree = np.diff(starts)
        for d in range(1, int(degree.max()) + 1):  # particles with d edges, all at once
            ps = np.nonzero(degree == d)[0]
            if not len(ps):
                continue
            slots = starts[ps][:, None] + np.arange(d)[None, :]
            ii, jj = np.meshgrid(np.arange(d), np.arange(d), indexing="ij")
            a, b = slots[:, ii.ravel()], slots[:, jj.ravel()]
            p_list.append(np.repeat(ps, d * d))
            i_list.append(which[a].ravel())
            j_list.append(which[b].ravel())
            s_list.append((sign[a] * sign[b]).ravel())
        term_i = np.concatenate(i_list).astype(np.int64)
        term_j = np.concatenate(j_list).astype(np.int64)
        first = self.aggregates[0]
        self.levels.append(_level_of(first[term_i], first[term_j], int(first.max()) + 1))
        # each unordered pair once (A is symmetric; the diagonal is the edge's own)
        once = term_i < term_j
        self.term_particle = np.concatenate(p_list).astype(np.int64)[once]
        self.term_i, self.term_j = term_i[once], term_j[once]
        self.term_sign = np.concatenate(s_list)[once]
        ri, rj = first[self.term_i], first[self.term_j]
        self.term_entry = self.levels[0].entry(ri, rj)
        self.term_entry_t = self.levels[0].entry(rj, ri)
        self.diag_entry = self.levels[0].entry(first, first)
        self.entry_maps = []
        for finer, coarser in zip(self.aggregates, self.aggregates[1:]):
            parent = np.zeros(int(finer.max()) + 1, np.int64)
            parent[finer] = coarser
            below = self.levels[-1]
            self.levels[-1].parent = parent
            rows = np.repeat(np.arange(below.count), np.diff(below.ptr))
            pr, pc = parent[rows], parent[below.col]
            self.levels.append(_level_of(pr, pc, int(coarser.max()) + 1))
            self.entry_maps.append(self.levels[-1].entry(pr, pc))
        self._pack()

    def _pack(self) -> None:
        """The levels' arrays concatenated for coarse_correction."""
        lv = self.levels
        cat = np.concatenate
        self.row_off = np.cumsum([0] + [v.count for v in lv]).astype(np.int64)
        self.ptr_off = np.cumsum([0] + [v.count + 1 for v in lv]).astype(np.int64)
        self.entry_off = np.cumsum([0] + [len(v.col) for v in lv]).astype(np.int64)
        self.ptr = cat([v.ptr for v in lv]).astype(np.int64)
        self.col = cat([v.col for v in lv]).astype(np.int64)
        self.values = np.zeros(int(self.entry_off[-1]))
        self.diag = cat([v.diag for v in lv]).astype(np.int64)
        self.rhs = np.zeros(int(self.row_off[-1]))
        self.sol = np.zeros_like(self.rhs)
        self.parent = cat([v.parent for v in lv]).astype(np.int64)
        self.entry_map = cat(self.entry_maps + [np.zeros(len(lv[-1].col), np.int64)]
                             ).astype(np.int64)

    def correct(self, x, inv_mass, rest, alive, alpha_t, lam, edge_slot,
                assemble: bool = True) -> None:
        """One coarse correction of λ (slot order, the sweeps' scratch) and x; without
        `assemble`, with the matrices of the last one (the first of a substep assembles
        them: the edges turn little between its passes, and they only shape the
        correction, whose residual r is always the positions' now)."""
        if not self.levels:
            return
        coarse_correction(x, inv_mass, self.model.edges, rest, alive, alpha_t, lam, edge_slot,
                          self.normals, self.aggregates[0], self.term_particle, self.term_i,
                          self.term_j, self.term_sign, self.term_entry, self.term_entry_t,
                          self.diag_entry, assemble,
                          self.row_off, self.ptr_off, self.entry_off, self.ptr, self.col,
                          self.values, self.diag, self.rhs, self.sol, self.parent,
                          self.entry_map, PRE_SWEEPS, POST_SWEEPS, COARSEST_SWEEPS)

    def level_matrix(self, k: int) -> np.ndarray:
        """Level k's PᵀAP of the last correction, dense (for tests)."""
        n = self.levels[k].count
        e0, e1 = self.entry_off[k], self.entry_off[k + 1]
        ptr = self.ptr[self.ptr_off[k]:self.ptr_off[k + 1]]
        out = np.zeros((n, n))
        out[np.repeat(np.arange(n), np.diff(ptr)), self.col[e0:e1]] = self.values[e0:e1]
        return out


def _level_of(rows: np.ndarray, cols: np.ndarray, count: int) -> AggregateLevel:
    keys = np.unique(rows * count + cols)
    return AggregateLevel(keys // count, keys % count, count)
