"""Cost of the ply-stress envelope (deployfx.stress.envelope) per stored sample, against kernels
run in the same process (one thread) on the paper's appendage (2.0 x 1.3 m, lay-up 2):

- baseline 1: the Green-strain shell force and tangent of the whole mesh (ShellModel.internal_force,
  what one Newton iteration of the full nonlinear model assembles);
- baseline 2: the linear force K u (scipy sparse product).

Then, on a real run (the nonlinear paper scene, 6 x 4 mesh, 5 s at dt = 0.01 s, through the
lock's first impact), the envelope's wall time against the run's, and the run's peak ply
stresses (Pa; no failure index: deployfx has no allowables for IM6/SC1081, and the strengths
below are placeholders that only set the amount of arithmetic).

The displacement series of the timing rows are mixtures of the cantilever's first modes (any
series costs the same). Times are minima over repeats. No assertions: speed is measured here.

    python bench/ply_stress_bench.py [--samples 3000] [--repeat 3] [--no-run]
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import deployfx as dfx  # noqa: E402
from deployfx import stress  # noqa: E402
from machine import describe  # noqa: E402

# Placeholders that exercise every criterion; not a material's allowables.
PLACEHOLDER = dfx.Strengths(Xt=1.0e9, Xc=1.0e9, Yt=5.0e7, Yc=2.0e8, S12=7.0e7, S23=6.0e7)


def min_time(f, repeat: int) -> float:
    """Seconds: the fastest of ``repeat`` calls of ``f``."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def panel(nx: int, ny: int) -> dfx.Plate:
    ply = dfx.Orthotropic(E1=177e9, E2=10.8e9, G12=7.6e9, G13=7.6e9, G23=8.504e9, nu12=0.27,
                          rho=1600)
    return dfx.Plate(2.0, 1.3, dfx.Laminate.from_angles(ply, 0.5e-3, [0, 90, 90, 0]), nx, ny)


def series(plate: dfx.Plate, n: int) -> tuple[np.ndarray, np.ndarray]:
    _, modes = plate.model.modes(4, plate.fixed_dofs("CFFF"))
    t = np.linspace(0.0, 30.0, n)
    amp = np.array([np.sin(2 * np.pi * f * t) for f in (0.8, 2.1, 4.9, 7.3)]) * 0.05
    return t, (modes @ amp).T


def timing_rows(samples: int, repeat: int) -> None:
    print(f"{'mesh':>6} {'where':>9} {'strain':>7} {'criteria':>8} {'us/sample':>10} "
          f"{'/ force+tangent':>16} {'/ K u':>8}")
    for nx, ny in ((6, 4), (15, 10)):
        plate = panel(nx, ny)
        shell = plate.model
        t, U = series(plate, samples)
        u = U[samples // 2]
        K = shell.stiffness_matrix()
        t_force = min_time(lambda: shell.internal_force(u), 20 * repeat)
        t_ku = min_time(lambda: K @ u, 20 * repeat)
        for where in ("centroid", "gauss"):
            for strain in ("linear", "green"):
                for criteria in (["tsai_wu"], list(stress.CRITERIA)):
                    def call():
                        stress.envelope(shell, PLACEHOLDER, t, U, criteria=criteria, where=where,
                                        strain=strain)
                    dt = min_time(call, repeat) / samples
                    print(f"{nx:>3}x{ny:<2} {where:>9} {strain:>7} {len(criteria):>8} "
                          f"{dt * 1e6:>10.2f} "
                          f"{dt / t_force:>16.3f} {dt / t_ku:>8.1f}")


def mesh_dofs(model, q: np.ndarray) -> np.ndarray:
    """(n, ndof) mesh displacements from a run's raw q (as Model.node_displacements does)."""
    elastic = q[:, model.system.num_positions - model.system.num_elastic:]
    full = np.zeros((len(q), model.shell.num_dofs))
    full[:, model.free_dofs] = elastic
    return full


def run_row() -> None:
    scene = dfx.scenes.paper2016(2, "nonlinear", nx=6, ny=4)
    t0 = time.perf_counter()
    r = scene.simulate(5.0, 0.01, progress=False)
    t_run = time.perf_counter() - t0
    model = scene.model
    U = mesh_dofs(model, r.q)
    t0 = time.perf_counter()
    env = stress.envelope(model.shell, PLACEHOLDER, r.t, U, strain="green", where="gauss")
    t_env = time.perf_counter() - t0
    print(f"\npaper scene, nonlinear, 6 x 4, 5 s ({len(r.t)} samples): run {t_run:.2f} s, "
          f"envelope (4 criteria, Gauss points, Green) {t_env * 1e3:.1f} ms = "
          f"{t_env / t_run:.2%} of the run")
    peaks = np.zeros(5)
    where_ = [None] * 5
    for k, u in enumerate(U):
        s = stress.ply_stresses(model.shell, u, strain="green", where="gauss").stress
        a = np.abs(s).reshape(-1, 5).max(axis=0)
        for c in range(5):
            if a[c] > peaks[c]:
                peaks[c] = a[c]
                e, _, ply, st = np.unravel_index(np.argmax(np.abs(s[..., c])), s.shape[:4])
                where_[c] = (r.t[k], e, ply, st)
    for c, name in enumerate(stress.COMPONENTS):
        t, e, ply, st = where_[c]
        print(f"  peak |{name}| = {peaks[c] / 1e6:8.2f} MPa at t = {t:.3f} s, element {e}, "
              f"ply {ply}, "
              f"station {('bottom', 'middle', 'top')[st]}")
    print(f"  (placeholder strengths: critical element {env.critical_element}, "
          f"ply {env.critical_ply}, "
          f"t = {env.critical_time_s:.3f} s)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=3000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-run", action="store_true", help="skip the paper run")
    args = ap.parse_args()
    print(f"{describe()}; {args.samples} samples per series")
    timing_rows(args.samples, args.repeat)
    if not args.no_run:
        run_row()


if __name__ == "__main__":
    main()
