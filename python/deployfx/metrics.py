"""Metrics of a deployment run, computed from its time series.

Pure functions on numpy arrays; nothing here is stored by hand or read from a solver's internals.
Units follow the series: time in s, angles in deg, forces in N, deflections in m, angular momenta
in N m s.

Conventions shared by every function:

- ``t`` is one-dimensional, finite and strictly increasing, with at least one sample.
- Every other series has the same number of samples as ``t`` (its leading dimension).
- Bad input (wrong shape or length, NaN or inf, out-of-range option) raises ``ValueError`` whose
  message names the parameter, what was expected and what was given.
- A metric the signal does not define (the hinge never locks, the angle never settles within the
  record, a zero reference momentum) is ``None``, never NaN.

Contact is read from the lock force: the lock is in contact at a sample where the force is > 0
(the contact laws never pull, so out of contact the force is exactly zero).
"""
from __future__ import annotations

import math
from typing import Optional

import numpy as np

#: Deployment angle of a deployed (locked) appendage, deg (90 stowed, 180 deployed).
DEPLOYED_ANGLE_DEG = 180.0


def _as_time(t: object, name: str = "t") -> np.ndarray:
    """``t`` as a float array: 1-D, at least one sample, finite, strictly increasing."""
    a = np.asarray(t)
    if a.ndim != 1 or a.size == 0:
        raise ValueError(f"{name} must be a non-empty 1-D array of times (s), got shape {a.shape}")
    if a.dtype.kind not in "iuf":
        raise ValueError(f"{name} must be real numbers, got dtype {a.dtype}")
    a = a.astype(float, copy=False)
    _check_finite(name, a)
    if a.size > 1:
        steps = a[1:] - a[:-1]  # np.diff's
        if not (steps > 0).all():
            k = int(np.flatnonzero(steps <= 0)[0])
            raise ValueError(f"{name} must be strictly increasing, got {name}[{k}] = {a[k]!r} "
                             f"followed by {name}[{k + 1}] = {a[k + 1]!r}")
    return a


def _check_finite(name: str, a: np.ndarray) -> None:
    bad = ~np.isfinite(a)
    if bad.any():
        k = np.unravel_index(int(np.flatnonzero(bad.ravel())[0]), a.shape)
        raise ValueError(f"{name} must be finite, got {a[k]!r} at index {tuple(map(int, k))}")


def _as_series(name: str, x: object, n: Optional[int], vector: bool = False) -> np.ndarray:
    """``x`` as a finite float array of shape (n,), or (n, 3) if ``vector`` (n=None: any n>=1)."""
    a = np.asarray(x)
    if a.dtype.kind not in "biuf":
        raise ValueError(f"{name} must be real numbers, got dtype {a.dtype}")
    a = a.astype(float, copy=False)
    expected = "(n, 3)" if vector else "(n,)"
    bad_rank = a.ndim != 2 or a.shape[1] != 3 if vector else a.ndim != 1
    if bad_rank or a.shape[0] == 0:
        raise ValueError(f"{name} must have shape {expected} with n >= 1, got {a.shape}")
    if n is not None and a.shape[0] != n:
        raise ValueError(f"{name} must have one value per time sample ({n}), got {a.shape[0]}")
    _check_finite(name, a)
    return a


def _as_option(name: str, value: object, low: float, high: float = math.inf,
               low_open: bool = False) -> float:
    """A real option in [low, high] (or (low, high] if ``low_open``): TypeError if not a real
    number, ValueError if out of range."""
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    v = float(value)
    below = v <= low if low_open else v < low
    if not math.isfinite(v) or below or v > high:
        bracket = "(" if low_open else "["
        raise ValueError(f"{name} must be in {bracket}{low:g}, {high:g}], got {v!r}")
    return v


def crossing_time(t: object, x: object, level: float) -> Optional[float]:
    """First time (s) at which ``x`` reaches ``level`` (x >= level), or None if it never does.

    If the first sample is already at or above ``level`` this is ``t[0]``; otherwise the time is
    interpolated linearly between the last sample below ``level`` and the first at or above it.
    """
    t = _as_time(t)
    x = _as_series("x", x, t.size)
    level = _as_option("level", level, -math.inf)
    above = np.flatnonzero(x >= level)
    if above.size == 0:
        return None
    i = int(above[0])
    if i == 0:
        return float(t[0])
    return float(t[i - 1] + (level - x[i - 1]) / (x[i] - x[i - 1]) * (t[i] - t[i - 1]))


def first_contact_time(t: object, lock_force: object) -> Optional[float]:
    """Time (s) of the first sample at which ``lock_force`` (N) is positive, or None.

    No interpolation: the force is exactly zero before contact, so the onset lies in
    (t[i-1], t[i]] and t[i] is the first instant at which contact is observed.
    """
    t = _as_time(t)
    f = _as_series("lock_force", lock_force, t.size)
    hit = np.flatnonzero(f > 0.0)
    return float(t[hit[0]]) if hit.size else None


def first_lock_time(t: object, lock_force: object = None, deployment_angle: object = None,
                    deployed_angle: float = DEPLOYED_ANGLE_DEG) -> Optional[float]:
    """First lock time (s): when the hinge first reaches its deployed, locked position.

    With ``lock_force`` (N): :func:`first_contact_time`. Without it, the first time the
    ``deployment_angle`` (deg) reaches ``deployed_angle`` (deg), by :func:`crossing_time`.
    None if the hinge never locks within the record. One of the two series is required.
    """
    if lock_force is not None:
        return first_contact_time(t, lock_force)
    if deployment_angle is not None:
        t = _as_time(t)
        angle = _as_series("deployment_angle", deployment_angle, t.size)
        return crossing_time(t, angle, deployed_angle)
    raise ValueError("first_lock_time needs lock_force or deployment_angle, got neither")


def _contact_runs(t: np.ndarray, f: np.ndarray, min_gap: float,
                  min_peak_fraction: float) -> list[tuple[int, int]]:
    # Maximal runs of samples with f > 0, as inclusive (first, last) index pairs.
    on = np.flatnonzero(f > 0.0)
    if on.size == 0:
        return []
    breaks = np.flatnonzero(np.diff(on) > 1)
    starts = on[np.r_[0, breaks + 1]]
    ends = on[np.r_[breaks, on.size - 1]]
    # Hysteresis in time: an opening shorter than min_gap is chatter within one contact.
    runs: list[list[int]] = []
    for s, e in zip(starts.tolist(), ends.tolist()):
        if runs and t[s] - t[runs[-1][1]] < min_gap:
            runs[-1][1] = e
        else:
            runs.append([s, e])
    floor = min_peak_fraction * float(f.max())
    return [(s, e) for s, e in runs if f[s:e + 1].max() >= floor]


def contact_intervals(t: object, lock_force: object, *, min_gap: float = 0.05,
                      min_peak_fraction: float = 1e-3) -> np.ndarray:
    """Separate contacts (impacts) of the lock, as an array (k, 2) of [first, last] times (s).

    Rule: a contact is a maximal run of samples with ``lock_force`` > 0. Two runs separated by an
    opening shorter than ``min_gap`` (s), measured from the last in-contact sample of one to the
    first in-contact sample of the next, are one contact (numerical chatter: the pin leaving the
    groove for a sample or two). A contact whose peak force is below ``min_peak_fraction`` times
    the record's peak force is round-off, not an impact, and is dropped. The times are those of the
    first and last in-contact samples; a contact still open at the end of the record counts.

    The defaults (0.05 s, i.e. five steps of the paper's dt = 0.01 s; 1e-3) sit far from both
    chatter (one or two steps) and the paper's rebounds (seconds apart, peaks within a factor 100).
    """
    t, _, runs = _impacts(t, lock_force, min_gap, min_peak_fraction)
    return np.array([[t[s], t[e]] for s, e in runs], dtype=float).reshape(len(runs), 2)


def impact_count(t: object, lock_force: object, *, min_gap: float = 0.05,
                 min_peak_fraction: float = 1e-3) -> int:
    """Number of impacts: the number of :func:`contact_intervals` (same rule and options)."""
    return len(_impacts(t, lock_force, min_gap, min_peak_fraction)[2])


def impact_peaks(t: object, lock_force: object, *, min_gap: float = 0.05,
                 min_peak_fraction: float = 1e-3) -> np.ndarray:
    """Peak lock force (N) of each impact of :func:`contact_intervals`, in time order, (k,)."""
    _, f, runs = _impacts(t, lock_force, min_gap, min_peak_fraction)
    return np.array([f[s:e + 1].max() for s, e in runs], dtype=float)


def _impacts(t: object, lock_force: object, min_gap: float, min_peak_fraction: float):
    # Validated (t, lock_force) and the inclusive (first, last) sample indices of each impact.
    t = _as_time(t)
    f = _as_series("lock_force", lock_force, t.size)
    min_gap = _as_option("min_gap", min_gap, 0.0)
    min_peak_fraction = _as_option("min_peak_fraction", min_peak_fraction, 0.0, 1.0)
    return t, f, _contact_runs(t, f, min_gap, min_peak_fraction)


def peak_lock_force(lock_force: object) -> float:
    """Largest lock force (N) over the record (0.0 if the lock never engages)."""
    return float(_as_series("lock_force", lock_force, None).max())


def max_abs(x: object, name: str = "x") -> float:
    """Largest absolute value of a scalar series ``x`` (its unit), e.g. a node's deflection in m.

    ``name`` is the series name used in error messages.
    """
    return float(np.abs(_as_series(name, x, None)).max())


def settling_time(t: object, x: object, tol: float, *, min_hold: float = 1.0) -> Optional[float]:
    """Settling time (s) of a scalar series: the earliest time after which ``x`` stays within
    ``tol`` (x's unit, > 0) of its final value ``x[-1]`` to the end of the record.

    The exit from the band is located by linear interpolation of |x - x[-1]| - tol between the
    last sample outside the band and the next sample; ``t[0]`` if no sample is outside. None if the
    band is held for less than ``min_hold`` (s) before the record ends: too short to call settled.
    """
    t = _as_time(t)
    x = _as_series("x", x, t.size)
    tol = _as_option("tol", tol, 0.0, low_open=True)
    min_hold = _as_option("min_hold", min_hold, 0.0)
    ts = _band_entry_time(t, x, tol)
    return ts if t[-1] - ts >= min_hold else None


def _band_entry_time(t: np.ndarray, x: np.ndarray, tol: float) -> float:
    excess = np.abs(x - x[-1]) - tol  # > 0 outside the band; excess[-1] = -tol < 0
    outside = np.flatnonzero(excess > 0.0)
    if outside.size == 0:
        return float(t[0])
    i = int(outside[-1])
    return float(t[i] + excess[i] / (excess[i] - excess[i + 1]) * (t[i + 1] - t[i]))


def lock_settling_time(t: object, deployment_angle: object, lock_force: object = None, *,
                       angle_tol: float = 0.1, force_tol_fraction: float = 0.01,
                       min_hold: float = 1.0) -> Optional[float]:
    """Settling time (s) of a deployment: the earliest time after which both
    - the ``deployment_angle`` (deg) stays within ``angle_tol`` (deg, default 0.1) of its final
      value, and
    - the ``lock_force`` (N), if given, stays within ``force_tol_fraction`` (default 1 %) of the
      record's peak lock force of its final value (so later impacts of more than 1 % of the peak
      delay settling; smaller ones do not),
    each by the rule of :func:`settling_time`, the later of the two. None if either band is held for
    less than ``min_hold`` (s) before the record ends. The paper (Fig. 7) reports steady state from
    t = 19.12 s.
    """
    t = _as_time(t)
    angle = _as_series("deployment_angle", deployment_angle, t.size)
    angle_tol = _as_option("angle_tol", angle_tol, 0.0, low_open=True)
    force_tol_fraction = _as_option("force_tol_fraction", force_tol_fraction, 0.0, 1.0,
                                    low_open=True)
    min_hold = _as_option("min_hold", min_hold, 0.0)
    ts = _band_entry_time(t, angle, angle_tol)
    if lock_force is not None:
        f = _as_series("lock_force", lock_force, t.size)
        scale = float(np.abs(f).max())
        if scale > 0.0:
            ts = max(ts, _band_entry_time(t, f, force_tol_fraction * scale))
    return ts if t[-1] - ts >= min_hold else None


def attitude_change(body_attitude: object) -> float:
    """Magnitude (deg) of the final attitude minus the initial one, |a[-1] - a[0]|.

    ``body_attitude`` is (n, 3) (Euclidean norm of the difference) or (n,) (absolute difference).
    """
    a = np.asarray(body_attitude)
    a = _as_series("body_attitude", a, None, vector=a.ndim == 2)
    return float(np.linalg.norm(np.atleast_1d(a[-1] - a[0])))


def momentum_drift(total_angular_momentum: object,
                   body_angular_momentum: object) -> Optional[float]:
    """Relative drift of the system's angular momentum (dimensionless):

        max_t |H(t) - H(0)| / max_t |H_b(t) - H_b(0)|

    with H the total and H_b the body's angular momentum (N m s), both (n, 3): the conservation
    error measured against the momentum the body exchanges with the appendage. With the paper's
    zero initial momenta this is max |H| / max |H_b|. None if the body never exchanges momentum
    (the ratio is undefined).
    """
    h = _as_series("total_angular_momentum", total_angular_momentum, None, vector=True)
    hb = _as_series("body_angular_momentum", body_angular_momentum, h.shape[0], vector=True)
    exchanged = float(np.linalg.norm(hb - hb[0], axis=1).max())
    if exchanged == 0.0:
        return None
    return float(np.linalg.norm(h - h[0], axis=1).max()) / exchanged
