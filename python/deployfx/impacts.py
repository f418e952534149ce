"""The lock's impacts: one record per contact of a lock wall, onset to separation, written by the
engine from every accepted step of a run, not from the output samples.

Inside a contact the engine takes the steps that resolve it, whatever the output step ``dt``
(``Result.metadata["contact_steps"]`` counts them): each impact's peak force and maximum
penetration are located (the vertex of the parabola through the largest step sample and its two
neighbours), its impulse is the integral of the normal force over the contact, and its approach
and rebound speeds are the pin's normal speed at the located onset and separation.

The paper's law (Kelvin-Voigt-Hertz, F = K delta^n + D delta') jumps to D delta'_0 at onset: on a
light fitting its peak is that jump, D times the approach speed, whatever the structure behind it.
Read it with the impulse, which is the structural load's measure.

A record is a frozen :class:`Impact`; ``Result.impacts`` gives a run's, in order of onset, and
``result.hinge(k).impacts`` hinge k's. They live in the metadata (``hinges[k]["impacts"]``), so
``Result.save`` keeps them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping, Optional

import numpy as np

__all__ = ["Impact", "WALLS", "peak_force"]

#: The lock's walls, by the engine's index: the stop at the deployed angle, and the latch that
#: holds the pin back once it has passed.
# Engine: cpp/deployfx/joint/hinge_lock.hpp (walls), joint/impact_record.hpp (the records).
WALLS = ("stop", "latch")


@dataclass(frozen=True)
class Impact:
    """One contact of a lock wall (SI units, in the field names)."""

    hinge: int
    wall: str                         #: "stop" or "latch"; a groove's "facet k"
    t_onset_s: float
    t_separation_s: Optional[float]   #: None: the pin was still on the wall when the run ended
    v_approach_m_s: float             #: the pin's normal speed into the wall at onset
    v_rebound_m_s: Optional[float]    #: its normal speed away from the wall at separation
    peak_force_N: float               #: located
    t_peak_s: float
    impulse_N_s: float                #: the integral of the normal force over the contact
    max_penetration_m: float          #: located
    steps: int                        #: the engine's accepted steps in contact

    @property
    def duration_s(self) -> Optional[float]:
        """Onset to separation (s); None while in contact at the run's end."""
        return None if self.t_separation_s is None else self.t_separation_s - self.t_onset_s

    @property
    def restitution(self) -> Optional[float]:
        """Rebound over approach speed; None while in contact at the run's end."""
        if self.v_rebound_m_s is None or not self.v_approach_m_s > 0:
            return None
        return self.v_rebound_m_s / self.v_approach_m_s

    def as_dict(self) -> dict[str, Any]:
        """The record as JSON-compatible fields (what the metadata keeps)."""
        return {name: getattr(self, name) for name in self.__dataclass_fields__}

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> "Impact":
        """The record from :meth:`as_dict`'s fields (e.g. read back from a saved result)."""
        return cls(**{name: d[name] for name in cls.__dataclass_fields__})


def _number(x) -> Optional[float]:
    x = float(x)
    return x if math.isfinite(x) else None


def contact_names(lock) -> tuple:
    """The names of a lock's contacts, by the engine's index: :data:`WALLS` for the stop-and-latch
    lock, ``"facet k"`` for a groove's facets (deployfx.groove.PinGroove)."""
    profile = getattr(lock, "profile", None)
    return WALLS if profile is None else tuple(f"facet {k}" for k in range(profile.num_facets))


def per_hinge(table: Mapping[str, np.ndarray], names: list) -> list[list[dict]]:
    """The engine's impact table (a dict of arrays, one entry per record) as each hinge's list of
    record dicts (:meth:`Impact.as_dict`), in order of onset; ``names[k]`` names hinge k's
    contacts (:func:`contact_names`)."""
    out: list[list[dict]] = [[] for _ in names]
    if not (table and len(table["t_onset"])):
        return out
    # Each column as Python numbers (floats, ints) in one call, not an entry at a time; each record
    # as Impact(...).as_dict() gives it (the columns are in the fields' order), without the
    # frozen dataclass's construction.
    for row in zip(*(np.asarray(table[key]).tolist() for key in _TABLE_COLUMNS)):
        k, wall, t_onset, t_separation, v_approach, v_rebound, peak, t_peak, impulse, penetration, steps = row
        out[k].append(dict(zip(_FIELDS, (k, names[k][wall], t_onset, _number(t_separation), v_approach,
                                         _number(v_rebound), peak, t_peak, impulse, penetration, steps))))
    return out


#: The engine's impact table's columns, in the order of Impact's fields (_FIELDS).
_TABLE_COLUMNS = ("hinge", "wall", "t_onset", "t_separation", "v_approach", "v_rebound", "peak_force", "t_peak",
                  "impulse", "max_penetration", "steps")
_FIELDS = tuple(Impact.__dataclass_fields__)


def strongest(records) -> Optional[Impact]:
    """The record with the largest peak force (the first of equals), or None."""
    best = None
    for r in records:
        if best is None or r.peak_force_N > best.peak_force_N:
            best = r
    return best


def peak_force(result, hinge: int = 0, t_end: Optional[float] = None) -> Optional[float]:
    """The largest located peak force (N) of hinge ``hinge``'s impacts in ``result`` whose peak
    is at or before ``t_end`` (s; None: all), 0.0 if it has none; None if the result carries no
    impact records (a result saved before deployfx recorded them, or built from series)."""
    infos = result.metadata.get("hinges")
    if not (isinstance(infos, list) and hinge < len(infos) and isinstance(infos[hinge], dict)
            and isinstance(infos[hinge].get("impacts"), list)):
        return None
    limit = math.inf if t_end is None else t_end * (1 + 1e-12)
    peaks = [r["peak_force_N"] for r in infos[hinge]["impacts"] if r["t_peak_s"] <= limit]
    return float(max(peaks)) if peaks else 0.0
