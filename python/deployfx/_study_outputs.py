"""A study's outputs (deployfx.study): scalars per sample and series on a common time grid.

Scalar outputs (one float per sample; NaN where the metric is undefined, e.g. a hinge that never
locks has no first lock time):

- a key of :meth:`deployfx.Result.summary` (``deployfx.results.SUMMARY_KEYS``), e.g.
  ``"peak_lock_force_N"``; a chain's per-hinge metrics take the hinge: ``"peak_lock_force_N[1]"``;
- a reduction of a series: ``"max(lock_force)"``, ``"min(...)"``, ``"absmax(...)"``,
  ``"mean(...)"`` (time-weighted, trapezoidal), ``"final(...)"`` (the last sample); a column of a
  2-D series by index: ``"max(lock_force[1])"``;
- in Python, a name mapped to a function of the :class:`~deployfx.Result` returning a number.

Series: names of 1-D series (or ``"name[k]"`` for a column), linearly interpolated onto the
study's time grid (s); kept as they are, bit for bit, when the run's times are the grid.
"""
from __future__ import annotations

import math
import numbers
import re
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np

from .results import SUMMARY_KEYS

REDUCTIONS = ("max", "min", "absmax", "mean", "final")
_SUMMARY = re.compile(r"^([A-Za-z_]\w*)(?:\[(\d+)\])?$")
_REDUCED = re.compile(r"^(\w+)\(\s*([A-Za-z_]\w*)(?:\[(\d+)\])?\s*\)$")


class OutputError(ValueError):
    """An output the study asked for cannot be taken from a run's result (a misnamed series):
    a mistake of the study, not of the sample, so the study stops."""


def parse_outputs(outputs: Union[Sequence[str], Mapping[str, Any]]) -> dict[str, Any]:
    """{variable name: spec}, each spec a checked string or a callable; ValueError naming it."""
    if isinstance(outputs, str):
        outputs = [outputs]
    items = outputs.items() if isinstance(outputs, Mapping) else [(o, o) for o in outputs]
    out = {}
    for name, spec in items:
        if not isinstance(name, str) or not name or "/" in name:
            raise ValueError(f"output name {name!r} is invalid: must be a non-empty string without '/'")
        if callable(spec):
            out[name] = spec
            continue
        if not isinstance(spec, str):
            raise TypeError(f"output {name!r} must be a string (a summary key or max(series), ...) "
                            f"or a function of the Result, got {type(spec).__name__}")
        m = _SUMMARY.match(spec)
        if m and m.group(1) in SUMMARY_KEYS:
            out[name] = spec
            continue
        m = _REDUCED.match(spec)
        if m:
            if m.group(1) not in REDUCTIONS:
                raise ValueError(f"output {spec!r}: unknown reduction {m.group(1)!r}; use one of "
                                 f"{', '.join(REDUCTIONS)}")
            out[name] = spec
            continue
        raise ValueError(f"output {spec!r} is invalid: must be a summary key ({', '.join(SUMMARY_KEYS)}; "
                         f"'key[k]' for hinge k of a chain) or a reduction of a series such as "
                         f"'max(lock_force)' ({', '.join(REDUCTIONS)})")
    if not out:
        raise ValueError("outputs is empty: give at least one output (e.g. 'peak_lock_force_N')")
    return out


def parse_series(series: Optional[Sequence[str]]) -> list[str]:
    if series is None:
        return []
    if isinstance(series, str):
        series = [series]
    for s in series:
        if not isinstance(s, str) or not _SUMMARY.match(s):
            raise ValueError(f"series {s!r} is invalid: must be a series name, or 'name[k]' for "
                             "column k of a 2-D series")
    if len(set(series)) != len(series):
        raise ValueError(f"series {list(series)} names a series twice")
    return list(series)


def _column(result, spec: str, name: str, index: Optional[str]) -> np.ndarray:
    if name not in result:
        raise OutputError(f"output {spec!r}: the result has no series {name!r}; it has "
                          f"{', '.join(result.series)}")
    a = np.asarray(result[name], dtype=float)
    if index is None and a.ndim == 2 and a.shape[1] == 1:  # a per-hinge series of one hinge
        a = a[:, 0]
    if index is None:
        if a.ndim != 1:
            raise OutputError(f"output {spec!r}: series {name!r} has shape {a.shape}; choose a "
                              f"column with '{name}[k]'")
        return a
    if a.ndim != 2 or int(index) >= a.shape[1]:
        raise OutputError(f"output {spec!r}: series {name!r} of shape {a.shape} has no column {index}")
    return a[:, int(index)]


def _number(spec: str, value: Any, index: Optional[str]) -> float:
    if isinstance(value, (list, tuple)):
        if index is None and len(value) == 1:  # a per-hinge metric of a one-hinge scene
            index = "0"
        if index is None:
            raise OutputError(f"output {spec!r} has one value per hinge ({len(value)} hinges): choose "
                              f"hinge k with '{spec}[k]'")
        if int(index) >= len(value):
            raise OutputError(f"output {spec!r}: the chain has {len(value)} hinges")
        value = value[int(index)]
    elif index is not None:
        raise OutputError(f"output {spec!r}: the metric is one number (one hinge), drop '[{index}]'")
    if value is None:
        return math.nan  # undefined for this sample (e.g. never locked): documented as NaN
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise OutputError(f"output {spec!r} is not a number: {value!r}")
    return float(value)


def scalar(result, name: str, spec: Any, summary: Callable[[], dict]) -> float:
    """The value of one scalar output for one result (``summary``: the cached Result.summary)."""
    if callable(spec):
        value = spec(result)
        if isinstance(value, np.generic):
            value = value.item()
        if isinstance(value, bool) or not isinstance(value, numbers.Real):
            raise OutputError(f"output {name!r}: the function returned {value!r}, not a number")
        return float(value)
    m = _SUMMARY.match(spec)
    if m and m.group(1) in SUMMARY_KEYS:
        s = summary()
        if m.group(1) not in s:
            raise OutputError(f"output {spec!r}: the scene does not measure {m.group(1)!r} (its summary has "
                              f"{', '.join(s)})")
        return _number(spec, s[m.group(1)], m.group(2))
    how, series, index = _REDUCED.match(spec).groups()
    a = _column(result, spec, series, index)
    if how == "max":
        return float(a.max())
    if how == "min":
        return float(a.min())
    if how == "absmax":
        return float(np.abs(a).max())
    if how == "final":
        return float(a[-1])
    t = np.asarray(result.t)
    trapezoid = getattr(np, "trapezoid", None) or np.trapz  # numpy < 2 has trapz only
    return float(trapezoid(a, t) / (t[-1] - t[0])) if t.size > 1 else float(a[0])


def resampled(result, spec: str, time: np.ndarray) -> np.ndarray:
    """Series ``spec`` on the study's time grid: the run's values where its times are the grid,
    else linear interpolation (NaN outside the run's time span)."""
    name, index = _SUMMARY.match(spec).groups()
    a = _column(result, spec, name, index)
    t = np.asarray(result.t)
    if t.shape == time.shape and np.array_equal(t, time):
        return a.copy()
    out = np.interp(time, t, a)
    out[(time < t[0]) | (time > t[-1])] = np.nan
    return out


def evaluate(result, outputs: Mapping[str, Any], series: Sequence[str], time: np.ndarray) -> tuple:
    """({output: float}, {series: array on ``time``}) of one result."""
    cache: dict = {}

    def summary() -> dict:
        if "s" not in cache:
            cache["s"] = result.summary()
        return cache["s"]

    return ({k: scalar(result, k, spec, summary) for k, spec in outputs.items()},
            {s: resampled(result, s, time) for s in series})
