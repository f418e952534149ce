"""Speed of deployfx.study on Dask (issue 26): samples per second of one study run as a plain
loop in this process, on 1 and 2 worker processes and on 2 threads of one process; and the
per-sample overhead of Dask against the plain loop, measured on a study whose runs do nothing.

    python bench/study_bench.py [--samples 32] [--model linear] [--t-end 5]

Every configuration runs the same study (the paper's scene, lay-up 2, 4 x 2 mesh, its spring,
clearance and friction varied over a Latin hypercube) into a fresh zarr store; the cluster is
started, and deployfx imported on its workers, before the clock starts (reported apart). Ratios
are against one worker process, measured in the same run. The issue asks for >= 1.7x with two workers on two idle
cores; on a machine shared with other jobs the ratio says more about the neighbours.
"""
from __future__ import annotations

import argparse
import importlib
import logging
import os
import shutil
import tempfile
import time
from pathlib import Path

import deployfx as dfx
from deployfx import study


class _Nothing:
    def simulate(self, t_end, dt):
        return dfx.Result({"t": [0.0, t_end], "x": [0.0, 0.0]})


def nothing(x: float = 0.0) -> _Nothing:
    """A 'scene' whose run does nothing: its study's time is the per-sample overhead."""
    return _Nothing()


def paper_study(samples: int, model: str, t_end: float) -> study.Study:
    return study.Study(dfx.scenes.paper2016, fixed={"layup": 2, "model": model, "nx": 4, "ny": 2},
                       vary={"tau0": study.Uniform(6.84, 7.56), "k_theta": study.Uniform(4.35, 4.81),
                             "clearance": study.Uniform(1e-4, 3e-4),
                             "friction.mu": study.Uniform(0.15, 0.35)},
                       samples=samples, sampler="lhs", outputs=["first_lock_time_s", "peak_lock_force_N"],
                       series=["deployment_angle"], t_end=t_end, dt=0.01)


def loop(st: study.Study) -> float:
    t0 = time.perf_counter()
    for i in range(st.size):
        st.run_sample(i)
    return time.perf_counter() - t0


def on_dask(st: study.Study, store: Path, workers: int, processes: bool) -> tuple[float, float]:
    """(cluster start-up s, study run s) on a fresh LocalCluster."""
    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    kw = (dict(n_workers=workers, threads_per_worker=1) if processes
          else dict(n_workers=1, threads_per_worker=workers))
    with LocalCluster(processes=processes, dashboard_address=None, silence_logs=logging.ERROR,
                      **kw) as cluster, Client(cluster) as client:
        client.wait_for_workers(kw["n_workers"])
        client.run(importlib.import_module, "deployfx.study")  # as the loop, imports done
        t1 = time.perf_counter()
        st.run(store, client=client, progress=False)
        t2 = time.perf_counter()
    shutil.rmtree(store)
    return t1 - t0, t2 - t1


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--samples", type=int, default=32)
    p.add_argument("--model", default="linear")
    p.add_argument("--t-end", type=float, default=5.0)
    p.add_argument("--overhead-samples", type=int, default=256)
    args = p.parse_args()
    st = paper_study(args.samples, args.model, args.t_end)
    tmp = Path(tempfile.mkdtemp(prefix="study_bench_"))
    print(f"study: paper2016 {args.model} 4 x 2, {args.t_end:g} s, {st.size} samples; "
          f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}")
    st.run_sample(0)  # warm the imports
    rows = [("plain loop, this process", 0.0, loop(st))]
    for label, workers, processes in (("Dask, 1 worker process", 1, True),
                                      ("Dask, 2 worker processes", 2, True),
                                      ("Dask, 2 threads, 1 process", 2, False)):
        start, run = on_dask(st, tmp / "s.zarr", workers, processes)
        rows.append((label, start, run))
    base = rows[1][2]
    print(f"{'configuration':30s} {'start-up s':>10s} {'run s':>8s} {'samples/s':>10s} "
          f"{'vs 1 worker':>11s}")
    for label, start, run in rows:
        print(f"{label:30s} {start:10.2f} {run:8.2f} {st.size / run:10.2f} {base / run:10.2f}x")
    # per-sample overhead: a study of runs that do nothing, plain loop against one worker
    n = args.overhead_samples
    empty = study.Study(nothing, vary={"x": study.Uniform(0.0, 1.0)}, samples=n, sampler="lhs",
                        outputs={"x_final": "final(x)"}, t_end=1.0, dt=1.0)
    t_loop = loop(empty)
    _, t_proc = on_dask(empty, tmp / "e.zarr", 1, True)
    _, t_thread = on_dask(empty, tmp / "e.zarr", 1, False)
    print(f"per-sample overhead ({n} runs that do nothing): plain loop {1e3 * t_loop / n:.2f} ms, "
          f"Dask 1 worker process {1e3 * t_proc / n:.2f} ms, Dask 1 thread {1e3 * t_thread / n:.2f} ms "
          f"(store writes included)")
    per_sample = (rows[1][2] - rows[0][2]) / st.size
    print(f"Dask against the plain loop on the paper's study, 1 worker: "
          f"{1e3 * per_sample:+.1f} ms per sample ({rows[0][2] / st.size * 1e3:.1f} ms per run)")
    shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
