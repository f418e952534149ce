"""The parts of a scene as immutable, checked values: what :class:`deployfx.Scene` collects and
compiles, what scene files read and write, and what a :class:`deployfx.Model` keeps of its scene.

Frames (docs/notation.md): B the base, C_k the body hinge k carries. C_k's origin lies on hinge
k's axis; in its parent P (B, or the body of an earlier hinge) its axes are
``R_PC(theta) = Rot(axis, theta) R_PC0``, theta the hinge travel from the stowed position (rad).
SI units throughout; every check raises ValueError or TypeError naming the parameter.
"""
from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import Any, Optional, Union

import numpy as np

from ._checks import as_float, as_int
from .contact import ContactLaw, Friction
from .plate import ShellModel
from .strengths import Strengths

__all__ = ["Fidelity", "RigidPart", "rigid_appendage", "Base", "SpinUp", "Hinge", "Appendage", "Lock", "Link"]


class Fidelity(str, enum.Enum):
    """A panel's model: one rigid body; finite elements with linear strain or Green strain (You
    et al. 2016, Eq. 14); these two reduced to a Ritz basis of a few modes
    (docs/engine-design.md, "Fidelity"); or the nonlinear one on a quadratic manifold of that
    basis, ``REDUCED_MANIFOLD`` (below). A str: ``Fidelity.NONLINEAR == "nonlinear"``, and every
    function that takes a fidelity takes its string too.

    ``REDUCED_MANIFOLD`` ("reduced-manifold"): the reduced-nonlinear basis (same ``modes``,
    ``derivative_modes``, ``derivative_partners``), whose elastic coordinates are only its bending
    Ritz coordinates q; the in-plane ones are slaved to them by the quadratic manifold of Jain,
    Tiso, Rutzmoser & Rixen (2017), ``eta = g(q) = [q; C(q, q)/2]``, C the Galerkin tensor of the
    basis, with the elastic energy that map condenses exactly (a quartic in q: Green strain
    without the in-plane vectors' own quadratic strains; docs/research/quadratic-manifold.md,
    section 3). The mesh moves by ``basis @ eta`` (:meth:`deployfx.Model.panel_coordinates`).
    Only for a flat panel with a mirror-symmetric laminate, whose basis splits into bending and
    in-plane vectors (ValueError otherwise); a hinge on it rides on the lifted mesh. It keeps the
    centrifugal stiffening of a spinning panel: the centrifugal load on the slaved in-plane
    coordinates reaches the bending rows through ``G^T`` and its derivative (Kane's spin-up beam
    at 4-10 rad/s, above the first bending frequency, within 0.2 % of the full nonlinear model:
    tests/test_spin_up_beam.py). Its ply stresses take von Karman's strain
    (:func:`deployfx.stress.strain_measure`)."""

    RIGID = "rigid"
    LINEAR = "linear"
    NONLINEAR = "nonlinear"
    REDUCED_LINEAR = "reduced-linear"
    REDUCED_NONLINEAR = "reduced-nonlinear"
    REDUCED_MANIFOLD = "reduced-manifold"

    def __str__(self) -> str:
        return self.value

    @property
    def deforms(self) -> bool:
        """True unless rigid: the panel has elastic coordinates."""
        return self is not Fidelity.RIGID

    @property
    def reduced(self) -> bool:
        """True for the reduced fidelities (the mesh moves in a Ritz basis; the elastic
        coordinates are its Ritz coordinates, or for ``REDUCED_MANIFOLD`` its bending ones)."""
        return self in (Fidelity.REDUCED_LINEAR, Fidelity.REDUCED_NONLINEAR, Fidelity.REDUCED_MANIFOLD)

    @property
    def slaved(self) -> bool:
        """True when the panel's coordinates (those the mesh moves by, ``Model.basis``) are a
        nonlinear function of its elastic coordinates (``REDUCED_MANIFOLD``); for every other
        fidelity they are the elastic coordinates themselves."""
        return self is Fidelity.REDUCED_MANIFOLD

    @classmethod
    def parse(cls, value: object, name: str = "fidelity") -> "Fidelity":
        """``value`` (a Fidelity or its string) as a Fidelity; ValueError naming ``name`` and the
        allowed values otherwise."""
        try:
            return cls(value)
        except ValueError:
            raise ValueError(f"{name} = {value!r} is invalid: must be one of "
                             f"{', '.join(repr(f.value) for f in cls)}") from None


def _frozen(a: np.ndarray) -> np.ndarray:
    a.setflags(write=False)
    return a


def vector(name: str, value, n: int = 3) -> np.ndarray:
    """``value`` as n finite floats (a read-only array), or ValueError naming ``name``."""
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}") from None
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}")
    return _frozen(a)


def matrix3(name: str, value) -> np.ndarray:
    """``value`` as a finite 3 x 3 matrix (a scalar means that times the identity)."""
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a 3 x 3 matrix (or a scalar times identity), got {value!r}") from None
    if a.shape == ():
        a = a * np.eye(3)
    if a.shape != (3, 3) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be a 3 x 3 matrix (or a scalar times identity), got {value!r}")
    return _frozen(a)


#: The largest mass (kg) and inertia entry (kg m^2) of a rigid part: the engine's bound
#: (multibody::check_rigid_inertia), beyond which the mass matrix leaves the doubles' range.
_MAX_RIGID = 1e50


@dataclass(frozen=True, eq=False)
class RigidPart:
    """A rigid body: mass (kg), centre of mass (m) and inertia about it (kg m^2), in its frame."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray

    @staticmethod
    def make(name: str, mass: float, com, inertia) -> "RigidPart":
        """A checked part: mass (kg, in [0, 1e50]), centre of mass (m, 3) and inertia about it
        (kg m^2, 3 x 3 symmetric positive semidefinite with entries within 1e50, or a scalar times
        identity); TypeError or ValueError naming ``<name>.mass``, ``<name>.com`` or
        ``<name>.inertia`` otherwise."""
        m = as_float(f"{name}.mass", mass)
        if not (np.isfinite(m) and 0 <= m <= _MAX_RIGID):
            raise ValueError(f"{name}.mass = {m} is out of range: must be finite, >= 0 and <= 1e50 (kg)")
        J = matrix3(f"{name}.inertia", inertia)
        if not np.abs(J).max() <= _MAX_RIGID:
            raise ValueError(f"{name}.inertia must have entries within 1e50 (kg m^2)")
        if np.abs(J - J.T).max() > 1e-12 * max(1.0, np.abs(J).max()) or np.linalg.eigvalsh(J).min() < -1e-12 * np.abs(J).max():
            raise ValueError(f"{name}.inertia must be symmetric positive semidefinite (kg m^2)")
        return RigidPart(m, vector(f"{name}.com", com), J)

    @staticmethod
    def zero() -> "RigidPart":
        """No body: zero mass and inertia (the default hinge fitting)."""
        return RigidPart(0.0, _frozen(np.zeros(3)), _frozen(np.zeros((3, 3))))

    def __add__(self, other: "RigidPart") -> "RigidPart":
        """Two parts in one frame as one rigid body (parallel axes)."""
        m = self.mass + other.mass
        if m == 0:
            return RigidPart(0.0, _frozen(np.zeros(3)), _frozen(self.inertia + other.inertia))
        c = (self.mass * self.com + other.mass * other.com) / m
        J = np.zeros((3, 3))
        for p in (self, other):
            r = p.com - c
            J += p.inertia + p.mass * (r @ r * np.eye(3) - np.outer(r, r))
        return RigidPart(m, _frozen(c), _frozen(J))


@dataclass(frozen=True, eq=False)
class Base:
    """The spacecraft body: its rigid inertia in B (``part``; a fixed yoke's is added by
    ``Scene.add_rigid_part``) and whether it floats (``free``) or is fixed to the ground (then it
    has no coordinates and its inertia is unused)."""

    part: RigidPart
    free: bool = True


@dataclass(frozen=True)
class SpinUp:
    """A prescribed hinge angle (Kane, Ryan & Banerjee 1987): rate
    omega_s / t_s [t - (t_s / 2 pi) sin(2 pi t / t_s)] up to t_s, then omega_s (rad/s, s)."""

    omega_s: float
    t_s: float

    def __post_init__(self) -> None:
        omega = as_float("spin_up.omega_s", self.omega_s)
        t_s = as_float("spin_up.t_s", self.t_s)
        if not np.isfinite(omega):
            raise ValueError(f"spin_up.omega_s = {omega} is out of range: must be finite (rad/s)")
        if not (np.isfinite(t_s) and t_s > 0):
            raise ValueError(f"spin_up.t_s = {t_s} is out of range: must be > 0 (s)")
        object.__setattr__(self, "omega_s", omega)
        object.__setattr__(self, "t_s", t_s)


@dataclass(frozen=True, eq=False)
class Hinge:
    """A revolute hinge and where it sits: ``parent`` ("base" or the index of an earlier hinge,
    whose body carries it), a ``point`` of its axis (m, within 1e4 m of the parent's origin) and
    its unit ``axis`` in the parent's frame, ``R_PC0`` the body frame's axes at theta = 0; the spring ``tau0 - k_theta theta``
    (N m, N m/rad) and damper ``c_theta`` (N m s/rad); the ``fitting`` (the rigid part turning with
    the body that the spring, damper and lock act on, in C); ``spin_up``: theta(t) prescribed
    instead; ``stowed_angle_deg``: the angle reported as the deployment angle at theta = 0 (the
    paper's yoke-appendage angle is 90 deg stowed)."""

    parent: Union[str, int]
    point: np.ndarray
    axis: np.ndarray
    R_PC0: np.ndarray
    tau0: float = 0.0
    k_theta: float = 0.0
    c_theta: float = 0.0
    fitting: RigidPart = field(default_factory=RigidPart.zero)
    spin_up: Optional[SpinUp] = None
    stowed_angle_deg: float = 0.0

    @staticmethod
    def make(name: str, parent, point, axis, R_PC0, *, tau0=0.0, k_theta=0.0, c_theta=0.0, fitting_inertia=0.0,
             fitting_mass=0.0, fitting_com=(0.0, 0.0, 0.0), spin_up=None, stowed_angle_deg=0.0,
             R_name: str = "R_PC0") -> "Hinge":
        """A checked hinge; errors name ``<name>.<parameter>``."""
        a = vector(f"{name}.axis", axis)
        if abs(np.linalg.norm(a) - 1) > 1e-9:
            raise ValueError(f"{name}.axis = {a.tolist()} must be a unit vector")
        R = matrix3(f"{name}.{R_name}", R_PC0)
        if np.abs(R.T @ R - np.eye(3)).max() > 1e-9 or np.linalg.det(R) < 0:
            raise ValueError(f"{name}.{R_name} must be a rotation matrix")
        values = {}
        # At most 1e50 in size, as the rigid parts (_MAX_RIGID): a preload of -1.8e308 N m (a fuzz
        # case) overflowed the first residual.
        for key, value, low in (("tau0", tau0, None), ("k_theta", k_theta, 0.0), ("c_theta", c_theta, 0.0)):
            v = as_float(f"{name}.{key}", value)
            if not (np.isfinite(v) and abs(v) <= _MAX_RIGID) or (low is not None and v < low):
                unit = {"tau0": "N m", "k_theta": "N m/rad", "c_theta": "N m s/rad"}[key]
                raise ValueError(f"{name}.{key} = {v} is out of range: must be finite"
                                 f"{' and within [-1e50, 1e50]' if low is None else ' and >= 0, at most 1e50'} ({unit})")
            values[key] = v
        if spin_up is not None and not isinstance(spin_up, SpinUp):
            try:
                omega_s, t_s = spin_up
            except (TypeError, ValueError):
                raise TypeError(f"{name}.spin_up must be (omega_s, t_s) or a deployfx.specs.SpinUp, "
                                f"got {spin_up!r}") from None
            spin_up = SpinUp(omega_s, t_s)
        stowed = as_float(f"{name}.stowed_angle_deg", stowed_angle_deg)
        if not np.isfinite(stowed):
            raise ValueError(f"{name}.stowed_angle_deg = {stowed} must be finite (deg)")
        fitting = RigidPart.make(f"{name}.fitting", fitting_mass, fitting_com, fitting_inertia)
        return Hinge(parent, vector(f"{name}.point", point), a, R, fitting=fitting, spin_up=spin_up,
                     stowed_angle_deg=stowed, **values)


@dataclass(frozen=True, eq=False)
class Appendage:
    """A panel: a shell mesh with node coordinates in its body frame (m), the dofs clamped to the
    frame (its root), its :class:`Fidelity`, Rayleigh damping C = alpha_M M + beta_K K (1/s, s),
    and for the reduced fidelities the clamped ``modes`` kept and the modal derivatives of every
    pair among the first ``derivative_modes`` (None: min(modes, 3)) and of each of the first
    ``derivative_partners`` modes with every mode and static correction (None: 1); ``strengths``: its plies' allowables
    (:class:`~deployfx.Strengths`, one for every ply or one per ply, bottom first), for the ply
    failure envelope of a run (``Model.simulate(..., stresses=True)``), or None."""

    shell: ShellModel
    fixed_dofs: tuple
    fidelity: Fidelity = Fidelity.NONLINEAR
    alpha_M: float = 0.0
    beta_K: float = 0.0
    modes: int = 10
    derivative_modes: Optional[int] = None
    strengths: Optional[tuple] = None
    derivative_partners: Optional[int] = None

    @staticmethod
    def make(name: str, shell, fixed_dofs, fidelity, damping, modes, derivative_modes,
             strengths=None, derivative_partners=None) -> "Appendage":
        """A checked panel; errors name ``<name>.<parameter>``."""
        if not isinstance(shell, ShellModel):
            raise TypeError(f"{name}.shell must be a deployfx.ShellModel, got {type(shell).__name__}")
        fidelity = Fidelity.parse(fidelity, f"{name}.fidelity")
        fixed = []
        for i in np.atleast_1d(np.asarray(fixed_dofs, dtype=object)).ravel():
            fixed.append(as_int(f"{name}.fixed_dofs[...]", i.item() if isinstance(i, np.generic) else i))
        fixed = sorted(set(fixed))
        if fixed and (fixed[0] < 0 or fixed[-1] >= shell.num_dofs):
            raise ValueError(f"{name}.fixed_dofs must lie in [0, {shell.num_dofs}) (6 dofs per node)")
        try:
            alpha_M, beta_K = damping
        except (TypeError, ValueError):
            raise ValueError(f"{name}.damping must be (alpha_M, beta_K), got {damping!r}") from None
        values = {}
        for key, v, unit in (("alpha_M", alpha_M, "1/s"), ("beta_K", beta_K, "s")):
            v = as_float(f"{name}.{key}", v)
            if not (np.isfinite(v) and v >= 0):
                raise ValueError(f"{name}.{key} = {v} is out of range: must be finite and >= 0 ({unit})")
            values[key] = v
        modes = as_int(f"{name}.modes", modes)
        n_free = shell.num_dofs - len(fixed)
        if fidelity.reduced and not 1 <= modes <= n_free:
            raise ValueError(f"{name}.modes = {modes} is out of range: must be in [1, {n_free}] (the free dofs)")
        if derivative_modes is not None:
            derivative_modes = as_int(f"{name}.derivative_modes", derivative_modes)
            if not 0 <= derivative_modes <= modes:
                raise ValueError(f"{name}.derivative_modes = {derivative_modes} is out of range: must be in "
                                 f"[0, modes = {modes}] or None")
        if derivative_partners is not None:
            derivative_partners = as_int(f"{name}.derivative_partners", derivative_partners)
            if not 0 <= derivative_partners <= modes:
                raise ValueError(f"{name}.derivative_partners = {derivative_partners} is out of range: must be in "
                                 f"[0, modes = {modes}] or None")
        if fidelity in (Fidelity.LINEAR, Fidelity.NONLINEAR) and n_free == 0:
            raise ValueError(f"{name}.fixed_dofs clamps every dof: a deforming panel needs free dofs (use "
                             "fidelity='rigid' for a panel that does not deform)")
        if strengths is not None:
            per_ply = (strengths,) if isinstance(strengths, Strengths) else tuple(strengths)
            plies = len(shell.laminate.plies)
            if not all(isinstance(s, Strengths) for s in per_ply) or len(per_ply) not in (1, plies):
                raise TypeError(f"{name}.strengths must be a deployfx.Strengths or one per ply ({plies}), "
                                f"got {strengths!r}")
            strengths = per_ply
        return Appendage(shell, tuple(fixed), fidelity, modes=modes, derivative_modes=derivative_modes,
                         strengths=strengths, derivative_partners=derivative_partners, **values)


@dataclass(frozen=True)
class Lock:
    """The hinge lock: the pin at ``pin_radius`` (m) from the axis seats at
    hinge travel ``theta_lock`` (rad); ``clearance`` (m) is its play once latched; ``law`` the
    normal contact force, ``friction`` the groove's Coulomb friction."""

    theta_lock: float
    pin_radius: float
    clearance: float
    law: ContactLaw
    friction: Friction = Friction(0.0)

    def __post_init__(self) -> None:
        if not isinstance(self.law, ContactLaw):
            raise TypeError(f"lock.law must be a deployfx.contact.ContactLaw, got {type(self.law).__name__}")
        if not isinstance(self.friction, Friction):
            raise TypeError(f"lock.friction must be a deployfx.contact.Friction, got {type(self.friction).__name__}")
        theta = as_float("lock.theta_lock", self.theta_lock)
        r = as_float("lock.pin_radius", self.pin_radius)
        c = as_float("lock.clearance", self.clearance)
        if not np.isfinite(theta):
            raise ValueError(f"lock.theta_lock = {theta} is out of range: must be finite (rad)")
        # A pin below a micrometre or a play beyond a full turn cannot be a hinge lock, and would
        # make the play in degrees (clearance / pin_radius) overflow.
        if not (np.isfinite(r) and 1e-6 <= r <= 1e3):
            raise ValueError(f"lock.pin_radius = {r} is out of range: must be in [1e-6, 1e3] (m)")
        if not (np.isfinite(c) and 0 <= c <= np.pi * r):
            raise ValueError(f"lock.clearance = {c} is out of range: must be in [0, pi pin_radius = {np.pi * r:g}] (m)")
        for key, v in (("theta_lock", theta), ("pin_radius", r), ("clearance", c)):
            object.__setattr__(self, key, v)

    @property
    def play_deg(self) -> float:
        """The pin's free play once latched, deg of hinge travel (clearance / pin radius)."""
        return float(np.degrees(self.clearance / self.pin_radius))


@dataclass(frozen=True, eq=False)
class Link:
    """Hinge k of a scene and what its body carries: the rigid ``parts`` (in C_k), an
    ``appendage`` (a panel) and a ``lock``: the stop-and-latch :class:`Lock` or a pin in a groove
    (:class:`deployfx.groove.PinGroove`)."""

    hinge: Hinge
    parts: tuple = ()
    appendage: Optional[Appendage] = None
    lock: Optional[Any] = None


def rigid_appendage(shell: ShellModel) -> RigidPart:
    """The undeformed mesh of a :class:`~deployfx.ShellModel` as one rigid body in its frame:
    mass (kg), centre of mass (m) and inertia about it (kg m^2), from its floating-frame shape
    integrals (the mass, first moment S0 and inertia J0 about the frame's origin; parallel axes)."""
    ffi = shell.floating_frame_inertia()
    m = float(ffi.mass)
    c = np.asarray(ffi.S0) / m
    J = np.asarray(ffi.J0) - m * (c @ c * np.eye(3) - np.outer(c, c))
    return RigidPart.make("appendage", m, c, 0.5 * (J + J.T))
