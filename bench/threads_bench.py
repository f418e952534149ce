"""Runs sharing one compiled model in threads (issue 23): two threads simulating the same
``deployfx.Model`` at once against the same two runs one after the other, in one process.

The model is immutable and each run has its own data (lock histories, memos), and the engine
releases the GIL for the whole run, so on two idle cores the two threads should take about half
the serial wall time (``parallel / serial`` near 0.5; 1.0 would mean the runs take turns). The
threads' results are checked bit for bit against the serial ones (a correctness check, not a
timing one). Each row is the median of ``--repeat`` measurements.

    python bench/threads_bench.py [--models rigid reduced-nonlinear nonlinear] [--t-end 5] [--mesh 6x4]

No assertions on time: speed is measured here, not tested.
"""
from __future__ import annotations

import argparse
import statistics
import threading
import time

import numpy as np

import deployfx as dfx
from machine import describe


def serial(model, t_end: float, dt: float) -> tuple[float, list]:
    start = time.perf_counter()
    results = [model.simulate(t_end, dt, progress=False) for _ in range(2)]
    return time.perf_counter() - start, results


def parallel(model, t_end: float, dt: float) -> tuple[float, list]:
    results = [None, None]

    def run(i: int) -> None:
        results[i] = model.simulate(t_end, dt, progress=False)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    start = time.perf_counter()
    for th in threads:
        th.start()
    for th in threads:
        th.join()
    return time.perf_counter() - start, results


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--models", nargs="+", default=["rigid", "reduced-nonlinear", "nonlinear"])
    ap.add_argument("--mesh", default="6x4", help="NXxNY")
    ap.add_argument("--t-end", type=float, default=5.0, help="simulated time of each run (s)")
    ap.add_argument("--dt", type=float, default=0.01, help="step (s)")
    ap.add_argument("--repeat", type=int, default=3, help="measurements per row (median)")
    args = ap.parse_args()
    nx, ny = (int(x) for x in args.mesh.lower().split("x"))
    print(f"paper2016 lay-up 2, {nx}x{ny}, t_end = {args.t_end:g} s, dt = {args.dt:g} s; two runs of one model; "
          f"{describe()}")
    print(f"{'model':18s} {'serial (s)':>10s} {'2 threads (s)':>13s} {'parallel/serial':>15s} {'same bits':>9s}")
    for name in args.models:
        model = dfx.scenes.paper2016(2, name, nx=nx, ny=ny).model
        model.simulate(min(args.t_end, 0.1), args.dt, progress=False)  # warm up (imports, first-call costs)
        s_times, p_times, same = [], [], True
        for _ in range(args.repeat):
            ts, rs = serial(model, args.t_end, args.dt)
            tp, rp = parallel(model, args.t_end, args.dt)
            s_times.append(ts)
            p_times.append(tp)
            same &= all(np.array_equal(a[k], b[k]) for a, b in zip(rs, rp) for k in a.series)
        s, p = statistics.median(s_times), statistics.median(p_times)
        print(f"{name:18s} {s:10.3f} {p:13.3f} {p / s:15.2f} {str(same):>9s}")


if __name__ == "__main__":
    main()
