"""Issue 6's speed targets against the least a step of this engine can cost (You et al. 2016,
lay-up 2, the paper's 30 s scene at dt = 0.01 s, generalized-alpha rho_inf = 0.8).

The targets: the full nonlinear 15 x 10 model in 1 s; the reduced nonlinear model with 10 modes in
20 ms. For each model, one timed run (the engine's wall time) and, through the bindings at the
run's state at ``--t-eval``, the median cost of one residual; with the cost of one solve of the
Newton matrix (the full models: scipy ``splu`` of the elastic block S_E = M + beta h^2 K, issue
6's floor, as in bench/newton_profile.py; the others: a dense LU solve of their matrix), the
bounds below which no run of this scheme can go:

- ``floor 1 it``: every integration step (``substeps``: output steps plus the event search's)
  converged by ONE Newton iteration with a kept matrix (one residual, one solve), and nothing
  else (no factorization, no event function, no output) costs anything;
- ``floor 2 it``: two such iterations, the least a step takes when Newton's convergence test
  reads a contraction rate from two increments (integrate/generalized_alpha.cpp) and the
  predictor misses by more than the tolerance (1e-10 of the accelerations), as it does after
  the lock's first impact;
- ``target / floor 1 it``: below 1, the target is out of reach of any Newton-based implicit step
  of this model at this step size, however fast its bookkeeping.

The rigid model's run (no elastic coordinates at all) is printed as what the engine's system
(base, hinge, lock, momentum rows, events, outputs) costs without an appendage; its residual's
time through the bindings is mostly the call's own (a few microseconds), so it has no floor.

No assertions: speed is measured here, not tested.

    python bench/targets.py [--t-end 30] [--mesh 15x10] [--models rigid reduced-nonlinear nonlinear]
"""
from __future__ import annotations

import argparse

import numpy as np
import scipy.linalg

import deployfx as dfx
from deployfx.integrators import GeneralizedAlpha
from newton_profile import RHO, profile, solve_floor, timed

TARGETS = {"nonlinear": 1.0, "reduced-nonlinear": 0.020}  # s, for the 30 s scene (issue 6)


def dense_solve(model: str, nx: int, ny: int, modes: int, dt: float, columns: int = 2000) -> float:
    """Seconds of one LU solve with the model's (dense) Newton matrix at rest: the median of a
    solve with ``columns`` right-hand sides at once, per column (one column's call would time
    scipy's argument checks, not the solve)."""
    scene = dfx.scenes.paper2016(layup=2, model=model, nx=nx, ny=ny, modes=modes)
    sys = scene.model.core
    p = GeneralizedAlpha(RHO)._params()
    c = (1 - p.alpha_f) / (1 - p.alpha_m)
    n = sys.num_velocities
    S = sys.newton_matrix(sys.initial_positions(), np.zeros(n), np.zeros(n), 0.0, 1.0,
                          p.gamma * dt * c, p.beta * dt * dt * c)
    lu = scipy.linalg.lu_factor(S)
    B = np.random.default_rng(0).standard_normal((n, columns))
    return timed(lambda: scipy.linalg.lu_solve(lu, B)) / columns


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=30.0, help="simulated time (s); the target's 30")
    ap.add_argument("--dt", type=float, default=0.01, help="step (s)")
    ap.add_argument("--t-eval", type=float, default=15.0,
                    help="time of the state the evaluations use (s): after the lock by default")
    ap.add_argument("--mesh", default="15x10", help="NXxNY")
    ap.add_argument("--modes", type=int, default=10, help="the reduced model's clamped modes")
    ap.add_argument("--models", nargs="+", default=["rigid", "reduced-nonlinear", "nonlinear"],
                    choices=["rigid", "reduced-linear", "reduced-nonlinear", "linear", "nonlinear"])
    args = ap.parse_args()
    nx, ny = (int(x) for x in args.mesh.lower().split("x"))
    beta = GeneralizedAlpha(RHO)._params().beta
    print(f"paper2016 lay-up 2, {args.mesh}, t_end = {args.t_end:g} s, dt = {args.dt:g} s, "
          f"generalized-alpha rho_inf = {RHO}; evaluations at t = {args.t_eval:g} s; "
          f"core built for {dfx._core.simd}")
    print(f"{'model':18s} {'target s':>8s} {'wall s':>8s} {'substeps':>8s} {'it/step':>7s} "
          f"{'res ms':>8s} {'solve ms':>8s} {'floor 1 it s':>12s} {'floor 2 it s':>12s} "
          f"{'wall/floor1':>11s} {'target/floor1':>13s}")
    sparse_solve = None
    for model in args.models:
        m = profile(model, nx, ny, args.modes, args.t_end, args.dt, args.t_eval, True)
        if model in ("linear", "nonlinear"):
            if sparse_solve is None:
                sparse_solve = solve_floor(nx, ny, args.dt, beta)
            solve = sparse_solve
        else:
            solve = dense_solve(model, nx, ny, args.modes, args.dt)
        substeps = m["wall"] / m["step"]
        target = TARGETS.get(model)
        line = (f"{model:18s} {(f'{target:g}' if target else '-'):>8s} {m['wall']:8.3f} "
                f"{substeps:8.0f} {m['its']:7.2f} {1e3 * m['res']:8.4f} {1e3 * solve:8.4f} ")
        if model == "rigid":
            line += f"{'-':>12s} {'-':>12s} {'-':>11s} {'-':>13s}"
        else:
            floor1 = substeps * (m["res"] + solve)
            ratio = f"{target / floor1:13.2f}" if target else f"{'-':>13s}"
            line += f"{floor1:12.3f} {2 * floor1:12.3f} {m['wall'] / floor1:11.1f} {ratio}"
        print(line, flush=True)


if __name__ == "__main__":
    main()
