"""Newton's tolerance as a trade knob (issue 27): what a looser convergence test saves and how far
it moves the outputs, on the paper scene (lay-up 2, groove lock, dt = 0.01 s).

For each model, the scene is run at each ``newton_tolerance`` (``Model.simulate``; the engine's
default is 1e-10) and against the same run converged at 1e-12 in the same process. Columns: CPU
time of the run (``time.process_time``, one core) and its ratio to the default tolerance's run,
measured alternately ``--repeat`` times (median); Newton iterations and factorizations; the
largest difference from the 1e-12 run of the hinge angle before the lock (t < 2.3 s, rad) and of
node E's deflection over the whole run (m); the first lock time and located peak lock force.

    python bench/newton_tolerance.py [--models reduced-linear:15x10 reduced-nonlinear:6x4 nonlinear:6x4]
                                     [--tolerances 1e-10 1e-8 1e-6 1e-4] [--t-end 30] [--repeat 3]

No assertions: the trade is measured here; tests/test_newton_tolerance.py tests the convergence.
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse
import statistics
import time

import numpy as np

from deployfx import scenes

REFERENCE = 1e-12


def run(scene, t_end: float, tol: float):
    start = time.process_time()
    r = scene.simulate(t_end, 0.01, newton_tolerance=tol, progress=False)
    return time.process_time() - start, r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", nargs="+", default=["reduced-linear:15x10", "reduced-nonlinear:6x4", "nonlinear:6x4"],
                    help="MODEL:NXxNY")
    ap.add_argument("--tolerances", nargs="+", type=float, default=[1e-10, 1e-8, 1e-6, 1e-4])
    ap.add_argument("--t-end", type=float, default=30.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    tols = [1e-10] + [t for t in args.tolerances if t != 1e-10]
    print(f"paper2016 lay-up 2, dt = 0.01 s, t_end = {args.t_end:g} s; reference: newton_tolerance = "
          f"{REFERENCE:g}; CPU: median of {args.repeat} alternating runs")
    print(f"{'model':<24}{'newton tol':>11}{'cpu s':>8}{'vs 1e-10':>9}{'newton':>8}{'fact':>7}"
          f"{'angle diff':>12}{'node E diff':>12}{'first lock s':>14}{'peak N':>10}")
    for spec in args.models:
        model, mesh = spec.split(":")
        nx, ny = (int(k) for k in mesh.split("x"))
        scene = scenes.paper2016(2, model, nx=nx, ny=ny)
        _, ref = run(scene, args.t_end, REFERENCE)
        cpu = {t: [] for t in tols}
        results = {}
        for _ in range(args.repeat):
            for t in tols:
                c, results[t] = run(scene, args.t_end, t)
                cpu[t].append(c)
        base = statistics.median(cpu[1e-10])
        before = ref.t < 2.3
        for t in tols:
            r = results[t]
            angle = np.abs(np.interp(ref.t[before], r.t, r.deployment_angle[:, 0]) - ref.deployment_angle[before, 0])
            node_E = np.abs(np.interp(ref.t, r.t, r.node_E_deflection) - ref.node_E_deflection)
            s = r.summary()
            c = statistics.median(cpu[t])
            print(f"{spec:<24}{t:>11.0e}{c:>8.3f}{c / base:>9.2f}{r.metadata['newton_iterations']:>8d}"
                  f"{r.metadata['factorizations']:>7d}{np.deg2rad(angle.max()):>12.2e}{node_E.max():>12.2e}"
                  f"{s['first_lock_time_s'][0]:>14.7f}{s['peak_lock_force_N'][0]:>10.1f}", flush=True)


if __name__ == "__main__":
    main()
