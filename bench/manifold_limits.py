"""Where the quadratic-manifold model (``reduced-manifold``) stops being accurate (issue 27).

Two sweeps against the full nonlinear model, each with reduced-nonlinear (the same 30-vector
basis, nothing slaved) beside it, so the slaving's own error shows apart from the basis's:

- amplitude: the paper's deployment (lay-up 2, groove lock, ``--mesh``, ``--t-end`` s) with the
  hinge spring's preload tau0 scaled by 1, 2, 4, 8: the panel's whip bends node E from 21 % to 70 %
  of the panel's length. Node E's history error (RMS over the run on the full model's samples,
  relative to its peak) and the first lock's time against the full model's;
- spin-up: Kane, Ryan & Banerjee's beam (20 x 1 strip, 30 s) at omega_s = 2, 4, 6, 10 rad/s, the
  last three above the first bending frequency 3.80 rad/s where the linear model diverges: the
  tip history's RMS error relative to the full model's peak.

CPU times are the whole ``simulate`` call (time.process_time, one BLAS thread). No assertions:
tests/test_reduced_manifold.py and tests/test_spin_up_beam.py hold the bounds.

    python bench/manifold_limits.py [--mesh 6x4] [--t-end 6]
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse
import time

import numpy as np

import deployfx as dfx

MODELS = ("nonlinear", "reduced-nonlinear", "reduced-manifold")


def timed(run):
    start = time.process_time()
    result = run()
    return result, time.process_time() - start


def amplitude(nx: int, ny: int, t_end: float) -> None:
    print(f"amplitude: paper2016 lay-up 2, {nx}x{ny}, {t_end:g} s, dt = 0.01 s, tau0 scaled")
    print(f"{'tau0':>6s} {'model':18s} {'max|E| m':>9s} {'% of L':>7s} {'E rms err':>10s} {'first lock s':>13s} "
          f"{'lock err ms':>11s} {'cpu s':>6s}")
    for factor in (1.0, 2.0, 4.0, 8.0):
        runs = {}
        for model in MODELS:
            scene = dfx.scenes.paper2016(2, model, nx=nx, ny=ny, tau0=7.2 * factor)
            runs[model] = timed(lambda: scene.simulate(t_end, 0.01))
        ref = runs["nonlinear"][0]
        w_ref = ref.node_E_deflection.reshape(len(ref.t))
        peak = np.abs(w_ref).max()
        lock_ref = ref.summary(hinge=0)["first_lock_time_s"]
        for model, (r, cpu) in runs.items():
            w = np.interp(ref.t, r.t, r.node_E_deflection.reshape(len(r.t)))
            lock = r.summary(hinge=0)["first_lock_time_s"]
            err = np.sqrt(np.mean((w - w_ref) ** 2)) / peak
            print(f"{factor:6g} {model:18s} {np.abs(w).max():9.4f} {100 * np.abs(w).max() / dfx.paper2016.LENGTH:7.0f} "
                  f"{100 * err:9.3f}% {lock:13.6f} {1e3 * (lock - lock_ref):+11.3f} {cpu:6.2f}", flush=True)


def spin_up() -> None:
    print("spin-up: Kane et al.'s beam, 20 x 1 strip, T_s = 15 s, 30 s, dt = 0.01 s")
    print(f"{'omega_s':>7s} {'model':18s} {'max|tip| m':>10s} {'tip rms err':>11s} {'cpu s':>6s}")
    for omega in (2.0, 4.0, 6.0, 10.0):
        runs = {m: timed(lambda m=m: dfx.scenes.spin_up_beam(omega, model=m).simulate(30.0, 0.01)) for m in MODELS}
        tip_ref = runs["nonlinear"][0].tip_deflection[:, 0]
        peak = np.abs(tip_ref).max()
        for model, (r, cpu) in runs.items():
            tip = r.tip_deflection[:, 0]
            err = np.sqrt(np.mean((tip - tip_ref) ** 2)) / peak
            print(f"{omega:7g} {model:18s} {np.abs(tip).max():10.4f} {err:11.2e} {cpu:6.2f}", flush=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mesh", default="6x4", help="NXxNY of the amplitude sweep")
    ap.add_argument("--t-end", type=float, default=6.0, help="simulated time of the amplitude sweep (s)")
    args = ap.parse_args()
    nx, ny = (int(x) for x in args.mesh.lower().split("x"))
    amplitude(nx, ny, args.t_end)
    print()
    spin_up()


if __name__ == "__main__":
    main()
