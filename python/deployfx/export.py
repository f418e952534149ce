"""Export of the deforming appendage for ParaView, through meshio (a maintained VTK writer).

:func:`write_vtk_series` writes one VTU file per recorded sample, ``<name>_<k>.vtu`` (ParaView
opens the numbered files as one time series), with the mesh's quads, the deformed node positions
in the appendage frame E (m) and point data ``displacement`` (m, E axes). The samples' times are
in ``<name>_times.csv``.
"""
from __future__ import annotations

from pathlib import Path
from typing import Union

import numpy as np

from .plate import ShellModel
from .results import Result


def write_vtk_series(result: Result, shell: ShellModel, directory: Union[str, Path], name: str = "appendage",
                     every: int = 1) -> list[Path]:
    """Write every ``every``-th sample of ``result.node_displacements`` (m, (n, nodes, 3)) on the
    mesh of ``shell`` (node coordinates in E) into ``directory``; returns the VTU paths."""
    try:
        import meshio
    except ImportError as e:  # pragma: no cover - meshio is in the test extras
        raise ImportError("write_vtk_series needs meshio: pip install meshio") from e
    if "node_displacements" not in result:
        raise ValueError("result has no node_displacements series (simulate a flexible appendage)")
    if not isinstance(shell, ShellModel):
        raise TypeError(f"shell must be a deployfx.ShellModel, got {type(shell).__name__}")
    if not (isinstance(every, int) and every >= 1):
        raise ValueError(f"every = {every!r} is out of range: must be an integer >= 1")
    u = result.node_displacements
    nodes = shell.nodes
    if u.shape[1:] != nodes.shape:
        raise ValueError(f"node_displacements has shape {u.shape[1:]} per sample, the mesh {nodes.shape}")
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    cells = [("quad", np.asarray(shell.quads, dtype=np.int64))]
    paths, times = [], []
    width = len(str(len(result.t) - 1))
    for k in range(0, len(result.t), every):
        path = out / f"{name}_{k:0{width}d}.vtu"
        meshio.write(path, meshio.Mesh(nodes + u[k], cells, point_data={"displacement": np.array(u[k])}))
        paths.append(path)
        times.append((k, result.t[k]))
    np.savetxt(out / f"{name}_times.csv", np.array(times), delimiter=",", header="sample,t_s", comments="",
               fmt=["%d", "%.10g"])
    return paths
