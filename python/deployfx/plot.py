"""Figures of deployment runs: the paper's Figs 7-13 (You et al. 2016) and the appendage's
deformed shape.

The time-series functions take one :class:`~deployfx.results.Result` or a sequence of them
(overlaid, e.g. linear vs nonlinear as in the paper) and return a
:class:`matplotlib.figure.Figure`. Any Result works: a per-hinge series draws one curve per hinge
(colour by hinge when there are several, else by run). Curves that coincide stay visible: the
first run is a wide solid line drawn underneath, each later run a narrower dashed (dash-dot,
dotted) line with its own sparse markers drawn over it. Curves are labelled with ``labels`` (one
per result) if given, else with each run's ``metadata["model"]`` (a lone run without one gets no
legend); vector components identically zero (below 1e-9 of the largest: the round-off of a motion
about one axis) are neither drawn nor in the legend. Axis labels carry the series' units (from
the result, else the paper scene's SI units; overlaid runs must agree). A figure the function
makes has a caption line with the runs' settings (:func:`caption`; none for results made by
hand). A result that lacks a needed series raises ``ValueError`` naming it. Functions with an
``ax`` argument draw into that Axes and return its figure; otherwise they make a new one.

Figures are built without pyplot, so nothing is shown, no global figure list grows and no
interactive backend is needed; save them with ``fig.savefig(path)``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional, Sequence, Union

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.tri import Triangulation

from . import _figure_text
from .animation import animate  # noqa: F401 (public as deployfx.plot.animate)
from .results import PathLike, Result

Results = Union[Result, Sequence[Result]]

# Units of the paper scene's series, used when a result states none.
_SCENE_UNITS = {"t": "s", "deployment_angle": "deg", "spring_torque": "N m", "lock_force": "N",
                "node_E_deflection": "m", "body_attitude": "deg",
                "body_angular_momentum": "N m s", "total_angular_momentum": "N m s"}
_COMPONENT_STYLES = (("x", "-"), ("y", "--"), ("z", ":"))


def deployment_angle(results: Results, labels: Optional[Sequence[str]] = None,
                     ax: Optional[Axes] = None) -> Figure:
    """Deployment angle (deg) against time (s), the paper's Fig. 7 (90 stowed, 180 deployed)."""
    return _scalar(results, labels, ax, "deployment_angle", _figure_text.DEPLOYMENT_ANGLE, "Deployment angle")


def spring_torque(results: Results, labels: Optional[Sequence[str]] = None,
                  ax: Optional[Axes] = None) -> Figure:
    """Hinge spring torque (N m) against time (s), the paper's Fig. 8 (there in N mm)."""
    return _scalar(results, labels, ax, "spring_torque", "spring torque", "Hinge spring torque")


def lock_force(results: Results, labels: Optional[Sequence[str]] = None,
               ax: Optional[Axes] = None) -> Figure:
    """Contact-impact force of the lock (N) against time (s), the paper's Fig. 9."""
    return _scalar(results, labels, ax, "lock_force", "lock force",
                   "Contact-impact force of the lock")


def node_deflection(results: Results, labels: Optional[Sequence[str]] = None,
                    ax: Optional[Axes] = None, series: str = "node_E_deflection") -> Figure:
    """Transverse deflection of a node (m) against time (s), the paper's Figs 10-11.

    ``series`` names the deflection series: ``node_<X>_deflection`` (default node E, the free-end
    corner) is labelled "deflection of node X"; any other name by itself, e.g. ``tip_deflection``.
    """
    if series.startswith("node_") and series.endswith("_deflection") and len(series) > 16:
        quantity = f"deflection of node {series[5:-11]}"
    else:
        quantity = series.replace("_", " ")
    return _scalar(results, labels, ax, series, quantity, "Transverse " + quantity)


def body_attitude(results: Results, labels: Optional[Sequence[str]] = None,
                  ax: Optional[Axes] = None) -> Figure:
    """Attitude angles of the spacecraft body (deg), three components against time (s), the
    paper's Fig. 13. Line style marks the component (x solid, y dashed, z dotted), colour the run and
    component; components identically zero are left out.
    """
    runs = _runs(results, labels)
    fig, ax, own = _axes(ax, (6.4, 4.0))
    _vector_lines(ax, runs, "body_attitude", "body attitude")
    _finish(ax, runs, "Attitude of the spacecraft body", legend=True)
    return _captioned(fig, runs, own)


def angular_momentum(results: Results, labels: Optional[Sequence[str]] = None) -> Figure:
    """Angular momentum against time (s), the paper's Fig. 12: the body's (top, N m s), exchanged
    with the appendage, three components (colour marks the run and component, line style the
    component: x solid, y dashed, z dotted); and the drift of the whole system's, which is
    conserved (bottom): |H(t) - H(0)| / H_ref, dimensionless, with H_ref the angular momentum
    the bodies carry (metadata ``momentum_scale``, as :meth:`Result.summary`'s
    ``momentum_drift``; else the peak of |``body_angular_momentum``|)."""
    runs = _runs(results, labels)
    _require_all(runs, ("body_angular_momentum", "total_angular_momentum"), vector=True)
    fig = Figure(figsize=(6.4, 6.0), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True)
    _vector_lines(top, runs, "body_angular_momentum", "body angular momentum")
    for k, (r, label) in enumerate(runs):
        H = np.asarray(r["total_angular_momentum"])
        bottom.plot(r.t, np.linalg.norm(H - H[0], axis=1) / _momentum_scale(r), label=label,
                    **_run_style(k, len(runs), len(r.t)))
    bottom.set_ylabel("total angular momentum drift\n|H - H(0)| / H_ref")
    top.set_title("Angular momentum")
    top.grid(True, alpha=0.3)
    if top.get_lines():
        top.legend(fontsize="small", ncols=len(runs))
    _finish(bottom, runs, None, legend=len(runs) > 1 and runs[0][1] is not None)
    top.set_xlabel("")
    return _captioned(fig, runs, True)


def _momentum_scale(r: Result) -> float:
    """H_ref of angular_momentum: the run's metadata ``momentum_scale`` (N m s), else the peak of
    |``body_angular_momentum``|; 1 if both are zero."""
    scale = r.metadata.get("momentum_scale")
    if isinstance(scale, dict) and scale.get("H_N_m_s"):
        return float(scale["H_N_m_s"])
    return float(np.linalg.norm(r["body_angular_momentum"], axis=1).max()) or 1.0


def caption(results: Results) -> str:
    """The caption of the figures (one or two lines): the runs' settings (:meth:`deployfx.Result.settings`:
    scene, mesh, dt, scheme, tolerance, deployfx version, start time), a setting the runs differ
    in as ``a / b``; '' for results made by hand. :func:`deployfx.plot.animate` shows the same."""
    return _figure_text.caption([r for r, _ in _runs(results, None)])


# (file, drawing function, series it needs, whether they are 3-vectors)
_PAPER_FIGURES = (
    ("deployment_angle.png", deployment_angle, ("deployment_angle",), False),
    ("spring_torque.png", spring_torque, ("spring_torque",), False),
    ("lock_force.png", lock_force, ("lock_force",), False),
    ("node_E_deflection.png", node_deflection, ("node_E_deflection",), False),
    ("body_angular_momentum.png", angular_momentum,
     ("body_angular_momentum", "total_angular_momentum"), True),
    ("body_attitude.png", body_attitude, ("body_attitude",), True),
)


def paper_figures(results: Results, out_dir: PathLike, labels: Optional[Sequence[str]] = None,
                  dpi: int = 150) -> list[Path]:
    """Write the paper's six figures as PNG files in ``out_dir`` (created if needed):
    ``deployment_angle.png``, ``spring_torque.png``, ``lock_force.png``, ``node_E_deflection.png``,
    ``body_angular_momentum.png`` and ``body_attitude.png``, at ``dpi`` dots per inch. Returns the
    paths, in that order. All needed series are checked before any file is written.
    """
    runs = _runs(results, labels)
    for _, _, names, vector in _PAPER_FIGURES:
        for name in names:
            _require(runs, name, vector)
    rs = [r for r, _ in runs]
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    for filename, draw, _, _ in _PAPER_FIGURES:
        path = out / filename
        draw(rs, labels).savefig(path, dpi=dpi)
        paths.append(path)
    return paths


def deformed_shape(nodes_xy: object, quads: object, w: object, ax: Optional[Axes] = None,
                   title: Optional[str] = None) -> Figure:
    """Filled contour of a transverse displacement field on a flat quadrilateral mesh.

    ``nodes_xy`` (n, 2) are the node coordinates in the mesh plane (m), ``quads`` (e, 4) the
    0-based node indices of each element in order around it, ``w`` (n,) the transverse
    displacement (m) of each node. Each quad is split into two triangles along its 0-2 diagonal
    and the field is interpolated linearly on them; the colour scale is symmetric about zero.
    """
    xy = _float_array("nodes_xy", nodes_xy, (None, 2))
    n = xy.shape[0]
    q = np.asarray(quads)
    if q.dtype.kind not in "iu" or q.ndim != 2 or q.shape[1] != 4 or q.shape[0] == 0:
        raise ValueError(f"quads must be an integer array of shape (e, 4), e >= 1, got "
                         f"{q.dtype} {q.shape}")
    if q.min() < 0 or q.max() >= n:
        raise ValueError(f"quads must index the {n} nodes (0 .. {n - 1}), got indices "
                         f"{q.min()} .. {q.max()}")
    w = _float_array("w", w, (n,))
    fig, ax, _ = _axes(ax, (6.4, 4.4))
    tri = Triangulation(xy[:, 0], xy[:, 1], np.concatenate([q[:, [0, 1, 2]], q[:, [0, 2, 3]]]))
    # Symmetric levels, widened by 1e-6 so that a field equal to its extreme (e.g. a uniform w,
    # a rigid translation) still falls strictly inside the top band and gets filled.
    top = (float(np.abs(w).max()) or 1.0) * (1.0 + 1e-6)
    filled = ax.tricontourf(tri, w, levels=np.linspace(-top, top, 21), cmap="RdBu_r")
    fig.colorbar(filled, ax=ax, label="w (m)")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    if title is not None:
        ax.set_title(title)
    return fig


def _runs(results: Results, labels: Optional[Sequence[str]]) -> list[tuple[Result, Optional[str]]]:
    # (result, label) pairs; label None means "no legend entry".
    rs = [results] if isinstance(results, Result) else list(results)
    if not rs:
        raise ValueError("results must hold at least one Result, got none")
    for k, r in enumerate(rs):
        if not isinstance(r, Result):
            raise TypeError(f"results[{k}] must be a Result, got {type(r).__name__}")
    if labels is not None:
        labels = [str(label) for label in labels]
        if len(labels) != len(rs):
            raise ValueError(f"labels must give one label per result ({len(rs)}), "
                             f"got {len(labels)}")
        return list(zip(rs, labels))
    models = [r.metadata.get("model") for r in rs]
    return [(r, m if isinstance(m, str) else (f"run {k + 1}" if len(rs) > 1 else None))
            for k, (r, m) in enumerate(zip(rs, models))]


def _require_all(runs, names: Sequence[str], vector: bool) -> None:
    for name in names:
        _require(runs, name, vector)


def _require(runs, name: str, vector: bool) -> None:
    for k, (r, label) in enumerate(runs):
        which = f"result {k}" + (f" ({label})" if label else "")
        if name not in r:
            raise ValueError(f"{which} has no series {name!r} (it has {', '.join(r.series)})")
        shape = r[name].shape
        if (vector and shape[1:] != (3,)) or (not vector and len(shape) not in (1, 2)):
            raise ValueError(f"{which}: series {name!r} must have shape "
                             f"{'(n, 3)' if vector else '(n,) or (n, hinges)'}, got {shape}")


_RUN_STYLES = ("-", "--", "-.", ":")
_RUN_MARKERS = ("o", "s", "^", "v", "D")


def _run_style(k: int, runs: int, samples: int) -> dict:
    """Line options of run k of ``runs``: the first a wide solid line underneath, each later one
    narrower, dashed, with about 12 markers (offset per run) and drawn over it."""
    if runs == 1:
        return dict(linestyle="-", linewidth=1.4)
    every = max(1, samples // 12)
    style = dict(linestyle=_RUN_STYLES[k % 4], linewidth=2.6 if k == 0 else 1.3, zorder=2 + k)
    if k:
        style.update(marker=_RUN_MARKERS[(k - 1) % len(_RUN_MARKERS)], markersize=4.5,
                     markevery=((k * every) // runs, every), markerfacecolor="none")
    return style


def _unit(runs, name: str) -> str:
    found = {r.units.get(name, _SCENE_UNITS.get(name, "")) for r, _ in runs}
    if len(found) > 1:
        raise ValueError(f"cannot overlay series {name!r} given in different units: "
                         f"{sorted(found)}")
    return found.pop()


def _quantity(runs, name: str, quantity: str) -> str:
    unit = _unit(runs, name)
    return _figure_text.label(quantity, unit)


def _axes(ax: Optional[Axes], figsize: tuple[float, float]) -> tuple[Figure, Axes, bool]:
    """The figure and axes to draw in, and whether the figure is this function's own."""
    if ax is not None:
        return ax.figure, ax, False
    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot(), True


def _captioned(fig: Figure, runs, own: bool) -> Figure:
    """The figure with the runs' settings as its bottom line, if it is the function's own."""
    text = _figure_text.caption([r for r, _ in runs]) if own else ""
    if text:
        fig.supxlabel(text, fontsize="x-small", color="0.35")
    return fig


def _scalar(results: Results, labels, ax: Optional[Axes], name: str, quantity: str,
            title: str) -> Figure:
    runs = _runs(results, labels)
    _require(runs, name, vector=False)
    fig, ax, own = _axes(ax, (6.4, 4.0))
    for k, (r, label) in enumerate(runs):
        y = np.asarray(r[name])
        y = y[:, None] if y.ndim == 1 else y
        H = y.shape[1]
        for h in range(H):
            text = label if H == 1 else (f"{label}, hinge {h}" if label else f"hinge {h}")
            ax.plot(r.t, y[:, h], color=f"C{(h if H > 1 else k) % 10}", label=text,
                    **_run_style(k, len(runs), len(r.t)))
    ax.set_ylabel(_quantity(runs, name, quantity))
    _finish(ax, runs, title, legend=any(line.get_label() and not line.get_label().startswith("_")
                                        for line in ax.get_lines()))
    return _captioned(fig, runs, own)


def _vector_lines(ax: Axes, runs, name: str, quantity: str) -> None:
    """The components of a (n, 3) series that are not identically zero (_shown_components) in
    some run; line style marks the component, colour the run and component, and later runs
    are drawn narrower over earlier ones with markers (_run_style)."""
    _require(runs, name, vector=True)
    for k, (r, label) in enumerate(runs):
        for j in _shown_components(runs, name):
            axis, style = _COMPONENT_STYLES[j]
            options = dict(_run_style(k, len(runs), len(r.t)), linestyle=style)
            ax.plot(r.t, r[name][:, j], color=f"C{(3 * k + j) % 10}", label=f"{label}, {axis}" if label else axis,
                    **options)
    ax.set_ylabel(_quantity(runs, name, quantity))


#: A vector component below this fraction of the series' largest is identically zero (round-off).
ZERO_COMPONENT = 1e-9


def _shown_components(runs, name: str) -> list[int]:
    """The components of series ``name`` above ZERO_COMPONENT of its largest over every run (all
    three if the series is zero throughout)."""
    peak = np.array([np.abs(np.asarray(r[name])).max(axis=0) for r, _ in runs]).max(axis=0)
    return [j for j in range(3) if peak[j] > ZERO_COMPONENT * peak.max()] or [0, 1, 2]


def _finish(ax: Axes, runs, title: Optional[str], legend: bool) -> None:
    ax.set_xlabel(_quantity(runs, "t", _figure_text.TIME))
    ax.grid(True, alpha=0.3)
    if title is not None:
        ax.set_title(title)
    if legend:
        ax.legend(fontsize="small")


def _float_array(name: str, value: object, shape: tuple[Optional[int], ...]) -> np.ndarray:
    a = np.asarray(value)
    ok = a.dtype.kind in "iuf" and a.ndim == len(shape) and a.shape[0] > 0 and all(
        s is None or s == got for s, got in zip(shape, a.shape))
    if not ok:
        dims = ["n" if s is None else str(s) for s in shape]
        want = f"({dims[0]},)" if len(dims) == 1 else f"({', '.join(dims)})"
        raise ValueError(f"{name} must be a real array of shape {want}, got {a.dtype} {a.shape}")
    a = a.astype(float, copy=False)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got NaN or inf")
    return a
