"""Cost of the paper's scene (You et al. 2016, lay-up 2) for the rigid, reduced (10 modes; the
quadratic-manifold model on the reduced nonlinear basis among them), linear and nonlinear models.

Each row is one ``paper2016(...).simulate(t_end, dt)`` run (the rigid and reduced ones: the
median of 5, they are cheap). Columns:

- ``dofs``: the appendage's elastic coordinates in the model (free dofs, the Ritz basis's size,
  or on the manifold its bending part; 0 for the rigid one);
- ``setup (s)``: compiling the scene (mesh, basis, modal coefficients; once per model);
- ``wall (s)``, ``s/sim s``: the engine's wall time of the run (metadata ``wall_time_s``), and
  per simulated second;
- ``ms/step``: wall time per integration step taken (``substeps``: output steps plus the extra
  steps of event location and error control); ``newton/step``, ``fact/step``: Newton iterations
  and factorizations of the iteration matrix per step;
- ``vs rigid``: the per-step cost over the rigid model's on the same mesh, run in the same
  process, so a noisy machine still gives meaningful ratios;
- ``vs floor``: the per-step cost over ONE forward/backward solve with the sparse LU of the
  elastic block S_E = M + beta h^2 K of the same mesh (scipy ``splu``, median of many), the floor
  of issue 6: a flexible step can hardly cost less than one such solve;
- ``lock (s)``: the summary's first lock time (the paper: 2.46 s), so the accuracy each model buys
  is read next to its cost ("-" when the run ends before the lock).

No assertions: speed is measured here, not tested.

    python bench/paper_bench.py [--quick] [--t-end 5] [--dt 0.01] [--meshes 4x2 6x4 15x10]
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import scipy.sparse.linalg

import deployfx as dfx
from deployfx.integrators import SimulationError
from machine import describe

MODELS = ("rigid", "reduced-linear", "reduced-nonlinear", "reduced-manifold", "linear", "nonlinear")
MODES = 10  # the reduced models' clamped modes (issue 6's target case)
BETA = 0.3  # Newmark beta of generalized-alpha at rho_inf = 0.8 is 0.309; the pattern is what costs


def solve_floor(nx: int, ny: int, h: float, repeat: int = 200) -> tuple[int, float]:
    """(free dofs, median seconds of one ``lu.solve``) for the appendage's elastic block."""
    plate = dfx.paper2016.appendage_plate(2, nx, ny)
    free = np.setdiff1d(np.arange(plate.model.num_dofs), plate.fixed_dofs("CFFF"))
    S = plate.model.mass_matrix() + BETA * h ** 2 * plate.model.stiffness_matrix()
    lu = scipy.sparse.linalg.splu(S.tocsr()[free][:, free].tocsc())
    b = np.random.default_rng(0).standard_normal(len(free))
    batch = 20  # solves per timing, so the timer's resolution does not matter
    times = []
    for _ in range(repeat // batch):
        t0 = time.perf_counter()
        for _ in range(batch):
            lu.solve(b)
        times.append((time.perf_counter() - t0) / batch)
    return len(free), statistics.median(times)


def run(model: str, nx: int, ny: int, t_end: float, dt: float) -> dict:
    """One timed run (the median of 5 for the cheap models); metadata plus dofs and lock time."""
    kw = dict(modes=MODES) if model.startswith("reduced") else {}
    t0 = time.perf_counter()
    scene = dfx.scenes.paper2016(layup=2, model=model, nx=nx, ny=ny, **kw)
    dofs = scene.model.layout(0)["num_elastic"]
    setup = time.perf_counter() - t0
    results = []
    for _ in range(1 if model in ("linear", "nonlinear") else 5):
        try:
            r, failure = scene.simulate(t_end, dt), ""
        except SimulationError as e:
            r, failure = e.result, "failed"
        results.append((r.metadata["wall_time_s"], r, failure))
    _, r, failure = sorted(results, key=lambda x: x[0])[len(results) // 2]
    out = r.metadata
    out.update(dofs=dofs, setup=setup, lock=r.summary(hinge=0).get("first_lock_time_s"), note=failure,
               t_sim=float(r.t[-1]))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="4x2 and 6x4 only, t_end = 3 s")
    ap.add_argument("--t-end", type=float, default=None, help="simulated time (s); default 5 (3 quick)")
    ap.add_argument("--dt", type=float, default=0.01, help="output step (s)")
    ap.add_argument("--meshes", nargs="+", default=None, help="NXxNY; default 4x2 6x4 15x10")
    ap.add_argument("--models", nargs="+", default=list(MODELS), choices=MODELS)
    args = ap.parse_args()
    t_end = args.t_end if args.t_end is not None else (3.0 if args.quick else 5.0)
    meshes = args.meshes or (["4x2", "6x4"] if args.quick else ["4x2", "6x4", "15x10"])
    models = ["rigid"] + [m for m in args.models if m != "rigid"]  # the baseline runs first

    print(f"paper2016 lay-up 2, t_end = {t_end:g} s, dt = {args.dt:g} s, generalized-alpha rho_inf = 0.8; "
          f"{describe()}")
    head = (f"{'model':17s} {'mesh':>6s} {'dofs':>5s} {'setup (s)':>9s} {'wall (s)':>9s} {'s/sim s':>8s} {'ms/step':>8s} "
            f"{'newton/step':>11s} {'fact/step':>9s} {'vs rigid':>9s} {'vs floor':>9s} {'lock (s)':>8s}")
    print(head)
    for mesh in meshes:
        nx, ny = (int(v) for v in mesh.lower().split("x"))
        n_free, t_floor = solve_floor(nx, ny, args.dt)
        rigid_step = None
        for model in models:
            m = run(model, nx, ny, t_end, args.dt)
            n = max(m["substeps"], 1)
            step = m["wall_time_s"] / n
            rigid_step = step if model == "rigid" else rigid_step
            lock = "-" if m["lock"] is None else f"{m['lock']:.3f}"
            if model in args.models:
                print(f"{model:17s} {mesh:>6s} {m['dofs']:5d} {m['setup']:9.3f} {m['wall_time_s']:9.3f} "
                      f"{m['wall_time_s'] / max(m['t_sim'], 1e-12):8.3f} {1e3 * step:8.3f} "
                      f"{m['newton_iterations'] / n:11.2f} {m['factorizations'] / n:9.3f} "
                      f"{step / rigid_step:9.1f} {step / t_floor:9.1f} {lock:>8s} {m['note']}")
        print(f"{'floor':17s} {mesh:>6s} {n_free:5d} one splu solve of S_E = M + {BETA:g} h^2 K: "
              f"{1e3 * t_floor:.4f} ms")


if __name__ == "__main__":
    main()
