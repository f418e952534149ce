"""Build a scene from parts, compile it into an immutable :class:`~deployfx.model.Model`.

A scene is a spacecraft base (free-floating or fixed), rigid parts fixed to it (a yoke, say), and
a tree of hinges: each hinge sits on the base or on the body of an earlier hinge (rigid, or a
deforming panel: the hinge then rides on the panel's mesh), and its body carries rigid parts, a
panel of any fidelity and a lock. Two wings of three panels each, a yoke and a panel, or one
hinge: one builder, one :class:`~deployfx.model.Model`. Each part is present only if the scene
needs it: a fixed base has no base coordinates, a rigid panel no finite elements, no lock no
contact events.

``compile()`` checks every parameter (ValueError or TypeError naming it) and returns the Model;
``Model.simulate`` runs it in C++ (GIL released) and returns a :class:`~deployfx.results.Result`.

Frames (docs/notation.md): B is the base (origin at its reference point), C_k the body of hinge
k: its origin on the hinge's axis, its axes ``R_PC(theta) = Rot(axis, theta) R_PC0`` in the
parent's, theta the hinge travel from the stowed position. SI units throughout.
"""
from __future__ import annotations

from typing import Optional, Sequence, Union

import numpy as np

from ._checks import as_int
from .contact import ContactLaw, Friction
from .plate import ShellModel
from .specs import Appendage, Base, Fidelity, Hinge, Link, Lock, RigidPart

__all__ = ["Scene", "FIDELITIES"]

#: The panel fidelities (the values of :class:`~deployfx.specs.Fidelity`).
FIDELITIES = tuple(f.value for f in Fidelity)


class Scene:
    """A mutable builder; every ``set_*``/``add_*`` returns the scene, so calls chain.

    One hinge: ``set_base``, ``set_hinge``, ``set_appendage`` and optionally ``set_lock``. A tree:
    ``add_hinge(parent, ...)`` for each hinge (``parent`` "base" or the index of an earlier hinge);
    ``set_appendage``, ``set_lock`` and ``add_rigid_part(..., body=k)`` fill hinge k's body (by
    default the last hinge declared). The parts are immutable values (:mod:`deployfx.specs`),
    readable as ``scene.base``, ``scene.base_parts`` and ``scene.links``.
    """

    def __init__(self) -> None:
        self._base: Optional[Base] = None
        self._base_parts: tuple = ()
        self._links: tuple = ()

    # -------------------------------------------------------------------------------- reading
    @property
    def base(self) -> Optional[Base]:
        """The base (None before ``set_base``)."""
        return self._base

    @property
    def base_parts(self) -> tuple:
        """The rigid parts fixed to the base (:class:`~deployfx.specs.RigidPart`, B)."""
        return self._base_parts

    @property
    def links(self) -> tuple:
        """One :class:`~deployfx.specs.Link` per hinge, in hinge order."""
        return self._links

    @property
    def num_hinges(self) -> int:
        """Hinges declared so far."""
        return len(self._links)

    def _index(self, hinge: Optional[int], what: str) -> int:
        """The index of hinge ``hinge`` (None: the last declared)."""
        if not self._links:
            raise ValueError(f"{what}: the scene has no hinge yet: call set_hinge() or add_hinge() first")
        if hinge is None:
            return len(self._links) - 1
        k = as_int(f"{what}.hinge", hinge)
        if not 0 <= k < len(self._links):
            raise ValueError(f"{what}.hinge = {k} is out of range: must be in [0, {len(self._links) - 1}] "
                             "(the hinges declared so far)")
        return k

    def _replace(self, k: int, **changes) -> None:
        link = self._links[k]
        values = dict(hinge=link.hinge, parts=link.parts, appendage=link.appendage, lock=link.lock)
        values.update(changes)
        self._links = self._links[:k] + (Link(**values),) + self._links[k + 1:]

    # ------------------------------------------------------------------------------- building
    def set_base(self, mass: float, inertia, *, com: Sequence[float] = (0.0, 0.0, 0.0), free: bool = True) -> "Scene":
        """The spacecraft body: mass (kg), inertia about its centre of mass (kg m^2, B axes; a
        scalar means isotropic), centre of mass in B (m). ``free=False`` fixes it to the ground
        (then it has no coordinates and mass and inertia are ignored)."""
        if not isinstance(free, (bool, np.bool_)):
            raise TypeError(f"base.free must be True or False, got {free!r}")
        part = RigidPart.make("base", mass, com, inertia)
        if free and part.mass <= 0:
            raise ValueError(f"base.mass = {part.mass} is out of range: must be > 0 (kg) for a free base")
        self._base = Base(part, bool(free))
        return self

    def add_rigid_part(self, mass: float, inertia, com: Sequence[float], *, body: Union[str, int] = "base") -> "Scene":
        """A rigid part fixed to a body: mass (kg), inertia about its centre of mass (kg m^2, the
        body's axes), centre of mass (m, the body's frame). ``body``: ``"base"`` (B: a yoke fixed to
        the spacecraft) or a hinge index k (the body hinge k carries, in its frame: a yoke that
        deploys, brackets)."""
        part = RigidPart.make("part", mass, com, inertia)
        if isinstance(body, str):
            if body != "base":
                raise ValueError(f"part.body = {body!r} is invalid: must be 'base' or a hinge index")
            self._base_parts = self._base_parts + (part,)
        else:
            k = self._index(body, "part")
            self._replace(k, parts=self._links[k].parts + (part,))
        return self

    def set_hinge(self, point: Sequence[float], axis: Sequence[float], *, R_BE0=np.eye(3), tau0: float = 0.0,
                  k_theta: float = 0.0, c_theta: float = 0.0, fitting_inertia=0.0, fitting_mass: float = 0.0,
                  fitting_com: Sequence[float] = (0.0, 0.0, 0.0), spin_up=None,
                  stowed_angle_deg: float = 0.0) -> "Scene":
        """Hinge 0, on the base (declared, or replaced keeping its body's parts, panel and lock): a
        point of its axis (m, B) and the axis (unit, B); ``R_BE0`` its body frame's axes at
        theta = 0; the rest as :meth:`add_hinge`."""
        hinge = Hinge.make("hinge", "base", point, axis, R_BE0, tau0=tau0, k_theta=k_theta, c_theta=c_theta,
                           fitting_inertia=fitting_inertia, fitting_mass=fitting_mass, fitting_com=fitting_com,
                           spin_up=spin_up, stowed_angle_deg=stowed_angle_deg, R_name="R_BE0")
        if self._links:
            self._replace(0, hinge=hinge)
        else:
            self._links = (Link(hinge),)
        return self

    def add_hinge(self, parent: Union[str, int], point: Sequence[float], axis: Sequence[float], *,
                  R_PE0=np.eye(3), tau0: float = 0.0, k_theta: float = 0.0, c_theta: float = 0.0,
                  fitting_inertia=0.0, fitting_mass: float = 0.0, fitting_com: Sequence[float] = (0.0, 0.0, 0.0),
                  spin_up=None, stowed_angle_deg: float = 0.0) -> "Scene":
        """A new hinge (index ``num_hinges``) on ``parent``: ``"base"``, or the index of an earlier
        hinge whose body carries it (a rigid body, or a panel: then the hinge rides on its mesh,
        bolted to the node nearest ``point``). A point of the axis (m) and the unit axis in the
        parent's frame; ``R_PE0``: this hinge's body frame at theta = 0, in the parent's axes.
        Spring ``tau0 - k_theta theta`` (N m, N m/rad), damper ``c_theta`` (N m s/rad). The fitting
        (the rigid part turning with the body that the spring, damper and lock act on): inertia
        (kg m^2 about its centre of mass), mass (kg), centre of mass (m), in the body frame.
        ``spin_up=(omega_s, t_s)`` prescribes theta(t) instead (Kane, Ryan & Banerjee 1987: rad/s,
        s). ``stowed_angle_deg``: the deployment angle reported at theta = 0 (deg)."""
        k = len(self._links)
        name = f"hinges[{k}]"
        if isinstance(parent, str):
            if parent != "base":
                raise ValueError(f"{name}.parent = {parent!r} is invalid: must be 'base' or a hinge index")
        else:
            p = as_int(f"{name}.parent", parent)
            if not 0 <= p < k:
                raise ValueError(f"{name}.parent = {p} is out of range: must be 'base'"
                                 + (f" or in [0, {k - 1}] (the hinges declared so far)" if k else " (no hinge yet)"))
            parent = p
        hinge = Hinge.make(name, parent, point, axis, R_PE0, tau0=tau0, k_theta=k_theta, c_theta=c_theta,
                           fitting_inertia=fitting_inertia, fitting_mass=fitting_mass, fitting_com=fitting_com,
                           spin_up=spin_up, stowed_angle_deg=stowed_angle_deg, R_name="R_PE0")
        self._links = self._links + (Link(hinge),)
        return self

    def set_appendage(self, shell: ShellModel, fixed_dofs: Sequence[int], *,
                      fidelity: Union[str, Fidelity] = Fidelity.NONLINEAR,
                      damping: tuple = (0.0, 0.0), modes: int = 10, derivative_modes: Optional[int] = None,
                      strengths=None, hinge: Optional[int] = None,
                      derivative_partners: Optional[int] = None) -> "Scene":
        """The panel of hinge ``hinge``'s body (None: the last hinge declared): a shell mesh with
        node coordinates in the body frame (m), the dofs clamped to the frame (its root edge) and
        the fidelity (:class:`~deployfx.specs.Fidelity`): "rigid" (one rigid body: the mesh's mass
        distribution), "linear" (linear strain) or "nonlinear" (Green strain, You et al. 2016
        Eq. 14), or these two reduced, "reduced-linear" and "reduced-nonlinear": the elastic
        motion in a Ritz basis of ``modes`` clamped vibration modes plus the static corrections
        for the root's acceleration loads (and, on a panel carrying hinges, unit loads at their
        attachment nodes) and, for Green strain, the modal derivatives of every pair among the
        first ``derivative_modes`` modes (None: min(modes, 3)) and of each of the first
        ``derivative_partners`` modes with every mode and with the static corrections (None: 1;
        a mode bent together with one whose derivatives with it are missing stiffens spuriously,
        docs/research/undamped-stability.md), with the exact polynomial internal force in that
        basis (docs/engine-design.md); or "reduced-manifold", that basis with its in-plane Ritz
        coordinates slaved to the bending ones on a quadratic manifold (a flat panel with a
        mirror-symmetric laminate; :class:`~deployfx.specs.Fidelity`). Any
        other fidelity on any body of a tree.
        ``damping = (alpha_M, beta_K)``: structural Rayleigh damping C = alpha_M M + beta_K K
        (1/s, s), a modal damping ratio (alpha_M / omega + beta_K omega) / 2.
        ``strengths``: the plies' allowables (:class:`~deployfx.Strengths`, one for all plies or
        one per ply, Pa) for the ply failure envelope of a run (``simulate(..., stresses=True)``,
        :mod:`deployfx.stress`); deployfx ships none."""
        k = self._index(hinge, "appendage")
        self._replace(k, appendage=Appendage.make("appendage", shell, fixed_dofs, fidelity, damping, modes,
                                                  derivative_modes, strengths, derivative_partners))
        return self

    def set_lock(self, theta_lock: float, pin_radius: float, clearance: float, law: ContactLaw, *,
                 friction: Friction = Friction(0.0), hinge: Optional[int] = None) -> "Scene":
        """The lock of hinge ``hinge`` (None: the last hinge declared): the pin (at ``pin_radius``
        m from the axis) seats at hinge travel ``theta_lock`` (rad); ``clearance`` (m) is its play
        once latched; ``law`` the normal contact force, ``friction`` the Coulomb friction along the
        pin's path (a stop wall in the hinge angle; a groove, :meth:`set_groove`, puts it along
        the groove's tangent). The lock is a stop at ``theta_lock`` and, once the pin has passed
        the latch, a latch that holds it back: the pin rests anywhere in the ``clearance`` between
        them."""
        # Engine: cpp/deployfx/joint/hinge_lock.hpp.
        k = self._index(hinge, "lock")
        self._replace(k, lock=Lock(theta_lock, pin_radius, clearance, law, friction))
        return self

    def set_groove(self, groove, *, hinge: Optional[int] = None) -> "Scene":
        """The lock of hinge ``hinge`` (None: the last hinge declared) as a pin sliding in a groove
        (:class:`deployfx.groove.PinGroove`: a profile of segments and arcs in the parent's hinge
        plane, the pin on the hinge's body, the normal law along the profile's normal and Coulomb
        friction along its tangent, You et al. 2016 Eq. 45; e.g. ``PinGroove.paper(law,
        friction)``). It replaces a stop-and-latch lock set before."""
        from .groove import PinGroove

        if not isinstance(groove, PinGroove):
            raise TypeError(f"groove must be a deployfx.groove.PinGroove, got {type(groove).__name__}")
        k = self._index(hinge, "lock")
        self._replace(k, lock=groove)
        return self

    # ------------------------------------------------------------------------------ compiling
    def compile(self, description: Optional[dict] = None):
        """Check and build the immutable :class:`~deployfx.model.Model` (ValueError names any bad
        parameter). ``description``: JSON-compatible notes kept in every result's metadata."""
        from ._compile import compile_model

        if self._base is None:
            raise ValueError("the scene has no base: call set_base() first")
        if not self._links:
            raise ValueError("the scene has no hinge: call set_hinge() or add_hinge() first")
        return compile_model(self, description)
