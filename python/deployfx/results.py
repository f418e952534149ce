"""Results of a simulation: named time series as read-only numpy arrays, their units, metadata.

A :class:`Result` is what ``simulate()`` returns. It is generic: the series depend on the scene.
The paper's scene (You et al. 2016) records

============================  ========  =========  ==============================================
name                          unit      shape      meaning
============================  ========  =========  ==============================================
``t``                         s         (n,)       time, strictly increasing
``deployment_angle``          deg       (n,)       yoke-appendage angle, 90 stowed, 180 deployed
``spring_torque``             N m       (n,)       hinge spring torque
``lock_force``                N         (n,)       normal contact force of the lock (>= 0)
``node_E_deflection``         m         (n,)       transverse deflection of node E (appendage frame)
``body_attitude``             deg       (n, 3)     attitude angles of the spacecraft body
``body_angular_momentum``     N m s     (n, 3)     angular momentum of the body
``total_angular_momentum``    N m s     (n, 3)     angular momentum of the whole system
============================  ========  =========  ==============================================

A chain of hinges (:class:`deployfx.chain.ChainModel`) records the per-hinge series as (n, N)
arrays, one column per hinge: ``deployment_angle`` (deg, each hinge's travel from stowed),
``spring_torque``, ``lock_force``, ... (see :meth:`deployfx.chain.ChainModel.simulate`).

Metadata is a JSON-compatible dict. Keys the engine writes: ``scene`` (parameters), ``model``
(``"rigid"``, ``"linear"``, ``"nonlinear"``), ``dt`` (s), ``integrator``, ``wall_time_s`` (s),
``steps`` (integration steps taken) and, when a run stopped early, ``failure`` (the message).

``save(path)`` writes one ``.npz`` (no pickle); :func:`load` reads it back bit for bit.

Files are written atomically (a temporary file beside the target, fsync'ed and renamed over it):
a save that fails or is killed leaves the previous file as it was. Each file ends with a
``deployfx_sha256`` entry, the SHA-256 of the header and of every series (name, dtype, shape,
bytes), that the header announces (``"checksum": "sha256"``): :func:`load` refuses a truncated
or altered file with a ValueError naming it. Files written before the checksum (no
``checksum`` in the header) are still read, unchecked beyond the zip format's own CRC-32.
"""
from __future__ import annotations

import copy
import hashlib
import json
import keyword
import math
import os
from pathlib import Path
from typing import Any, Mapping, Optional, Union

import numpy as np

from . import _atomic, metrics
from .metrics import _as_time

PathLike = Union[str, os.PathLike]

_FORMAT = "deployfx.Result"
_VERSION = 1
_HEADER = "deployfx_header"  # archive entry of the JSON header
_PREFIX = "series/"  # archive entries of the arrays; never collides with np.savez's parameters
_CHECKSUM = "deployfx_sha256"  # the last archive entry: SHA-256 of the header and the series

#: Keys of :meth:`Result.summary`, in order.
SUMMARY_KEYS = ("first_lock_time_s", "impacts", "peak_lock_force_N", "settling_time_s",
                "max_node_E_deflection_m", "body_attitude_change_deg", "momentum_drift",
                "steps", "wall_time_s")


class Result:
    """Named time series of one run, with units and metadata.

    Parameters
    ----------
    series
        Mapping of name to array. ``"t"`` (s, 1-D, finite, strictly increasing) is required; every
        other series has leading dimension ``len(t)``. Values must be finite real numbers. Names
        are Python identifiers not starting with ``_`` and not clashing with Result's own
        attributes, so each series is also an attribute: ``result.deployment_angle``.
    units
        Mapping of series name to unit string, e.g. ``{"deployment_angle": "deg"}``; ``t`` is
        ``"s"`` unless given. Series without an entry have no stated unit.
    metadata
        JSON-compatible mapping (str keys; None, bool, int, finite float, str, lists, dicts; numpy
        scalars and arrays are converted to Python numbers and lists).

    The arrays are copies of the inputs, marked read-only, so a result cannot be altered silently;
    ``t`` is stored as float64, other series keep their dtype. Bad shapes or values raise
    ``ValueError``, wrong types ``TypeError``, each naming the series, unit or metadata key.
    """

    def __init__(self, series: Mapping[str, Any], units: Optional[Mapping[str, str]] = None,
                 metadata: Optional[Mapping[str, Any]] = None):
        if not isinstance(series, Mapping):
            raise TypeError(f"series must be a mapping of name to array, "
                            f"got {type(series).__name__}")
        if "t" not in series:
            raise ValueError(f"series must contain 't' (time, s), got {sorted(series)}")
        t = _frozen(_as_time(series["t"]).copy())
        arrays = {"t": t}
        for name, value in series.items():
            if name == "t":
                continue
            _check_name(name)
            a = np.array(value, copy=True)
            if a.dtype.kind not in "biuf":
                raise ValueError(f"series {name!r} must hold real numbers, got dtype {a.dtype}")
            if a.ndim == 0 or a.shape[0] != t.size:
                raise ValueError(f"series {name!r} must have leading dimension len(t) = {t.size}, "
                                 f"got shape {a.shape}")
            metrics._check_finite(f"series {name!r}", a)
            arrays[name] = _frozen(a)
        self._series = arrays
        self._units = _check_units(units, arrays)
        self._metadata = _to_json_value(dict(metadata or {}), "metadata")

    @property
    def series(self) -> tuple[str, ...]:
        """Names of the series, ``"t"`` first."""
        return tuple(self._series)

    @property
    def units(self) -> dict[str, str]:
        """Unit of each series that has one, e.g. ``{"t": "s", "lock_force": "N"}`` (a copy)."""
        return dict(self._units)

    @property
    def metadata(self) -> dict[str, Any]:
        """Run metadata (a deep copy; see the module docstring for the keys the engine writes)."""
        return copy.deepcopy(self._metadata)

    @property
    def failure(self) -> Optional[str]:
        """The message of a run that stopped early, None for a complete run."""
        return self._metadata.get("failure")

    def __getattr__(self, name: str) -> np.ndarray:
        series = self.__dict__.get("_series")
        if series is not None and name in series:
            return series[name]
        raise AttributeError(f"Result has no series {name!r}; it has {', '.join(series or ())}")

    def __getitem__(self, name: str) -> np.ndarray:
        """The series ``name`` (read-only array)."""
        try:
            return self._series[name]
        except KeyError:
            raise KeyError(f"Result has no series {name!r}; "
                           f"it has {', '.join(self._series)}") from None

    def __contains__(self, name: object) -> bool:
        return name in self._series

    def __dir__(self) -> list[str]:
        return sorted(set(super().__dir__()) | set(self._series))

    def __repr__(self) -> str:
        t = self._series["t"]
        parts = []
        for name, a in self._series.items():
            if name == "t":
                continue
            shape = "" if a.ndim == 1 else "[" + "x".join(map(str, a.shape[1:])) + "]"
            unit = f" ({self._units[name]})" if name in self._units else ""
            parts.append(f"{name}{shape}{unit}")
        span = f"t = {t[0]:g} .. {t[-1]:g} {self._units.get('t', '')}".rstrip()
        text = f"Result({t.size} samples, {span}; series: {', '.join(parts) or 'none'}"
        if "model" in self._metadata:
            text += f"; model={self._metadata['model']!r}"
        if self.failure is not None:
            text += f"; stopped early: {self.failure}"
        return text + ")"

    def save(self, path: PathLike) -> Path:
        """Write the result to one ``.npz`` file at exactly ``path``; returns the path.

        Arrays are stored as they are (lossless); units, metadata and the series order as a JSON
        header inside the archive. Nothing is pickled.
        """
        header = json.dumps({"format": _FORMAT, "version": _VERSION, "series": list(self._series),
                             "units": self._units, "metadata": self._metadata,
                             "checksum": "sha256"}, allow_nan=False)
        path = Path(path)
        entries = {_PREFIX + name: a for name, a in self._series.items()}
        digest = _digest(header, self._series)
        with _atomic.atomic_open(path, "wb") as fh:
            np.savez(fh, **{_HEADER: np.array(header)}, **entries, **{_CHECKSUM: np.array(digest)})
        return path

    def to_dataframe(self):
        """A pandas DataFrame indexed by ``t`` (s), one column per scalar series; vector series
        become ``name_x``, ``name_y``, ``name_z`` (3 components) or ``name[0]``, ``name[1]``, ...
        (``name[i,j]`` for higher ranks). ``df.attrs["units"]`` maps each column to its unit.
        """
        try:
            import pandas as pd
        except ImportError as exc:
            raise ImportError("Result.to_dataframe needs pandas: pip install pandas "
                              "(or pip install 'deployfx[test]')") from exc
        columns: dict[str, np.ndarray] = {}
        units: dict[str, str] = {}
        for name, a in self._series.items():
            if name == "t":
                continue
            for column, values in _columns(name, a):
                if column in columns:
                    raise ValueError(f"series {name!r} gives column {column!r}, which another "
                                     "series already uses")
                columns[column] = values
                if name in self._units:
                    units[column] = self._units[name]
        index = pd.Index(np.array(self._series["t"]), name="t")
        df = pd.DataFrame({c: np.array(v) for c, v in columns.items()}, index=index)
        df.attrs["units"] = units
        return df

    def summary(self) -> dict[str, Any]:
        """Metrics of the run computed from its series (see :mod:`deployfx.metrics`), in the order
        of ``SUMMARY_KEYS``. Every key is always present; a value is None when the series it
        needs is absent or the metric is undefined (e.g. the hinge never locks).

        - ``first_lock_time_s`` (s): first sample with ``lock_force`` > 0, or, without a lock
          force, the first time ``deployment_angle`` reaches 180 deg (interpolated).
        - ``impacts``: number of separate contacts in ``lock_force`` (chatter shorter than 0.05 s
          merged, contacts below 1e-3 of the peak dropped).
        - ``peak_lock_force_N`` (N): max of ``lock_force``.
        - ``settling_time_s`` (s): ``deployment_angle`` within 0.1 deg of its final value, or
          within the lock's free play if wider (metadata ``lock_play_deg``: a latched pin may rest
          anywhere in its groove), and ``lock_force`` within 1 % of its peak of its final value
          from then on, for at least 1 s.
        - ``max_node_E_deflection_m`` (m): max |``node_E_deflection``|.
        - ``body_attitude_change_deg`` (deg): |``body_attitude``[-1] - ``body_attitude``[0]|.
        - ``momentum_drift``: max |H - H(0)| / max |H_b - H_b(0)| from ``total_angular_momentum``
          and ``body_angular_momentum``.
        - ``steps``, ``wall_time_s`` (s): from the metadata.

        A chain of hinges records ``lock_force`` and ``deployment_angle`` as (n, N) series, one
        column per hinge: the four lock metrics are then lists with one value per hinge.
        """
        s = self._series
        t = s["t"]
        force, angle = s.get("lock_force"), s.get("deployment_angle")
        out: dict[str, Any] = dict.fromkeys(SUMMARY_KEYS)
        if force is not None or angle is not None:
            out["first_lock_time_s"] = _per_hinge(metrics.first_lock_time, t, force, angle)
        if force is not None:
            out["impacts"] = _per_hinge(metrics.impact_count, t, force)
            out["peak_lock_force_N"] = _per_hinge(metrics.peak_lock_force, None, force)
        if angle is not None:
            out["settling_time_s"] = self._settling_time(t, angle, force)
        if "node_E_deflection" in s:
            out["max_node_E_deflection_m"] = metrics.max_abs(s["node_E_deflection"],
                                                             "node_E_deflection")
        if "body_attitude" in s:
            out["body_attitude_change_deg"] = metrics.attitude_change(s["body_attitude"])
        if "total_angular_momentum" in s and "body_angular_momentum" in s:
            out["momentum_drift"] = metrics.momentum_drift(s["total_angular_momentum"],
                                                           s["body_angular_momentum"])
        out["steps"] = self._metadata.get("steps")
        out["wall_time_s"] = self._metadata.get("wall_time_s")
        return out

    def _settling_time(self, t, angle, force):
        """metrics.lock_settling_time per hinge, its angle band widened to the lock's play."""
        play = self._metadata.get("lock_play_deg")
        if angle.ndim == 1:
            return metrics.lock_settling_time(t, angle, force, angle_tol=_angle_band(play))
        plays = play if isinstance(play, (list, tuple)) else [play] * angle.shape[1]
        return [metrics.lock_settling_time(t, angle[:, k], None if force is None else force[:, k],
                                           angle_tol=_angle_band(plays[k]))
                for k in range(angle.shape[1])]


#: deg: the settling band of a deployment angle (Result.summary), unless the lock's play is wider.
SETTLING_ANGLE_TOL_DEG = 0.1


def _angle_band(play_deg) -> float:
    return max(SETTLING_ANGLE_TOL_DEG, float(play_deg)) if play_deg is not None else SETTLING_ANGLE_TOL_DEG


def load(path: PathLike) -> Result:
    """Read a :class:`Result` written by :meth:`Result.save` (arrays bit for bit, same units,
    metadata and series order). Refuses pickled content, and raises ValueError naming the file
    for one that is truncated, altered (its SHA-256 does not match) or not a result file."""
    # The file is opened here, not by np.load, which leaks its handle on a broken archive.
    with open(Path(path), "rb") as fh:
        # Whatever a damaged archive raises inside zipfile or numpy (BadZipFile, EOFError,
        # NotImplementedError for a garbled compression method, struct.error, ...) is the file's
        # fault: a ValueError naming it, with the cause chained.
        try:
            archive = np.load(fh, allow_pickle=False)
        except Exception as e:  # noqa: BLE001
            raise ValueError(f"{path} is not a readable deployfx result file: "
                             f"{type(e).__name__}: {e}") from e
        if not isinstance(archive, np.lib.npyio.NpzFile):
            raise ValueError(f"{path} is not a deployfx result file (a bare .npy array, not an "
                             "archive)")
        try:
            with archive:
                header, series = _read_archive(archive, path)
        except Exception as e:  # noqa: BLE001 - see above
            if isinstance(e, ValueError) and str(e).startswith(str(path)):
                raise
            raise ValueError(f"{path} is truncated or corrupted: {type(e).__name__}: {e}") from e
    try:
        return Result(series, header["units"], header["metadata"])
    except (ValueError, TypeError) as e:
        raise ValueError(f"{path}: {e}") from e


def _read_archive(archive, path) -> tuple[dict, dict]:
    """The header and the series of an open result archive, checked against its checksum."""
    if _HEADER not in archive.files:
        raise ValueError(f"{path} is not a deployfx result file (no {_HEADER} entry)")
    text = str(archive[_HEADER])
    header = json.loads(text)
    if not isinstance(header, dict) or header.get("format") != _FORMAT or \
            not isinstance(header.get("version"), int):
        raise ValueError(f"{path} is not a deployfx result file (format "
                         f"{header.get('format') if isinstance(header, dict) else header!r})")
    if header["version"] > _VERSION:
        raise ValueError(f"{path} has result format version {header['version']}; this deployfx "
                         f"reads up to version {_VERSION}")
    names, units, metadata = header.get("series"), header.get("units"), header.get("metadata")
    if not (isinstance(names, list) and all(isinstance(n, str) for n in names)
            and isinstance(units, dict) and isinstance(metadata, dict)):
        raise ValueError(f"{path} has a malformed header (series, units, metadata)")
    missing = [name for name in names if _PREFIX + name not in archive.files]
    if missing:
        raise ValueError(f"{path} is missing the series {missing}")
    series = {name: archive[_PREFIX + name] for name in names}
    checksum = header.get("checksum")
    if checksum is not None:  # files written before the checksum have none
        if checksum != "sha256" or _CHECKSUM not in archive.files:
            raise ValueError(f"{path} is truncated or corrupted: its header announces a "
                             f"{checksum!r} checksum and the {_CHECKSUM} entry is missing")
        if str(archive[_CHECKSUM]) != _digest(text, series):
            raise ValueError(f"{path} is corrupted: its content does not match its SHA-256 "
                             f"checksum (altered after it was saved)")
    return header, series


def _digest(header: str, series: Mapping[str, np.ndarray]) -> str:
    """SHA-256 (hex) of the header text and of every series' name, dtype, shape and bytes."""
    h = hashlib.sha256(header.encode("utf-8"))
    for name, a in series.items():
        h.update(json.dumps([name, a.dtype.str, list(a.shape)]).encode("utf-8"))
        h.update(np.ascontiguousarray(a).view(np.uint8).reshape(-1).data if a.size else b"")
    return h.hexdigest()


def _per_hinge(metric, t, *series):
    """``metric(t, *series)``, or for (n, N) series (a chain of hinges) the list of the metric of
    each column; ``t`` None: the metric takes the series only. None series stay None."""
    hinges = next((a.shape[1] for a in series if a is not None and a.ndim == 2), None)
    args = () if t is None else (t,)
    if hinges is None:
        return metric(*args, *series)
    return [metric(*args, *(a if a is None or a.ndim == 1 else a[:, k] for a in series))
            for k in range(hinges)]


def _frozen(a: np.ndarray) -> np.ndarray:
    a.flags.writeable = False
    return a


def _check_name(name: object) -> None:
    if not isinstance(name, str) or not name.isidentifier() or keyword.iskeyword(name):
        raise ValueError(f"series names must be Python identifiers, got {name!r}")
    if name.startswith("_") or hasattr(Result, name):
        raise ValueError(f"series name {name!r} is reserved (leading underscore or an attribute "
                         "of Result)")


def _check_units(units: Optional[Mapping[str, str]], arrays: Mapping[str, np.ndarray]) -> dict:
    out = {"t": "s"}
    for name, unit in dict(units or {}).items():
        if name not in arrays:
            raise ValueError(f"units names {name!r}, which is not a series; series: {list(arrays)}")
        if not isinstance(unit, str):
            raise TypeError(f"units[{name!r}] must be a string, "
                            f"got {type(unit).__name__} {unit!r}")
        out[name] = unit
    return {name: out[name] for name in arrays if name in out}


def _to_json_value(value: Any, where: str) -> Any:
    """``value`` in the form JSON gives back (tuples as lists, numpy as Python); TypeError for
    what JSON cannot hold, ValueError for NaN or inf."""
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{where} must be finite, got {value!r}")
        return value
    if isinstance(value, (list, tuple)):
        return [_to_json_value(v, f"{where}[{k}]") for k, v in enumerate(value)]
    if isinstance(value, Mapping):
        out = {}
        for key, v in value.items():
            if not isinstance(key, str):
                raise TypeError(f"{where} keys must be strings, got {key!r}")
            out[key] = _to_json_value(v, f"{where}[{key!r}]")
        return out
    raise TypeError(f"{where} must be JSON-compatible (None, bool, int, float, str, list, dict), "
                     f"got {type(value).__name__}")


def _columns(name: str, a: np.ndarray):
    """(column name, 1-D values) pairs of one series for a DataFrame."""
    if a.ndim == 1:
        yield name, a
    elif a.shape[1:] == (3,):
        for k, axis in enumerate("xyz"):
            yield f"{name}_{axis}", a[:, k]
    else:
        for index in np.ndindex(*a.shape[1:]):
            yield f"{name}[{','.join(map(str, index))}]", a[(slice(None),) + index]
