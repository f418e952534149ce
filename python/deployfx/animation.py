"""Animation of a deployment: the spacecraft base, every hinge axis and every panel in world
coordinates, written to a GIF (Pillow) or an MP4 (ffmpeg: the system's or imageio-ffmpeg's,
``_video``) with matplotlib's 3-D axes.

Positions come from the engine's own kinematics (:meth:`deployfx.Model.frames`, the same forward
pass the equations of motion use): panel k's node i is at

    p_W = o_W_k + R_WC_k (X_i + u_i)

with C_k's origin ``o_W_k`` and axes ``R_WC_k`` in W, ``X_i`` the node in C_k and ``u_i`` its
elastic displacement (zero for a rigid panel; :meth:`deployfx.Model.node_displacements`). They are
computed from the raw ``q`` series that every run keeps. A hinge on a panel rides on its deformed
mesh.

Figures are built without pyplot (nothing is shown, no interactive backend is needed).
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Optional, Sequence

import numpy as np

from . import _core, _figure_text, _video
from ._checks import as_float
from .model import Model
from .results import PathLike, Result

__all__ = ["animate", "base_poses", "body_frames", "world_points"]


def _model_of(model: Any) -> Model:
    """A Model, or the ``.model`` of a ready scene (e.g. ``scenes.paper2016(...)``)."""
    if isinstance(model, Model):
        return model
    inner = getattr(model, "model", None)
    if isinstance(inner, Model):
        return inner
    raise TypeError(f"model must be a deployfx.Model (or a scene with a .model), got {type(model).__name__}")


def _q_series(model: Model, result: Result) -> np.ndarray:
    if not isinstance(result, Result):
        raise TypeError(f"result must be a deployfx.Result, got {type(result).__name__}")
    if "q" not in result:
        raise ValueError("result has no 'q' series (the raw coordinates every run records): was it made by "
                         "Model.simulate?")
    q = np.asarray(result["q"], dtype=float)
    if q.ndim != 2 or q.shape[1] != model.num_positions:
        raise ValueError(f"result's 'q' has shape {q.shape}; this model has {model.num_positions} coordinates: "
                         f"was the result made by another model?")
    return q


def base_poses(model: Any, result: Result) -> tuple[np.ndarray, np.ndarray]:
    """The base's position ``r_W`` (m, (n, 3)) and attitude ``R_WB`` ((n, 3, 3)) at each output
    time of ``result``; zero and identity for a fixed base. ``model``: the :class:`Model` that
    made ``result`` or a ready scene holding one as ``.model``."""
    m = _model_of(model)
    return m.base_poses(_q_series(m, result))


def body_frames(model: Any, result: Result) -> tuple[np.ndarray, np.ndarray]:
    """Every body frame C_k in W at each output time of ``result``: axes ``R_WC`` ((n, H, 3, 3),
    column j = C_k's axis j in W) and origins ``o_W`` (m, (n, H, 3), on hinge k's axis), from the
    engine's kinematics (:meth:`deployfx.Model.frames`)."""
    m = _model_of(model)
    return m.frames(_q_series(m, result), result.t)


def world_points(model: Any, result: Result, hinge: Optional[int] = None, scale: float = 1.0) -> np.ndarray:
    """Hinge ``hinge``'s panel nodes in W (m), shape (len(t), nodes, 3), at each output time of
    ``result`` (None: the model's only panel); ``scale`` magnifies the elastic displacements (1 =
    true shape; 0 = undeformed)."""
    scale = as_float("scale", scale)
    m = _model_of(model)
    return m.world_points(_q_series(m, result), hinge, t=result.t, scale=scale)


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


def _picture(m: Model, result: Result, scale: float) -> dict:
    """What animate draws: every panel (a deforming one coloured by its elastic displacement, a
    rigid one in its own colour), every hinge axis, the base's pose."""
    q = _q_series(m, result)
    R_WC, o_W = m.frames(q, result.t)
    r_W, R_WB = m.base_poses(q)
    panels = [k for k, s in enumerate(m.shells) if s is not None]
    nodes = [np.asarray(m.shells[k].nodes, dtype=float) for k in panels]
    span = max((float(np.ptp(X, axis=0).max()) for X in nodes), default=0.0) or 1.0
    axes = []
    for k, L in enumerate(m.links):
        a = L.hinge.R_PC0.T @ L.hinge.axis          # the axis in C_k (Rot(axis, theta) keeps it)
        a_W = np.einsum("kij,j->ki", R_WC[:, k], a)
        axes.append(o_W[:, k, None, :] + 0.5 * span * np.stack([-a_W, a_W], axis=1))
    disp = [np.linalg.norm(m.node_displacements(q, k), axis=2) if m.deforming[k] else None for k in panels]
    angle = result.deployment_angle if "deployment_angle" in result else _angles_deg(m, q, result.t)
    angle = np.asarray(angle).reshape(len(q), -1)
    first = m.links[0].hinge.point
    return dict(points=[m.world_points(q, k, t=result.t, scale=scale) for k in panels],
                quads=[np.asarray(m.shells[k].quads, dtype=int) for k in panels], disp=disp,
                axes=np.stack(axes, axis=1), r_W=r_W, R_WB=R_WB, point=np.asarray(first), span=span,
                label=lambda i: _figure_text.DEPLOYMENT_ANGLE + " " + ", ".join(f"{d:.1f}" for d in angle[i]) + " deg")


def _frame_text(t: float, angles: str) -> str:
    """A frame's label, in the plots' words (deployfx.plot: "time (s)", "deployment angle (deg)")."""
    return f"{_figure_text.TIME} {t:7.3f} s   {angles}"


def _angles_deg(m: Model, q: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Each hinge's deployment angle (deg, (n, H)): its stowed angle plus its travel, read from
    ``q`` (Model.layout), or for a prescribed hinge its angle at ``t``."""
    out = np.empty((len(q), m.num_hinges))
    for k, L in enumerate(m.links):
        i = m.layout(k)["iq_theta"]
        if i >= 0:
            theta = q[:, i]
        else:
            driver = _core.SpinUpDriver(omega_s=L.hinge.spin_up.omega_s, t_s=L.hinge.spin_up.t_s)
            theta = np.array([driver.evaluate(float(x))[0] for x in t])
        out[:, k] = L.hinge.stowed_angle_deg + np.degrees(theta)
    return out


def animate(model: Any, result: Result, path: PathLike, *, fps: float = 20.0, frames: Optional[int] = None,
            scale: float = 1.0, base_size: Optional[float] = None, dpi: int = 100,
            figsize: Sequence[float] = (6.4, 5.4), elev: float = 20.0, azim: float = -60.0,
            title: Optional[str] = None) -> Path:
    """Write an animation of the deployment to ``path`` (``.gif`` through Pillow, ``.mp4`` through
    ffmpeg) and return the path.

    Each frame shows, in world axes (m), the base as a wire cube with its pose, every hinge axis
    and every panel: a deforming one's quads coloured by the magnitude of their elastic
    displacement (m; ``scale`` times it drawn), a rigid one in its own colour; with the time (s)
    and each hinge's deployment angle (deg, as the result's ``deployment_angle``), labelled in
    the plots' words, and the plots' caption line (:func:`deployfx.plot.caption`).

    ``model``: the :class:`~deployfx.Model` that made ``result`` (or a ready scene with a
    ``.model``). ``fps``: frames per second of the movie; ``frames``: how many (default: all
    samples, at most 200), at the samples nearest to evenly spaced times, so the movie lasts
    ``frames / fps`` s. ``base_size``: the cube's half side (m; default 0.9 of the first hinge
    point's largest coordinate, or 5 % of the panels' span if the hinge is at B's origin). ``dpi``,
    ``figsize`` (inches), ``elev``, ``azim`` (deg): the picture and the view. Raises RuntimeError
    for ``.mp4`` when there is no ffmpeg (neither on PATH nor from ``pip install "deployfx[video]"``).
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
    ffmpeg = _video.ffmpeg_path() if suffix == ".mp4" else None

    scale = as_float("scale", scale)
    if not np.isfinite(scale):
        raise ValueError(f"scale = {scale} must be finite")
    m = _model_of(model)
    pic = _picture(m, result, scale)
    t = np.asarray(result["t"], dtype=float)
    idx = _frame_indices(t, frames)
    r_W, R_WB, span = pic["r_W"], pic["R_WB"], pic["span"]

    if base_size is None:
        base_size = 0.9 * float(np.abs(pic["point"]).max()) or 0.05 * span
    base_size = float(base_size)
    if not (np.isfinite(base_size) and base_size >= 0):
        raise ValueError(f"base_size = {base_size} is out of range: must be >= 0 (m)")
    cubes = r_W[idx, None, :] + np.einsum("kij,nj->kni", R_WB[idx], base_size * _CORNERS)  # (f, 8, 3)
    hinges = pic["axes"][idx]                                                            # (f, H, 2, 3)
    meshes = [P[idx] for P in pic["points"]]                                             # (f, nodes, 3)

    # One cube of the scene's extent, so the axes' scales are equal and fixed.
    pts = np.concatenate([P.reshape(-1, 3) for P in meshes] + [cubes.reshape(-1, 3), hinges.reshape(-1, 3)])
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
    disp = [None if d is None else d[idx] for d in pic["disp"]]                          # (f, nodes) each
    cmap = matplotlib.colormaps["viridis"]
    norm = None
    if any(d is not None for d in disp):
        norm = colors.Normalize(0.0, max(float(d.max()) for d in disp if d is not None) or 1.0)
        fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.6, label="elastic displacement (m)")
    polys = []
    for j, (P, quads) in enumerate(zip(meshes, pic["quads"])):
        face = {} if disp[j] is not None else {"facecolor": f"C{j % 10}"}              # rigid panels
        polys.append(Poly3DCollection(P[0][quads], edgecolor="k", linewidth=0.3, **face))
        ax.add_collection3d(polys[-1])
    edges = [ax.plot(*cubes[0][list(e)].T, color="0.3", lw=1.0)[0] for e in _EDGES]
    hinge_lines = [ax.plot(*h.T, color="tab:red", lw=1.5)[0] for h in hinges[0]]
    label = fig.text(0.02, 0.97, "", va="top", family="monospace")
    caption = _figure_text.caption([result])
    if caption:  # the plots' caption line (deployfx.plot.caption)
        fig.supxlabel(caption, fontsize="x-small", color="0.35")

    writer = PillowWriter(fps=fps) if ffmpeg is None else FFMpegWriter(fps=fps)
    path.parent.mkdir(parents=True, exist_ok=True)
    with matplotlib.rc_context({"animation.ffmpeg_path": ffmpeg} if ffmpeg else {}), \
            writer.saving(fig, str(path), dpi):
        for f, k in enumerate(idx):
            for poly, P, quads, d in zip(polys, meshes, pic["quads"], disp):
                poly.set_verts(P[f][quads])
                if d is not None:
                    poly.set_facecolor(cmap(norm(d[f][quads].mean(axis=1))))
            for line, e in zip(edges, _EDGES):
                line.set_data_3d(*cubes[f][list(e)].T)
            for line, h in zip(hinge_lines, hinges[f]):
                line.set_data_3d(*h.T)
            label.set_text(_frame_text(t[k], pic["label"](k)))
            writer.grab_frame()
    return path
