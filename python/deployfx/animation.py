"""Animation of a deployment: the spacecraft base and the appendage mesh in world coordinates,
written to a GIF (Pillow) or an MP4 (ffmpeg) with matplotlib's 3-D axes.

World coordinates of the appendage's node ``i`` (frames in docs/notation.md)::

    p_W = r_W + R_WB (p_B + R_BE(theta) (X_i + u_i)),   R_BE(theta) = Rot(axis, theta) R_BE0

with ``r_W`` and ``R_WB`` the base's position and attitude (identity for a fixed base), ``p_B``,
``axis`` and ``R_BE0`` the hinge's point, axis and stowed frame, ``X_i`` the node in E and ``u_i``
its elastic displacement in E. They come from the raw ``q`` series that
:meth:`Model.simulate <deployfx.scene.Model.simulate>` keeps by default (``q = [r_W, quaternion
(w, x, y, z) of R_WB] [theta] [free elastic dofs]``) and the hinge geometry of the scene.

Figures are built without pyplot (nothing is shown, no interactive backend is needed).
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Optional, Sequence

import numpy as np

from ._checks import as_float
from .results import PathLike, Result
from .scene import Model, Scene

__all__ = ["animate", "base_poses", "hinge_geometry", "world_points"]


def _model_of(model: Any) -> Model:
    """A Model, or the ``.model`` of a ready scene (e.g. ``scenes.paper2016(...)``)."""
    if isinstance(model, Model):
        return model
    inner = getattr(model, "model", None)
    if isinstance(inner, Model):
        return inner
    raise TypeError(f"model must be a deployfx.Model (or a scene with a .model), "
                    f"got {type(model).__name__}")


def hinge_geometry(model: Any, hinge: Any = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The hinge's point (m, in B), unit axis (in B) and ``R_BE0`` (3 x 3, E's axes at theta = 0).

    ``hinge``: a :class:`~deployfx.scene.Scene` (its hinge), a mapping with ``point``, ``axis``
    and optionally ``R_BE0`` (identity by default), or None: then taken from ``model.scene``
    (a ready scene such as ``scenes.paper2016(...)`` keeps it), ``model.hinge`` or
    ``model.description["hinge"]``, whichever exists (a compiled :class:`Model` keeps it).
    """
    if hinge is None:
        candidates = [getattr(model, "scene", None), getattr(model, "hinge", None)]
        desc = getattr(_model_of(model), "description", None) or {}
        candidates.append(desc.get("hinge") if isinstance(desc, Mapping) else None)
        hinge = next((c for c in candidates if c is not None), None)
        if hinge is None:
            raise ValueError("hinge is required: the model does not carry its hinge geometry; pass "
                             "hinge=the Scene it was compiled from, or a mapping with point, axis "
                             "and R_BE0")
    if isinstance(hinge, Scene):
        if hinge._hinge is None:
            raise ValueError("hinge: the scene has no hinge (call set_hinge() first)")
        hinge = hinge._hinge
    if not isinstance(hinge, Mapping):
        raise TypeError(f"hinge must be a Scene or a mapping with point, axis, R_BE0, "
                        f"got {type(hinge).__name__}")
    for key in ("point", "axis"):
        if key not in hinge:
            raise ValueError(f"hinge is missing {key!r} (needs point, axis and optionally R_BE0)")
    point = np.asarray(hinge["point"], dtype=float)
    axis = np.asarray(hinge["axis"], dtype=float)
    R0 = np.asarray(hinge.get("R_BE0", np.eye(3)), dtype=float)
    if point.shape != (3,) or axis.shape != (3,) or R0.shape != (3, 3):
        raise ValueError(f"hinge: point and axis must be 3-vectors and R_BE0 3 x 3, got shapes "
                         f"{point.shape}, {axis.shape}, {R0.shape}")
    norm = np.linalg.norm(axis)
    if not norm > 0:
        raise ValueError("hinge.axis must be nonzero")
    return point, axis / norm, R0


def _rotation_about(axis: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """Rot(axis, theta) for each theta (rad): (n, 3, 3), Rodrigues' formula."""
    K = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]], [-axis[1], axis[0], 0.0]])
    s, c = np.sin(theta)[:, None, None], np.cos(theta)[:, None, None]
    return np.eye(3) + s * K + (1.0 - c) * (K @ K)


def _quaternion_matrix(Q: np.ndarray) -> np.ndarray:
    """Rotation matrices (n, 3, 3) of quaternions (n, 4) in (w, x, y, z) order (normalised here)."""
    Q = Q / np.linalg.norm(Q, axis=1, keepdims=True)
    w, x, y, z = Q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def _q_series(model: Model, result: Result) -> np.ndarray:
    if not isinstance(result, Result):
        raise TypeError(f"result must be a deployfx.Result, got {type(result).__name__}")
    if "q" not in result:
        raise ValueError("result has no 'q' series (the raw coordinates): run Model.simulate with "
                         "its default series, e.g. scene.model.simulate(t_end, dt)")
    q = np.asarray(result["q"], dtype=float)
    n = model.system.num_positions
    if q.ndim != 2 or q.shape[1] != n:
        raise ValueError(f"result's 'q' has shape {q.shape}; this model has {n} coordinates: "
                         f"was the result made by another model?")
    return q


def base_poses(model: Any, result: Result) -> tuple[np.ndarray, np.ndarray]:
    """The base's position ``r_W`` (m, (n, 3)) and attitude ``R_WB`` ((n, 3, 3)) at each output
    time of ``result``; zero and identity for a fixed base."""
    m = _model_of(model)
    q = _q_series(m, result)
    if not m.base_free:
        return np.zeros((len(q), 3)), np.broadcast_to(np.eye(3), (len(q), 3, 3)).copy()
    return q[:, :3].copy(), _quaternion_matrix(q[:, 3:7])


def _theta(model: Model, result: Result, q: np.ndarray) -> np.ndarray:
    """Hinge travel (rad) per output time: the ``theta`` series, else its coordinate in q."""
    if "theta" in result:
        return np.asarray(result["theta"], dtype=float)
    first = 7 if model.base_free else 0
    elastic = getattr(model.system, "num_elastic", model.free_dofs.size)
    if model.system.num_positions - first - elastic != 1:
        raise ValueError("result has no 'theta' series and the hinge is driven (no coordinate): "
                         "keep 'theta' in the result")
    return q[:, first]


def world_points(model: Any, result: Result, hinge: Any = None, scale: float = 1.0) -> np.ndarray:
    """The appendage's nodes in world coordinates (m), shape (len(t), nodes, 3), at each output
    time of ``result`` (which must hold the raw ``q`` series; see the module docstring).

    ``model``: the :class:`~deployfx.scene.Model` that made ``result`` (or a ready scene with a
    ``.model``); ``hinge``: see :func:`hinge_geometry`; ``scale``: magnification of the elastic
    displacements (1 = true shape; 0 = undeformed).
    """
    m = _model_of(model)
    if m.shell is None:
        raise ValueError("model has no appendage mesh to place")
    scale = as_float("scale", scale)
    if not np.isfinite(scale):
        raise ValueError(f"scale = {scale} must be finite")
    point, axis, R0 = hinge_geometry(model, hinge)
    q = _q_series(m, result)
    theta = _theta(m, result, q)
    r_W, R_WB = base_poses(m, result)
    # The nodes in E, (n, N, 3), then in B and in W.
    X = np.asarray(m.shell.nodes, dtype=float)[None] + scale * m.node_displacements(q)
    R_BE = _rotation_about(axis, theta) @ R0
    p_B = point + np.einsum("kij,knj->kni", R_BE, X)
    return r_W[:, None, :] + np.einsum("kij,knj->kni", R_WB, p_B)


# A cube's 12 edges as pairs of corner indices; corners are the sign patterns of (x, y, z).
_CORNERS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
_EDGES = [(i, j) for i in range(8) for j in range(i + 1, 8)
          if np.count_nonzero(_CORNERS[i] != _CORNERS[j]) == 1]


def _frame_indices(t: np.ndarray, frames: Optional[int]) -> np.ndarray:
    n = len(t)
    if frames is None:
        frames = min(n, 200)
    if isinstance(frames, bool) or not isinstance(frames, (int, np.integer)):
        raise TypeError(f"frames must be an integer, got {type(frames).__name__} {frames!r}")
    if not 1 <= frames <= n:
        raise ValueError(f"frames = {frames} is out of range: must be in [1, {n}] (the result's "
                         f"samples)")
    if frames == 1:
        return np.array([n - 1])
    # Nearest samples to evenly spaced times; distinct because frames <= samples.
    target = np.linspace(t[0], t[-1], frames)
    idx = np.clip(np.searchsorted(t, target), 1, n - 1)
    idx = np.where(target - t[idx - 1] <= t[idx] - target, idx - 1, idx)
    return _distinct(idx, n)


def _distinct(idx: np.ndarray, n: int) -> np.ndarray:
    """Sorted indices made strictly increasing within [0, n) (repeats nudged forward, then back)."""
    idx = idx.copy()
    for k in range(1, len(idx)):
        idx[k] = max(idx[k], idx[k - 1] + 1)
    for k in range(len(idx) - 1, -1, -1):
        idx[k] = min(idx[k], n - 1 - (len(idx) - 1 - k))
    return idx


def animate(model: Any, result: Result, path: PathLike, fps: float = 20.0,
            frames: Optional[int] = None, hinge: Any = None, scale: float = 1.0,
            base_size: Optional[float] = None, dpi: int = 100,
            figsize: Sequence[float] = (6.4, 5.4), elev: float = 20.0, azim: float = -60.0,
            title: Optional[str] = None) -> Path:
    """Write an animation of the deployment to ``path`` (``.gif`` through Pillow, ``.mp4`` through
    ffmpeg) and return the path.

    Each frame shows, in world axes (m), the base as a wire cube with its pose, the hinge axis and
    the appendage's quads coloured by the magnitude of their elastic displacement (m), with the
    time (s) and the hinge travel (deg).

    ``model``, ``result``, ``hinge``, ``scale``: as :func:`world_points` (``result`` must hold the
    raw ``q``: e.g. ``scene.model.simulate(t_end, dt)``). ``fps``: frames per second of the
    movie; ``frames``: how many (default: all samples, at most 200), at the samples nearest to
    evenly spaced times, so the movie lasts ``frames / fps`` s. ``base_size``: the cube's half
    side (m; default 0.9 of the hinge point's largest coordinate, or 5 % of the appendage's span
    if the hinge is at B's origin). ``dpi``, ``figsize`` (inches), ``elev``, ``azim`` (deg): the
    picture and the view. Raises RuntimeError for ``.mp4`` when ffmpeg is not installed.
    """
    import matplotlib
    from matplotlib import cm, colors
    from matplotlib.animation import FFMpegWriter, PillowWriter
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".gif", ".mp4"):
        raise ValueError(f"path = {str(path)!r} must end in .gif or .mp4")
    fps = as_float("fps", fps)
    if not (np.isfinite(fps) and fps > 0):
        raise ValueError(f"fps = {fps} is out of range: must be > 0 (frames per second)")
    if isinstance(dpi, bool) or not isinstance(dpi, (int, np.integer)) or dpi <= 0:
        raise ValueError(f"dpi = {dpi!r} must be a positive integer")
    if suffix == ".mp4" and not FFMpegWriter.isAvailable():
        raise RuntimeError("writing .mp4 needs ffmpeg, which was not found: install it (Debian: "
                           "apt-get install ffmpeg) or write a .gif")

    m = _model_of(model)
    t = np.asarray(result["t"] if isinstance(result, Result) else [], dtype=float)
    P = world_points(model, result, hinge, scale)          # checks model, result, hinge, scale
    idx = _frame_indices(t, frames)
    point, axis, _ = hinge_geometry(model, hinge)
    r_W, R_WB = base_poses(m, result)
    theta = _theta(m, result, _q_series(m, result))
    disp = np.linalg.norm(m.node_displacements(_q_series(m, result)[idx]), axis=2)  # (f, N)
    quads = np.asarray(m.shell.quads, dtype=int)

    nodes = np.asarray(m.shell.nodes, dtype=float)
    span = float(np.ptp(nodes, axis=0).max()) or 1.0
    if base_size is None:
        base_size = 0.9 * float(np.abs(point).max()) or 0.05 * span
    base_size = float(base_size)
    if not (np.isfinite(base_size) and base_size >= 0):
        raise ValueError(f"base_size = {base_size} is out of range: must be >= 0 (m)")
    cube = base_size * _CORNERS
    cubes = r_W[idx, None, :] + np.einsum("kij,nj->kni", R_WB[idx], cube)          # (f, 8, 3)
    ends = point + 0.5 * span * np.array([-axis, axis])                             # hinge axis, B
    hinges = r_W[idx, None, :] + np.einsum("kij,nj->kni", R_WB[idx], ends)          # (f, 2, 3)

    # One cube of the scene's extent, so the axes' scales are equal and fixed.
    pts = np.concatenate([P[idx].reshape(-1, 3), cubes.reshape(-1, 3), hinges.reshape(-1, 3)])
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    centre, half = (lo + hi) / 2, 0.55 * float((hi - lo).max() or 1.0)

    fig = Figure(figsize=tuple(figsize), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    ax.view_init(elev=elev, azim=azim)
    for i, c in enumerate("xyz"):
        getattr(ax, f"set_{c}lim")(centre[i] - half, centre[i] + half)
        getattr(ax, f"set_{c}label")(f"{c} (m)")
    ax.set_box_aspect((1, 1, 1))
    if title:
        ax.set_title(title)
    norm = colors.Normalize(0.0, float(disp.max()) or 1.0)
    cmap = matplotlib.colormaps["viridis"]
    mesh = Poly3DCollection(P[idx[0]][quads], edgecolor="k", linewidth=0.3)
    ax.add_collection3d(mesh)
    edges = [ax.plot(*cubes[0][list(e)].T, color="0.3", lw=1.0)[0] for e in _EDGES]
    hinge_line = ax.plot(*hinges[0].T, color="tab:red", lw=1.5)[0]
    fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.6,
                 label="elastic displacement (m)")
    label = fig.text(0.02, 0.97, "", va="top", family="monospace")

    writer = PillowWriter(fps=fps) if suffix == ".gif" else FFMpegWriter(fps=fps)
    path.parent.mkdir(parents=True, exist_ok=True)
    with writer.saving(fig, str(path), dpi):
        for f, k in enumerate(idx):
            mesh.set_verts(P[k][quads])
            mesh.set_facecolor(cmap(norm(disp[f][quads].mean(axis=1))))
            for line, e in zip(edges, _EDGES):
                line.set_data_3d(*cubes[f][list(e)].T)
            hinge_line.set_data_3d(*hinges[f].T)
            label.set_text(f"t = {t[k]:7.3f} s   hinge travel {np.degrees(theta[k]):6.1f} deg")
            writer.grab_frame()
    return path
