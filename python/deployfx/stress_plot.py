"""Figures of a run's failure envelope (:func:`deployfx.stress.envelope`).

Each function returns a :class:`matplotlib.figure.Figure` built without pyplot (nothing shown, no
backend needed); pass ``ax`` to draw into an existing Axes. Save with ``fig.savefig(path)``.
"""
from __future__ import annotations

from typing import Optional

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import PolyCollection
from matplotlib.figure import Figure

from .plate import Plate, ShellModel
from .stress import StressEnvelope

__all__ = ["critical_ply", "critical_history"]

_STATIONS = ("bottom", "middle", "top")


def critical_ply(shell: ShellModel, env: StressEnvelope, ax: Optional[Axes] = None) -> Figure:
    """The critical ply's failure index on every element of the panel at its worst time (the
    governing criterion), one colour per quad, the critical element outlined. The mesh is drawn
    in its own plane: x-y for a mesh at constant z, else its two principal directions (m)."""
    shell = _check(shell, env)
    xy, labels = _plane(np.asarray(shell.nodes, dtype=float))
    quads = np.asarray(shell.quads)
    fig, ax = _axes(ax, (6.4, 4.4))
    polys = PolyCollection(xy[quads], array=env.critical_field, cmap="viridis", edgecolors="0.4",
                           linewidths=0.3)
    top = float(env.critical_field.max())
    polys.set_clim(0.0, top if top > 0 else 1.0)
    ax.add_collection(polys)
    ax.add_collection(PolyCollection(xy[quads[[env.critical_element]]], facecolors="none",
                                     edgecolors="red", linewidths=1.5))
    ax.autoscale_view()
    ax.set_aspect("equal")
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    fig.colorbar(polys, ax=ax, label=f"{env.critical_criterion} failure index (-)")
    ax.set_title(f"ply {env.critical_ply} at t = {env.critical_time_s:.4g} s; "
                 f"max {env.max_failure_index:.3g} in element {env.critical_element} "
                 f"(margin {env.min_failure_margin:.3g})", fontsize="small")
    return fig


def critical_history(env: StressEnvelope, ax: Optional[Axes] = None) -> Figure:
    """The critical element's failure index in the critical ply against time (s), with the
    panel's largest index at each sample in grey and ``env.impact_times`` as vertical lines; the
    failure line FI = 1 is drawn once the index passes 0.5."""
    if not isinstance(env, StressEnvelope):
        raise TypeError(f"env must be a deployfx.stress.StressEnvelope, got {type(env).__name__}")
    fig, ax = _axes(ax, (6.4, 4.0))
    c = env.criteria.index(env.critical_criterion)
    ax.plot(env.t, env.peak_index[:, c], color="0.6", linewidth=0.8, label="panel maximum")
    ax.plot(env.t, env.critical_history, color="C0", linewidth=1.2,
            label=f"element {env.critical_element}, ply {env.critical_ply}")
    for i, t in enumerate(env.impact_times):
        ax.axvline(t, color="C3", linestyle=":", linewidth=0.9,
                   label="lock impact" if i == 0 else None)
    if env.max_failure_index >= 0.5:
        ax.axhline(1.0, color="k", linestyle="--", linewidth=0.8, label="failure (FI = 1)")
    ax.set_xlabel("time (s)")
    ax.set_ylabel(f"{env.critical_criterion} failure index (-)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    return fig


def _check(shell: object, env: object) -> ShellModel:
    if isinstance(shell, Plate):
        shell = shell.model
    if not isinstance(shell, ShellModel):
        raise TypeError(f"shell must be a deployfx.ShellModel, got {type(shell).__name__}")
    if not isinstance(env, StressEnvelope):
        raise TypeError(f"env must be a deployfx.stress.StressEnvelope, got {type(env).__name__}")
    if env.critical_field.shape != (len(shell.quads),):
        raise ValueError(f"env has {env.critical_field.shape[0]} elements, the shell "
                         f"{len(shell.quads)}: pass the shell the envelope was computed on")
    return shell


def _plane(nodes: np.ndarray) -> tuple[np.ndarray, tuple[str, str]]:
    if np.ptp(nodes[:, 2]) <= 1e-9 * max(np.ptp(nodes), 1e-300):
        return nodes[:, :2], ("x (m)", "y (m)")
    centred = nodes - nodes.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    return centred @ vt[:2].T, ("in-plane 1 (m)", "in-plane 2 (m)")


def _axes(ax: Optional[Axes], figsize: tuple[float, float]) -> tuple[Figure, Axes]:
    if ax is not None:
        return ax.figure, ax
    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()
