"""Speed of the paper's 150-element appendage model: assembly and the first 10 cantilever modes.

Prints a table of median wall times with ratios against baselines run in the same process on the
same matrices (scipy's ARPACK shift-invert ``eigsh`` and LAPACK's dense ``eigh``), so a noisy
machine still gives meaningful ratios. No assertions: speed is measured here, not tested.

    python bench/modal_bench.py [--repeat 20] [--nx 15 --ny 10] [--modes 10]
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np
import scipy.linalg
import scipy.sparse.linalg

import deployfx as dfx


def median_time(fn, repeat: int):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=20)
    ap.add_argument("--nx", type=int, default=15)
    ap.add_argument("--ny", type=int, default=10)
    ap.add_argument("--modes", type=int, default=10)
    ap.add_argument("--layup", type=int, default=2)
    args = ap.parse_args()
    n = args.modes

    t_asm, plate = median_time(lambda: dfx.paper2016.appendage_plate(args.layup, args.nx, args.ny),
                               args.repeat)
    t_modes, f = median_time(lambda: plate.natural_frequencies(n, "CFFF"), args.repeat)

    free = np.setdiff1d(np.arange(plate.model.num_dofs), plate.fixed_dofs("CFFF"))
    K = plate.model.stiffness_matrix()[free][:, free].tocsc()
    M = plate.model.mass_matrix()[free][:, free].tocsc()

    def arpack():
        lam = scipy.sparse.linalg.eigsh(K, k=n, M=M, sigma=0.0, which="LM", return_eigenvectors=True)[0]
        return np.sort(np.sqrt(lam)) / (2 * np.pi)

    Kd, Md = K.toarray(), M.toarray()

    def dense():
        lam = scipy.linalg.eigh(Kd, Md, subset_by_index=[0, n - 1], eigvals_only=False)[0]
        return np.sqrt(lam) / (2 * np.pi)

    t_arpack, f_arpack = median_time(arpack, args.repeat)
    t_dense, f_dense = median_time(dense, max(3, args.repeat // 5))

    print(f"appendage lay-up {args.layup}: {args.nx} x {args.ny} elements, {plate.model.num_dofs} dofs "
          f"({len(free)} free), {n} modes, median of {args.repeat} runs")
    print(f"{'step':44s} {'time (ms)':>10s} {'vs ARPACK':>10s} {'max |df|/f vs ARPACK':>21s}")
    rows = [
        ("deployfx assembly (mesh, K, M)", t_asm, None),
        ("deployfx modes (shift-invert Lanczos)", t_modes, f),
        ("deployfx assembly + modes", t_asm + t_modes, None),
        ("baseline: scipy eigsh (ARPACK, shift-invert)", t_arpack, f_arpack),
        ("baseline: scipy eigh (dense LAPACK)", t_dense, f_dense),
    ]
    for name, t, freq in rows:
        acc = "" if freq is None else f"{np.max(np.abs(freq - f_arpack) / f_arpack):.1e}"
        print(f"{name:44s} {1e3 * t:10.2f} {t / t_arpack:10.3f} {acc:>21s}")
    print("(dense LAPACK loses digits to the stiffness spread: thin-plate rotations are stiff and light)")


if __name__ == "__main__":
    main()
