"""Animation of a deployment: the spacecraft base and the appendage mesh in world coordinates,
written to a GIF (Pillow) or an MP4 (ffmpeg: the system's or imageio-ffmpeg's, ``_video``) with
matplotlib's 3-D axes.

World coordinates of the appendage's node ``i`` (frames in docs/notation.md)::

    p_W = r_W + R_WB (p_B + R_BE(theta) (X_i + u_i)),   R_BE(theta) = Rot(axis, theta) R_BE0

with ``r_W`` and ``R_WB`` the base's position and attitude (identity for a fixed base), ``p_B``,
``axis`` and ``R_BE0`` the hinge's point, axis and stowed frame, ``X_i`` the node in E and ``u_i``
its elastic displacement in E. They come from the raw ``q`` series that
:meth:`Model.simulate <deployfx.scene.Model.simulate>` keeps by default (``q = [r_W, quaternion
(w, x, y, z) of R_WB] [theta] [free elastic dofs]``) and the hinge geometry of the scene.

A chain of hinges (:class:`~deployfx.chain.ChainModel`) places each panel the same way,
composing the hinge frames from the base out (:func:`body_frames`)::

    R_WE_k = R_WP_k Rot(axis_k, theta_k) R_PE0_k,   o_W_k = o_W_P + R_WP_k point_k,
    p_W = o_W_k + R_WE_k (X_i + u_i)

with P_k the parent's frame (B for hinge 0: ``o_W_P = r_W``, ``R_WP = R_WB``; else E_{k-1}),
``point_k``, ``axis_k`` and ``R_PE0_k`` hinge k's geometry in P_k (``ChainModel.hinges``),
``X_i`` the panel's nodes in E_k (``ChainModel.shells[k]``) and ``u_i`` their elastic displacement
(zero for a rigid panel; ``ChainModel.node_displacements``); ``q = [r_W, quaternion] [theta_0 ..
theta_N-1] [elastic coordinates]`` (base blocks for a free base only). A hinge on a flexible panel
rides on its deformed mesh (its point and axes move with the attachment node's displacement and
rotation): the frames then come from the engine (``ChainModel.system.frames``).

Figures are built without pyplot (nothing is shown, no interactive backend is needed).
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping, Optional, Sequence

import numpy as np

from . import _video
from ._checks import as_float
from .chain import ChainModel
from .results import PathLike, Result
from .scene import Model, Scene

__all__ = ["animate", "base_poses", "body_frames", "hinge_geometry", "world_points"]


def _chain_of(model: Any) -> Optional[ChainModel]:
    """The ChainModel ``model`` is (or holds as ``.model``), else None."""
    if isinstance(model, ChainModel):
        return model
    inner = getattr(model, "model", None)
    return inner if isinstance(inner, ChainModel) else None


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


def _q_series(model: Any, result: Result) -> np.ndarray:
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
    time of ``result``; zero and identity for a fixed base. ``model``: a :class:`Model`, a
    :class:`~deployfx.chain.ChainModel` or a ready scene holding one as ``.model``."""
    m = _chain_of(model) or _model_of(model)
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


def body_frames(model: Any, result: Result) -> tuple[np.ndarray, np.ndarray]:
    """A chain's hinge frames E_k in world coordinates at each output time of ``result`` (which
    must hold the raw ``q``): their axes ``R_WE`` ((n, N, 3, 3), column j = E_k's axis j in W)
    and origins ``o_W`` (m, (n, N, 3), on hinge k's axis), composed from the base out as in the
    module docstring. ``model``: the :class:`~deployfx.chain.ChainModel` that made ``result`` (or
    a ready scene holding one as ``.model``)."""
    chain = _chain_of(model)
    if chain is None:
        raise TypeError(f"model must be a deployfx.ChainModel (a chain of hinges), got {type(model).__name__}")
    q = _q_series(chain, result)
    first = 7 if chain.base_free else 0
    o_P, R_WP = base_poses(chain, result)
    n, N = len(q), chain.num_hinges
    R_WE, o_W = np.empty((n, N, 3, 3)), np.empty((n, N, 3))
    if any(a >= 0 for a in chain.attachment_nodes):  # hinges riding on deformed panels: the engine's
        for i in range(n):
            R, o = chain.system.frames(q[i])
            R_WE[i] = np.asarray(R).reshape(3, N, 3).transpose(1, 0, 2)
            o_W[i] = np.asarray(o).T
        return R_WE, o_W
    for k, h in enumerate(chain.hinges):
        axis = np.asarray(h["axis"], dtype=float)
        R_PE = _rotation_about(axis / np.linalg.norm(axis), q[:, first + k]) @ np.asarray(h["R_PE0"], dtype=float)
        o_W[:, k] = o_P + np.einsum("kij,j->ki", R_WP, np.asarray(h["point"], dtype=float))
        R_WE[:, k] = R_WP @ R_PE
        o_P, R_WP = o_W[:, k], R_WE[:, k]
    return R_WE, o_W


def _panel_index(chain: ChainModel, hinge: Any) -> int:
    """The hinge whose panel is meant: ``hinge`` (an index), or the only panel when None."""
    panels = [k for k, s in enumerate(chain.shells) if s is not None]
    if hinge is None:
        if len(panels) != 1:
            raise ValueError(f"hinge is required for a chain with {len(panels)} panels: pass the index of the "
                             f"hinge whose panel to place (panels on hinges {panels})")
        return panels[0]
    if isinstance(hinge, bool) or not isinstance(hinge, (int, np.integer)):
        raise TypeError(f"hinge must be a hinge index (int) for a chain, got {type(hinge).__name__}")
    if not 0 <= hinge < chain.num_hinges:
        raise ValueError(f"hinge = {hinge} is out of range: must be in [0, {chain.num_hinges - 1}]")
    if chain.shells[hinge] is None:
        raise ValueError(f"hinge = {hinge} carries no panel (set_appendage(..., hinge={hinge})); panels on "
                         f"hinges {panels}")
    return int(hinge)


def _appendage_frames(m: Model, model: Any, result: Result, hinge: Any) -> tuple[np.ndarray, np.ndarray]:
    """One hinge: E's origin ``o_W`` (m, (n, 3)) and axes ``R_WE`` ((n, 3, 3)) in W."""
    point, axis, R0 = hinge_geometry(model, hinge)
    q = _q_series(m, result)
    theta = _theta(m, result, q)
    r_W, R_WB = base_poses(m, result)
    return r_W + np.einsum("kij,j->ki", R_WB, point), R_WB @ (_rotation_about(axis, theta) @ R0)


def world_points(model: Any, result: Result, hinge: Any = None, scale: float = 1.0) -> np.ndarray:
    """The appendage's nodes in world coordinates (m), shape (len(t), nodes, 3), at each output
    time of ``result`` (which must hold the raw ``q`` series; see the module docstring).

    ``model``: the :class:`~deployfx.scene.Model` that made ``result`` (or a ready scene with a
    ``.model``); ``hinge``: see :func:`hinge_geometry`; ``scale``: magnification of the elastic
    displacements (1 = true shape; 0 = undeformed).

    For a :class:`~deployfx.chain.ChainModel`: the panel of hinge ``hinge`` (its index; None: the
    chain's only panel), its mesh ``ChainModel.shells[hinge]`` plus ``scale`` times its elastic
    displacement (zero for a rigid panel) placed with :func:`body_frames`.
    """
    scale = as_float("scale", scale)
    if not np.isfinite(scale):
        raise ValueError(f"scale = {scale} must be finite")
    chain = _chain_of(model)
    if chain is not None:
        k = _panel_index(chain, hinge)
        R_WE, o_W = body_frames(chain, result)
        X = np.asarray(chain.shells[k].nodes, dtype=float)[None] + scale * chain.node_displacements(
            _q_series(chain, result), k)
        return o_W[:, k, None, :] + np.einsum("kij,knj->kni", R_WE[:, k], X)
    m = _model_of(model)
    if m.shell is None:
        raise ValueError("model has no appendage mesh to place")
    o_W, R_WE = _appendage_frames(m, model, result, hinge)
    # The nodes in E, (n, N, 3), then in W.
    X = np.asarray(m.shell.nodes, dtype=float)[None] + scale * m.node_displacements(_q_series(m, result))
    return o_W[:, None, :] + np.einsum("kij,knj->kni", R_WE, X)


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


def _one_hinge_picture(model: Any, result: Result, hinge: Any, scale: float) -> dict:
    """What animate draws for a one-hinge Model: one mesh coloured by its elastic displacement."""
    m = _model_of(model)
    P = world_points(model, result, hinge, scale)          # checks model, result, hinge, scale
    point, axis, _ = hinge_geometry(model, hinge)
    q = _q_series(m, result)
    r_W, R_WB = base_poses(m, result)
    theta = _theta(m, result, q)
    nodes = np.asarray(m.shell.nodes, dtype=float)
    span = float(np.ptp(nodes, axis=0).max()) or 1.0
    ends = point + 0.5 * span * np.array([-axis, axis])                             # hinge axis, B
    hinges = r_W[:, None, :] + np.einsum("kij,nj->kni", R_WB, ends)                 # (n, 2, 3)
    return dict(points=[P], quads=[np.asarray(m.shell.quads, dtype=int)],
                disp=np.linalg.norm(m.node_displacements(q), axis=2), axes=hinges[:, None],
                r_W=r_W, R_WB=R_WB, point=point, span=span,
                label=lambda k: f"hinge travel {np.degrees(theta[k]):6.1f} deg")


def _chain_picture(chain: ChainModel, result: Result, hinge: Any, scale: float) -> dict:
    """What animate draws for a chain: every panel (deformed, ``scale`` times its elastic
    displacement) in its own colour, every hinge axis."""
    if hinge is not None:
        raise ValueError("hinge must be None for a chain: its hinges' geometry is in ChainModel.hinges")
    R_WE, o_W = body_frames(chain, result)                  # checks result
    r_W, R_WB = base_poses(chain, result)
    panels = [k for k, s in enumerate(chain.shells) if s is not None]
    nodes = [np.asarray(chain.shells[k].nodes, dtype=float) for k in panels]
    span = max((float(np.ptp(X, axis=0).max()) for X in nodes), default=0.0) or 1.0
    # Hinge k's axis in W: R_WP axis = R_WE R_PE0^T axis (Rot(axis, theta) keeps the axis).
    axes = []
    for k, h in enumerate(chain.hinges):
        a = np.asarray(h["R_PE0"], dtype=float).T @ (np.asarray(h["axis"], dtype=float) / np.linalg.norm(h["axis"]))
        a_W = np.einsum("kij,j->ki", R_WE[:, k], a)
        axes.append(o_W[:, k, None, :] + 0.5 * span * np.stack([-a_W, a_W], axis=1))
    q = _q_series(chain, result)
    theta = q[:, 7 if chain.base_free else 0:]
    return dict(points=[world_points(chain, result, k, scale) for k in panels],
                quads=[np.asarray(chain.shells[k].quads, dtype=int) for k in panels], disp=None,
                axes=np.stack(axes, axis=1), r_W=r_W, R_WB=R_WB,
                point=np.asarray(chain.hinges[0]["point"], dtype=float), span=span,
                label=lambda k: "hinge travel " + ", ".join(f"{d:.1f}" for d in np.degrees(theta[k])) + " deg")


def animate(model: Any, result: Result, path: PathLike, fps: float = 20.0,
            frames: Optional[int] = None, hinge: Any = None, scale: float = 1.0,
            base_size: Optional[float] = None, dpi: int = 100,
            figsize: Sequence[float] = (6.4, 5.4), elev: float = 20.0, azim: float = -60.0,
            title: Optional[str] = None) -> Path:
    """Write an animation of the deployment to ``path`` (``.gif`` through Pillow, ``.mp4`` through
    ffmpeg) and return the path.

    Each frame shows, in world axes (m), the base as a wire cube with its pose, the hinge axis and
    the appendage's quads coloured by the magnitude of their elastic displacement (m), with the
    time (s) and the hinge travel (deg). For a :class:`~deployfx.chain.ChainModel` (or a ready
    scene holding one): every hinge axis and every panel (each in its own colour; a flexible one
    deformed, ``scale`` times) placed with :func:`body_frames`, and each hinge's travel (deg);
    ``hinge`` must then be None.

    ``model``, ``result``, ``hinge``, ``scale``: as :func:`world_points` (``result`` must hold the
    raw ``q``: e.g. ``scene.model.simulate(t_end, dt)``). ``fps``: frames per second of the
    movie; ``frames``: how many (default: all samples, at most 200), at the samples nearest to
    evenly spaced times, so the movie lasts ``frames / fps`` s. ``base_size``: the cube's half
    side (m; default 0.9 of the (first) hinge point's largest coordinate, or 5 % of the
    appendage's span if the hinge is at B's origin). ``dpi``, ``figsize`` (inches), ``elev``,
    ``azim`` (deg): the picture and the view. Raises RuntimeError for ``.mp4`` when there is no
    ffmpeg (neither on PATH nor from ``pip install "deployfx[video]"``).
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

    t = np.asarray(result["t"] if isinstance(result, Result) else [], dtype=float)
    chain = _chain_of(model)
    pic = (_one_hinge_picture(model, result, hinge, scale) if chain is None
           else _chain_picture(chain, result, hinge, scale))
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
    disp = None if pic["disp"] is None else pic["disp"][idx]                             # (f, nodes)
    cmap = matplotlib.colormaps["viridis"]
    if disp is not None:
        norm = colors.Normalize(0.0, float(disp.max()) or 1.0)
        fig.colorbar(cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.6,
                     label="elastic displacement (m)")
    polys = []
    for j, (P, quads) in enumerate(zip(meshes, pic["quads"])):
        face = {} if disp is not None else {"facecolor": f"C{j % 10}"}             # rigid panels
        polys.append(Poly3DCollection(P[0][quads], edgecolor="k", linewidth=0.3, **face))
        ax.add_collection3d(polys[-1])
    edges = [ax.plot(*cubes[0][list(e)].T, color="0.3", lw=1.0)[0] for e in _EDGES]
    hinge_lines = [ax.plot(*h.T, color="tab:red", lw=1.5)[0] for h in hinges[0]]
    label = fig.text(0.02, 0.97, "", va="top", family="monospace")

    writer = PillowWriter(fps=fps) if ffmpeg is None else FFMpegWriter(fps=fps)
    path.parent.mkdir(parents=True, exist_ok=True)
    with matplotlib.rc_context({"animation.ffmpeg_path": ffmpeg} if ffmpeg else {}), \
            writer.saving(fig, str(path), dpi):
        for f, k in enumerate(idx):
            for poly, P, quads in zip(polys, meshes, pic["quads"]):
                poly.set_verts(P[f][quads])
                if disp is not None:
                    poly.set_facecolor(cmap(norm(disp[f][quads].mean(axis=1))))
            for line, e in zip(edges, _EDGES):
                line.set_data_3d(*cubes[f][list(e)].T)
            for line, h in zip(hinge_lines, hinges[f]):
                line.set_data_3d(*h.T)
            label.set_text(f"t = {t[k]:7.3f} s   {pic['label'](k)}")
            writer.grab_frame()
    return path
