"""Scenes shared by tests: :func:`locked_array`, notebooks/02's array (a yoke and two flexible
aluminium panels, hinge 2 riding on panel 1), every hinge locking on stop-and-latch walls with the
Kelvin-Voigt-Hertz law and Coulomb friction (mu = 0.2)."""
from __future__ import annotations

import numpy as np

import deployfx as dfx


def _Ry(a: float) -> np.ndarray:
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def locked_array(fidelity: str, nx: int, *, free: bool = True) -> dfx.Model:
    """The array with its panels at ``fidelity`` (4 modes if reduced) on an ``nx`` x 2 mesh, on a
    free (or fixed) base, compiled."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 3e-3)])
    plate = dfx.Plate(0.6, 0.4, lam, nx=nx, ny=2)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += 0.02
    nodes[:, 1] -= 0.2
    panel, root = dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")
    law, friction = dfx.contact.ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4), dfx.contact.Friction(0.2)
    spring = dict(c_theta=0.05, fitting_inertia=0.005)
    lock = dict(pin_radius=0.025, clearance=1e-4, law=law, friction=friction)
    return (dfx.Scene().set_base(mass=300.0, inertia=50.0, free=free)
            .add_hinge("base", point=(0.4, 0, 0), axis=(0, 1, 0), R_PE0=_Ry(-np.pi / 2), tau0=4.0, k_theta=0.3,
                       **spring)
            .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (0.3, 0, 0), body=0)
            .set_lock(np.pi / 2, **lock)
            .add_hinge(0, point=(0.6, 0, 0), axis=(0, 1, 0), R_PE0=_Ry(np.pi), tau0=1.5, k_theta=0.1, **spring)
            .set_appendage(panel, root, fidelity=fidelity, modes=4)
            .set_lock(np.pi, **lock)
            .add_hinge(1, point=(0.64, 0, 0), axis=(0, -1, 0), R_PE0=_Ry(np.pi), tau0=0.5, k_theta=0.1, **spring)
            .set_appendage(panel, root, fidelity=fidelity, modes=4)
            .set_lock(np.pi, **lock)
            .compile())
