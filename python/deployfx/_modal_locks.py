"""The locks of a state for modal analysis (deployfx.modal_analysis): each hinge's contact
history derived from a run's sample or a given configuration (latched, the walls in contact, a
groove's latch pin on its support), and the active set of walls at an equilibrium
(docs/modes.md, "The lock")."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

from .groove import PinGroove

#: A wall penetrated by less than this (m) at an equilibrium is touched, not in contact: the pin
#: rests on it with no force (Newton lands on the contact's edge only to its tolerance; the
#: paper's Hertz law pushes 1 mN at 1 nm).
TOUCH = 1e-9


@dataclass(frozen=True)
class _Locks:
    """What the locks' histories are derived from besides the configuration: the run's latch
    states (per hinge, or None), each groove's latch-pin support, and the run (its impact records
    say which walls are in contact at ``t``) when the state is its sample as it stands."""

    latched: Optional[np.ndarray]
    supports: dict
    result: Any
    t: float


def _locks(model, q, result, i, t) -> _Locks:
    """The lock context of a state: a run's sample ``i`` (``result``) or a given q."""
    latched = None
    if result is not None and "latched" in result:
        latched = np.atleast_1d(np.asarray(result["latched"])[i]).astype(bool)
        latched = latched if latched.shape == (model.num_hinges,) else None  # a hinge view: from theta
    supports = {}
    for k, link in enumerate(model.links):
        L, iq = link.lock, model.core.layout(k)["iq_theta"]
        if not isinstance(L, PinGroove) or iq < 0:
            continue
        thetas = [q[iq]] if result is None else np.asarray(result["q"], dtype=float)[: i + 1, iq]
        supports[k] = _groove_support(L, thetas)
    return _Locks(latched, supports, result, t)


def _groove_support(L, thetas) -> int:
    """The facet a groove's sprung latch pin rests on after the hinge angles ``thetas`` (a run's
    samples up to the state; one angle for a given state): as a run starts (the first facet the
    pin meets from its bore), kept while it carries the pin (``drop_margin`` >= 0), else the pin
    drops onto the next facet it meets (the feasible one of largest compression below the last)."""
    support = L.start_history(thetas[0]).support
    if L.latch is None:
        return support
    w_last = np.inf
    for theta in thetas:
        h = L.start_history(theta)
        h.support = support
        pos = L.position(theta, h)
        if support >= 0 and pos["found"] and pos["drop_margin"] >= 0:
            w_last = pos["w"]
            continue
        best, w_best = h.support, -np.inf
        for f in range(L.profile.num_facets):
            h.support = f
            p = L.position(theta, h)
            if p["found"] and p["drop_margin"] >= 0 and w_best < p["w"] < w_last:
                best, w_best = f, p["w"]
        if w_best == -np.inf:  # nothing below: where a run would start from here
            best = L.start_history(theta).support
            h.support = best
            w_best = L.position(theta, h)["w"]
        support, w_last = best, w_best
    return support


def _in_progress(result, k: int, wall: str, t: float):
    """The impact record of hinge k's contact on ``wall`` in progress at t, or None."""
    for r in reversed(result.impacts):
        if r.hinge == k and r.wall == wall and r.t_onset_s <= t and (r.t_separation_s is None or r.t_separation_s > t):
            return r
    return None


def _walls(model, q, v, locks: _Locks, tol: float = 0.0) -> dict:
    """Per lock on an undriven hinge, its contacts: a stop-and-latch lock's ``(latched, stop,
    latch)``, latched as the run says or once theta has passed the latch; a groove's ``(support,
    closed facets)``. A wall is in contact where the run's impact records have a contact in
    progress at t (a run's sample as it stands), else where the pin penetrates it by more than
    ``tol`` (m; a groove's facet tried closed under the run's start history at theta)."""
    out = {}
    for k, link in enumerate(model.links):
        L = link.lock
        lay = model.core.layout(k)
        if L is None or lay["iq_theta"] < 0:
            continue  # no lock, or a prescribed hinge's: it acts on no unknown
        theta, rate = q[lay["iq_theta"]], v[lay["iv_theta"]]
        rec = locks.result
        if not isinstance(L, PinGroove):  # the stop-and-latch lock (specs.Lock)
            theta_latch = L.theta_lock - L.clearance / L.pin_radius
            held = bool(locks.latched[k]) if locks.latched is not None else bool(theta >= theta_latch)
            if rec is not None:
                stop = _in_progress(rec, k, "stop", locks.t) is not None
                latch = _in_progress(rec, k, "latch", locks.t) is not None
            else:
                stop = L.pin_radius * (theta - L.theta_lock) > tol
                latch = held and L.pin_radius * (theta_latch - theta) > tol
            out[k] = (held, bool(stop), bool(latch))
            continue
        support = locks.supports[k]
        closed = []
        for f in range(L.profile.num_facets):
            if f == support:
                continue  # carried by the latch spring: no contact of its own
            if rec is not None:
                if _in_progress(rec, k, f"facet {f}", locks.t) is not None:
                    closed.append(f)
            elif L.facet_state(f, theta, rate, _groove_history(L, theta, support, (f,)))["delta"] > tol:
                closed.append(f)
        out[k] = (support, tuple(closed))
    return out


def _groove_history(L, theta, support: int, closed) -> Any:
    """A groove's history at theta: as a run's start, the latch pin on ``support``, the facets
    ``closed`` in contact (armed)."""
    h = L.start_history(theta)
    h.support = support
    facets = h.facets
    for f in closed:
        facets[f].armed = facets[f].closed = facets[f].inside = True
    h.facets = facets
    return h


def _set_locks(model, data, q, v, walls: dict, locks: _Locks) -> None:
    """Each lock's history from ``walls`` (:func:`_walls`), with the approach speed of a contact
    in progress from the run's impact records, else the pin's speed (at least 1 mm/s, the
    engine's floor): only the Hunt-Crossley laws read it."""
    from . import _core

    def onset(k, wall, speed):
        r = None if locks.result is None else _in_progress(locks.result, k, wall, locks.t)
        return max(r.v_approach_m_s if r is not None else abs(speed), 1e-3)

    for k, state in walls.items():
        L = model.links[k].lock
        lay = model.core.layout(k)
        theta, rate = q[lay["iq_theta"]], v[lay["iv_theta"]]
        if not isinstance(L, PinGroove):  # the stop-and-latch lock (specs.Lock)
            h = _core.LockHistory()
            h.latched, h.stop_contact, h.latch_contact = state
            h.stop_inside, h.latch_inside = h.stop_contact, h.latch_contact
            h.stop_v0 = onset(k, "stop", L.pin_radius * rate)
            h.latch_v0 = onset(k, "latch", L.pin_radius * rate)
        else:
            support, closed = state
            h = _groove_history(L, theta, support, closed)
            facets = h.facets
            for f in closed:
                facets[f].v0 = onset(k, f"facet {f}", L.lever(f, theta, h) * rate)
            h.facets = facets
        data.set_lock(k, h)
