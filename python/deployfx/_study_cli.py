"""``deployfx study``: run a study file on Dask into a zarr store, and report on a store.

- ``deployfx study run study.toml --out study.zarr [--workers N] [--scheduler ADDR] [--threads]
  [--limit K] [--retry-failed] [--no-progress]``: runs the study (resuming a store that exists);
  exit status 0 when every sample computed, 1 when some failed (recorded in the store).
- ``deployfx study report study.zarr [--out DIR]``: prints the statistics of each output, the
  Sobol' indices (a study sampled with ``saltelli``) and the failed samples, and writes the
  scatter matrix, the histograms and the indices' bar chart as PNG files.

dask, xarray, zarr and SALib are imported when a subcommand runs (``pip install
"deployfx[study]"``), so the rest of the command line works without them.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np


def add_study_parser(sub) -> None:
    """Add the ``study`` subcommand to the ``deployfx`` parser's subparsers."""
    s = sub.add_parser("study", help="parameter studies on Dask: run a study file, report on a store")
    ss = s.add_subparsers(dest="study_command", required=True)
    r = ss.add_parser("run", help="run a study file into a zarr store (resumes an existing store)")
    r.add_argument("file", help="the study file (.toml or .json; docs/study.md)")
    r.add_argument("--out", required=True, help="the zarr store (a directory, e.g. study.zarr)")
    r.add_argument("--workers", type=int, help="workers of the embedded LocalCluster (default: "
                                               "one per core)")
    r.add_argument("--scheduler", help="address of a running Dask scheduler (e.g. tcp://head:8786) "
                                       "instead of the embedded cluster")
    r.add_argument("--threads", action="store_true",
                   help="embedded cluster: threads in one process instead of one process each")
    r.add_argument("--limit", type=int, help="run at most this many pending samples, then stop")
    r.add_argument("--retry-failed", action="store_true", help="run the failed samples again")
    r.add_argument("--no-progress", action="store_true", help="no progress bar")
    r.set_defaults(run=_run)
    p = ss.add_parser("report", help="statistics, Sobol' indices and figures of a study's store")
    p.add_argument("store", help="the study's zarr store")
    p.add_argument("--out", help="directory for the figures (default: STORE's name + '_report')")
    p.set_defaults(run=_report)


def _modules():
    try:
        from . import study
    except ImportError as e:  # pragma: no cover - the extra is part of the test environment
        raise RuntimeError(f"deployfx study needs the study extra: pip install \"deployfx[study]\" "
                           f"({e})") from e
    return study


def _run(args: argparse.Namespace) -> int:
    study = _modules()
    if args.scheduler and (args.workers or args.threads):
        raise ValueError("--scheduler runs on an existing cluster: --workers and --threads are for "
                         "the embedded one")
    st = study.load_study(args.file)
    print(f"{st!r} -> {args.out}", flush=True)
    ds = st.run(args.out, workers=args.workers, scheduler=args.scheduler,
                processes=not args.threads, progress=not args.no_progress, limit=args.limit,
                retry_failed=args.retry_failed)
    status = np.asarray(ds["status"].values)
    done, failed, pending = (int(np.sum(status == k)) for k in (1, 2, 0))
    print(f"{done} samples computed, {failed} failed, {pending} pending, in {args.out}")
    return 1 if failed else 0


def _report(args: argparse.Namespace) -> int:
    study = _modules()
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import pandas as pd

    from . import study_plot

    store = Path(args.store)
    ds = study.open(store).load()
    status = np.asarray(ds["status"].values)
    print(f"study {store}: {status.size} samples ({ds.attrs['sampler']}), parameters "
          f"{', '.join(ds.attrs['parameters'])}")
    with pd.option_context("display.width", 160, "display.max_columns", 20):
        print(study.statistics(ds).to_string(float_format=lambda v: f"{v:.6g}"))
    out = Path(args.out) if args.out else store.with_name(store.stem + "_report")
    out.mkdir(parents=True, exist_ok=True)
    written = []
    for name, fig in (("scatter_matrix.png", study_plot.scatter_matrix(ds)),
                      ("histograms.png", study_plot.histograms(ds))):
        fig.savefig(out / name, dpi=110)
        plt.close(fig)
        written.append(out / name)
    if ds.attrs["sampler"] == "saltelli":
        computed = []
        for o in ds.attrs["outputs"]:
            try:
                computed.append(study.sobol(ds, [o]))
            except ValueError as e:
                print(f"Sobol' indices of {o}: not computed: {e}")
        if computed:
            import xarray as xr

            idx = xr.concat(computed, dim="output")
            print("Sobol' indices (first order S1, total ST, +- half-width of the 95 % interval):")
            table = idx.to_dataframe().reset_index().set_index(["output", "parameter"])
            print(table.to_string(float_format=lambda v: f"{v:.4f}"))
            fig = study_plot.sobol_bars(idx)
            fig.savefig(out / "sobol_indices.png", dpi=110)
            plt.close(fig)
            written.append(out / "sobol_indices.png")
    failed = np.flatnonzero(status == 2)
    if failed.size:
        print(f"{failed.size} failed samples:")
        for i in failed[:10]:
            print(f"  sample {i}: {ds['error'].values[i]}")
        if failed.size > 10:
            print(f"  ... ({failed.size - 10} more in the store's 'error')")
    print(f"wrote {', '.join(str(p) for p in written)}")
    return 0
