"""A chain of hinges: a base (free-floating or fixed) carrying rigid bodies in series on spring
hinges, as a solar array's yoke and panels (issue 5). Built with :class:`deployfx.Scene`
(``set_hinge``/``add_hinge``, then ``set_appendage``, ``set_lock``, ``add_rigid_part(body=k)``);
``Scene.compile()`` returns a :class:`ChainModel` when the scene has several hinges.

Frames: B the base; E_k hinge k's body frame, its origin on hinge k's axis, its axes
``R_PE_k(theta_k) = Rot(axis_k, theta_k) R_PE0_k`` in the parent P (B for hinge 0, E_{k-1} after).
Every body of a chain is rigid: a rigid appendage is the mass distribution of its mesh, merged with
the hinge's fitting and the parts on that body (parallel axes). SI units.
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

#: Units of the series of :meth:`ChainModel.simulate` ((n, N): one column per hinge).
SERIES_UNITS = {
    "t": "s",
    "deployment_angle": "deg", "deployment_rate": "deg/s", "theta": "rad", "theta_rate": "rad/s",
    "spring_torque": "N m", "lock_force": "N", "lock_torque": "N m", "latched": "1",
    "body_attitude": "deg", "total_angular_momentum": "N m s", "body_angular_momentum": "N m s",
    "total_linear_momentum": "N s", "body_linear_momentum": "N s",
    "kinetic_energy": "J", "potential_energy": "J",
    "q": "m, rad (base position, quaternion, hinge angles)",
}


@dataclass(frozen=True)
class ChainModel:
    """A compiled chain of ``num_hinges`` rigid bodies on spring hinges: immutable, reusable."""

    system: _core.HingeChain = field(repr=False)
    num_hinges: int
    base_free: bool
    locks: tuple  #: per hinge: True if it has a lock
    description: dict = field(default_factory=dict)
    #: Per hinge: ``point`` (m), unit ``axis`` and ``R_PE0`` in the parent's frame, and the body's
    #: ``mass`` (kg), ``com`` (m, E_k) and ``inertia`` (kg m^2 about the com, E_k axes).
    hinges: tuple = field(default=(), repr=False)
    #: Per hinge: its lock's free play once latched, deg (clearance / pin radius); None: no lock.
    lock_play_deg: tuple = ()
    #: Per hinge: the :class:`~deployfx.ShellModel` of its rigid panel (node coordinates in E_k, m),
    #: or None for a body without a panel (a yoke); to place the panels in world coordinates
    #: (deployfx.animation, deployfx.export).
    shells: tuple = field(default=(), repr=False)

    def simulate(self, t_end: float, dt: float, scheme=GeneralizedAlpha(0.8), tolerance: Optional[float] = None,
                 progress: Optional[bool] = None, metadata: Optional[dict] = None,
                 q0: Optional[np.ndarray] = None, v0: Optional[np.ndarray] = None) -> Result:
        """Run to ``t_end`` (s) with output step ``dt`` (s), from rest at the stowed configuration
        unless ``q0``/``v0`` are given (``q = [r_W (m), quaternion (w, x, y, z)]`` for a free base,
        then the hinge angles (rad); ``v = [v_W (m/s), w_B (rad/s)]``, then the rates (rad/s)).
        ``scheme``, ``tolerance`` (m or rad; None: fixed steps), ``progress``: as
        :meth:`deployfx.Model.simulate`.

        The result's series (``(n, N)``: one column per hinge, in chain order):
        ``deployment_angle`` (deg, each hinge's travel from stowed) and ``deployment_rate``
        (deg/s), ``theta`` (rad) and ``theta_rate`` (rad/s), ``spring_torque`` (N m),
        ``lock_force`` (N, >= 0), ``lock_torque`` (N m), ``latched`` (1 once the hinge's lock has
        latched); ``body_attitude`` (deg, (n, 3): the base's rotation vector R_WB), momenta in W
        ((n, 3)): ``total_angular_momentum`` and ``body_angular_momentum`` (N m s, about W's
        origin; the body is the base), ``total_linear_momentum`` and ``body_linear_momentum``
        (N s); ``kinetic_energy`` and ``potential_energy`` (J, the springs); the raw ``q``.
        Raises :class:`~deployfx.integrators.SimulationError` (with ``.result``) as Model.simulate.
        """
        t_end, dt, tol, scheme = _run_arguments(t_end, dt, scheme, tolerance)
        q0 = self.system.initial_positions() if q0 is None else _state("q0", q0, self.system.num_positions)
        v0 = np.zeros(self.system.num_velocities) if v0 is None else _state("v0", v0, self.system.num_velocities)
        raw, wall = _timed_run(lambda progress: _core.simulate_chain(
            self.system, q0, v0, t_end, dt, scheme._params(), tolerance=tol, progress=progress), t_end, progress)
        meta = dict(self.description)
        meta.update(metadata or {})
        meta.update(model="rigid chain", hinges=self.num_hinges, lock_play_deg=list(self.lock_play_deg))
        return _run_result(raw, self._series(raw), dict(SERIES_UNITS), meta, scheme, dt, t_end, tolerance,
                           wall, conservative=True)

    def _series(self, raw: dict) -> dict:
        q = raw["q"]
        attitude = base_attitude_deg(q, self.base_free)
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
            "q": q,
        }


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
    specs, geometry = [], []
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
        if a is not None:
            if a["fidelity"] != "rigid":
                raise ValueError(f"hinges[{k}] appendage fidelity = {a['fidelity']!r} is not supported in a chain: "
                                 f"a chain of several hinges takes rigid panels only (fidelity='rigid'); "
                                 f"flexible panels are for one-hinge scenes")
            rigid = rigid + rigid_appendage(a["shell"])
        if rigid.mass == 0 and not np.any(rigid.inertia):
            raise ValueError(f"hinges[{k}] carries no body: give it an appendage (set_appendage(..., hinge={k})), "
                             f"a rigid part (add_rigid_part(..., body={k})) or a fitting")
        try:
            lock = _lock_spec(link["lock"])
        except ValueError as e:
            raise ValueError(f"hinges[{k}].{e}") from None
        specs.append(_core.ChainHingeSpec(h["point"], h["axis"], h["R_BE0"], h["tau0"], h["k_theta"],
                                          h["c_theta"], rigid.mass, rigid.com, rigid.inertia, lock=lock))
        geometry.append({"point": h["point"].copy(), "axis": h["axis"].copy(), "R_PE0": h["R_BE0"].copy(),
                         "mass": rigid.mass, "com": rigid.com.copy(), "inertia": rigid.inertia.copy()})
    system = _core.HingeChain(free, body.mass if free else 1.0, body.inertia if free else np.eye(3),
                              base_com=body.com, hinges=specs)
    return ChainModel(system=system, num_hinges=len(specs), base_free=free,
                      locks=tuple(link["lock"] is not None for link in links),
                      description=dict(description or {}), hinges=tuple(geometry),
                      lock_play_deg=tuple(_lock_play_deg(link["lock"]) for link in links),
                      shells=tuple(None if link["appendage"] is None else link["appendage"]["shell"]
                                   for link in links))
