"""A checked :class:`~deployfx.scene.Scene` compiled into the engine's model (``Scene.compile``):
the hinge specs with their rigid parts merged, each panel's spec, lock and driver, and the tip
node whose deflection every run reports."""
from __future__ import annotations

from typing import Optional

import numpy as np

from . import _core
from .groove import PinGroove
from .model import Model
from .plate import ShellModel


def _tip(shell: ShellModel, axis_C: np.ndarray) -> tuple[int, np.ndarray]:
    """The node farthest from the hinge axis (through C's origin along ``axis_C``), among those
    within 1e-9 of the farthest the one nearest the axis' foot; and the unit direction in which
    a rotation about the axis moves it (the panel's normal there if it lies on the axis)."""
    X = np.asarray(shell.nodes, dtype=float)
    along = X @ axis_C
    dist = np.linalg.norm(X - np.outer(along, axis_C), axis=1)
    far = np.flatnonzero(dist >= dist.max() - 1e-9 * max(dist.max(), 1.0))
    node = int(far[np.argmin(np.abs(along[far]))])
    d = np.cross(axis_C, X[node])
    if np.linalg.norm(d) < 1e-12:
        quads = np.asarray(shell.quads, dtype=int)
        quad = quads[np.flatnonzero((quads == node).any(axis=1))[0]]
        d = np.cross(X[quad[2]] - X[quad[0]], X[quad[3]] - X[quad[1]])
    return node, d / np.linalg.norm(d)


def compile_model(scene, description: Optional[dict]) -> Model:
    """The :class:`Model` of a checked :class:`~deployfx.scene.Scene` (``Scene.compile``)."""
    base = scene.base
    body = base.part
    for p in scene.base_parts:
        body = body + p
    specs, tips, dirs = [], [], []
    children = {k: [] for k in range(len(scene.links))}
    for k, link in enumerate(scene.links):
        if link.hinge.parent != "base":
            children[link.hinge.parent].append(k)
    for k, link in enumerate(scene.links):
        h = link.hinge
        rigid = h.fitting
        for p in link.parts:
            rigid = rigid + p
        if link.appendage is None and rigid.mass == 0 and not np.any(rigid.inertia) and not children[k]:
            raise ValueError(f"hinges[{k}] carries no body: give it an appendage (set_appendage(..., hinge={k})), "
                             f"a rigid part (add_rigid_part(..., body={k})) or a fitting")
        panel = None
        a = link.appendage
        if a is not None:
            panel = _core.PanelSpec(shell=a.shell._impl, fixed_dofs=list(a.fixed_dofs), fidelity=a.fidelity.value,
                                    alpha_M=a.alpha_M, beta_K=a.beta_K, modes=a.modes,
                                    derivative_modes=-1 if a.derivative_modes is None else a.derivative_modes,
                                    derivative_partners=-1 if a.derivative_partners is None else a.derivative_partners)
        lock = None
        if isinstance(link.lock, PinGroove):
            lock = link.lock._impl
        elif link.lock is not None:
            L = link.lock
            try:
                lock = _core.HingeLockSpec(theta_lock=L.theta_lock, pin_radius=L.pin_radius, clearance=L.clearance,
                                           law=L.law._impl, mu=L.friction.mu, v_reg=L.friction.v_reg)
            except ValueError as e:
                raise ValueError(f"hinges[{k}].{e}") from None
        driver = None if h.spin_up is None else _core.SpinUpDriver(omega_s=h.spin_up.omega_s, t_s=h.spin_up.t_s)
        specs.append(_core.HingeSpec(parent=-1 if h.parent == "base" else int(h.parent), point=h.point, axis=h.axis,
                                     R_PC0=h.R_PC0, tau0=h.tau0, k_theta=h.k_theta, c_theta=h.c_theta, driver=driver,
                                     lock=lock, body=_core.RigidInertia(mass=rigid.mass, com=rigid.com,
                                                                        inertia=rigid.inertia), panel=panel))
        if a is None:
            tips.append(-1)
            dirs.append(np.zeros(3))
        else:
            node, d = _tip(a.shell, h.R_PC0.T @ h.axis)
            tips.append(node)
            dirs.append(d)
    core = _core.Model(base_free=base.free, base=_core.RigidInertia(mass=body.mass if base.free else 1.0,
                                                                    com=body.com,
                                                                    inertia=body.inertia if base.free else np.eye(3)),
                       hinges=specs)
    return Model(core=core, base_free=base.free, links=scene.links, description=dict(description or {}),
                 tip_nodes=tuple(tips), tip_directions=tuple(dirs))
