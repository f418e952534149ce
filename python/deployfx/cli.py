"""Command line for deployfx (``deployfx --version``; ``deployfx run --help`` shows every default).

- ``deployfx run paper2016 --layup 2 --model nonlinear --t-end 30 --dt 0.01 --out DIR``: the
  deployment and locking of You et al. (2016); writes ``summary.json`` (the summary's metrics and
  the run's ``settings``: Result.settings and the command), ``timeseries.csv`` (one per model)
  and the paper's figures; ``--model both`` overlays linear and nonlinear; ``--json`` prints the
  summary; ``--model reduced-nonlinear --modes 10`` runs a reduced appendage,
  ``--model reduced-manifold`` the same basis with its in-plane coordinates slaved to the bending
  ones (deployfx.specs.Fidelity).
- ``deployfx run spin-up-beam --omega-s 4``: the spin-up beam of Kane, Ryan & Banerjee (1987).
- ``deployfx run SCENE.toml``: a scene file (deployfx.save_scene, TOML or JSON).
- ``deployfx appendage``: modes of the paper's laminated appendage.

A run that cannot give what was asked (``--t-end`` or ``--dt`` not > 0, an output directory that
cannot be written, an unknown scene) is refused before it starts, exit status 2. A ``--dt`` that
does not resolve the scene's periods (deployfx.resolution) warns on standard error with the
period and a step that resolves it; lock contacts need no step of their own (the engine resolves
each contact whatever ``dt``).

Every file is written atomically (deployfx._atomic): a run that is killed while writing leaves the
previous file as it was, never a partial one.
"""
from __future__ import annotations

import argparse
import csv
import hashlib
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


#: The ready scenes ``deployfx run`` knows by name; anything else is a scene file's path.
READY_SCENES = ("paper2016", "spin-up-beam")
#: s: the default output and maximum step (``--dt``); the spin-up beam's resolves its beam's ten
#: kept modes (deployfx.resolution: 57 Hz, 4 steps a period).
DEFAULT_DT = {"paper2016": 0.01, "spin-up-beam": 0.002, "file": 0.01}
#: The options that shape a ready scene, with their defaults: a scene file holds its own.
_SCENE_OPTIONS = {"model": "nonlinear", "modes": 10, "layup": 2, "nx": paper2016.NX, "ny": paper2016.NY,
                  "damping": None, "lock_geometry": "groove", "omega_s": 4.0, "t_s": 15.0}


def _check_run(args: argparse.Namespace) -> None:
    """Refuse, before any work, a run that cannot give what was asked: ValueError naming the
    option. Sets ``args.dt`` to its scene's default when not given."""
    kind = args.scene if args.scene in READY_SCENES else "file"
    if kind == "file":
        path = Path(args.scene)
        if path.suffix.lower() not in (".toml", ".json"):
            raise ValueError(f"scene = {args.scene!r} is invalid: must be {' or '.join(READY_SCENES)}, or a "
                             f"scene file (.toml or .json, deployfx.save_scene)")
        if not path.is_file():
            raise ValueError(f"scene = {args.scene!r}: no such scene file")
        given = [k for k, default in _SCENE_OPTIONS.items() if getattr(args, k) != default]
        if given:
            raise ValueError(f"--{given[0].replace('_', '-')} shapes a ready scene; a scene file holds its own "
                             f"(edit the file, or build it with deployfx.Scene)")
    if args.dt is None:
        args.dt = DEFAULT_DT[kind]
    for name, value in (("t-end", args.t_end), ("dt", args.dt)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"--{name} = {value:g} is out of range: must be > 0 (s)")
    if args.out:
        _check_writable(Path(args.out))


def _check_writable(out: Path) -> None:
    """Create ``out`` and write a file in it, or ValueError naming ``--out``."""
    try:
        out.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=out):
            pass
    except OSError as e:
        raise ValueError(f"--out = {str(out)!r} cannot be written: {e.strerror or e}") from e


def _scenes(args: argparse.Namespace) -> list:
    """(label, scene) pairs to run: a ready scene (one per model with ``--model both``) or the
    scene file's compiled Model."""
    from . import scene_file, scenes

    if args.scene == "paper2016":
        extra = {"lock_geometry": args.lock_geometry}
        if args.damping is not None:
            extra["damping"] = tuple(args.damping)
        models = ("linear", "nonlinear") if args.model == "both" else (args.model,)
        return [(model if not model.startswith("reduced") else f"{model}-{args.modes}",
                 scenes.paper2016(args.layup, model, nx=args.nx, ny=args.ny, modes=args.modes, **extra))
                for model in models]
    if args.scene == "spin-up-beam":
        models = ("linear", "nonlinear") if args.model == "both" else (args.model,)
        return [(model, scenes.spin_up_beam(args.omega_s, args.t_s, model)) for model in models]
    path = Path(args.scene)
    digest = hashlib.sha256(path.read_bytes()).hexdigest()
    model = scene_file.load_scene(path).compile(
        description={"scene": str(path), "parameters": {"scene_file": str(path.resolve()), "sha256": digest}})
    return [(path.stem, model)]


def _run(args: argparse.Namespace) -> int:
    from . import resolution

    _check_run(args)
    runs = _scenes(args)
    for message in dict.fromkeys(resolution.step_warning(scene, args.dt) for _, scene in runs):
        if message:
            print(f"deployfx: warning: {message}", file=sys.stderr)
    results, labels = [], []
    for label, scene in runs:
        if not args.json:
            print(f"{args.scene}, {label}: {args.t_end:g} s at dt = {args.dt:g} s ...", flush=True)
        try:
            results.append(scene.simulate(args.t_end, args.dt))
        except SimulationError as e:
            print(f"deployfx: {label} run stopped: {e}", file=sys.stderr)
            results.append(e.result)
        labels.append(label)
    command = ["deployfx"] + getattr(args, "argv", [])
    summaries = {label: dict(r.summary(), settings=dict(r.settings(), command=command))
                 for label, r in zip(labels, results)}
    summary = summaries[labels[0]] if len(labels) == 1 else summaries
    if args.json:
        print(json.dumps(summary, indent=2))
    else:
        for label, s in summaries.items():
            print(f"{label}:")
            for key, value in s.items():
                if key != "settings":
                    print(f"  {key}: {_format(value)}")
            print("  settings: " + ", ".join(f"{k} {_format(v)}" for k, v in s["settings"].items()
                                             if k not in ("parameters", "command")))
    if args.out:
        out = Path(args.out)
        _atomic.write_text(out / "summary.json", json.dumps(summary, indent=2) + "\n")
        for label, r in zip(labels, results):
            _write_csv(r, out / (f"timeseries_{label}.csv" if len(labels) > 1 else "timeseries.csv"))
        # Drawn into a temporary directory beside the figures, then each renamed into place.
        with tempfile.TemporaryDirectory(dir=out, prefix=".figures-") as tmp:
            paths = [out / p.name for p in _figures(args.scene, results, labels, Path(tmp))]
            for p in paths:
                _atomic.replace(Path(tmp) / p.name, p)
        if not args.json:
            print(f"wrote {out / 'summary.json'}, the time series and {len(paths)} figures")
    failed = [r for r in results if r.failure]
    return 1 if failed else 0


def _figures(scene: str, results: list, labels: list, out: Path) -> list[Path]:
    """The run's figures as PNG files in ``out``: the paper's six for paper2016; for another
    scene those of what it has (deployment angle; lock force with a lock; tip deflection with a
    deforming panel; momentum and attitude with a free base)."""
    from . import plot

    if scene == "paper2016":
        return plot.paper_figures(results, out, labels=labels)
    meta = results[0].metadata
    hinges = meta.get("hinges", [])
    figures = [("deployment_angle.png", plot.deployment_angle)]
    if any(h.get("lock") for h in hinges):
        figures.append(("lock_force.png", plot.lock_force))
    if any(h.get("fidelity") not in (None, "rigid") for h in hinges):
        figures.append(("tip_deflection.png",
                        lambda rs, labels: plot.node_deflection(rs, labels, series="tip_deflection")))
    if meta.get("base_free"):
        figures += [("body_angular_momentum.png", plot.angular_momentum), ("body_attitude.png", plot.body_attitude)]
    paths = []
    for name, draw in figures:
        draw(results, labels).savefig(out / name, dpi=150)
        paths.append(out / name)
    return paths


class _HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Shows each option's default, except where there is none (None) or it is a flag."""

    def _get_help_string(self, action):
        if action.default is None or isinstance(action.default, bool):
            return action.help
        return super()._get_help_string(action)


def build_parser() -> argparse.ArgumentParser:
    """The ``deployfx`` command's parser: subcommands ``appendage`` and ``run`` (see the module
    docstring); the parsed namespace's ``run`` is the function that executes the subcommand."""
    from . import __version__

    p = argparse.ArgumentParser(prog="deployfx", description=__doc__.splitlines()[0])
    p.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    a = sub.add_parser("appendage", help="modes of the paper's laminated appendage", formatter_class=_HelpFormatter)
    a.add_argument("--layup", type=int, choices=(1, 2), default=2, help="1: [0/0/0/0], 2: [0/90/90/0]")
    a.add_argument("--nx", type=int, default=paper2016.NX, help="elements along the 2.0 m length")
    a.add_argument("--ny", type=int, default=paper2016.NY, help="elements across the 1.3 m width")
    a.add_argument("--modes", type=int, default=10, help="number of modes")
    a.add_argument("--out", help="directory for appendage_frequencies.csv and appendage_modes.png")
    a.set_defaults(run=_appendage)

    r = sub.add_parser("run", help="simulate paper2016, spin-up-beam or a scene file", formatter_class=_HelpFormatter,
                       description=_RUN_DESCRIPTION)
    r.add_argument("scene", help="paper2016, spin-up-beam, or a scene file (.toml or .json, "
                                 "deployfx.save_scene)")
    r.add_argument("--model", choices=("rigid", "linear", "nonlinear", "reduced-linear", "reduced-nonlinear",
                                       "reduced-manifold", "both"),
                   default=_SCENE_OPTIONS["model"],
                   help="appendage fidelity; both = linear and nonlinear overlaid (spin-up-beam: linear or nonlinear)")
    r.add_argument("--modes", type=int, default=_SCENE_OPTIONS["modes"],
                   help="paper2016, reduced models: clamped vibration modes in the basis")
    r.add_argument("--layup", type=int, choices=(1, 2), default=_SCENE_OPTIONS["layup"],
                   help="paper2016: 1 [0/0/0/0], 2 [0/90/90/0]")
    r.add_argument("--nx", type=int, default=_SCENE_OPTIONS["nx"], help="paper2016: elements along the length")
    r.add_argument("--ny", type=int, default=_SCENE_OPTIONS["ny"], help="paper2016: elements across the width")
    r.add_argument("--damping", type=float, nargs=2, metavar=("ALPHA_M", "BETA_K"),
                   help="paper2016: the appendage's Rayleigh damping, alpha_M (1/s) and beta_K (s); "
                        "default 0.7 0 (7 %% at the first mode); 0 0: the paper's undamped equations")
    r.add_argument("--lock-geometry", choices=("groove", "stop-latch"), default=_SCENE_OPTIONS["lock_geometry"],
                   help="paper2016: the lock, the pin riding a groove into its notch (Eq. 45) or "
                        "stop-and-latch walls in the hinge angle")
    r.add_argument("--omega-s", type=float, default=_SCENE_OPTIONS["omega_s"],
                   help="spin-up-beam: final hub rate, rad/s")
    r.add_argument("--t-s", type=float, default=_SCENE_OPTIONS["t_s"], help="spin-up-beam: spin-up time, s")
    r.add_argument("--t-end", type=float, default=30.0, help="simulated time, s (> 0)")
    r.add_argument("--dt", type=float,
                   help=f"output and maximum step, s (> 0); default {DEFAULT_DT['paper2016']:g} "
                        f"(spin-up-beam {DEFAULT_DT['spin-up-beam']:g}); a step that does not resolve the "
                        f"scene's periods warns, with the step that does; lock contacts need no step of "
                        f"their own")
    r.add_argument("--out", help="directory for summary.json, the time series (CSV) and the figures")
    r.add_argument("--json", action="store_true", help="print the summary as JSON on stdout")
    r.set_defaults(run=_run)
    from ._study_cli import add_study_parser  # deployfx study run/report (issue 26)

    add_study_parser(sub)
    return p


_RUN_DESCRIPTION = """Simulate a scene and report what it measures (summary.json with the run's
settings, the time series, figures). A step that does not resolve the scene (fewer than 20 steps
a period of a swing on the hinge springs, or 4 of a panel's highest kept mode; deployfx.resolution)
gives a warning with that period and a step that resolves it. Lock contacts
need no step of their own: the engine shortens its steps inside each contact to resolve it,
whatever dt (docs/engine-design.md, "Contacts resolved at the default step")."""


def main(argv: Optional[Sequence[str]] = None) -> int:
    """Run the ``deployfx`` command on ``argv`` (None: ``sys.argv[1:]``) and return its exit
    status: 0 on success, 1 if a run stopped early (what it computed is still reported and
    written), 2 for a bad parameter (ValueError, TypeError or RuntimeError; the message goes to
    standard error). A malformed command line exits with status 2 from argparse."""
    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser().parse_args(argv)
    args.argv = argv
    try:
        return args.run(args)
    except (ValueError, TypeError, RuntimeError) as e:
        print(f"deployfx: error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
