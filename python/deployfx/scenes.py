"""Ready scenes, built with :class:`deployfx.scene.Scene` like any user scene.

- :func:`paper2016`: You et al. (2016), a laminated appendage deploying from a free-floating
  spacecraft and slamming into its lock (numbers: ``shared/design/paper2016-scenario.md``).
- :func:`spin_up_beam`: the spin-up beam of Kane, Ryan & Banerjee (1987), J. Guid. Control Dyn.
  10(2), 139-151: a cantilever on a hub whose rate is ramped to omega_s over t_s.

Units: the paper's N mm and degrees are converted here; everything inside is SI.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Optional, Sequence, Union

import numpy as np

from . import _node_rows
from . import paper2016 as _paper
from ._checks import check_field_types
from .contact import ContactLaw, Friction
from .groove import PinGroove
from .integrators import GeneralizedAlpha, SimulationError
from .materials import Isotropic, Laminate, Ply
from .model import Model
from .plate import Plate, ShellModel
from .results import Result
from .scene import Scene
from .specs import Fidelity, Lock
from .strengths import Strengths

N_MM_PER_DEG = 1e-3 * 180.0 / np.pi  # 1 N mm/deg in N m/rad


def _Ry(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _transverse(translations: _node_rows.NodeTranslations, q: np.ndarray) -> np.ndarray:
    """Mean transverse displacement (m, the panel frame's z) of the nodes of ``translations``
    (_node_rows.node_translations) from the recorded coordinates."""
    z = translations(q)[:, :, 2]
    return np.add.reduce(z, axis=1) / z.shape[1]  # np.mean's sum and division, without its overhead


# --------------------------------------------------------------------------------------------
# You et al. (2016)

@dataclass(frozen=True)
class Paper2016Parameters:
    """The paper's scene (Tables 1-2 and text) in SI; fields marked *choice* are deployfx's
    where the paper is silent (paper2016-scenario.md)."""

    layup: int = 2
    model: str = "nonlinear"
    nx: int = _paper.NX                         #: elements along the 2.0 m length
    ny: int = _paper.NY                         #: elements across the 1.3 m width
    body_mass: float = 3000.0                   #: kg
    body_inertia: float = 500.0                 #: kg m^2 (Jxx = Jyy = Jzz)
    yoke_mass: float = 2.0                      #: kg
    yoke_inertia: tuple = (1.0, 1.0, 0.5)       #: kg m^2 about its centre of mass
    yoke_com_x: float = 0.815                   #: m from the body centroid (choice)
    hinge_x: float = 0.83                       #: m, l_b + a_h
    root_offset: float = 0.03                   #: m, b_h: hinge axis to the root edge
    tau0: float = 7200.0 * 1e-3                 #: N m (7200 N mm)
    k_theta: float = 80.0 * N_MM_PER_DEG        #: N m/rad (80 N mm/deg)
    c_theta: float = 0.0                        #: N m s/rad
    fitting_inertia: float = 0.02               #: kg m^2, hinge fitting (choice, docs/engine-design.md)
    lock: bool = True
    pin_radius: float = 0.03                    #: m (choice)
    clearance: float = 0.2e-3                   #: m, play once latched (choice)
    contact: ContactLaw = ContactLaw("paper", K=1e6 / (1e-3) ** 1.5, n=1.5, D=1e6)  #: 1e6 N/mm^1.5, 1e3 N s/mm
    friction: Friction = Friction(0.25)         #: mu = 0.25
    #: The lock's geometry: "groove" (default), the paper's "cylindrical pin slides along the
    #: locking groove": a pin on a latch spring riding a track into a notch, friction along the
    #: groove's tangent (Eq. 45; deployfx.groove.PinGroove.paper, docs/research/pin-groove.md); or
    #: "stop-latch", walls in the hinge angle (a stop at 180 deg, a latch one clearance before it)
    #: whose friction acts along the pin's path, i.e. as extra impact damping (the default before
    #: session 17).
    lock_geometry: str = "groove"
    base_free: bool = True
    #: Structural damping of the appendage, Rayleigh (alpha_M 1/s, beta_K s) (choice): the paper
    #: gives none, yet its vibration decays and it reports a steady state from 19.12 s, which
    #: needs dissipation besides the lock's (undamped, the panel rings and the pin taps in its
    #: play for ever; README). alpha_M = 0.7 1/s is 7 % of critical at the first clamped mode of
    #: lay-up 2 (0.80 Hz; lay-up 1: 0.85 Hz, 6.5 %), 4 % at the second, less above
    #: (zeta = alpha_M / (2 omega)); the 6 x 4 scene then settles at 16.6 s (5 %: 21.8 s, 10 %:
    #: 13.3 s; on the stop-and-latch walls 17.9 s). Mass-proportional, because stiffness-proportional damping over-damps the stiff
    #: root modes (zeta ~ 100) and generalized-alpha then overshoots in energy at large steps.
    #: (0, 0): the paper's undamped equations.
    damping: tuple = (0.7, 0.0)
    #: Reduced models: clamped vibration modes in the Ritz basis (Scene.set_appendage).
    modes: int = 10
    derivative_modes: Optional[int] = None      #: None: min(modes, 3) (Scene.set_appendage)
    derivative_partners: Optional[int] = None   #: None: 1 (Scene.set_appendage)
    #: 1: the paper's spacecraft; 2: a second, mirrored yoke and appendage on the opposite side of
    #: the base (hinge at (-hinge_x, 0, 0)), deploying at the same time (hinge 1).
    wings: int = 1
    #: The plies' strength allowables (deployfx.Strengths, Pa) for the ply failure envelope
    #: (``simulate(..., stresses=True)``); the paper gives none for IM6/SC1081, nor does deployfx.
    strengths: Union[Strengths, Sequence[Strengths], None] = None  #: one for all plies, or one per ply

    def __post_init__(self) -> None:
        check_field_types(self)  # lock='no' is an error, not a lock (issue 29)


def _parameters(p: Paper2016Parameters) -> dict:
    """The parameters as JSON values (Result.settings): the contact law and friction as a scene
    file writes them (deployfx.scene_file), strengths as their fields."""
    from .scene_file import _write_friction, _write_law

    def value(v):
        if isinstance(v, ContactLaw):
            return _write_law(v)
        if isinstance(v, Friction):
            return _write_friction(v)
        if isinstance(v, Strengths):  # its fields, not the core object it keeps
            return {f.name: getattr(v, f.name) for f in dataclasses.fields(v) if f.init}
        if isinstance(v, (list, tuple)):
            return [value(x) for x in v]
        return v

    return {f.name: value(getattr(p, f.name)) for f in dataclasses.fields(p)}


class Paper2016Scene:
    """The compiled scene; :meth:`simulate` returns the paper's series (issue 4) in the one
    vocabulary of :mod:`deployfx.results`, plus ``node_E_deflection`` and ``node_mid_deflection``
    (m, (n,): hinge 0's panel, transverse, its frame's z)."""

    def __init__(self, p: Paper2016Parameters):
        fidelity = Fidelity.parse(p.model, "model")
        if p.lock_geometry not in ("stop-latch", "groove"):
            raise ValueError(f"lock_geometry = {p.lock_geometry!r} is invalid: must be 'stop-latch' or 'groove'")
        if isinstance(p.wings, bool) or p.wings not in (1, 2):
            raise ValueError(f"wings = {p.wings!r} is out of range: must be 1 or 2")
        self.parameters = p
        plate = _paper.appendage_plate(p.layup, p.nx, p.ny)
        nodes = plate.model.nodes.copy()
        nodes[:, 0] += p.root_offset        # root edge b_h from the hinge axis
        nodes[:, 1] -= _paper.WIDTH / 2     # centred on the hinge point
        shell = ShellModel(nodes, plate.model.quads, plate.laminate)
        fixed = plate.fixed_dofs("CFFF")
        scene = Scene().set_base(p.body_mass, p.body_inertia, free=p.base_free)
        # Wing 1 along +x; wing 2 its mirror image through the base's y-z plane: the hinge axis -y
        # and the panel frame's y flipped, so that both frames stay right-handed.
        R_mirror = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])
        for wing, (sign, R_BE0) in enumerate([(1.0, _Ry(-np.pi / 2)), (-1.0, R_mirror)][:p.wings]):
            scene.add_rigid_part(p.yoke_mass, np.diag(p.yoke_inertia), (sign * p.yoke_com_x, 0.0, 0.0))
            scene.add_hinge("base", point=(sign * p.hinge_x, 0.0, 0.0), axis=(0.0, sign, 0.0), R_PE0=R_BE0,
                            tau0=p.tau0, k_theta=p.k_theta, c_theta=p.c_theta, fitting_inertia=p.fitting_inertia,
                            stowed_angle_deg=90.0)
            scene.set_appendage(shell, fixed, fidelity=fidelity, damping=p.damping, modes=p.modes,
                                derivative_modes=p.derivative_modes, strengths=p.strengths,
                                derivative_partners=p.derivative_partners)
            if p.lock:
                # Either geometry: the pin seats at 180 deg, pin_radius from the axis, with
                # clearance of play (Lock checks both, naming them, for the groove too).
                lock = Lock(np.pi / 2, p.pin_radius, p.clearance, p.contact, p.friction)
                if p.lock_geometry == "groove":
                    scene.set_groove(PinGroove.paper(p.contact, p.friction, seat=lock.pin_radius,
                                                     clearance=lock.clearance))
                else:
                    scene.set_lock(lock.theta_lock, lock.pin_radius, lock.clearance, p.contact, friction=p.friction)
        self.scene = scene  #: the :class:`Scene` before compile (e.g. for deployfx.save_scene)
        self.model = scene.compile(description={"scene": "paper2016", "layup": p.layup, "mesh": f"{p.nx}x{p.ny}",
                                                "model": str(fidelity), "wings": p.wings,
                                                "parameters": _parameters(p)})
        # Node E: the free-end corner (x = L, y = W); also the free end's mid-width node.
        self.node_E = p.ny * (p.nx + 1) + p.nx
        self.node_mid = (p.ny // 2) * (p.nx + 1) + p.nx
        self._translations = tuple(_node_rows.node_translations(self.model, 0, [node]) for node in (self.node_E, self.node_mid))

    def _series(self, model: Model, raw: dict) -> dict:
        E, mid = self._translations  # of self.model, the one model that calls this
        return {"node_E_deflection": _transverse(E, raw["q"]), "node_mid_deflection": _transverse(mid, raw["q"])}

    UNITS = {"node_E_deflection": "m", "node_mid_deflection": "m"}

    def simulate(self, t_end: float = 30.0, dt: float = 0.01, *, scheme=GeneralizedAlpha(0.8),
                 tolerance: Optional[float] = None, progress: Optional[bool] = None, **options) -> Result:
        """Deployment from stowed (90 deg) at rest for ``t_end`` s with output step ``dt`` s: the
        series of :mod:`deployfx.results` (``deployment_angle`` 90 stowed, 180 deployed, per hinge)
        and ``node_E_deflection``, ``node_mid_deflection`` (m). ``scheme``, ``tolerance``,
        ``progress`` and further ``options`` (``nodes``, ``stop``, ``q0``, ...): see
        :meth:`deployfx.Model.simulate`."""
        return self.model.simulate(t_end, dt, scheme=scheme, series=self._series, units=self.UNITS,
                                   tolerance=tolerance, progress=progress, **options)


def paper2016(layup: int = 2, model: str = "nonlinear", **overrides) -> Paper2016Scene:
    """You et al. (2016): lay-up 1 ([0/0/0/0]) or 2 ([0/90/90/0]); model (a
    :class:`~deployfx.specs.Fidelity`) "rigid", "linear", "nonlinear", "reduced-linear",
    "reduced-nonlinear" or "reduced-manifold" (the reduced ones with ``modes=k``; the panel is flat
    and both lay-ups symmetric, as the manifold needs); ``wings=2`` adds the mirrored second wing; any field
    of :class:`Paper2016Parameters` may be overridden by keyword."""
    names = {f.name for f in dataclasses.fields(Paper2016Parameters)}
    unknown = sorted(set(overrides) - names)
    if unknown:
        raise TypeError(f"paper2016() got unknown parameters {unknown}; allowed: {sorted(names)}")
    if layup not in _paper.LAYUPS:
        raise ValueError(f"layup = {layup!r} is out of range: must be 1 or 2")
    return Paper2016Scene(Paper2016Parameters(layup=layup, model=model, **overrides))


# --------------------------------------------------------------------------------------------
# Kane, Ryan & Banerjee (1987)

#: The beam: L (m), EI (N m^2), rho A (kg/m), EA (N).
SPIN_UP_BEAM = {"L": 10.0, "EI": 1.4e4, "rhoA": 1.2, "EA": 2.8e7}


def spin_up_strip(nx: int = 20, width: float = 0.2) -> Plate:
    """The spin-up beam as a plate strip with the beam's EA, EI and rho A: an isotropic strip
    (nu = 0, so the plate's D b is the beam's EI) of thickness h = sqrt(12 EI/EA) = 77.5 mm,
    E = EA/(b h) and rho = rho A/(b h); one element across the ``width`` b (m)."""
    L, EI, rhoA, EA = (SPIN_UP_BEAM[k] for k in ("L", "EI", "rhoA", "EA"))
    h = np.sqrt(12 * EI / EA)
    material = Isotropic(E=EA / (width * h), nu=0.0, rho=rhoA / (width * h))
    return Plate(L, width, Laminate([Ply(material, h, 0.0)]), nx, 1)


class SpinUpBeamScene:
    """The compiled spin-up beam; :meth:`simulate` returns the series of :mod:`deployfx.results`:
    ``tip_deflection`` ((n, 1), m: the tip's deflection in the plane of rotation, positive in the
    direction of rotation as in Kane et al.) and ``deployment_angle`` (deg, the hub angle)."""

    def __init__(self, omega_s: float, t_s: float, model: str, nx: int):
        strip = spin_up_strip(nx)
        self.omega_s, self.t_s = omega_s, t_s
        self.length = SPIN_UP_BEAM["L"]
        # Fixed hub; the beam along E's x, bending in the plane of rotation (E's z): the hinge
        # axis is E's y, the strip's width direction.
        self.model = (Scene()
                      .set_base(1.0, 1.0, free=False)
                      .set_hinge(point=(0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0), spin_up=(omega_s, t_s))
                      .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity=model)
                      .compile(description={"scene": "spin_up_beam", "omega_s": omega_s, "t_s": t_s,
                                            "mesh": f"{nx}x1", "model": model,
                                            "parameters": {"omega_s_rad_per_s": omega_s, "t_s_s": t_s,
                                                           "model": model, "nx": nx, **SPIN_UP_BEAM}}))

    def simulate(self, t_end: float = 30.0, dt: float = 0.01, *, scheme=GeneralizedAlpha(0.9),
                 divergence_limit: Optional[float] = None, tolerance: Optional[float] = None,
                 newton_tolerance: Optional[float] = None, checkpoint_at=None, resume=None) -> Result:
        """Spin-up from rest. A run whose tip leaves ``divergence_limit`` (m, default L/2: far
        beyond small-strain validity) is divergent: :class:`~deployfx.integrators.SimulationError`
        says when, with the series up to then in ``.result`` (the linear model above
        omega_1 = 3.80 rad/s). ``tolerance``, ``newton_tolerance``, ``checkpoint_at``, ``resume``: see
        :meth:`deployfx.Model.simulate`."""
        limit = 0.5 * self.length if divergence_limit is None else float(divergence_limit)
        try:
            result = self.model.simulate(t_end, dt, scheme=scheme, tolerance=tolerance,
                                         newton_tolerance=newton_tolerance, checkpoint_at=checkpoint_at, resume=resume)
        except SimulationError as e:
            result, failure = e.result, str(e)
        else:
            failure = ""
        tip = result.tip_deflection[:, 0]
        out = np.flatnonzero(np.abs(tip) > limit)
        if out.size:
            k = int(out[0])
            t_div = float(result.t[k])
            kept = {name: result[name][: k + 1] for name in result.series}
            meta = result.metadata
            meta["failure"] = (f"diverged: |tip deflection| = {abs(tip[k]):.3g} m > {limit:g} m at "
                               f"t = {t_div:.4g} s (model {self.model.fidelities[0]})")
            partial = Result(kept, units=result.units, metadata=meta)
            raise SimulationError(meta["failure"] + ("; the linear model softens as K - Omega^2 M and "
                                  "diverges above the first bending frequency, 3.80 rad/s"
                                  if self.model.fidelities[0] == "linear" else ""), partial)
        if failure:
            raise SimulationError(failure, result)
        return result


def spin_up_beam(omega_s: float, t_s: float = 15.0, model: str = "nonlinear", nx: int = 20) -> SpinUpBeamScene:
    """Kane, Ryan & Banerjee (1987): hub rate Omega(t) = (omega_s/t_s)[t - (t_s/2 pi)
    sin(2 pi t/t_s)] for t <= t_s, then omega_s (rad/s, s); model: any deforming
    :class:`~deployfx.specs.Fidelity` ("linear", "nonlinear", or these reduced, or
    "reduced-manifold"); ``nx`` elements along the 10 m beam."""
    fidelity = Fidelity.parse(model, "model")
    if not fidelity.deforms:
        raise ValueError(f"model = {model!r} is invalid: the spin-up beam must deform (any fidelity but 'rigid')")
    return SpinUpBeamScene(float(omega_s), float(t_s), str(fidelity), int(nx))
