"""Measure a candidate on the clipped sheet: CPU ms a frame (process time: the machine is
shared), the settled centre sag against a reference, and the energy an undamped sheet loses
in 2 s as a share of its free energy (released flat; E_eq from a settled damped run).

    python tools/solver_lab/bench.py CANDIDATE CELLS [CELLS...]
CANDIDATE: lbfgs:IT:SUB (the registered solver), qn:IT:SUB[:THETA] (its prototype, qn.py,
with the θ-scheme), pd:IT:SUB[:RHO] (pd.py), xpbd:IT:SUB / hpbd:IT:SUB, or default:SOLVER
(4 substeps, adaptive).
Run with OPENBLAS_NUM_THREADS=1: a threaded BLAS spins on a shared 2-core machine."""
import sys
import time

import numpy as np

sys.path.insert(0, "tools/solver_lab")
from common import centre_height, simulation

try:
    from cloth_tui.sim.solvers.xpbd.fabric_constraints import fabric_energy
except ImportError:
    from cloth_tui.sim.fabric_solve import fabric_energy


def make(candidate, cells, damping=5.0, preset="denim"):
    kind, *rest = candidate.split(":")
    if kind == "default":
        return simulation(cells, solver=rest[0], substeps=4, iterations=4, adaptive=True,
                          damping=damping, preset=preset)
    it, sub = int(rest[0]), int(rest[1])
    if kind == "qn":
        from qn import QuasiNewtonFabric
        sim = simulation(cells, substeps=sub, iterations=1, damping=damping, preset=preset)
        theta = float(rest[2]) if len(rest) > 2 else 1.0
        swap(sim, QuasiNewtonFabric(sim.model, sim.step.h, it, theta=theta))
        return sim
    if kind == "lbfgs":
        sim = simulation(cells, solver="lbfgs", substeps=sub, iterations=it, damping=damping,
                         preset=preset)
        return sim
    if kind == "pd":
        from pd import ChebyshevPD
        sim = simulation(cells, substeps=sub, iterations=1, damping=damping, preset=preset)
        rho = float(rest[2]) if len(rest) > 2 else 0.95
        swap(sim, ChebyshevPD(sim.model, sim.step.h, it, rho=rho))
        return sim
    return simulation(cells, solver=kind, substeps=sub, iterations=it, damping=damping,
                      preset=preset)


def swap(sim, stage):
    """Put `stage` in place of the scene's fabric projection."""
    effects = sim.step.effects
    i = next(k for k, e in enumerate(effects) if e.name.startswith("project_fabric"))
    effects[i] = stage
    return sim


def total_energy(sim):
    m, x, v = sim.model, sim.state.x, sim.state.v
    ke = 0.5 * float((m.mass[:, None] * v * v).sum())
    pe = 9.81 * float((m.mass * x[:, 1]).sum())
    return ke + pe + sum(fabric_energy(x, m).values())


def timing(candidate, cells, frames=60, settle=60, preset="denim"):
    sim = make(candidate, cells, preset=preset)
    for _ in range(settle):
        sim.advance_frame()
    times = []
    for _ in range(frames):
        t0 = time.process_time()
        sim.advance_frame()
        times.append(time.process_time() - t0)
    return 1e3 * np.median(times), 1e3 * (np.percentile(times, 90) - np.percentile(times, 10))


def sag(candidate, cells, seconds=4.0, preset="denim"):
    sim = make(candidate, cells, preset=preset)
    for _ in range(int(seconds * 60)):
        sim.advance_frame()
    return 1 - centre_height(sim), total_energy(sim)


def energy_loss(candidate, cells, e_eq, seconds=2.0, preset="denim"):
    sim = make(candidate, cells, damping=0.0, preset=preset)
    e0 = total_energy(sim)
    for _ in range(int(seconds * 60)):
        sim.advance_frame()
    return (e0 - total_energy(sim)) / (e0 - e_eq)


if __name__ == "__main__":
    cand = sys.argv[1]
    what = sys.argv[2]
    preset = sys.argv[3]
    for cells in map(int, sys.argv[4:]):
        if what == "time":
            ms, spread = timing(cand, cells, preset=preset)
            print(f"{cand} {preset} {cells}: {ms:.2f} ms/frame (p10-p90 {spread:.2f})", flush=True)
        elif what == "sag":
            s, e = sag(cand, cells, preset=preset)
            print(f"{cand} {preset} {cells}: sag {s:.5f} E_settled {e:.6f}", flush=True)
        elif what.startswith("energy"):
            e_eq = float(what.split("=")[1])
            loss = energy_loss(cand, cells, e_eq, preset=preset)
            print(f"{cand} {preset} {cells}: energy loss 2 s {100 * loss:.1f} %", flush=True)
