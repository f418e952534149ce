"""Modified Newton's reuse of a dense iteration matrix, per model (issue 27: "refactor less, a
contraction-based reuse policy per fidelity, measured").

The rigid and reduced models factorize a dense iteration matrix (the border and the modal block).
Newton keeps it while the iterations contract by at least ``contraction_dense`` per iteration
(integrate::NewtonOptions; ``_core.CONTRACTION_DENSE_DEFAULT``: 0.03 since session 20, 0.01
before) and forms a fresh one otherwise. This script runs the paper scene (lay-up 2, 30 s at
dt = 0.01 s, generalized-alpha rho_inf = 0.8) at several thresholds: CPU of the engine's run
(``_core.simulate``, ``time.process_time``, one core), median of ``--repeat`` runs alternated in
one process, and its ratio to the 0.01 run (the baseline); Newton iterations and factorizations;
and how far the run moves from the 0.01 run (largest difference of the hinge angle, rad: every
run meets the same Newton tolerance, so only differences of that size are expected). The default
is marked ``*``.

A looser threshold accepts more steps near the tolerance with a kept matrix, whose last increment
leaves an error of the tolerance's size (a fresh matrix's leaves its square), and that error has a
sign: a second table runs tests/test_extremes.py's energy scene (the rigid panel on the free base,
no lock, undamped, generalized-alpha rho_inf = 1, 1000 s at dt = 0.01 s) at each threshold and
prints max |E(t) - E(0)| over the peak kinetic energy (the test holds it below 1e-6).

    python bench/newton_reuse.py [--models rigid reduced-linear reduced-linear:nolock reduced-nonlinear]
                                 [--contractions 0.01 0.03 0.1 0.3 0.6] [--t-end 30] [--repeat 3]

No assertions: speed is measured here, not tested.
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse
import statistics
import time

import numpy as np

import deployfx as dfx
from deployfx import _core
from deployfx.integrators import GeneralizedAlpha

BASELINE = 0.01


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", nargs="+", default=["rigid", "reduced-linear", "reduced-linear:nolock", "reduced-nonlinear"],
                    help="MODEL or MODEL:nolock (the stop-and-latch scene without its lock, bench/vs_exudyn.py's)")
    ap.add_argument("--contractions", nargs="+", type=float, default=[0.01, 0.03, 0.1, 0.3, 0.6])
    ap.add_argument("--mesh", default="15x10")
    ap.add_argument("--t-end", type=float, default=30.0)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    nx, ny = (int(k) for k in args.mesh.split("x"))
    values = [BASELINE] + [c for c in args.contractions if c != BASELINE]
    scheme = GeneralizedAlpha(0.8)._params()
    print(f"paper2016 lay-up 2, {args.mesh}, t_end = {args.t_end:g} s, dt = 0.01 s, rho_inf = 0.8; CPU: median of "
          f"{args.repeat} runs alternated in one process; * the default")
    print(f"{'model':<24}{'contraction':>12}{'cpu s':>9}{'vs 0.01':>9}{'newton':>8}{'fact':>7}{'angle diff':>12}")
    for spec in args.models:
        model, _, variant = spec.partition(":")
        lock = variant != "nolock"
        extra = {} if lock else {"lock": False, "lock_geometry": "stop-latch"}
        core = dfx.scenes.paper2016(2, model, nx=nx, ny=ny, **extra).model.core
        q0, v0 = core.initial_positions(), np.zeros(core.num_velocities)
        cpu = {c: [] for c in values}
        raw = {}
        for _ in range(args.repeat):
            for c in values:
                start = time.process_time()
                raw[c] = _core.simulate(core, q0, v0, t_end=args.t_end, dt=0.01, scheme=scheme, contraction_dense=c)
                cpu[c].append(time.process_time() - start)
        base = statistics.median(cpu[BASELINE])
        for c in values:
            r, m = raw[c], statistics.median(cpu[c])
            angle = np.max(np.abs(r["theta"][:, 0] - raw[BASELINE]["theta"][:, 0])) if len(r["t"]) == len(raw[BASELINE]["t"]) else np.nan
            mark = "*" if c == _core.CONTRACTION_DENSE_DEFAULT else " "
            print(f"{spec:<24}{c:>11g}{mark}{m:>9.3f}{m / base:>9.2f}{int(np.sum(r['newton_iterations'])):>8}"
                  f"{int(r['factorizations']):>7}{angle:>12.1e}")
    print("\nrigid, no lock, undamped, rho_inf = 1, 1000 s (tests/test_extremes.py's energy scene)")
    print(f"{'contraction':>12}{'energy error / peak KE':>24}{'newton':>8}{'fact':>7}")
    core = dfx.scenes.paper2016(2, "rigid", nx=2, ny=1, lock=False, lock_geometry="stop-latch").model.core
    q0, v0 = core.initial_positions(), np.zeros(core.num_velocities)
    for c in values:
        r = _core.simulate(core, q0, v0, t_end=1000.0, dt=0.01, scheme=GeneralizedAlpha(1.0)._params(),
                           contraction_dense=c)
        E = r["kinetic_energy"] + r["potential_energy"]
        drift = np.max(np.abs(E - E[0])) / np.max(r["kinetic_energy"])
        mark = "*" if c == _core.CONTRACTION_DENSE_DEFAULT else " "
        print(f"{c:>11g}{mark}{drift:>24.2e}{int(np.sum(r['newton_iterations'])):>8}{int(r['factorizations']):>7}")


if __name__ == "__main__":
    main()
