"""Export of the deforming appendage for ParaView, through meshio (a maintained VTK writer).

:func:`write_vtk_series` writes one VTU file per recorded sample, ``<name>_<k>.vtu`` (ParaView
opens the numbered files as one time series), with the mesh's quads, the deformed node positions
(m) and point data ``displacement`` (m, the elastic displacement). The samples' times are in
``<name>_times.csv``.

Positions are in the appendage frame E by default (``frame="appendage"``), or in world
coordinates W (``frame="world"``, with the ``model`` that made the run: the base's pose and the
hinge's travel from its raw ``q``, as :func:`deployfx.animation.world_points`). A chain of hinges
(:class:`~deployfx.chain.ChainModel`) is written in W, its panels (deformed, for flexible ones)
merged into one mesh per sample with cell data ``hinge`` (the index of the hinge whose panel each
quad is).
"""
from __future__ import annotations

from pathlib import Path
from typing import Any, Optional, Union

import numpy as np

from .plate import ShellModel
from .results import Result

_FRAMES = ("appendage", "world")  # the frames write_vtk_series writes positions in


def write_vtk_series(result: Result, shell: Optional[ShellModel], directory: Union[str, Path],
                     name: str = "appendage", every: int = 1, frame: Optional[str] = None,
                     model: Any = None) -> list[Path]:
    """Write every ``every``-th sample of the run ``result`` into ``directory``; returns the VTU
    paths.

    ``frame="appendage"`` (the default for one hinge): the mesh of ``shell`` (node coordinates in
    E, m) plus ``result.node_displacements`` (m, (n, nodes, 3), E axes), in E.
    ``frame="world"``: the same nodes placed in W (m) at each sample, ``displacement`` in W's
    axes; needs ``model``, the :class:`~deployfx.scene.Model` that made ``result`` (or a ready
    scene with a ``.model``, e.g. ``scenes.paper2016(...)``), and ``result``'s raw ``q`` series;
    ``shell`` may then be None (the model's mesh). A :class:`~deployfx.chain.ChainModel` as
    ``model`` (``shell`` None, ``frame`` None or "world"): every panel in W, merged, with cell
    data ``hinge`` and ``displacement`` the elastic displacement in W's axes (zero on rigid panels).
    """
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - meshio is in the test extras
        raise ImportError("write_vtk_series needs meshio: pip install meshio") from e
    from . import animation

    if not isinstance(result, Result):
        raise TypeError(f"result must be a deployfx.Result, got {type(result).__name__}")
    if not (isinstance(every, int) and not isinstance(every, bool) and every >= 1):
        raise ValueError(f"every = {every!r} is out of range: must be an integer >= 1")
    chain = animation._chain_of(model)
    if frame is None:
        frame = "world" if chain is not None else "appendage"
    if frame not in _FRAMES:
        raise ValueError(f"frame = {frame!r} is invalid: must be one of {', '.join(_FRAMES)}")
    cell_data = None
    if chain is not None:
        if frame != "world":
            raise ValueError("frame = 'appendage' is undefined for a chain of hinges (one frame per panel): "
                             "use frame='world'")
        if shell is not None:
            raise ValueError("shell must be None for a chain: its panels' meshes are in ChainModel.shells")
        panels = [k for k, s in enumerate(chain.shells) if s is not None]
        if not panels:
            raise ValueError("the chain has no panel to export (set_appendage(..., hinge=k))")
        points = np.concatenate([animation.world_points(chain, result, hinge=k) for k in panels], axis=1)
        quads, offset, body = [], 0, []
        for k in panels:
            s = chain.shells[k]
            quads.append(np.asarray(s.quads, dtype=np.int64) + offset)
            body.append(np.full(len(s.quads), k, dtype=np.int64))
            offset += s.nodes.shape[0]
        quads = np.concatenate(quads)
        cell_data = {"hinge": [np.concatenate(body)]}
        R_WE, _ = animation.body_frames(chain, result)
        q = animation._q_series(chain, result)
        disp = np.concatenate([np.einsum("kij,knj->kni", R_WE[:, k], chain.node_displacements(q, k))
                               for k in panels], axis=1)
    else:
        if model is None and frame == "world":
            raise ValueError("frame = 'world' needs model: the Model that made the result (for the base's "
                             "pose and the hinge geometry)")
        if shell is None:
            shell = getattr(animation._model_of(model), "shell", None) if model is not None else None
            if shell is None:
                raise ValueError("shell is required (the appendage's mesh) unless model carries one")
        if not isinstance(shell, ShellModel):
            raise TypeError(f"shell must be a deployfx.ShellModel, got {type(shell).__name__}")
        nodes = shell.nodes
        quads = np.asarray(shell.quads, dtype=np.int64)
        if frame == "appendage":
            if "node_displacements" not in result:
                raise ValueError("result has no node_displacements series (simulate a flexible appendage, "
                                 "or export frame='world' with the model)")
            disp = result.node_displacements
            if disp.shape[1:] != nodes.shape:
                raise ValueError(f"node_displacements has shape {disp.shape[1:]} per sample, the mesh "
                                 f"{nodes.shape}")
            points = nodes + disp
        else:
            m = animation._model_of(model)
            if m.shell is None or m.shell.nodes.shape != nodes.shape:
                raise ValueError("shell is not the mesh of model's appendage (pass shell=None to use the model's)")
            points = animation.world_points(model, result)
            _, R_WE = animation._appendage_frames(m, model, result, None)
            u = m.node_displacements(animation._q_series(m, result))
            disp = np.einsum("kij,knj->kni", R_WE, u)
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    cells = [("quad", quads)]
    paths, times = [], []
    width = len(str(len(result.t) - 1))
    for k in range(0, len(result.t), every):
        path = out / f"{name}_{k:0{width}d}.vtu"
        meshio.write(path, meshio.Mesh(np.array(points[k]), cells, point_data={"displacement": np.array(disp[k])},
                                       cell_data=cell_data))
        paths.append(path)
        times.append((k, result.t[k]))
    np.savetxt(out / f"{name}_times.csv", np.array(times), delimiter=",", header="sample,t_s", comments="",
               fmt=["%d", "%.10g"])
    return paths
