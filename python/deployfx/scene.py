"""Build a scene from parts, compile it into an immutable model, simulate it.

A scene is a spacecraft base (free-floating or fixed), rigid parts fixed to it (a yoke, say),
one revolute hinge (spring with preload, damper, or a prescribed angle), the hinge fitting, one
appendage (a shell mesh in the hinge frame E, rigid or flexible) and optionally a lock. Each part
is present only if the scene needs it: a fixed base has no base coordinates, a rigid appendage no
finite elements, no lock no contact events. ``compile()`` validates every parameter and returns a
:class:`Model`; ``Model.simulate`` runs it in C++ (GIL released) and returns a
:class:`~deployfx.results.Result`.

Frames (docs/notation.md): B is the base (origin at its reference point), E the hinge frame: its
origin on the hinge axis, its axes ``R_BE(theta) = Rot(axis, theta) R_BE0``; theta is the hinge
travel from the stowed position. SI units throughout.

A chain of hinges (issue 5: a yoke and panels, as on solar arrays) is declared hinge by hinge
with ``Scene.add_hinge(parent, ...)``, hinge k on the body of hinge k - 1, each with its own
spring, lock, rigid parts and appendage (rigid, reduced-linear or reduced-nonlinear), in its
frame E_k (axes ``Rot(axis_k, theta_k) R_PE0_k`` in the parent's); it compiles into a
:class:`~deployfx.chain.ChainModel`. A hinge on a flexible panel rides on its deforming mesh.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Optional, Sequence

import numpy as np

from . import _core
from ._checks import as_float, as_int, as_int_sequence
from .contact import ContactLaw, Friction
from ._run import ENERGY_GROWTH_LIMIT, _run_arguments, _run_result, _timed_run  # noqa: F401 (ENERGY_GROWTH_LIMIT: public here)
from .integrators import GeneralizedAlpha
from .plate import ShellModel
from .results import Result

FIDELITIES = ("rigid", "linear", "nonlinear", "reduced-linear", "reduced-nonlinear")


def _vector(name: str, value, n: int = 3) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be {n} finite numbers, got {value!r}")
    return a


def _matrix3(name: str, value) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape == ():
        a = a * np.eye(3)
    if a.shape != (3, 3) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be a 3 x 3 matrix (or a scalar times identity), got {value!r}")
    return a


@dataclass(frozen=True)
class RigidPart:
    """A rigid body: mass (kg), centre of mass (m) and inertia about it (kg m^2), in its frame."""

    mass: float
    com: np.ndarray
    inertia: np.ndarray

    @staticmethod
    def make(name: str, mass: float, com, inertia) -> "RigidPart":
        """A checked part: mass (kg, >= 0), centre of mass (m, 3) and inertia about it (kg m^2,
        3 x 3 symmetric positive semidefinite, or a scalar times identity); TypeError or
        ValueError naming ``<name>.mass``, ``<name>.com`` or ``<name>.inertia`` otherwise."""
        m = as_float(f"{name}.mass", mass)
        if not (np.isfinite(m) and m >= 0):
            raise ValueError(f"{name}.mass = {m} is out of range: must be >= 0 (kg)")
        J = _matrix3(f"{name}.inertia", inertia)
        if np.abs(J - J.T).max() > 1e-12 * max(1.0, np.abs(J).max()) or np.linalg.eigvalsh(J).min() < 0:
            raise ValueError(f"{name}.inertia must be symmetric positive semidefinite (kg m^2)")
        return RigidPart(m, _vector(f"{name}.com", com), J)

    def __add__(self, other: "RigidPart") -> "RigidPart":
        """Two parts in one frame as one rigid body (parallel axes)."""
        m = self.mass + other.mass
        if m == 0:
            return RigidPart(0.0, np.zeros(3), self.inertia + other.inertia)
        c = (self.mass * self.com + other.mass * other.com) / m
        J = np.zeros((3, 3))
        for p in (self, other):
            r = p.com - c
            J += p.inertia + p.mass * (r @ r * np.eye(3) - np.outer(r, r))
        return RigidPart(m, c, J)


@dataclass(frozen=True)
class Model:
    """A compiled scene: immutable, reusable for many runs."""

    system: _core.HingedSystem = field(repr=False)
    shell: Optional[ShellModel] = field(repr=False)
    fidelity: str
    base_free: bool
    has_lock: bool
    fixed_dofs: tuple = field(repr=False)
    description: dict = field(default_factory=dict)
    #: The hinge's geometry: ``point`` (m, B), unit ``axis`` (B) and ``R_BE0`` (E's axes at theta = 0),
    #: to place the appendage in world coordinates (deployfx.animation).
    hinge: Optional[dict] = field(default=None, repr=False)
    #: No driver: nothing in the scene can add energy (springs, contact and damping only store or
    #: dissipate it), so energy growth is a numerical failure and ``simulate`` reports it.
    conservative: bool = True
    #: The lock's free play once latched, deg of hinge travel (clearance / pin radius); None
    #: without a lock. The pin may rest anywhere in it: the settling band (Result.summary).
    lock_play_deg: Optional[float] = None

    @property
    def reduced(self) -> bool:
        """True for the reduced fidelities (elastic coordinates are Ritz coordinates eta)."""
        return self.fidelity.startswith("reduced")

    @property
    def free_dofs(self) -> np.ndarray:
        """The appendage's free elastic dofs (indices into the mesh's 6-per-node dofs)."""
        if self.shell is None or self.fidelity == "rigid":
            return np.zeros(0, dtype=int)
        n = self.shell.num_dofs
        return np.setdiff1d(np.arange(n), np.asarray(self.fixed_dofs, dtype=int))

    @property
    def basis(self) -> Optional[np.ndarray]:
        """Reduced fidelities: the Ritz basis, mesh dofs = ``basis @ eta`` (read-only, (6 nodes x
        r), M-orthonormal: eta in kg^0.5 m); None for a full model."""
        return self.system.basis if self.reduced else None

    @property
    def basis_info(self) -> Optional[dict]:
        """Reduced fidelities: ``modes``, ``static_corrections`` and ``modal_derivatives`` proposed,
        the basis ``size`` kept and its Ritz values ``omega2`` ((rad/s)^2); None otherwise."""
        return self.system.basis_info if self.reduced else None

    def node_displacements(self, q: np.ndarray) -> np.ndarray:
        """Node translations in the appendage frame E (m), shape (len(q), nodes, 3), from recorded
        coordinates ``q`` (the raw ``q`` series); zeros for a rigid appendage."""
        q = np.atleast_2d(q)
        n_nodes = self.shell.num_dofs // 6 if self.shell is not None else 0
        elastic = q[:, self.system.num_positions - self.system.num_elastic:]
        if self.reduced:
            full = elastic @ self.system.basis.T
        else:
            full = np.zeros((len(q), 6 * n_nodes))
            free = self.free_dofs
            if free.size:
                full[:, free] = elastic
        return full.reshape(len(q), n_nodes, 6)[:, :, :3]

    def simulate(self, t_end: float, dt: float, scheme=GeneralizedAlpha(0.8),
                 series: Optional[Callable[["Model", dict], dict]] = None,
                 units: Optional[dict] = None, metadata: Optional[dict] = None,
                 tolerance: Optional[float] = None, progress: Optional[bool] = None) -> Result:
        """Run from rest at the stowed configuration to ``t_end`` (s) with output step ``dt`` (s).

        ``tolerance`` (m or rad, absolute): error-controlled steps of at most ``dt``, keeping the
        local displacement error estimate h^2 |beta - 1/6| |a_n+1 - a_n| below it; None: fixed
        steps of ``dt``. Contact switches are located in time either way.

        ``progress``: a tqdm progress bar (True), none (False), or by default one only when
        standard error is a terminal (interactive use; scripts, notebooks' logs and CI stay
        quiet). Ctrl-C stops the run within 0.2 s with a SimulationError holding the results.

        ``series(model, raw)`` maps the engine's raw output (``t``, ``q``, ``v``, ``theta``,
        ``theta_rate``, ``spring_torque``, ``lock_force``, ``lock_torque``, ``kinetic_energy``,
        ``potential_energy``, ``linear_momentum``, ``angular_momentum``,
        ``base_angular_momentum``, ``base_linear_momentum``; momenta in world axes, angular about
        the world origin; the appendage's are the totals minus the base's) to the result's
        series; by default all of them are kept, with ``q`` and ``node_displacements``.
        Raises :class:`~deployfx.integrators.SimulationError` with ``.result`` (the series up to
        the failure) if a step cannot be completed, or if an undriven run's total energy grew by
        more than ``ENERGY_GROWTH_LIMIT`` of its peak kinetic energy (numerical divergence: the
        message gives the time).
        """
        t_end, dt, tol, scheme = _run_arguments(t_end, dt, scheme, tolerance)
        q0 = self.system.initial_positions()
        v0 = np.zeros(self.system.num_velocities)
        raw, wall = _timed_run(lambda progress: _core.simulate_hinged(
            self.system, q0, v0, t_end, dt, scheme._params(), tolerance=tol, progress=progress), t_end, progress)
        if series:
            out = series(self, raw)
        else:
            out = {k: raw[k] for k in _RAW_SERIES}
            out["q"] = raw["q"]
            out["node_displacements"] = self.node_displacements(raw["q"])
        meta = dict(self.description)
        meta.update(metadata or {})
        meta.update(model=self.fidelity, lock_play_deg=self.lock_play_deg)
        if self.reduced:
            info = self.basis_info
            meta.update(modes=info["modes"], static_corrections=info["static_corrections"],
                        modal_derivatives=info["modal_derivatives"], basis_size=info["size"])
        return _run_result(raw, out, units or _RAW_UNITS, meta, scheme, dt, t_end, tolerance, wall,
                           self.conservative)


_RAW_SERIES = ("t", "theta", "theta_rate", "spring_torque", "lock_force", "lock_torque", "kinetic_energy",
               "potential_energy", "linear_momentum", "angular_momentum", "base_angular_momentum",
               "base_linear_momentum")
_RAW_UNITS = {"q": "m, rad (base position, quaternion, hinge angle, elastic dofs)",
              "node_displacements": "m", "t": "s", "theta": "rad", "theta_rate": "rad/s", "spring_torque": "N m", "lock_force": "N",
              "lock_torque": "N m", "kinetic_energy": "J", "potential_energy": "J", "linear_momentum": "N s",
              "angular_momentum": "N m s", "base_angular_momentum": "N m s", "base_linear_momentum": "N s"}


class Scene:
    """A mutable builder; every ``set_*``/``add_*`` returns the scene, so calls chain.

    One hinge: ``set_base``, ``set_hinge``, ``set_appendage`` and optionally ``set_lock``. A chain of
    hinges (a yoke and panels, as on solar arrays): declare hinge 0 on the base (``set_hinge`` or
    ``add_hinge(parent="base", ...)``), then each further hinge on the previous body with
    ``add_hinge(parent=k - 1, ...)``; ``set_appendage``, ``set_lock`` and ``add_rigid_part(...,
    body=k)`` attach a panel, a lock or a rigid part (a yoke) to hinge k's body (by default the
    last hinge declared). A panel of a chain may be rigid, "reduced-linear" or "reduced-nonlinear"
    (a chain's Newton matrix is dense: the full models are refused there), and a flexible panel
    may carry the next hinge (attached to its nearest node, docs/research/flexible-chain.md).
    """

    def __init__(self) -> None:
        self._base: Optional[tuple] = None
        self._parts: list[RigidPart] = []
        # One entry per hinge: its hinge, appendage and lock dicts and the rigid parts on its body.
        self._links: list[dict] = [_new_link()]

    def _assign(self, k: int, key: str, value) -> None:
        """Hinge k's entry ``key`` = ``value``, copying the entries rather than changing them, so a
        shallow copy of the scene (copy.copy) keeps its own parts, as attributes did."""
        links = list(self._links)
        if k == len(links):
            links.append(_new_link())
        links[k] = dict(links[k], **{key: value})
        self._links = links

    # Hinge 0's parts, under the names a one-hinge scene has always used (deployfx.scene_file).
    _hinge = property(lambda self: self._links[0]["hinge"], lambda self, value: self._assign(0, "hinge", value))
    _appendage = property(lambda self: self._links[0]["appendage"],
                          lambda self, value: self._assign(0, "appendage", value))
    _lock = property(lambda self: self._links[0]["lock"], lambda self, value: self._assign(0, "lock", value))

    @property
    def num_hinges(self) -> int:
        """Hinges declared so far (0 before the first ``set_hinge``/``add_hinge``)."""
        return len(self._links) if self._links[0]["hinge"] is not None else 0

    def _index(self, hinge: Optional[int], what: str) -> int:
        """The index of hinge ``hinge`` (None: the last declared, or hinge 0 before any)."""
        if hinge is None:
            return len(self._links) - 1
        k = as_int(f"{what}.hinge", hinge)
        if not 0 <= k < len(self._links):
            raise ValueError(f"{what}.hinge = {k} is out of range: must be in [0, {len(self._links) - 1}] "
                             "(the hinges declared so far)")
        return k

    def set_base(self, mass: float, inertia, com: Sequence[float] = (0.0, 0.0, 0.0), free: bool = True) -> "Scene":
        """The spacecraft body: mass (kg), inertia about its centre of mass (kg m^2, B axes; a
        scalar means isotropic), centre of mass in B (m). ``free=False`` fixes it to the ground
        (then it has no coordinates and mass and inertia are ignored)."""
        part = RigidPart.make("base", mass, com, inertia)
        if free and part.mass <= 0:
            raise ValueError(f"base.mass = {part.mass} is out of range: must be > 0 (kg) for a free base")
        self._base = (part, bool(free))
        return self

    def add_rigid_part(self, mass: float, inertia, com: Sequence[float], body="base") -> "Scene":
        """A rigid part fixed to a body: mass (kg), inertia about its centre of mass (kg m^2, the
        body's axes), centre of mass (m, the body's frame). ``body``: ``"base"`` (B: a yoke fixed to
        the spacecraft) or a hinge index k (the body hinge k carries, in its frame: a yoke that
        deploys, a panel's frame or fittings)."""
        part = RigidPart.make("part", mass, com, inertia)
        if isinstance(body, str) and body == "base":
            self._parts.append(part)
        else:
            if isinstance(body, str):
                raise ValueError(f"part.body = {body!r} is invalid: must be 'base' or a hinge index")
            k = self._index(body, "part")
            self._assign(k, "parts", self._links[k]["parts"] + [part])
        return self

    def set_hinge(self, point: Sequence[float], axis: Sequence[float], R_BE0=np.eye(3), tau0: float = 0.0,
                  k_theta: float = 0.0, c_theta: float = 0.0, fitting_inertia=0.0, fitting_mass: float = 0.0,
                  fitting_com: Sequence[float] = (0.0, 0.0, 0.0),
                  spin_up: Optional[tuple[float, float]] = None) -> "Scene":
        """The revolute hinge on the base (hinge 0): a point of its axis (m, B) and the axis (unit,
        B); ``R_BE0`` the appendage frame's axes at theta = 0; spring torque ``tau0 - k_theta theta``
        (N m, N m/rad), viscous damping ``c_theta`` (N m s/rad). The fitting (the rigid part turning
        with E that the spring, damper and lock act on): inertia (kg m^2 about its centre of mass,
        E axes), mass (kg), centre of mass (m, E). ``spin_up=(omega_s, t_s)`` prescribes theta(t)
        instead (Kane, Ryan & Banerjee 1987: rad/s, s; one-hinge scenes only)."""
        hinge = _hinge_dict("hinge", point, axis, R_BE0, "R_BE0", tau0, k_theta, c_theta, fitting_inertia,
                            fitting_mass, fitting_com)
        if spin_up is not None:
            spin_up = (as_float("spin_up.omega_s", spin_up[0]), as_float("spin_up.t_s", spin_up[1]))
        hinge["spin_up"] = spin_up
        self._assign(0, "hinge", hinge)
        return self

    def add_hinge(self, parent, point: Sequence[float], axis: Sequence[float], R_PE0=np.eye(3),
                  tau0: float = 0.0, k_theta: float = 0.0, c_theta: float = 0.0, fitting_inertia=0.0,
                  fitting_mass: float = 0.0, fitting_com: Sequence[float] = (0.0, 0.0, 0.0)) -> "Scene":
        """The next hinge of a serial chain, on its ``parent``: ``"base"`` for hinge 0, else the
        index of the previous hinge (its body: k - 1 for hinge k). A point of the axis (m) and the
        unit axis in the parent's frame (B, or the previous hinge's frame E); ``R_PE0``: this hinge's
        frame E at theta = 0, in the parent's axes. Spring ``tau0 - k_theta theta`` (N m, N m/rad),
        damper ``c_theta`` (N m s/rad) and fitting (kg m^2 about its centre of mass, kg, m; E) as in
        :meth:`set_hinge`. Then ``set_appendage``, ``set_lock`` and ``add_rigid_part(body=k)`` fill
        this hinge's body."""
        n = self.num_hinges
        expected = "base" if n == 0 else n - 1
        allowed = ("'base' (the first hinge)" if n == 0 else
                   f"{n - 1} (the last hinge's body: deployfx builds serial chains)")
        if isinstance(parent, str):
            same = parent == expected
        else:
            same = expected != "base" and as_int("hinge.parent", parent) == expected
        if not same:
            raise ValueError(f"hinge.parent = {parent!r} is out of range: must be {allowed}")
        name = f"hinges[{n}]"
        hinge = _hinge_dict(name, point, axis, R_PE0, "R_PE0", tau0, k_theta, c_theta, fitting_inertia,
                            fitting_mass, fitting_com)
        hinge["spin_up"] = None
        self._assign(n, "hinge", hinge)
        return self

    def set_appendage(self, shell: ShellModel, fixed_dofs: Sequence[int], fidelity: str = "nonlinear",
                      damping: tuple[float, float] = (0.0, 0.0), modes: int = 10,
                      derivative_modes: Optional[int] = None, hinge: Optional[int] = None) -> "Scene":
        """The appendage: a shell mesh with node coordinates in E (m), the dofs clamped to E (its
        root edge) and the fidelity: "rigid" (one rigid body: the mesh's mass distribution),
        "linear" (linear strain) or "nonlinear" (Green strain, You et al. 2016 Eq. 14), or these
        two reduced, "reduced-linear" and "reduced-nonlinear": the elastic motion in a Ritz basis
        of ``modes`` clamped vibration modes plus the static corrections for the root's
        acceleration loads and, for Green strain, the modal derivatives of every pair among the
        first ``derivative_modes`` modes (None: min(modes, 6)), with the exact polynomial internal
        force in that basis (docs/engine-design.md).
        ``damping = (alpha_M, beta_K)``: structural Rayleigh damping C = alpha_M M + beta_K K
        (1/s, s), a modal damping ratio (alpha_M / omega + beta_K omega) / 2.
        ``hinge``: the hinge whose body the appendage is (None: the last hinge declared). A chain
        of several hinges takes "rigid", "reduced-linear" and "reduced-nonlinear" panels (its
        Newton matrix is dense: the full models would cost O(dofs^2); compile() says so)."""
        if not isinstance(shell, ShellModel):
            raise TypeError(f"shell must be a deployfx.ShellModel, got {type(shell).__name__}")
        if fidelity not in FIDELITIES:
            raise ValueError(f"fidelity = {fidelity!r} is invalid: must be one of {', '.join(FIDELITIES)}")
        fixed = sorted(set(as_int_sequence("fixed_dofs", fixed_dofs)))
        if fixed and (fixed[0] < 0 or fixed[-1] >= shell.num_dofs):
            raise ValueError(f"fixed_dofs must lie in [0, {shell.num_dofs})")
        if len(damping) != 2:
            raise ValueError(f"damping must be (alpha_M, beta_K), got {damping!r}")
        alpha_M, beta_K = (as_float(f"appendage.{k}", v) for k, v in zip(("alpha_M", "beta_K"), damping))
        modes = as_int("appendage.modes", modes)
        n_free = shell.num_dofs - len(fixed)
        if fidelity.startswith("reduced") and not 1 <= modes <= n_free:
            raise ValueError(f"appendage.modes = {modes} is out of range: must be in [1, {n_free}] "
                             "(the free dofs)")
        if derivative_modes is not None:
            derivative_modes = as_int("appendage.derivative_modes", derivative_modes)
            if not 0 <= derivative_modes <= modes:
                raise ValueError(f"appendage.derivative_modes = {derivative_modes} is out of range: must be "
                                 f"in [0, modes = {modes}] or None")
        self._assign(self._index(hinge, "appendage"), "appendage", dict(
            shell=shell, fixed=tuple(fixed), fidelity=fidelity, alpha_M=alpha_M, beta_K=beta_K, modes=modes,
            derivative_modes=derivative_modes))
        return self

    def set_lock(self, theta_lock: float, pin_radius: float, clearance: float, law: ContactLaw,
                 friction: Friction = Friction(0.0), hinge: Optional[int] = None) -> "Scene":
        """The lock: the pin (at ``pin_radius`` m from the axis) seats at hinge travel
        ``theta_lock`` (rad); ``clearance`` (m) is its play once latched; ``law`` the normal
        contact force, ``friction`` the groove's Coulomb friction (see joint/hinge_lock.hpp).
        ``hinge``: the hinge it locks (None: the last hinge declared)."""
        if not isinstance(law, ContactLaw):
            raise TypeError(f"law must be a deployfx.contact.ContactLaw, got {type(law).__name__}")
        if not isinstance(friction, Friction):
            raise TypeError(f"friction must be a deployfx.contact.Friction, got {type(friction).__name__}")
        self._assign(self._index(hinge, "lock"), "lock", dict(
            theta_lock=as_float("lock.theta_lock", theta_lock), pin_radius=as_float("lock.pin_radius", pin_radius),
            clearance=as_float("lock.clearance", clearance), law=law, friction=friction))
        return self

    def compile(self, description: Optional[dict] = None):
        """Validate and build the immutable model (ValueError names any bad parameter): a
        :class:`Model` for one hinge with an appendage, a :class:`~deployfx.chain.ChainModel` for a
        chain of several hinges (or one hinge carrying rigid parts only)."""
        if self._base is None:
            raise ValueError("the scene has no base: call set_base() first")
        first = self._links[0]
        if len(self._links) > 1 or (first["appendage"] is None and first["parts"]):  # a yoke alone, too
            from .chain import compile_chain

            return compile_chain(self._base, self._parts, self._links, description)
        for name in ("hinge", "appendage"):
            if self._links[0][name] is None:
                raise ValueError(f"the scene has no {name}: call set_{name}() first")
        base, free = self._base
        for p in self._parts:
            base = base + p
        h, a = self._hinge, self._appendage
        if h["spin_up"] is not None and self._lock is not None:
            raise ValueError("a hinge with a prescribed angle (spin_up) cannot have a lock")
        lock = _lock_spec(self._lock)
        f = h["fitting"]
        for p in self._links[0]["parts"]:  # parts on the hinge's body turn with E, as the fitting does
            f = f + p
        system = _core.HingedSystem(free, base.mass if free else 1.0, base.inertia if free else np.eye(3),
                                    h["point"], h["axis"], h["R_BE0"], h["tau0"], h["k_theta"], h["c_theta"],
                                    h["spin_up"], a["shell"]._impl, list(a["fixed"]), a["fidelity"],
                                    base_com=base.com, fitting_mass=f.mass, fitting_com=f.com,
                                    fitting_inertia=f.inertia, lock=lock, alpha_M=a["alpha_M"],
                                    beta_K=a["beta_K"], modes=a["modes"],
                                    derivative_modes=-1 if a["derivative_modes"] is None else a["derivative_modes"])
        return Model(system=system, shell=a["shell"], fidelity=a["fidelity"], base_free=free,
                     has_lock=lock is not None, fixed_dofs=a["fixed"], description=dict(description or {}),
                     hinge={k: h[k].copy() for k in ("point", "axis", "R_BE0")},
                     conservative=h["spin_up"] is None, lock_play_deg=_lock_play_deg(self._lock))


def _new_link() -> dict:
    return dict(hinge=None, appendage=None, lock=None, parts=[])


def _hinge_dict(name: str, point, axis, R, R_name: str, tau0, k_theta, c_theta, fitting_inertia,
                fitting_mass, fitting_com) -> dict:
    """A hinge's parameters, checked, with errors naming ``<name>.<parameter>``. The key ``R_BE0``
    holds the hinge frame's axes at theta = 0 in its parent's (B for hinge 0: set_hinge's R_BE0,
    add_hinge's R_PE0)."""
    axis = _vector(f"{name}.axis", axis)
    if abs(np.linalg.norm(axis) - 1) > 1e-9:
        raise ValueError(f"{name}.axis = {axis.tolist()} must be a unit vector")
    R = _matrix3(f"{name}.{R_name}", R)
    if np.abs(R.T @ R - np.eye(3)).max() > 1e-9 or np.linalg.det(R) < 0:
        raise ValueError(f"{name}.{R_name} must be a rotation matrix")
    fitting = RigidPart.make(f"{name}.fitting", fitting_mass, fitting_com, fitting_inertia)
    return dict(point=_vector(f"{name}.point", point), axis=axis, R_BE0=R,
                tau0=as_float(f"{name}.tau0", tau0), k_theta=as_float(f"{name}.k_theta", k_theta),
                c_theta=as_float(f"{name}.c_theta", c_theta), fitting=fitting)


def _lock_play_deg(lock: Optional[dict]) -> Optional[float]:
    """The lock's free play once latched, in degrees of hinge travel (clearance / pin radius);
    None without a lock."""
    return None if lock is None else float(np.degrees(lock["clearance"] / lock["pin_radius"]))


def _lock_spec(lock: Optional[dict]):
    """The engine's lock from the builder's dict (None: no lock)."""
    if lock is None:
        return None
    return _core.HingeLockSpec(lock["theta_lock"], lock["pin_radius"], lock["clearance"], lock["law"]._impl,
                               lock["friction"].mu, lock["friction"].v_reg)
