"""The hinge lock as a pin sliding in a groove (You et al. 2016, Fig. 1; Eq. 45: the normal force
along the contact normal n, friction mu F_n along the tangent t). SI units: m, rad, N, N m, s.

- A :class:`GrooveProfile` is a chain of :class:`Line`, :class:`Arc` and :class:`ArcAbout`
  elements in the parent body's hinge plane (origin on the hinge axis). Walking the chain, the
  free space where the pin lives is on the left (outward normal n = left normal of the direction
  t); the chain is split at its concave corners into facets, each one contact.
  :meth:`GrooveProfile.query` gives a pin's gap, normal, tangent and their derivatives.
- A :class:`PinGroove` is a pin of radius ``pin_radius`` on the child body, at ``pin_distance``
  from the axis in direction ``pin_angle`` (or on a :class:`LatchSpring`, a massless follower),
  against a profile: the torque on the hinge angle theta and its derivatives. The pin is a
  circle whose centre carries the forces (its own spin, theta' rho at its rim, is neglected against
  its centre's speed); each facet of the profile is one contact, armed only once the pin has been
  on its free side, so a latch face behind the pin acts only after the pin has passed it.
- :meth:`PinGroove.stop_latch` expresses today's stop-plus-latch lock (:class:`deployfx.specs.Lock`)
  as one profile; :meth:`PinGroove.paper` the groove chosen for the paper's scene
  (docs/research/pin-groove.md).
"""
# The engine's model and its limits, for developers: cpp/deployfx/joint/pin_groove.hpp.
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence, Union

import numpy as np

from . import _core
from ._checks import as_float
from .contact import ContactLaw, Friction

History = _core.PinGrooveHistory  #: facets (one FacetContact each: armed, closed, inside, v0), support


def _point(name: str, value) -> np.ndarray:
    p = np.asarray(value, dtype=float)
    if p.shape != (2,) or not np.all(np.isfinite(p)):
        raise ValueError(f"{name} = {value!r} is out of range: must be 2 finite coordinates (m)")
    return p


def _nonneg(name: str, value, unit: str) -> float:
    v = as_float(name, value)
    if not (np.isfinite(v) and v >= 0):
        raise ValueError(f"{name} = {v} is out of range: must be >= 0 ({unit})")
    return v


def _play(name: str, value) -> Optional[float]:
    """A lock's free play (deg of hinge travel, >= 0), or None."""
    if value is None:
        return None
    v = as_float(name, value)
    if not (np.isfinite(v) and 0.0 <= v <= 360.0):
        raise ValueError(f"{name} = {v} is out of range: must be in [0, 360] (deg of hinge travel)")
    return v


def _finite(name: str, value, unit: str) -> float:
    v = as_float(name, value)
    if not np.isfinite(v):
        raise ValueError(f"{name} = {v} is out of range: must be finite ({unit})")
    return v


@dataclass(frozen=True)
class Line:
    """A segment from ``start`` to ``end`` (m)."""
    start: Sequence[float]
    end: Sequence[float]

    def _build(self):
        return _core.GrooveElement.line(_point("line.start", self.start), _point("line.end", self.end))


@dataclass(frozen=True)
class Arc:
    """The minor arc (sweep <= pi) from ``start`` to ``end`` of signed ``radius`` (m): > 0 turns
    left (counter-clockwise; concave seen from the pin), < 0 turns right (convex);
    |radius| >= half the chord."""
    start: Sequence[float]
    end: Sequence[float]
    radius: float

    def _build(self):
        return _core.GrooveElement.arc(_point("arc.start", self.start), _point("arc.end", self.end),
                                       as_float("arc.radius", self.radius))


@dataclass(frozen=True)
class ArcAbout:
    """The arc about ``centre`` from ``start`` to ``end`` (m), counter-clockwise if ``ccw``; any
    sweep below a full turn."""
    start: Sequence[float]
    end: Sequence[float]
    centre: Sequence[float]
    ccw: bool

    def _build(self):
        if not isinstance(self.ccw, (bool, np.bool_)):
            raise TypeError(f"arc_about.ccw must be a bool, got {type(self.ccw).__name__}")
        return _core.GrooveElement.arc_about(_point("arc_about.start", self.start),
                                             _point("arc_about.end", self.end),
                                             _point("arc_about.centre", self.centre), bool(self.ccw))


Element = Union[Line, Arc, ArcAbout]


@dataclass(frozen=True)
class PinQuery:
    """A pin against one facet. gap (m, < 0 penetration), point (the facet's closest point, m),
    n (outward unit normal = d gap / d c), t (unit tangent, the chain's direction), dn_dc
    (d n / d c = d^2 gap / d c^2, 1/m), facet, element, at_vertex (the closest point is a convex
    corner), chain_length (m along the chain); in_range is False when the closest point is an
    end of the facet (no contact)."""
    in_range: bool
    gap: float
    point: np.ndarray
    n: np.ndarray
    t: np.ndarray
    dn_dc: np.ndarray
    facet: int
    element: int
    at_vertex: bool
    chain_length: float


class GrooveProfile:
    """A chain of groove elements (continuous to 1e-9 m x max(1, extent)); see the module doc."""

    def __init__(self, elements: Sequence[Element]):
        items = list(elements)
        for i, e in enumerate(items):
            if not isinstance(e, (Line, Arc, ArcAbout)):
                raise TypeError(f"profile.elements[{i}] must be a Line, Arc or ArcAbout, got {type(e).__name__}")
        self.elements = tuple(items)
        self._impl = _core.GrooveProfile([e._build() for e in items])

    @classmethod
    def _wrap(cls, impl) -> "GrooveProfile":
        """A profile built in the core (stop_latch, paper), its elements read back: segments as
        :class:`Line`, arcs as :class:`ArcAbout` (what a scene file writes)."""
        p = cls.__new__(cls)
        elements = []
        for k in range(impl.num_elements):
            e = impl.element(k)
            start, end = [float(x) for x in e.start], [float(x) for x in e.end]
            elements.append(ArcAbout(start, end, [float(x) for x in e.centre], bool(e.sweep > 0))
                            if e.is_arc else Line(start, end))
        p.elements = tuple(elements)
        p._impl = impl
        return p

    @property
    def num_facets(self) -> int:
        """The number of facets (contacts): the chain split at its concave corners."""
        return self._impl.num_facets

    @property
    def closed(self) -> bool:
        """Whether the chain's last end meets its first start (a loop: no free ends)."""
        return self._impl.closed

    def facet_elements(self, facet: int) -> tuple[int, int]:
        """(first element, count) of a facet; indices wrap on a closed chain."""
        return self._impl.facet_elements(int(facet))

    def query(self, facet: int, c, rho: float) -> PinQuery:
        """A pin of radius ``rho`` (m, >= 0) centred at ``c`` (m) against ``facet``."""
        d = self._impl.query(int(facet), _point("c", c), _nonneg("rho", rho, "m"))
        return PinQuery(**d)

    def closest(self, c, rho: float) -> PinQuery:
        """Against the whole profile: the in-range facet nearest to ``c`` (gap +inf if none)."""
        return PinQuery(**self._impl.closest(_point("c", c), _nonneg("rho", rho, "m")))


@dataclass(frozen=True)
class LatchSpring:
    """A spring-loaded latch pin in a radial bore (a massless follower): its centre at ``stop`` (m
    from the axis) with the spring at ``preload`` (N), pushed back up to ``travel`` (m) with rate
    ``stiffness`` (N/m); the spring pushes toward the axis if ``toward_axis``."""
    stop: float
    travel: float
    preload: float
    stiffness: float
    toward_axis: bool = True

    def _build(self):
        return _core.LatchSpring(toward_axis=bool(self.toward_axis), stop=as_float("latch.stop", self.stop),
                                 travel=as_float("latch.travel", self.travel),
                                 preload=as_float("latch.preload", self.preload),
                                 stiffness=as_float("latch.stiffness", self.stiffness))


@dataclass(frozen=True)
class Load:
    """torque (N m on theta), d_theta (N m/rad), d_rate (N m s/rad), normal_force (N, all facets
    and the support), support_force (N), pin_position (m from the axis), support_lost."""
    torque: float
    d_theta: float
    d_rate: float
    normal_force: float
    support_force: float
    pin_position: float
    support_lost: bool


class PinGroove:
    """A hinge lock: a pin against a groove profile (the model: this module's docstring).

    profile : :class:`GrooveProfile` in the parent's hinge plane (m).
    pin_distance : the pin centre's distance from the hinge axis, m (> 0; unused with a latch).
    pin_angle : the pin's direction in the child's hinge plane, rad.
    pin_radius : the pin's own radius, m (>= 0).
    law, friction : the normal law (:class:`deployfx.contact.ContactLaw`) and Coulomb friction
        along the facet's tangent (:class:`deployfx.contact.Friction`, regularised at v_reg).
    latch : an optional :class:`LatchSpring`.
    play_deg : the pin's free play once held, deg of hinge travel (>= 0), if known: the settling
        metric's angle band (``Result.summary``); None (default) for a general profile, whose
        play the geometry does not name (the metric then uses its 0.1 deg band).
    """

    def __init__(self, profile: GrooveProfile, pin_distance: float, pin_angle: float, pin_radius: float,
                 law: ContactLaw, friction: Friction = Friction(0.0), latch: Optional[LatchSpring] = None, *,
                 play_deg: Optional[float] = None):
        if not isinstance(profile, GrooveProfile):
            raise TypeError(f"profile must be a GrooveProfile, got {type(profile).__name__}")
        if not isinstance(law, ContactLaw):
            raise TypeError(f"law must be a deployfx.contact.ContactLaw, got {type(law).__name__}")
        if not isinstance(friction, Friction):
            raise TypeError(f"friction must be a deployfx.contact.Friction, got {type(friction).__name__}")
        if latch is not None and not isinstance(latch, LatchSpring):
            raise TypeError(f"latch must be a LatchSpring or None, got {type(latch).__name__}")
        self.profile, self.law, self.friction, self.latch = profile, law, friction, latch
        self.pin_distance, self.pin_angle = as_float("pin_distance", pin_distance), as_float("pin_angle", pin_angle)
        self.pin_radius = as_float("pin_radius", pin_radius)
        self._play_deg = _play("play_deg", play_deg)
        self._impl = _core.PinGrooveSpec(
            profile=profile._impl, pin_distance=as_float("pin_distance", pin_distance),
            pin_angle=as_float("pin_angle", pin_angle), pin_radius=as_float("pin_radius", pin_radius),
            law=law._impl, friction=friction._impl, latch=None if latch is None else latch._build())

    @classmethod
    def _wrap(cls, impl, law: ContactLaw, friction: Friction, latch: Optional[LatchSpring],
              play_deg: Optional[float]) -> "PinGroove":
        g = cls.__new__(cls)
        g.profile, g.law, g.friction, g.latch, g._impl = GrooveProfile._wrap(impl.profile), law, friction, latch, impl
        g.pin_distance, g.pin_angle, g.pin_radius = impl.pin_distance, impl.pin_angle, impl.pin_radius
        g._play_deg = _play("play_deg", play_deg)
        return g

    @property
    def play_deg(self) -> Optional[float]:
        """The pin's free play once held, deg of hinge travel: the constructor's ``play_deg`` (the
        paper groove's and the stop-and-latch profile's are their clearance over the pin's
        distance from the axis); None where the profile does not name it."""
        return self._play_deg

    @classmethod
    def stop_latch(cls, lock, rho: float, pin_angle: float = 0.0) -> "PinGroove":
        """Today's stop-plus-latch lock (a :class:`deployfx.specs.Lock`) as one profile of three
        facets (stop, slot bottom, latch), for a pin of radius ``rho`` (m, in [0, pin_radius/2))."""
        from .specs import Lock
        if not isinstance(lock, Lock):
            raise TypeError(f"lock must be a deployfx.specs.Lock, got {type(lock).__name__}")
        impl = _core.stop_latch_groove(cls._hinge_lock(lock), _nonneg("rho", rho, "m"),
                                       _finite("pin_angle", pin_angle, "rad"))
        return cls._wrap(impl, lock.law, lock.friction, None, lock.play_deg)

    @staticmethod
    def _hinge_lock(lock):
        return _core.HingeLockSpec(theta_lock=lock.theta_lock, pin_radius=lock.pin_radius, clearance=lock.clearance,
                                   law=lock.law._impl, mu=lock.friction.mu, v_reg=lock.friction.v_reg)

    @classmethod
    def paper(cls, law: ContactLaw, friction: Friction, **parameters) -> "PinGroove":
        """The groove chosen for You et al. (2016) (docs/research/pin-groove.md): a latch pin on a
        spring riding a track about the hinge axis into a notch. ``parameters`` override
        :data:`PAPER_DEFAULTS` (m, rad, N, N/m)."""
        p = _core.PaperGrooveParameters()
        for key, value in parameters.items():
            if key not in PAPER_DEFAULTS:
                raise TypeError(f"paper groove has no parameter {key!r}; known: {', '.join(PAPER_DEFAULTS)}")
            setattr(p, key, _finite(f"paper_groove.{key}", value, "SI"))
        impl = _core.paper_groove(p, law._impl, friction._impl)
        L = impl.latch
        latch = LatchSpring(L.stop, L.travel, L.preload, L.stiffness, L.toward_axis)
        return cls._wrap(impl, law, friction, latch, float(np.degrees(p.clearance / p.seat)))

    # -- runs: the history is a run's state, kept by the caller

    def start_history(self, theta: float) -> History:
        """The history at the start of a run at hinge angle ``theta`` (rad)."""
        return _core.groove_start_history(self._impl, _finite("theta", theta, "rad"))

    def load(self, theta: float, rate: float, history: History) -> Load:
        """The lock's torque on theta and its derivatives at (``theta`` rad, ``rate`` rad/s)."""
        d = _core.groove_load(self._impl, history, _finite("theta", theta, "rad"), _finite("rate", rate, "rad/s"))
        return Load(**d)

    def position(self, theta: float, history: History) -> dict:
        """The pin's position: s (m from the axis), ds (m/rad), d2s (m/rad^2), w (spring
        compression, m), drop_margin (m), found, beyond (past the drop with this history: the pin
        held where the drop left it, until update_history drops it), bottomed."""
        return _core.groove_pin_position(self._impl, history, _finite("theta", theta, "rad"))

    def facet_state(self, facet: int, theta: float, rate: float, history: History) -> dict:
        """A facet's contact (joint::wall_states for a facet): contact, F (N), delta (m),
        delta_dot (m/s), positive into the facet."""
        return _core.groove_facet_state(self._impl, history, int(facet), _finite("theta", theta, "rad"),
                                        _finite("rate", rate, "rad/s"))

    def lever(self, facet: int, theta: float, history: History) -> float:
        """d delta / d theta of a facet (m/rad, > 0 when theta drives the pin into it): the pin's
        effective mass along its normal is 1 / (lever^2 e^T M^-1 e)."""
        return _core.groove_facet_lever(self._impl, history, int(facet), _finite("theta", theta, "rad"))

    def contact_resolution(self, theta: float, history: History) -> tuple[float, float]:
        """(hinge-angle error a step in contact may make, rad; shortest step worth taking, s)
        over the closed facets with an impact time scale T; (inf, 0) with none."""
        return _core.groove_contact_resolution(self._impl, history, _finite("theta", theta, "rad"))

    def events(self, theta: float, rate: float, history: History) -> np.ndarray:
        """The event functions (one per facet, then the latch's drop), positive while modes hold."""
        return _core.groove_events(self._impl, history, _finite("theta", theta, "rad"), _finite("rate", rate, "rad/s"))

    def update_history(self, history: History, theta: float, rate: float, margins=None) -> None:
        """Switch modes after an accepted step at (theta, rate); ``margins`` one per event."""
        m = None if margins is None else np.asarray(margins, dtype=float)
        _core.groove_update_history(self._impl, history, _finite("theta", theta, "rad"),
                                    _finite("rate", rate, "rad/s"), m)


#: The paper groove's parameters (m, rad, N m; docs/research/pin-groove.md).
# Engine: cpp/deployfx/joint/lock_profiles.hpp.
PAPER_DEFAULTS = {k: getattr(_core.PaperGrooveParameters(), k) for k in (
    "theta_lock", "pin_angle", "seat", "pin_radius", "notch_depth", "clearance", "stop_height", "track_start",
    "preload", "stiffness", "stop_below_seat", "travel")}


def hinge_lock_load(lock, history, theta: float, rate: float) -> dict:
    """Today's lock torque (joint::lock_load) for a :class:`deployfx.specs.Lock` and a
    ``_core.LockHistory``: torque, d_theta, d_rate, normal_force (a reference for comparisons)."""
    return _core.hinge_lock_load(PinGroove._hinge_lock(lock), history, _finite("theta", theta, "rad"),
                                 _finite("rate", rate, "rad/s"))
