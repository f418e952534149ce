"""Cost of the compiled kernels a nonlinear step repeats, against numpy/scipy baselines run in the
same process (one thread), for the paper's appendage (lay-up 2):

- the full model's Green-strain shell force and tangent (every element, assembled), against the
  linear model's force K u (scipy sparse product): what a nonlinear residual and matrix cost in
  linear forces;
- the full model's nine floating-frame products M_ij z (body/floating_frame_inertia: every
  d-dependent inertia integral is built from them, several times per Newton iteration), against
  scipy's nine sparse products with the same matrices: the core reads each pair M_ij, M_ji =
  M_ij^T once;
- the reduced model's modal force and tangent (fem/modal_internal_force: the quartic term is a
  symmetric product with the (r (r + 1) / 2)^2 coefficient matrix), against numpy's product with a
  dense symmetric matrix of that size (OpenBLAS dgemv, which picks its kernel for the CPU at run
  time): how close the compiled core comes to a tuned BLAS on the same arithmetic.

The header names the vector instructions the core was compiled for (CMake option
DEPLOYFX_NATIVE). Times are the minimum over many calls, the least noisy estimate of a kernel's
own cost. No assertions: speed is measured here, not tested.

    python bench/kernel_bench.py [--nx 15 --ny 10] [--modes 10] [--repeat 200]
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

import deployfx as dfx  # noqa: E402
from deployfx import _core  # noqa: E402
from machine import describe  # noqa: E402


def min_time(f, repeat: int) -> float:
    """Seconds: the fastest of ``repeat`` calls of ``f``."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - t0)
    return best


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--nx", type=int, default=15)
    ap.add_argument("--ny", type=int, default=10)
    ap.add_argument("--modes", type=int, default=10)
    ap.add_argument("--repeat", type=int, default=200)
    args = ap.parse_args()

    scene = dfx.scenes.paper2016(2, "reduced-nonlinear", nx=args.nx, ny=args.ny, modes=args.modes)
    shell = scene.model.shells[0]
    Phi = np.asarray(scene.model.basis(0))
    r = Phi.shape[1]
    rng = np.random.default_rng(0)
    eta = 1e-2 * rng.standard_normal(r)
    u = Phi @ eta  # a deflected panel: the nonlinear terms are not zero
    K = shell.stiffness_matrix().tocsr()

    t_shell = min_time(lambda: shell._impl.internal_force(u), max(10, args.repeat // 4))
    t_linear = min_time(lambda: K @ u, args.repeat)

    ffi = shell.floating_frame_inertia()
    Mij = [ffi.Mij(i, j).tocsr() for i in range(3) for j in range(3)]
    # A new z each call, as for the modal force below: the core keeps its last few products.
    shifts = [0]

    def products() -> None:
        shifts[0] += 1
        z = u.copy()
        z[-1] += 1e-12 * shifts[0]
        ffi.products(z)

    t_products = min_time(products, args.repeat)
    t_scipy9 = min_time(lambda: [M @ u for M in Mij], args.repeat)

    modal = _core.ModalInternalForce(shell._impl, Phi, True)
    calls = [0]

    def modal_force() -> None:  # a new eta each call: the kernel memoizes its last one
        calls[0] += 1
        e = eta.copy()
        e[0] += 1e-12 * calls[0]
        modal.internal_force(e)

    t_modal = min_time(modal_force, args.repeat)
    n_pairs = r * (r + 1) // 2
    B = rng.standard_normal((n_pairs, n_pairs))
    B = B + B.T
    x = rng.standard_normal(n_pairs)
    t_gemv = min_time(lambda: B @ x, args.repeat)

    print(f"paper2016 lay-up 2 appendage, {args.nx} x {args.ny} elements, {shell.num_dofs} dofs; "
          f"reduced basis of {r} vectors ({args.modes} modes); {describe()}; "
          f"minimum of up to {args.repeat} calls")
    print(f"{'kernel':58s} {'time (us)':>10s} {'vs baseline':>12s}")
    rows = [
        ("full model: Green-strain force + tangent (assembled)", t_shell, t_linear),
        ("  baseline: linear force K u (scipy sparse)", t_linear, t_linear),
        ("full model: floating-frame products M_ij z (all nine)", t_products, t_scipy9),
        ("  baseline: nine scipy sparse products M_ij z", t_scipy9, t_scipy9),
        (f"reduced model: modal force + tangent (r = {r})", t_modal, t_gemv),
        (f"  baseline: numpy B x, B dense {n_pairs} x {n_pairs}", t_gemv, t_gemv),
    ]
    for name, t, base in rows:
        print(f"{name:58s} {1e6 * t:10.1f} {t / base:12.2f}")


if __name__ == "__main__":
    main()
