"""Export of a run's panels for ParaView, through meshio (a maintained VTK writer).

:func:`write_vtk_series` writes one VTU file per exported sample, ``<name>_<k>.vtu``, and a
ParaView collection ``<name>.pvd`` that lists them with their times (open it in ParaView: the
time slider is the run's time, s); the times are also in ``<name>_times.csv``. Each file holds the
panels' quads at their deformed positions (m) with point data ``displacement`` (m, the elastic
displacement) and cell data ``hinge`` (the hinge whose panel each quad is).

Positions are in world coordinates W (``frame="world"``: every panel of the model, placed by the
engine's kinematics, :meth:`deployfx.Model.frames`) or in one panel's own frame C_k
(``frame="panel"``, ``hinge=k``).

:func:`write_modes_vtk` writes the modes about a state (:class:`deployfx.Modes`): the panels at
that state, one point-data vector per mode (warp by it in ParaView to see the shape).
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Optional, Sequence, Union
from xml.sax.saxutils import quoteattr

import numpy as np

from .results import Result

_FRAMES = ("world", "panel")  # the frames write_vtk_series writes positions in


def _samples(t: np.ndarray, every: int, times: Optional[Sequence[float]]) -> np.ndarray:
    """The indices to export: every ``every``-th sample, or the samples nearest ``times`` (s)."""
    if times is None:
        if isinstance(every, bool) or not isinstance(every, (int, np.integer)) or every < 1:
            raise ValueError(f"every = {every!r} is out of range: must be an integer >= 1")
        return np.arange(0, len(t), int(every))
    want = np.atleast_1d(np.asarray(times, dtype=float))
    if want.size == 0 or not np.all(np.isfinite(want)) or want.min() < t[0] or want.max() > t[-1]:
        raise ValueError(f"times must be finite and within the run's [{t[0]:g}, {t[-1]:g}] s, got {times!r}")
    idx = np.clip(np.searchsorted(t, want), 1, len(t) - 1) if len(t) > 1 else np.zeros(want.size, dtype=int)
    if len(t) > 1:
        idx = np.where(want - t[idx - 1] <= t[idx] - want, idx - 1, idx)
    return np.unique(idx)


def write_vtk_series(model: Any, result: Result, directory: Union[str, Path], *, name: str = "deployment",
                     every: int = 1, times: Optional[Sequence[float]] = None, frame: str = "world",
                     hinge: Optional[int] = None) -> list[Path]:
    """Write the run ``result`` of ``model`` (the :class:`~deployfx.Model` that made it, or a
    ready scene with a ``.model``) into ``directory``; returns the VTU paths (the ``.pvd``
    collection and ``_times.csv`` are written beside them).

    ``every``: every ``every``-th sample; ``times`` (s): instead, the samples nearest these times.
    ``frame="world"``: every panel, in W (m), ``displacement`` in W's axes (zero on rigid panels);
    ``frame="panel"``: hinge ``hinge``'s panel in its frame C_k (None: the model's only panel).
    """
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - meshio is in the test extras
        raise ImportError("write_vtk_series needs meshio: pip install meshio") from e
    from .animation import _model_of, _q_series

    m = _model_of(model)
    if not isinstance(result, Result):
        raise TypeError(f"result must be a deployfx.Result, got {type(result).__name__}")
    if frame not in _FRAMES:
        raise ValueError(f"frame = {frame!r} is invalid: must be one of {', '.join(_FRAMES)}")
    q = _q_series(m, result)
    t = np.asarray(result.t)
    idx = _samples(t, every, times)
    q = q[idx]
    if frame == "panel":
        panels = [m._hinge(hinge, panel=True)]
    else:
        if hinge is not None:
            raise ValueError("hinge must be None for frame='world' (every panel is written)")
        panels = [k for k, s in enumerate(m.shells) if s is not None]
        if not panels:
            raise ValueError("the model has no panel to export (Scene.set_appendage)")
        R_WC, _ = m.frames(q, t[idx])
    points, disp, quads, owner, offset = [], [], [], [], 0
    for k in panels:
        shell = m.shells[k]
        u = m.node_displacements(q, k)
        if frame == "panel":
            points.append(np.asarray(shell.nodes, dtype=float)[None] + u)
            disp.append(u)
        else:
            points.append(m.world_points(q, k, t=t[idx]))
            disp.append(np.einsum("kij,knj->kni", R_WC[:, k], u))
        quads.append(np.asarray(shell.quads, dtype=np.int64) + offset)
        owner.append(np.full(len(shell.quads), k, dtype=np.int64))
        offset += shell.nodes.shape[0]
    points, disp = np.concatenate(points, axis=1), np.concatenate(disp, axis=1)
    cells = [("quad", np.concatenate(quads))]
    cell_data = {"hinge": [np.concatenate(owner)]}
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    paths = []
    width = len(str(len(t) - 1))
    for j, k in enumerate(idx):
        path = out / f"{name}_{k:0{width}d}.vtu"
        meshio.write(path, meshio.Mesh(points[j], cells, point_data={"displacement": disp[j]}, cell_data=cell_data))
        paths.append(path)
    np.savetxt(out / f"{name}_times.csv", np.column_stack([idx, t[idx]]), delimiter=",", header="sample,t_s",
               comments="", fmt=["%d", "%.10g"])
    entries = "\n".join(f'    <DataSet timestep="{float(t[k])!r}" group="" part="0" file={quoteattr(p.name)}/>'
                        for k, p in zip(idx, paths))
    (out / f"{name}.pvd").write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                                     f"  <Collection>\n{entries}\n  </Collection>\n</VTKFile>\n", encoding="utf-8")
    return paths


def write_modes_vtk(modes: Any, path: Union[str, Path]) -> Path:
    """Write ``modes`` (``Model.modes``) as one VTU file at ``path``: every panel of the model at
    the state linearised about (m, W), point data ``mode_<j>`` (j from 1, ascending frequency) the
    nodes' motion per unit shape (:meth:`deployfx.Modes.world_shapes`: bodies and elastic
    together, W axes), cell data ``hinge``; the frequencies (Hz) and damping ratios beside it in
    ``<stem>_modes.csv``. Returns the VTU path."""
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - meshio is in the test extras
        raise ImportError("write_modes_vtk needs meshio: pip install meshio") from e
    from .modal_analysis import Modes

    if not isinstance(modes, Modes):
        raise TypeError(f"modes must be a deployfx.Modes (Model.modes), got {type(modes).__name__}")
    m = modes.model
    panels = [k for k, s in enumerate(m.shells) if s is not None]
    if not panels:
        raise ValueError("the model has no panel to export (Scene.set_appendage)")
    points, quads, owner, shapes, offset = [], [], [], [], 0
    for k in panels:
        shell = m.shells[k]
        points.append(m.world_points(modes.q, k, t=modes.t)[0])
        shapes.append(modes.world_shapes(k))
        quads.append(np.asarray(shell.quads, dtype=np.int64) + offset)
        owner.append(np.full(len(shell.quads), k, dtype=np.int64))
        offset += shell.nodes.shape[0]
    shapes = np.concatenate(shapes, axis=1)
    point_data = {f"mode_{j + 1}": shapes[j] for j in range(len(modes))}
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    meshio.write(path, meshio.Mesh(np.concatenate(points), [("quad", np.concatenate(quads))], point_data=point_data,
                                   cell_data={"hinge": [np.concatenate(owner)]}))
    table = np.column_stack([np.arange(1, len(modes) + 1), modes.frequencies_hz, modes.damping_ratios])
    np.savetxt(path.with_name(f"{path.stem}_modes.csv"), table, delimiter=",", header="mode,frequency_hz,damping_ratio",
               comments="", fmt=["%d", "%.10g", "%.10g"])
    return path
