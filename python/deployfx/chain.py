"""A chain of hinges: a base (free-floating or fixed) carrying bodies in series on spring hinges,
as a solar array's yoke and panels (issue 5). Built with :class:`deployfx.Scene`
(``set_hinge``/``add_hinge``, then ``set_appendage``, ``set_lock``, ``add_rigid_part(body=k)``);
``Scene.compile()`` returns a :class:`ChainModel` when the scene has several hinges.

Frames: B the base; E_k hinge k's body frame, its origin on hinge k's axis, its axes
``R_PE_k(theta_k) = Rot(axis_k, theta_k) R_PE0_k`` in the parent P (B for hinge 0, E_{k-1} after).
A rigid appendage is the mass distribution of its mesh, merged with the hinge's fitting and the
parts on that body (parallel axes). A flexible one ("reduced-linear" or "reduced-nonlinear": see
CHAIN_FIDELITIES) is a panel in its floating frame E_k, root edge clamped to it, with its elastic coordinates appended to q after the
hinge angles, in hinge order; a hinge carried by a flexible panel rides on its deforming mesh,
bolted to the node nearest the hinge point (``ChainModel.attachment_nodes``) and rigid from there
to the hinge point (docs/research/flexible-chain.md). SI units.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from . import _core
from ._run import _run_arguments, _run_result, _timed_run, base_attitude_deg
from .integrators import GeneralizedAlpha
from .results import Result
from .scene import RigidPart, _lock_play_deg, _lock_spec

#: The appendage fidelities a chain takes (Scene.set_appendage): the full finite-element models
#: ("linear", "nonlinear") are refused, their dense Newton matrix being too costly.
CHAIN_FIDELITIES = ("rigid", "reduced-linear", "reduced-nonlinear")

#: Units of the series of :meth:`ChainModel.simulate` ((n, N): one column per hinge); a run with
#: flexible panels adds ``node_displacements_<k>`` (m) for each flexible panel k.
SERIES_UNITS = {
    "t": "s",
    "deployment_angle": "deg", "deployment_rate": "deg/s", "theta": "rad", "theta_rate": "rad/s",
    "spring_torque": "N m", "lock_force": "N", "lock_torque": "N m", "latched": "1",
    "body_attitude": "deg", "total_angular_momentum": "N m s", "body_angular_momentum": "N m s",
    "total_linear_momentum": "N s", "body_linear_momentum": "N s",
    "kinetic_energy": "J", "potential_energy": "J", "strain_energy": "J",
    "tip_displacement": "m", "tip_deflection": "m",
    "q": "m, rad (base position, quaternion, hinge angles, elastic coordinates)",
}


@dataclass(frozen=True)
class ChainModel:
    """A compiled chain of ``num_hinges`` bodies (rigid, or flexible panels) on spring hinges:
    immutable, reusable."""

    system: _core.HingeChain = field(repr=False)
    num_hinges: int
    base_free: bool
    locks: tuple  #: per hinge: True if it has a lock
    description: dict = field(default_factory=dict)
    #: Per hinge: ``point`` (m), unit ``axis`` and ``R_PE0`` in the parent's frame, and the body's
    #: ``mass`` (kg), ``com`` (m, E_k) and ``inertia`` (kg m^2 about the com, E_k axes), undeformed.
    hinges: tuple = field(default=(), repr=False)
    #: Per hinge: its lock's free play once latched, deg (clearance / pin radius); None: no lock.
    lock_play_deg: tuple = ()
    #: Per hinge: the :class:`~deployfx.ShellModel` of its panel (node coordinates in E_k, m), or
    #: None for a body without a panel (a yoke); to place the panels in world coordinates
    #: (deployfx.animation, deployfx.export).
    shells: tuple = field(default=(), repr=False)
    #: Per hinge: its panel's fidelity ("rigid", "linear", ..., see Scene.set_appendage), or None.
    fidelities: tuple = ()
    #: Per hinge: the tip node of its panel (the node farthest from the hinge axis, the one nearest
    #: the axis' foot among equals: the free edge's middle), whose displacement the
    #: ``tip_displacement`` and ``tip_deflection`` series give; -1 without a panel.
    tip_nodes: tuple = ()

    @property
    def flexible(self) -> tuple:
        """Per hinge: True if its body is a flexible panel (has elastic coordinates)."""
        return tuple(self.system.num_elastic(k) > 0 for k in range(self.num_hinges))

    @property
    def attachment_nodes(self) -> tuple:
        """Per hinge: the node of its flexible parent panel it is attached to (the node nearest its
        hinge point), or -1 (on the base or a rigid parent)."""
        return tuple(self.system.attachment_node(k) for k in range(self.num_hinges))

    def basis_info(self, hinge: int) -> Optional[dict]:
        """A reduced panel's basis: ``modes``, ``static_corrections`` and ``modal_derivatives``
        proposed, the ``size`` kept and its Ritz values ``omega2`` ((rad/s)^2); None otherwise.
        A panel carrying the next hinge adds six static corrections: unit loads at its attachment
        node."""
        return self.system.basis_info(_hinge_index(self, hinge))

    def node_displacements(self, q: np.ndarray, hinge: int) -> np.ndarray:
        """Hinge ``hinge``'s panel: node translations in its frame E_k (m), shape (len(q), nodes, 3),
        from recorded coordinates ``q`` (the raw ``q`` series); zeros for a rigid panel."""
        k = _hinge_index(self, hinge)
        shell = self.shells[k]
        if shell is None:
            raise ValueError(f"hinge = {k} carries no panel (set_appendage(..., hinge={k}))")
        q = np.atleast_2d(np.asarray(q, dtype=float))
        if q.shape[1] != self.system.num_positions:
            raise ValueError(f"q has {q.shape[1]} coordinates per sample, the model {self.system.num_positions}")
        n_nodes = shell.num_dofs // 6
        n = self.system.num_elastic(k)
        if n == 0:
            return np.zeros((len(q), n_nodes, 3))
        start = self.system.elastic_position(k)
        full = q[:, start:start + n] @ self.system.displacement_map(k).T
        return full.reshape(len(q), n_nodes, 6)[:, :, :3]

    def simulate(self, t_end: float, dt: float, scheme=GeneralizedAlpha(0.8), tolerance: Optional[float] = None,
                 progress: Optional[bool] = None, metadata: Optional[dict] = None,
                 q0: Optional[np.ndarray] = None, v0: Optional[np.ndarray] = None) -> Result:
        """Run to ``t_end`` (s) with output step ``dt`` (s), from rest at the stowed configuration
        unless ``q0``/``v0`` are given (``q = [r_W (m), quaternion (w, x, y, z)]`` for a free base,
        then the hinge angles (rad), then each flexible panel's elastic coordinates in hinge order
        (``system.elastic_position(k)``, ``system.num_elastic(k)``: Ritz coordinates, kg^0.5 m);
        ``v = [v_W (m/s), w_B (rad/s)]``, then the rates).
        ``scheme``, ``tolerance`` (m or rad; None: fixed steps), ``progress``: as
        :meth:`deployfx.Model.simulate`.

        The result's series (``(n, N)``: one column per hinge, in chain order):
        ``deployment_angle`` (deg, each hinge's travel from stowed) and ``deployment_rate``
        (deg/s), ``theta`` (rad) and ``theta_rate`` (rad/s), ``spring_torque`` (N m),
        ``lock_force`` (N, >= 0), ``lock_torque`` (N m), ``latched`` (1 once the hinge's lock has
        latched); ``body_attitude`` (deg, (n, 3): the base's rotation vector R_WB), momenta in W
        ((n, 3)): ``total_angular_momentum`` and ``body_angular_momentum`` (N m s, about W's
        origin; the body is the base), ``total_linear_momentum`` and ``body_linear_momentum``
        (N s); ``kinetic_energy`` and ``potential_energy`` (J, the springs and the panels' strain
        energy), ``strain_energy`` (J, per hinge: its panel's); per hinge, its panel's tip node
        (``tip_nodes``) in the panel's frame E_k: ``tip_displacement`` ((n, N, 3), m) and
        ``tip_deflection`` ((n, N), m: along the panel's normal there), zero for rigid bodies; for
        each flexible panel k, ``node_displacements_<k>`` ((n, nodes, 3), m, E_k axes); the raw
        ``q``.
        Raises :class:`~deployfx.integrators.SimulationError` (with ``.result``) as Model.simulate.
        """
        t_end, dt, tol, scheme = _run_arguments(t_end, dt, scheme, tolerance)
        q0 = self.system.initial_positions() if q0 is None else _state("q0", q0, self.system.num_positions)
        v0 = np.zeros(self.system.num_velocities) if v0 is None else _state("v0", v0, self.system.num_velocities)
        raw, wall = _timed_run(lambda progress: _core.simulate_chain(
            self.system, q0, v0, t_end, dt, scheme._params(), tolerance=tol, progress=progress), t_end, progress)
        meta = dict(self.description)
        meta.update(metadata or {})
        flexible = any(self.flexible)
        meta.update(model="flexible chain" if flexible else "rigid chain", hinges=self.num_hinges,
                    lock_play_deg=list(self.lock_play_deg), fidelities=list(self.fidelities))
        for k in range(self.num_hinges):
            info = self.system.basis_info(k)
            if info is not None:
                meta[f"basis_size_{k}"] = info["size"]
        series = self._series(raw)
        units = dict(SERIES_UNITS, **{k: "m" for k in series if k.startswith("node_displacements_")})
        return _run_result(raw, series, units, meta, scheme, dt, t_end, tolerance,
                           wall, conservative=True)

    def _series(self, raw: dict) -> dict:
        q = raw["q"]
        attitude = base_attitude_deg(q, self.base_free)
        n, N = len(q), self.num_hinges
        tip = np.zeros((n, N, 3))
        deflection = np.zeros((n, N))
        panels = {}
        for k, shell in enumerate(self.shells):
            if shell is None or self.system.num_elastic(k) == 0:
                continue
            u = self.node_displacements(q, k)
            panels[f"node_displacements_{k}"] = u
            tip[:, k] = u[:, self.tip_nodes[k]]
            deflection[:, k] = tip[:, k] @ _node_normal(shell, self.tip_nodes[k])
        return {
            "t": raw["t"],
            "deployment_angle": np.degrees(raw["theta"]),
            "deployment_rate": np.degrees(raw["theta_rate"]),
            "theta": raw["theta"], "theta_rate": raw["theta_rate"],
            "spring_torque": raw["spring_torque"], "lock_force": raw["lock_force"],
            "lock_torque": raw["lock_torque"], "latched": raw["latched"],
            "body_attitude": attitude,
            "total_angular_momentum": raw["angular_momentum"],
            "body_angular_momentum": raw["base_angular_momentum"],
            "total_linear_momentum": raw["linear_momentum"],
            "body_linear_momentum": raw["base_linear_momentum"],
            "kinetic_energy": raw["kinetic_energy"], "potential_energy": raw["potential_energy"],
            "strain_energy": raw["strain_energy"], "tip_displacement": tip, "tip_deflection": deflection,
            **panels,
            "q": q,
        }


def _hinge_index(model: ChainModel, hinge) -> int:
    if isinstance(hinge, bool) or not isinstance(hinge, (int, np.integer)):
        raise TypeError(f"hinge must be a hinge index (int), got {type(hinge).__name__}")
    if not 0 <= hinge < model.num_hinges:
        raise ValueError(f"hinge = {hinge} is out of range: must be in [0, {model.num_hinges - 1}]")
    return int(hinge)


def _tip_node(shell, axis_E: np.ndarray) -> int:
    """The node farthest from the hinge axis (through E's origin along ``axis_E``); among those
    within 1e-9 of the farthest, the one nearest the axis' foot (the free edge's middle)."""
    X = np.asarray(shell.nodes, dtype=float)
    along = X @ axis_E
    dist = np.linalg.norm(X - np.outer(along, axis_E), axis=1)
    far = np.flatnonzero(dist >= dist.max() - 1e-9 * max(dist.max(), 1.0))
    return int(far[np.argmin(np.abs(along[far]))])


def _node_normal(shell, node: int) -> np.ndarray:
    """The unit normal of the first quad holding ``node`` (the cross product of its diagonals)."""
    X = np.asarray(shell.nodes, dtype=float)
    quads = np.asarray(shell.quads, dtype=int)
    quad = quads[np.flatnonzero((quads == node).any(axis=1))[0]]
    n = np.cross(X[quad[2]] - X[quad[0]], X[quad[3]] - X[quad[1]])
    return n / np.linalg.norm(n)


def _state(name: str, value, n: int) -> np.ndarray:
    a = np.asarray(value, dtype=float)
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be {n} finite numbers, got shape {a.shape}")
    return a


def rigid_appendage(shell) -> RigidPart:
    """The undeformed mesh of a :class:`~deployfx.ShellModel` as one rigid body in its frame:
    mass (kg), centre of mass (m) and inertia about it (kg m^2), from its floating-frame shape
    integrals (the mass, first moment S0 and inertia J0 about the frame's origin; parallel axes)."""
    ffi = shell.floating_frame_inertia()
    m = float(ffi.mass)
    c = np.asarray(ffi.S0) / m
    J = np.asarray(ffi.J0) - m * (c @ c * np.eye(3) - np.outer(c, c))
    return RigidPart(m, c, 0.5 * (J + J.T))


def compile_chain(base: tuple, base_parts: list, links: list, description: Optional[dict]) -> ChainModel:
    """The :class:`ChainModel` of a Scene's base, base parts and hinge entries (``Scene.compile``)."""
    body, free = base
    for p in base_parts:
        body = body + p
    specs, geometry, fidelities, tips = [], [], [], []
    for k, link in enumerate(links):
        h, a = link["hinge"], link["appendage"]
        if h is None:
            raise ValueError("the scene has no hinge 0: call set_hinge() or add_hinge(parent='base') first")
        if h["spin_up"] is not None:
            raise ValueError("hinges[0].spin_up: a prescribed hinge angle is for one-hinge scenes; a chain of "
                             "several hinges has spring hinges only")
        rigid = h["fitting"]
        for p in link["parts"]:
            rigid = rigid + p
        total, panel = rigid, {}
        if a is not None:
            total = rigid + rigid_appendage(a["shell"])
            if a["fidelity"] not in CHAIN_FIDELITIES:
                raise ValueError(f"hinges[{k}] appendage fidelity = {a['fidelity']!r} is not supported in a chain: "
                                 f"must be one of {', '.join(map(repr, CHAIN_FIDELITIES))} (a chain's Newton matrix "
                                 f"is dense, so the full finite-element models cost O(dofs^2) per matrix; rigid "
                                 f"panels only, or reduced ones)")
            if a["fidelity"] == "rigid":
                rigid = total
            else:  # a flexible panel in E_k: the engine compiles its shape integrals and basis
                panel = dict(shell=a["shell"]._impl, fixed_dofs=list(a["fixed"]), fidelity=a["fidelity"],
                             alpha_M=a["alpha_M"], beta_K=a["beta_K"], modes=a["modes"],
                             derivative_modes=-1 if a["derivative_modes"] is None else a["derivative_modes"])
        if total.mass == 0 and not np.any(total.inertia):
            raise ValueError(f"hinges[{k}] carries no body: give it an appendage (set_appendage(..., hinge={k})), "
                             f"a rigid part (add_rigid_part(..., body={k})) or a fitting")
        try:
            lock = _lock_spec(link["lock"])
        except ValueError as e:
            raise ValueError(f"hinges[{k}].{e}") from None
        specs.append(_core.ChainHingeSpec(h["point"], h["axis"], h["R_BE0"], h["tau0"], h["k_theta"],
                                          h["c_theta"], rigid.mass, rigid.com, rigid.inertia, lock=lock, **panel))
        geometry.append({"point": h["point"].copy(), "axis": h["axis"].copy(), "R_PE0": h["R_BE0"].copy(),
                         "mass": total.mass, "com": total.com.copy(), "inertia": total.inertia.copy()})
        fidelities.append(None if a is None else a["fidelity"])
        tips.append(-1 if a is None else _tip_node(a["shell"], h["R_BE0"].T @ h["axis"]))
    system = _core.HingeChain(free, body.mass if free else 1.0, body.inertia if free else np.eye(3),
                              base_com=body.com, hinges=specs)
    return ChainModel(system=system, num_hinges=len(specs), base_free=free,
                      locks=tuple(link["lock"] is not None for link in links),
                      description=dict(description or {}), hinges=tuple(geometry),
                      lock_play_deg=tuple(_lock_play_deg(link["lock"]) for link in links),
                      shells=tuple(None if link["appendage"] is None else link["appendage"]["shell"]
                                   for link in links),
                      fidelities=tuple(fidelities), tip_nodes=tuple(tips))
