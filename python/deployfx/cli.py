"""Command line: ``deployfx appendage`` (modal analysis of the paper's appendage).

The deployment simulation of You et al. (2016) (``deployfx run paper2016``) arrives with the
multibody engine; until then the CLI exposes the structural model it will use.
"""
from __future__ import annotations

import argparse
import csv
import sys
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from . import paper2016


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
        with open(out / "appendage_frequencies.csv", "w", newline="") as fh:
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
    fig.savefig(path, dpi=110)
    plt.close(fig)


def build_parser() -> argparse.ArgumentParser:
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
    return p


def main(argv: Optional[Sequence[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except (ValueError, TypeError, RuntimeError) as e:
        print(f"deployfx: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
