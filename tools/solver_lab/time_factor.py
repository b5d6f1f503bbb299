"""Time SciPy's sparse LU of the fabric matrix P = M/h² + K (per coordinate) on the clipped sheet:
factor once, solve (N, 3); the cost that bounds the lbfgs solver's iterations.

    OPENBLAS_NUM_THREADS=1 python tools/solver_lab/time_factor.py 32 64 128 256"""
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

sys.path.insert(0, "tools/solver_lab")
from common import simulation

from cloth_tui.sim.fabric.bending import bending_hessian

for cells in map(int, sys.argv[1:]):
    t0 = time.perf_counter()
    sim = simulation(cells)
    t1 = time.perf_counter()
    m, f, N = sim.model, sim.model.fabric, sim.model.num_particles
    h = 1 / 60
    e = m.edges
    k = 1 / np.asarray(f.compliance)
    rows = [np.arange(N), e[:, 0], e[:, 1], e[:, 0], e[:, 1]]
    cols = [np.arange(N), e[:, 1], e[:, 0], e[:, 0], e[:, 1]]
    vals = [m.mass / h**2, -k, -k, k, k]
    r, c, v = bending_hessian(f.stencils, f.material.bending, N)
    A = sp.coo_matrix((np.concatenate(vals + [v]),
                       (np.concatenate(rows + [r]), np.concatenate(cols + [c]))),
                      shape=(N, N)).tocsc()
    for spec in ("MMD_AT_PLUS_A", "COLAMD"):
        t2 = time.perf_counter()
        lu = sla.splu(A, permc_spec=spec, options={"SymmetricMode": True})
        t3 = time.perf_counter()
        b = np.random.rand(N, 3)
        for _ in range(3):
            t4 = time.perf_counter()
            lu.solve(b)
            t5 = time.perf_counter()
        print(cells, spec, f"build {t1 - t0:.2f}s factor {t3 - t2:.3f}s "
              f"solve3 {1e3 * (t5 - t4):.2f}ms nnzL+U {lu.L.nnz + lu.U.nnz}", flush=True)
