"""Issue 27's speed targets against the least a step of this engine can cost (You et al. 2016,
lay-up 2, the paper's 30 s scene at dt = 0.01 s, generalized-alpha rho_inf = 0.8).

The targets (CPU time of one core): the full nonlinear 15 x 10 model in 4 s; the reduced
nonlinear model with 10 modes in 0.25 s; the quadratic-manifold model (``reduced-manifold``) in
60 ms. For each model, one timed run (the engine's ``_core.simulate``, no Python
post-processing, ``time.process_time``) and, through the bindings at the run's state at
``--t-eval``, the median CPU time of one residual and of the engine's own bordered solve of its
Newton matrix at that state (``_core.bordered_solve_cost``: the block LDL^T of the elastic block's
symmetric part with the Schur complement on the border for the full meshes, a dense LU for the
reduced models' modal block; the solve unrefined, as a Newton step with a kept matrix takes it).
With them, the bounds below which no run of this scheme can go:

- ``floor 1 it``: every integration step (``substeps``: output steps plus the event search's)
  converged by ONE Newton iteration with a kept matrix (one residual, one solve), and nothing
  else (no factorization, no event function, no output) costs anything;
- ``floor 2 it``: two such iterations, the least a step takes when Newton's convergence test
  reads a contraction rate from two increments (integrate/generalized_alpha.cpp) and the
  predictor misses by more than the tolerance (1e-10 of the accelerations), as it does after
  the lock's first impact;
- ``target / floor 1 it``: below 1, the target is out of reach of any Newton-based implicit step
  of this model at this step size, however fast its bookkeeping.

``fact ms`` is one numeric factorization of that matrix (its pattern analysed once) and
``exact ms`` one solve refined against the elastic block's skew part (a fresh matrix's step). Until
issue 27 the floor timed scipy's ``splu`` solve of M + beta h^2 K (126-140 us on 15 x 10), which the
engine never uses.

The rigid model's run (no elastic coordinates at all) is printed as what the engine's system
(base, hinge, lock, momentum rows, events, outputs) costs without an appendage; its residual's
time through the bindings is mostly the call's own (a few microseconds), so it has no floor.

No assertions: speed is measured here, not tested.

    python bench/targets.py [--t-end 30] [--mesh 15x10] [--models rigid reduced-nonlinear nonlinear]
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse
import time

import numpy as np
import scipy.sparse as sp

from deployfx import _core
from machine import describe
from newton_profile import RHO, profile

#: s of CPU time, for the 30 s scene (issue 27).
TARGETS = {"nonlinear": 4.0, "reduced-nonlinear": 0.25, "reduced-manifold": 0.060}


def engine_solve(S: np.ndarray, border: int) -> dict:
    """The engine's bordered solver on the Newton matrix S (dense, from the binding) with the
    first ``border`` coordinates (base, hinge) as its dense border: method and CPU seconds of one
    factorization, one solve and one refined solve (``_core.bordered_solve_cost``). The elastic
    block gets the engine's pattern: whole 6 x 6 node blocks, structurally symmetric, zeros
    stored (dropping the dense copy's zeros would leave a pattern the block LDL^T cannot group)."""
    A, B = S[:border, :border], S[:border, border:]
    C, Ed = S[border:, :border], S[border:, border:]
    n = Ed.shape[0]
    if n % 6 == 0 and n > 36:  # a mesh: its node blocks
        nodes = n // 6
        mask = np.abs(Ed).reshape(nodes, 6, nodes, 6).sum(axis=(1, 3)) > 0
        mask = np.kron(mask | mask.T, np.ones((6, 6), dtype=bool))
        rows, cols = np.nonzero(mask)
        E = sp.csc_matrix((Ed[rows, cols], (rows, cols)), shape=(n, n))
    else:  # a reduced model's modal block: dense
        E = sp.csc_matrix(np.where(Ed == 0, 0.0, Ed))
    r = np.random.default_rng(0).standard_normal(S.shape[0])
    return _core.bordered_solve_cost(np.ascontiguousarray(A), np.ascontiguousarray(B),
                                     np.ascontiguousarray(C), E, r, 0.3)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=30.0, help="simulated time (s); the target's 30")
    ap.add_argument("--dt", type=float, default=0.01, help="step (s)")
    ap.add_argument("--t-eval", type=float, default=15.0,
                    help="time of the state the evaluations use (s): after the lock by default")
    ap.add_argument("--mesh", default="15x10", help="NXxNY")
    ap.add_argument("--modes", type=int, default=10, help="the reduced model's clamped modes")
    models = ["rigid", "reduced-linear", "reduced-nonlinear", "reduced-manifold", "linear", "nonlinear"]
    ap.add_argument("--models", nargs="+", default=["rigid", "reduced-nonlinear", "reduced-manifold", "nonlinear"],
                    choices=models)
    args = ap.parse_args()
    nx, ny = (int(x) for x in args.mesh.lower().split("x"))
    print(f"paper2016 lay-up 2, {args.mesh}, t_end = {args.t_end:g} s, dt = {args.dt:g} s, "
          f"generalized-alpha rho_inf = {RHO}; evaluations at t = {args.t_eval:g} s; CPU time of one "
          f"core (time.process_time); {describe()}")
    print(f"{'model':18s} {'target s':>8s} {'cpu s':>8s} {'substeps':>8s} {'it/step':>7s} "
          f"{'res ms':>8s} {'solve ms':>8s} {'exact ms':>8s} {'fact ms':>8s} {'floor 1 it s':>12s} "
          f"{'floor 2 it s':>12s} {'cpu/floor1':>10s} {'target/floor1':>13s} solver")
    for model in args.models:
        target = TARGETS.get(model)
        m = profile(model, nx, ny, args.modes, args.t_end, args.dt, args.t_eval, True,
                    clock=time.process_time)
        substeps = m["wall"] / m["step"]
        line = (f"{model:18s} {(f'{target:g}' if target else '-'):>8s} {m['wall']:8.3f} "
                f"{substeps:8.0f} {m['its']:7.2f} {1e3 * m['res']:8.4f} ")
        if model == "rigid":
            line += (f"{'-':>8s} {'-':>8s} {'-':>8s} {'-':>12s} {'-':>12s} {'-':>10s} {'-':>13s} -")
        else:
            cost = engine_solve(m["state"]["S"], m["state"]["border"])
            floor1 = substeps * (m["res"] + cost["solve"])
            ratio = f"{target / floor1:13.2f}" if target else f"{'-':>13s}"
            line += (f"{1e3 * cost['solve']:8.4f} {1e3 * cost['solve_exact']:8.4f} "
                     f"{1e3 * cost['factorize']:8.4f} {floor1:12.3f} {2 * floor1:12.3f} "
                     f"{m['wall'] / floor1:10.1f} {ratio} {cost['method']}")
        print(line, flush=True)


if __name__ == "__main__":
    main()
