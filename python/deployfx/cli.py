"""Command line for deployfx.

- ``deployfx run paper2016 --layup 2 --model nonlinear --t-end 30 --dt 0.01 --out DIR``: the
  deployment and locking of You et al. (2016); writes ``summary.json``, ``timeseries.csv`` (one
  per model) and the paper's figures; ``--model both`` overlays linear and nonlinear; ``--json``
  prints the summary; ``--model reduced-nonlinear --modes 10`` runs a reduced appendage.
- ``deployfx run spin-up-beam --omega-s 4``: the spin-up beam of Kane, Ryan & Banerjee (1987).
- ``deployfx appendage``: modes of the paper's laminated appendage.

Every file is written atomically (deployfx._atomic): a run that is killed while writing leaves the
previous file as it was, never a partial one.
"""
from __future__ import annotations

import argparse
import csv
import json
import sys
import tempfile
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from . import _atomic, paper2016
from .integrators import SimulationError


def _appendage(args: argparse.Namespace) -> int:
    plate = paper2016.appendage_plate(args.layup, args.nx, args.ny)
    angles = "/".join(f"{a:g}" for a in paper2016.LAYUPS[args.layup])
    f, w = plate.modes(args.modes, "CFFF")
    print(f"You et al. (2016) appendage, lay-up {args.layup} [{angles}], "
          f"{paper2016.LENGTH} m x {paper2016.WIDTH} m x {plate.laminate.thickness * 1e3:g} mm, "
          f"{args.nx} x {args.ny} MITC4 shell elements")
    print(f"mass: {plate.mass:.4f} kg")
    print("cantilever natural frequencies (root edge x = 0 clamped):")
    print(" mode    f (Hz)")
    for k, fk in enumerate(f, 1):
        print(f"{k:5d} {fk:9.4f}")
    if args.out:
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        with _atomic.atomic_open(out / "appendage_frequencies.csv", "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(["mode", "frequency_Hz"])
            writer.writerows([k, f"{fk:.8g}"] for k, fk in enumerate(f, 1))
        png = out / "appendage_modes.png"
        _plot_modes(plate, f, w, png)
        print(f"wrote {out / 'appendage_frequencies.csv'} and {png}")
    return 0


def _plot_modes(plate, f: np.ndarray, w: np.ndarray, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    n = min(6, len(f))
    cols = 3 if n > 2 else n
    rows = -(-n // cols)
    fig, axes = plt.subplots(rows, cols, figsize=(4.0 * cols + 1.0, 2.9 * rows + 0.6),
                             squeeze=False, layout="constrained")
    for k, ax in enumerate(axes.flat):
        if k >= n:
            ax.axis("off")
            continue
        shape = w[k] / np.abs(w[k]).max()
        cs = ax.contourf(plate.x, plate.y, shape, levels=np.linspace(-1, 1, 21), cmap="RdBu_r")
        ax.set_title(f"mode {k + 1}: {f[k]:.3f} Hz")
        ax.set_aspect("equal")
        if k // cols == rows - 1:
            ax.set_xlabel("x (m), clamped root at x = 0")
        if k % cols == 0:
            ax.set_ylabel("y (m)")
    fig.colorbar(cs, ax=axes.ravel().tolist(), shrink=0.8, label="normalised w")
    fig.suptitle("Cantilever modes of the laminated appendage (transverse displacement)")
    with _atomic.atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=110)
    plt.close(fig)


def _write_csv(result, path: Path) -> None:
    """The run's series as CSV columns: scalars as they are, per-hinge series one column per hinge
    (``name[k]``), 3-vectors one per component (``name_x``); the raw coordinates and mesh fields
    are left to Result.save."""
    from .results import PER_HINGE_SERIES

    df_cols = []
    for name in result.series:
        if name in ("q", "v") or name.startswith("node_displacements"):
            continue
        a = result[name]
        unit = result.units.get(name, "")
        if a.ndim == 1:
            df_cols.append((f"{name} ({unit})", a))
        elif name in PER_HINGE_SERIES:
            for k in range(a.shape[1]):
                if a.ndim == 2:
                    df_cols.append((f"{name}[{k}] ({unit})", a[:, k]))
                else:
                    for j, axis in enumerate("xyz"):
                        df_cols.append((f"{name}[{k}]_{axis} ({unit})", a[:, k, j]))
        elif a.ndim == 2 and a.shape[1] == 3:  # vectors (attitude, momenta): one column each
            for j, axis in enumerate("xyz"):
                df_cols.append((f"{name}_{axis} ({unit})", a[:, j]))
        # fields over the mesh (node displacements) and raw coordinates are saved by Result.save
    with _atomic.atomic_open(path, "w", newline="") as fh:
        writer = csv.writer(fh)
        writer.writerow([c for c, _ in df_cols])
        for k in range(len(result.t)):
            writer.writerow([f"{a[k]:.10g}" for _, a in df_cols])


def _format(value) -> str:
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, list):
        return "[" + ", ".join(_format(v) for v in value) + "]"
    return str(value)


def _run(args: argparse.Namespace) -> int:
    from . import scenes

    results, labels = [], []
    if args.scene == "paper2016":
        models = ("linear", "nonlinear") if args.model == "both" else (args.model,)
        for model in models:
            extra = {} if args.damping is None else {"damping": tuple(args.damping)}
            scene = scenes.paper2016(args.layup, model, nx=args.nx, ny=args.ny, modes=args.modes, **extra)
            if not args.json:
                print(f"paper2016 lay-up {args.layup}, {model} model, {args.nx} x {args.ny} mesh: "
                      f"{args.t_end:g} s at dt = {args.dt:g} s ...", flush=True)
            try:
                results.append(scene.simulate(args.t_end, args.dt))
            except SimulationError as e:
                print(f"deployfx: {model} run stopped: {e}", file=sys.stderr)
                results.append(e.result)
            labels.append(model if not model.startswith("reduced") else f"{model}-{args.modes}")
    else:
        scene = scenes.spin_up_beam(args.omega_s, args.t_s, args.model if args.model != "both" else "nonlinear")
        try:
            results.append(scene.simulate(args.t_end, args.dt))
        except SimulationError as e:
            print(f"deployfx: run stopped: {e}", file=sys.stderr)
            results.append(e.result)
        labels.append(str(scene.model.fidelities[0]))
    summaries = {label: r.summary() for label, r in zip(labels, results)}
    summary = summaries[labels[0]] if len(labels) == 1 else summaries
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        for label, s in summaries.items():
            print(f"{label}:")
            for key, value in s.items():
                print(f"  {key}: {_format(value)}")
    if args.out:
        from . import plot

        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        _atomic.write_text(out / "summary.json", json.dumps(summary, indent=2) + "\n")
        for label, r in zip(labels, results):
            _write_csv(r, out / (f"timeseries_{label}.csv" if len(labels) > 1 else "timeseries.csv"))
        if args.scene == "paper2016":
            # Drawn into a temporary directory beside the figures, then each renamed into place.
            with tempfile.TemporaryDirectory(dir=out, prefix=".figures-") as tmp:
                paths = [out / p.name for p in plot.paper_figures(results, tmp, labels=labels)]
                for p in paths:
                    _atomic.replace(Path(tmp) / p.name, p)
        else:
            fig = plot.node_deflection(results, labels=labels, series="tip_deflection")
            paths = [out / "tip_deflection.png"]
            with _atomic.atomic_path(paths[0]) as tmp:
                fig.savefig(tmp, dpi=150)
        if not args.json:
            print(f"wrote {out / 'summary.json'}, the time series and {len(paths)} figures")
    failed = [r for r in results if r.failure]
    return 1 if failed else 0


def build_parser() -> argparse.ArgumentParser:
    """The ``deployfx`` command's parser: subcommands ``appendage`` and ``run`` (see the module
    docstring); the parsed namespace's ``run`` is the function that executes the subcommand."""
    p = argparse.ArgumentParser(prog="deployfx", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    a = sub.add_parser("appendage", help="modes of the paper's laminated appendage")
    a.add_argument("--layup", type=int, choices=(1, 2), default=2,
                   help="1: [0/0/0/0], 2: [0/90/90/0] (default 2)")
    a.add_argument("--nx", type=int, default=paper2016.NX, help="elements along the 2.0 m length")
    a.add_argument("--ny", type=int, default=paper2016.NY, help="elements across the 1.3 m width")
    a.add_argument("--modes", type=int, default=10, help="number of modes (default 10)")
    a.add_argument("--out", help="directory for appendage_frequencies.csv and appendage_modes.png")
    a.set_defaults(run=_appendage)

    r = sub.add_parser("run", help="simulate a ready scene: paper2016 or spin-up-beam")
    r.add_argument("scene", choices=("paper2016", "spin-up-beam"))
    r.add_argument("--model", choices=("rigid", "linear", "nonlinear", "reduced-linear", "reduced-nonlinear", "both"),
                   default="nonlinear",
                   help="appendage fidelity; both = linear and nonlinear overlaid (default nonlinear)")
    r.add_argument("--modes", type=int, default=10,
                   help="paper2016, reduced models: clamped vibration modes in the basis (default 10)")
    r.add_argument("--layup", type=int, choices=(1, 2), default=2, help="paper2016: 1 [0/0/0/0], 2 [0/90/90/0]")
    r.add_argument("--nx", type=int, default=paper2016.NX, help="paper2016: elements along the length")
    r.add_argument("--ny", type=int, default=paper2016.NY, help="paper2016: elements across the width")
    r.add_argument("--damping", type=float, nargs=2, metavar=("ALPHA_M", "BETA_K"),
                   help="paper2016: the appendage's Rayleigh damping, alpha_M (1/s) and beta_K (s); "
                        "default 0.7 0 (7 %% at the first mode); 0 0: the paper's undamped equations")
    r.add_argument("--omega-s", type=float, default=4.0, help="spin-up-beam: final hub rate, rad/s")
    r.add_argument("--t-s", type=float, default=15.0, help="spin-up-beam: spin-up time, s")
    r.add_argument("--t-end", type=float, default=30.0, help="simulated time, s (default 30)")
    r.add_argument("--dt", type=float, default=0.01, help="output and maximum step, s (default 0.01)")
    r.add_argument("--out", help="directory for summary.json, the time series (CSV) and the figures")
    r.add_argument("--json", action="store_true", help="print the summary as JSON on stdout")
    r.set_defaults(run=_run)
    from ._study_cli import add_study_parser  # deployfx study run/report (issue 26)

    add_study_parser(sub)
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Run the ``deployfx`` command on ``argv`` (None: ``sys.argv[1:]``) and return its exit
    status: 0 on success, 1 if a run stopped early (what it computed is still reported and
    written), 2 for a bad parameter (ValueError, TypeError or RuntimeError; the message goes to
    standard error). A malformed command line exits with status 2 from argparse."""
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except (ValueError, TypeError, RuntimeError) as e:
        print(f"deployfx: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
