"""A panel's node translations read from a run's recorded coordinates: the rows of its
displacement map for chosen nodes, taken once per model or scene (Model.node_displacements, the
``nodes`` series of a run, the scenes' node series)."""
from __future__ import annotations

import functools
from dataclasses import dataclass
from typing import Callable, Mapping, Optional, Sequence

import numpy as np


@dataclass(frozen=True)
class NodeTranslations:
    """Translations (m, (n, count, 3), C_k axes) of ``count`` nodes of a panel at each recorded
    ``q``: ``rows`` (3 count x r) of its displacement map times its panel coordinates, which are
    its ``width`` elastic coordinates (q's columns from ``start``) or, where the fidelity slaves
    some (the quadratic manifold), ``lift`` of them (Model.panel_coordinates; None: no call);
    zeros for a panel that does not deform (``rows`` None)."""

    count: int
    rows: Optional[np.ndarray]
    start: int
    width: int = 0
    lift: Optional[Callable[[np.ndarray], np.ndarray]] = None

    def __call__(self, q: np.ndarray) -> np.ndarray:
        if self.rows is None:
            return np.zeros((len(q), self.count, 3))
        eta = q[:, self.start:self.start + self.width]
        if self.lift is not None:
            eta = self.lift(eta)
        return (eta @ self.rows.T).reshape(len(q), self.count, 3)


def node_translations(model, hinge: Optional[int] = None,
                      nodes: Optional[Sequence[int]] = None) -> NodeTranslations:
    """:meth:`Model.node_displacements` of these nodes of ``model`` as a function of ``q``, the
    displacement map's rows taken once (a scene's series at every run: ``translations(q)``, no
    checks of ``q``)."""
    k = model._hinge(hinge, panel=True)
    n_nodes = model.shells[k].num_dofs // 6
    idx = np.arange(n_nodes) if nodes is None else np.asarray(nodes, dtype=int)
    if idx.size and (idx.min() < 0 or idx.max() >= n_nodes):
        raise ValueError(f"nodes must lie in [0, {n_nodes}) (the panel's nodes)")
    lay = model.core.layout(k)
    if lay["num_elastic"] == 0:
        return NodeTranslations(idx.size, None, 0)
    rows = (6 * idx[:, None] + np.arange(3)[None]).ravel()
    D = model.core.displacement_map(k)[rows]
    D.flags.writeable = False
    lift = functools.partial(model._lift, k) if model.fidelities[k].slaved else None
    return NodeTranslations(idx.size, D, lay["iq_elastic"], lay["num_elastic"], lift)


def node_sets(model, nodes) -> dict:
    """``simulate``'s ``nodes`` checked: {hinge: node indices} (``"all"``: every node of every
    panel; None: none); ValueError or TypeError naming what is wrong."""
    if nodes is None:
        return {}
    panels = [k for k in range(model.num_hinges) if model.shells[k] is not None]
    if isinstance(nodes, str):
        if nodes != "all":
            raise ValueError(f"nodes = {nodes!r} is invalid: must be 'all', a mapping {{hinge: [node, ...]}} or None")
        return {k: np.arange(model.shells[k].num_dofs // 6) for k in panels}
    if not isinstance(nodes, Mapping):
        raise TypeError(f"nodes must be 'all', a mapping {{hinge: [node, ...]}} or None, got {type(nodes).__name__}")
    out = {}
    for k, idx in nodes.items():
        k = model._hinge(k, panel=True)
        idx = np.atleast_1d(np.asarray(idx))
        if idx.dtype.kind not in "iu":
            raise TypeError(f"nodes[{k}] must be node indices (integers), got {idx.dtype}")
        n_nodes = model.shells[k].num_dofs // 6
        if idx.size and (idx.min() < 0 or idx.max() >= n_nodes):
            raise ValueError(f"nodes[{k}] must lie in [0, {n_nodes}) (hinge {k}'s panel nodes)")
        out[k] = idx.astype(int)
    return out
