"""Contact laws of the hinge lock: normal force laws, regularised Coulomb friction and the
1-DOF impact that characterises them. SI units: m, m/s, N, kg, s, J.

Normal force for penetration ``delta`` (m, > 0 in contact) and penetration rate ``delta_dot``
(m/s, > 0 approaching), never pulling (``F = max(F, 0)``, ``F = 0`` for ``delta <= 0``):

- ``"kelvin-voigt-hertz"`` (alias ``"paper"``, You et al. 2016): F = K delta^n + D delta_dot;
- ``"hunt-crossley"`` (Hunt & Crossley 1975): F = K delta^n (1 + 3 (1 - e)/2 delta_dot / v0);
- ``"lankarani-nikravesh"`` (Lankarani & Nikravesh 1990): c = 3 (1 - e^2)/4 in place of 3 (1 - e)/2;
- ``"flores"`` (Flores, Machado, Silva & Martins 2011): c = 8 (1 - e)/(5 e).

``v0`` (m/s) is the approach speed at contact onset, which the caller keeps per contact. The
restitution a Hunt-Crossley-type law really gives follows from x - ln(1 + x) = -e x - ln(1 - e x)
with x = c (see :func:`impact` and docs/research/engine-references.md Sec. 4): only Flores comes
close to the ``e`` it is tuned for over the whole range (within 0.045).

Friction: F_t = -mu F_n tanh(v_t / v_reg) (Coulomb, regularised below the slip speed v_reg).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Union

import numpy as np

from . import _core
from ._checks import as_float

ArrayLike = Union[float, np.ndarray]

_KINDS = {
    "kelvin-voigt-hertz": _core.ContactLaw.Kind.kelvin_voigt_hertz,
    "paper": _core.ContactLaw.Kind.kelvin_voigt_hertz,
    "hunt-crossley": _core.ContactLaw.Kind.hunt_crossley,
    "lankarani-nikravesh": _core.ContactLaw.Kind.lankarani_nikravesh,
    "flores": _core.ContactLaw.Kind.flores,
}


def _broadcast(**args) -> tuple[tuple[int, ...], list]:
    """The arguments as flat float arrays of one broadcast shape; ValueError naming the argument
    for a non-finite entry (a NaN in would be a NaN out), TypeError for a non-number."""
    arrays = []
    for name, a in args.items():
        try:
            a = np.asarray(a, dtype=float)
        except (TypeError, ValueError) as e:
            raise TypeError(f"{name} must be a real number or an array of them, got {a!r}") from e
        bad = ~np.isfinite(a)
        if bad.any():
            first = float(a[bad].flat[0]) if a.ndim else float(a)
            raise ValueError(f"{name} = {first!r} is out of range: must be finite")
        arrays.append(a)
    try:
        arrays = np.broadcast_arrays(*arrays)
    except ValueError as e:
        shapes = ", ".join(f"{k} {np.shape(a)}" for k, a in zip(args, arrays))
        raise ValueError(f"the arguments do not broadcast together: {shapes}") from e
    return arrays[0].shape, [np.ascontiguousarray(a).ravel() for a in arrays]


def _shaped(shape: tuple[int, ...], outputs) -> tuple:
    if shape == ():
        return tuple(float(o[0]) for o in outputs)
    return tuple(np.asarray(o).reshape(shape) for o in outputs)


@dataclass(frozen=True)
class ContactLaw:
    """A normal contact force law.

    Parameters
    ----------
    kind : "kelvin-voigt-hertz" (alias "paper"), "hunt-crossley", "lankarani-nikravesh" or
        "flores".
    K : contact stiffness, N/m^n (> 0).
    n : force exponent (>= 1; 1.5 for Hertz's point contact, 1 for a linear spring).
    D : damping coefficient, N s/m (>= 0), Kelvin-Voigt only (leave 0 for the others).
    e : restitution coefficient the law is tuned for, 0 < e <= 1, Hunt-Crossley family only
        (leave 1 for Kelvin-Voigt).
    """

    kind: str
    K: float
    n: float = 1.5
    D: float = 0.0
    e: float = 1.0
    _impl: _core.ContactLaw = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.kind, str):
            raise TypeError(f"contact.kind must be a string, got {type(self.kind).__name__} "
                            f"{self.kind!r}")
        if self.kind not in _KINDS:
            kinds = ", ".join(map(repr, _KINDS))
            raise ValueError(f"contact.kind = {self.kind!r} is not one of {kinds}")
        if self.kind == "paper":
            object.__setattr__(self, "kind", "kelvin-voigt-hertz")
        args = {k: as_float(f"contact.{k}", getattr(self, k)) for k in ("K", "n", "D", "e")}
        object.__setattr__(self, "_impl", _core.ContactLaw(_KINDS[self.kind], **args))

    @property
    def hysteresis_factor(self) -> float:
        """c in F = K delta^n (1 + c delta_dot / v0) (dimensionless); 0 for Kelvin-Voigt."""
        return self._impl.hysteresis_factor

    def force(self, delta: ArrayLike, delta_dot: ArrayLike, v0: ArrayLike | None = None) -> tuple:
        """Force (N) and its partial derivatives dF/ddelta (N/m) and dF/ddelta_dot (N s/m) at
        penetration ``delta`` (m) and rate ``delta_dot`` (m/s); the derivatives are 0 where the
        force is clamped at 0. ``v0`` (m/s, > 0), the approach speed at contact onset, is
        required by the Hunt-Crossley family. Arguments broadcast; scalars in give floats out."""
        if v0 is None:
            if self._impl.needs_onset_speed:
                raise ValueError(f"v0 (approach speed at contact onset, m/s) is required by "
                                 f"{self.kind}")
            v0 = 0.0
        shape, (d, dd, v) = _broadcast(delta=delta, delta_dot=delta_dot, v0=v0)
        return _shaped(shape, self._impl.force_many(d, dd, v))


@dataclass(frozen=True)
class Friction:
    """Coulomb friction regularised at low slip: F_t = -mu F_n tanh(v_t / v_reg).

    Parameters
    ----------
    mu : friction coefficient (>= 0).
    v_reg : regularisation slip speed, m/s (> 0): below it the law is viscous (slope
        mu F_n / v_reg); at |v_t| = 10 v_reg, |F_t| is within 4.2e-9 relative of mu F_n.
        No true sticking: a tangential load F < mu F_n creeps at v_reg atanh(F / (mu F_n)).
    """

    mu: float
    v_reg: float = 1e-4
    _impl: _core.CoulombFriction = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        args = {k: as_float(f"friction.{k}", getattr(self, k)) for k in ("mu", "v_reg")}
        object.__setattr__(self, "_impl", _core.CoulombFriction(**args))

    def force(self, v_t: ArrayLike, F_n: ArrayLike) -> tuple:
        """Tangential force F_t (N) and its derivatives dF_t/dv_t (N s/m) and dF_t/dF_n, at slip
        velocity ``v_t`` (m/s) and normal force ``F_n`` (N; <= 0 gives no friction). Arguments
        broadcast; scalars in give floats out."""
        shape, (v, n) = _broadcast(v_t=v_t, F_n=F_n)
        return _shaped(shape, self._impl.force_many(v, n))


@dataclass(frozen=True)
class Impact:
    """A point mass hitting a compliant surface (:func:`impact`).

    restitution : exit speed / impact speed; max_penetration : m; contact_duration : s, onset
    to separation (F back to 0); peak_force : N; energy_lost : J, m (v0^2 - v_exit^2) / 2;
    steps : RK4 steps. With ``record=True``: t (s), delta (m), delta_dot (m/s), force (N) at
    every step, onset and separation included; otherwise empty arrays.
    """

    restitution: float
    max_penetration: float
    contact_duration: float
    peak_force: float
    energy_lost: float
    steps: int
    t: np.ndarray
    delta: np.ndarray
    delta_dot: np.ndarray
    force: np.ndarray


def _check_law(law: object) -> ContactLaw:
    if not isinstance(law, ContactLaw):
        raise TypeError(f"law must be a ContactLaw, got {type(law).__name__}")
    return law


def impact_time_scale(law: ContactLaw, mass_kg: float, v0_m_s: float) -> float:
    """The contact's time scale T (s): maximum penetration / v0 (exact for the undamped Hertz
    law and the Hunt-Crossley family), or m / D if shorter (Kelvin-Voigt)."""
    m, v0 = as_float("mass_kg", mass_kg), as_float("v0_m_s", v0_m_s)
    return _core.impact_time_scale(_check_law(law)._impl, m, v0)


def impact(law: ContactLaw, mass_kg: float, v0_m_s: float, dt_s: float | None = None,
           record: bool = False) -> Impact:
    """Integrate m delta'' = -F(delta, delta') from first contact (delta = 0, delta' = v0) to
    separation, in C++ with RK4 and the turning point and separation located to round-off.

    ``dt_s`` defaults to T / 4000 (T = :func:`impact_time_scale`; T / 1e5 to T / 10 accepted);
    the error is O((dt/T)^4) for n = 1 and O((dt/T)^2.5) for n = 1.5 (delta^n is not smooth at
    onset): ~1e-11 relative on restitution, penetration and duration at the default step.

    A contact that lasts longer than 1000 T is not integrated (ValueError naming the law's K, D
    and e): the law's damping then holds the mass in the contact and its spring is too weak to
    push it out in any useful time. Nor is one needing more than 10^7 steps (a ``dt_s`` far below
    the default). Ctrl-C interrupts a long run (KeyboardInterrupt).
    """
    _check_law(law)
    m, v0 = as_float("mass_kg", mass_kg), as_float("v0_m_s", v0_m_s)
    dt = impact_time_scale(law, m, v0) / 4000 if dt_s is None else as_float("dt_s", dt_s)
    d = _core.simulate_impact(law._impl, m, v0, dt, bool(record))
    return Impact(d["restitution"], d["max_penetration"], d["contact_duration"], d["peak_force"],
                  d["energy_lost"], int(d["steps"]), d["t"], d["delta"], d["delta_dot"], d["force"])
