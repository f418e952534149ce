"""Results of a simulation: named time series as read-only numpy arrays, their units, metadata.

A :class:`Result` is what ``simulate()`` returns, with one series vocabulary for every scene (one
hinge, a chain, a tree): H is the number of hinges, in hinge order; ``result.hinge(k)`` gives a
Result whose per-hinge series are hinge k's 1-D columns.

=============================  ========  ==========  =============================================
name                           unit      shape       meaning
=============================  ========  ==========  =============================================
``t``                          s         (n,)        time, strictly increasing
``deployment_angle``           deg       (n, H)      the hinge's stowed angle + its travel
``deployment_rate``            deg/s     (n, H)      its rate
``spring_torque``              N m       (n, H)      tau0 - k_theta theta
``lock_force``                 N         (n, H)      the lock's normal contact force (>= 0)
``lock_torque``                N m       (n, H)      the lock's torque on the hinge
``latched``                    1         (n, H)      1 once the lock has latched
``hinge_force``                N         (n, H, 3)   the force the parent exerts on the hinge's
                                                     subtree through the joint, body axes
``hinge_moment``               N m       (n, H, 3)   its moment about the hinge point, across the
                                                     axis (the axial torque: spring, lock)
``strain_energy``              J         (n, H)      the panel's (0: rigid or none)
``tip_displacement``           m         (n, H, 3)   the panel's tip node, body axes
``tip_deflection``             m         (n, H)      along the hinge rotation's direction there
``body_attitude``              deg       (n, 3)      the base's rotation vector
``body_angular_momentum``      N m s     (n, 3)      the base's, about W's origin
``total_angular_momentum``     N m s     (n, 3)      the whole system's
``body_linear_momentum``       N s       (n, 3)      the base's
``total_linear_momentum``      N s       (n, 3)      the whole system's
``kinetic_energy``             J         (n,)
``potential_energy``           J         (n,)        springs and strain energy
``q``, ``v``                             (n, nq/nv)  the coordinates and velocities (Model.layout)
=============================  ========  ==========  =============================================

A scene may add its own series (the paper's ``node_E_deflection``, m, (n,)), and a run asked for
node displacements adds ``node_displacements_<k>`` (m, (n, nodes, 3)).

Metadata is a JSON-compatible dict. Keys the engine writes: the scene's description (a ready
scene's ``scene`` name and ``parameters``), ``hinges`` (per hinge: parent, fidelity, lock,
lock_play_deg, driven, spin_up, stowed_angle_deg, mesh, a reduced panel's basis and its
elastic coordinates), ``base_free``, ``dt`` (s),
``t_end`` (s), ``integrator``, ``tolerance``, ``deployfx_version``, ``run_started_utc``,
``wall_time_s``, the step counts and, when a run stopped early, ``failure``;
:meth:`Result.settings` gathers the ones that say how the run was made.

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
import os
from pathlib import Path
from typing import Any, Mapping, Optional, Union

import numpy as np

from . import _result_file, metrics
from ._result_checks import check_units, checked_arrays, frozen, frozen_copies, to_json_value
from .metrics import _as_time

PathLike = Union[str, os.PathLike]


#: The series with one column per hinge ((n, H, ...)): Result.hinge(k) takes column k.
PER_HINGE_SERIES = ("deployment_angle", "deployment_rate", "spring_torque", "lock_force", "lock_torque", "latched",
                    "hinge_force", "hinge_moment", "strain_energy", "tip_displacement", "tip_deflection")
#: The per-hinge series with a vector per hinge ((n, H, 3)).
_VECTOR_PER_HINGE_SERIES = ("hinge_force", "hinge_moment", "tip_displacement")
#: Per-hinge metrics of :meth:`Result.summary` (lists, one value per hinge), in order.
HINGE_KEYS = ("first_lock_time_s", "impacts", "peak_lock_force_N", "peak_lock_force_time_s", "peak_impact_impulse_N_s",
              "settling_time_s", "max_tip_deflection_m", "max_tip_deflection_time_s", "tip_deflection_after_spin_up_m",
              "peak_hinge_force_N", "peak_hinge_moment_Nm", "min_failure_margin", "critical_ply", "critical_element",
              "critical_time_s")
#: System metrics of :meth:`Result.summary`, in order.
SYSTEM_KEYS = ("max_node_E_deflection_m", "body_attitude_change_deg", "momentum_drift", "steps", "wall_time_s")
#: Every key :meth:`Result.summary` may give, in order.
SUMMARY_KEYS = HINGE_KEYS + SYSTEM_KEYS


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

    #: The run's :class:`~deployfx.checkpoint.Checkpoint` objects (``simulate(checkpoint_at=...)``);
    #: not saved with the result (each has its own ``save``).
    checkpoints: tuple = ()

    def __init__(self, series: Mapping[str, Any], units: Optional[Mapping[str, str]] = None,
                 metadata: Optional[Mapping[str, Any]] = None):
        if not isinstance(series, (dict, Mapping)):  # a dict without typing's ABC check
            raise TypeError(f"series must be a mapping of name to array, "
                            f"got {type(series).__name__}")
        if "t" not in series:
            raise ValueError(f"series must contain 't' (time, s), got {sorted(series)}")
        t = frozen(_as_time(series["t"]).copy())
        arrays = {"t": t}
        arrays.update(frozen_copies(checked_arrays(series, t.size, _RESERVED_NAMES)))
        self._series = arrays
        self._units = check_units(units, arrays)
        self._metadata = to_json_value(dict(metadata or {}), "metadata")

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
        return _result_file.write(Path(path), self._series, self._units, self._metadata)

    def to_dataframe(self):
        """A pandas DataFrame indexed by ``t`` (s), one column per scalar series; vector series
        become ``name_x``, ``name_y``, ``name_z`` (3 components) or ``name[0]``, ``name[1]``, ...
        (``name[i,j]`` for higher ranks); per-hinge series one column per hinge, ``name[k]``
        (``name[k]_x``, ... for their vectors). ``df.attrs["units"]`` maps each column to its unit.
        """
        try:
            import pandas as pd
        except ImportError as exc:
            raise ImportError("Result.to_dataframe needs pandas: pip install pandas "
                              "(or pip install 'deployfx[test]')") from exc
        columns: dict[str, np.ndarray] = {}
        units: dict[str, str] = {}
        view = self._hinge_axes()[1]
        for name, a in self._series.items():
            if name == "t":
                continue
            for column, values in _columns(name, a, per_hinge=name in PER_HINGE_SERIES and not view):
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

    def hinge(self, k: int) -> "Result":
        """Hinge k's view: each per-hinge series (``PER_HINGE_SERIES``, (n, H, ...)) replaced by its
        column k, the system series as they are, and the metadata's ``hinges`` reduced to hinge
        k's entry (its summary then gives scalars)."""
        H = self.num_hinges
        if isinstance(k, bool) or not isinstance(k, (int, np.integer)):
            raise TypeError(f"k must be a hinge index (int), got {type(k).__name__}")
        if not 0 <= k < H:
            raise ValueError(f"k = {k} is out of range: must be in [0, {H - 1}] (the run's hinges)")
        view = self._hinge_axes()[1]
        series = {name: (a[:, k] if name in PER_HINGE_SERIES and not view else a)
                  for name, a in self._series.items()}
        meta = copy.deepcopy(self._metadata)
        if isinstance(meta.get("hinges"), list) and len(meta["hinges"]) == H:
            meta["hinges"] = [meta["hinges"][k]]
        meta["hinge_index"] = int(k)
        return Result(series, self._units, meta)

    @property
    def impacts(self) -> tuple:
        """The lock impacts of the run (:class:`deployfx.impacts.Impact`, one per contact of a
        lock wall, located from every step the engine took), in order of onset; a hinge view's
        are its hinge's."""
        from .impacts import Impact

        infos = self._metadata.get("hinges")
        records = [Impact.from_dict(r) for info in (infos if isinstance(infos, list) else [])
                   if isinstance(info, dict) for r in info.get("impacts", ())]
        return tuple(sorted(records, key=lambda r: r.t_onset_s))

    @property
    def num_hinges(self) -> int:
        """The run's hinges: the width of its per-hinge series (1 for a hinge view)."""
        return self._hinge_axes()[0]

    def _hinge_axes(self) -> tuple[int, bool]:
        """(H, view): the width of the per-hinge series, and whether they are one hinge's columns
        ((n,), or (n, 3) for the vector series) rather than (n, H, ...)."""
        for name in PER_HINGE_SERIES:
            a = self._series.get(name)
            if a is not None:
                column_ndim = 2 if name in _VECTOR_PER_HINGE_SERIES else 1
                return (1, True) if a.ndim == column_ndim else (int(a.shape[1]), False)
        hinges = self._metadata.get("hinges")
        return (len(hinges) if isinstance(hinges, list) else 0), False

    def summary(self, hinge: Optional[int] = None) -> dict[str, Any]:
        """Metrics of the run computed from its series (see :mod:`deployfx.metrics`), in the order
        of ``SUMMARY_KEYS``: per-hinge metrics as lists (one value per hinge; None where the metric
        does not apply to that hinge) and system metrics. A key is left out when the scene has
        nothing it measures (no lock, no deforming panel, a fixed base). ``hinge=k``: hinge k's
        value of each per-hinge metric instead of the list (a hinge view, ``result.hinge(k)``,
        gives scalars too).

        Per hinge:

        - ``first_lock_time_s`` (s): the first sample with ``lock_force`` > 0 (hinges with a lock).
        - ``impacts``: separate contacts in ``lock_force`` (chatter shorter than 0.05 s merged,
          contacts below 1e-3 of the peak dropped).
        - ``peak_lock_force_N`` (N), ``peak_lock_force_time_s`` (s), ``peak_impact_impulse_N_s``
          (N s): the largest located peak among the run's impact records (:attr:`impacts`), when
          it was, and that impact's impulse; a result without records (older files) gives the max
          of ``lock_force`` and its sample time, and no impulse.
        - ``settling_time_s`` (s): ``deployment_angle`` within 0.1 deg of its final value, or within
          the lock's free play if wider (metadata ``hinges[k].lock_play_deg``: a latched pin may
          rest anywhere in its groove), and ``lock_force`` within 1 % of its peak of its final value
          from then on, for at least 1 s.
        - ``max_tip_deflection_m`` (m), ``max_tip_deflection_time_s`` (s): max |``tip_deflection``|
          and its first sample time (hinges carrying a deforming panel).
        - ``tip_deflection_after_spin_up_m`` (m): max |``tip_deflection``| once a prescribed
          spin-up has reached its final rate, t >= t_s (metadata ``hinges[k].spin_up``; None if
          the run ends before t_s).
        - ``peak_hinge_force_N``, ``peak_hinge_moment_Nm``: max |``hinge_force``|, |``hinge_moment``|.
        - ``min_failure_margin``, ``critical_ply`` (0-based from the bottom), ``critical_element``
          (an index into the panel's quads), ``critical_time_s``: the ply failure envelope of a run
          with ``stresses=True`` (metadata ``hinges[k]["stress"]``; deployfx.stress).

        System: ``max_node_E_deflection_m`` (m, the paper's node E, when recorded),
        ``body_attitude_change_deg`` (deg, |``body_attitude``[-1] - ``body_attitude``[0]|, free base),
        ``momentum_drift`` (free base: the total linear and angular momentum's largest change
        relative to the momentum the bodies carry, metadata ``momentum_scale``), ``steps`` and ``wall_time_s`` (s) from the metadata.
        """
        s = self._series
        t = s["t"]
        H, view = self._hinge_axes()
        infos = self._metadata.get("hinges")
        if not (isinstance(infos, list) and len(infos) == H):
            infos = [{} for _ in range(H)]

        def column(name: str, k: int):
            a = s.get(name)
            if a is None:
                return None
            return a if view else a[:, k]

        per: dict[str, list] = {key: [None] * H for key in HINGE_KEYS}
        measured = set()  # the keys some hinge measures (a value of None there: undefined, e.g. never locked)
        for k in range(H):
            info = infos[k]
            force, angle = column("lock_force", k), column("deployment_angle", k)
            if force is not None and info.get("lock", True):
                measured.update(("first_lock_time_s", "impacts", "peak_lock_force_N"))
                per["first_lock_time_s"][k] = metrics.first_contact_time(t, force)
                per["impacts"][k] = metrics.impact_count(t, force)
                records = info.get("impacts")
                if isinstance(records, list):
                    from .impacts import Impact, strongest

                    measured.update(("peak_lock_force_time_s", "peak_impact_impulse_N_s"))
                    peak = strongest(Impact.from_dict(r) for r in records)
                    if peak is not None:
                        per["peak_lock_force_N"][k] = peak.peak_force_N
                        per["peak_lock_force_time_s"][k] = peak.t_peak_s
                        per["peak_impact_impulse_N_s"][k] = peak.impulse_N_s
                    else:
                        per["peak_lock_force_N"][k] = 0.0
                else:
                    measured.add("peak_lock_force_time_s")
                    per["peak_lock_force_N"][k] = metrics.peak_lock_force(force)
                    if force.max() > 0:
                        per["peak_lock_force_time_s"][k] = float(t[int(np.argmax(force))])
                if angle is not None:
                    measured.add("settling_time_s")
                    per["settling_time_s"][k] = metrics.lock_settling_time(
                        t, angle, force, angle_tol=_angle_band(info.get("lock_play_deg")))
            tip = column("tip_deflection", k)
            if tip is not None and info.get("fidelity") not in (None, "rigid"):
                measured.update(("max_tip_deflection_m", "max_tip_deflection_time_s"))
                per["max_tip_deflection_m"][k] = metrics.max_abs(tip, "tip_deflection")
                per["max_tip_deflection_time_s"][k] = float(t[int(np.argmax(np.abs(tip)))])
                spin_up = info.get("spin_up")
                if isinstance(spin_up, dict) and "t_s_s" in spin_up:
                    measured.add("tip_deflection_after_spin_up_m")
                    after = np.asarray(tip)[np.asarray(t) >= spin_up["t_s_s"]]
                    per["tip_deflection_after_spin_up_m"][k] = float(np.abs(after).max()) if after.size else None
            for key, name in (("peak_hinge_force_N", "hinge_force"), ("peak_hinge_moment_Nm", "hinge_moment")):
                a = column(name, k)
                if a is not None:
                    measured.add(key)
                    per[key][k] = float(np.linalg.norm(a, axis=-1).max())
            if isinstance(info.get("stress"), dict):  # a run with stresses=True (Model.simulate)
                for key in ("min_failure_margin", "critical_ply", "critical_element", "critical_time_s"):
                    measured.add(key)
                    per[key][k] = info["stress"].get(key)
        out: dict[str, Any] = {}
        for key in HINGE_KEYS:
            values = per[key]
            if key not in measured:
                continue
            if view:
                out[key] = values[0]
            elif hinge is not None:
                k = self._summary_hinge(hinge, H)
                out[key] = values[k]
            else:
                out[key] = values
        if "node_E_deflection" in s:
            out["max_node_E_deflection_m"] = metrics.max_abs(s["node_E_deflection"], "node_E_deflection")
        free = self._metadata.get("base_free", True)
        if free and "body_attitude" in s:
            out["body_attitude_change_deg"] = metrics.attitude_change(s["body_attitude"])
        if free and "total_angular_momentum" in s and "body_angular_momentum" in s:
            drift = self._momentum_drift()
            if drift is not None:
                out["momentum_drift"] = drift
        for key in ("steps", "wall_time_s"):
            if self._metadata.get(key) is not None:
                out[key] = self._metadata[key]
        return out

    def settings(self) -> dict[str, Any]:
        """How the run was made, from its metadata (None where a result built by hand lacks it):
        ``scene`` (a ready scene's name or a scene file), ``parameters`` (the scene's
        parameters), ``mesh`` and ``fidelity`` (per hinge: the panel's ``{"nodes", "quads"}`` and
        fidelity, None without a panel), ``dt`` (s), ``t_end`` (s), ``scheme``, ``tolerance``
        (None: fixed steps of ``dt``), ``newton_tolerance``, ``deployfx_version`` and
        ``run_started_utc``."""
        m = self._metadata
        hinges = m.get("hinges") if isinstance(m.get("hinges"), list) else None
        per = (lambda key: None if hinges is None else [h.get(key) if isinstance(h, dict) else None for h in hinges])
        return copy.deepcopy({"scene": m.get("scene"), "parameters": m.get("parameters"), "mesh": per("mesh"),
                              "fidelity": per("fidelity"), "dt": m.get("dt"), "t_end": m.get("t_end"),
                              "scheme": m.get("integrator"), "tolerance": m.get("tolerance"),
                              "newton_tolerance": m.get("newton_tolerance"),
                              "deployfx_version": m.get("deployfx_version"),
                              "run_started_utc": m.get("run_started_utc")})

    def _momentum_drift(self) -> Optional[float]:
        """The total momentum's largest change relative to the momentum the bodies carry
        (metadata ``momentum_scale``: the peak of the sum of the bodies' |P| and |H|), the larger
        of the linear and the angular; without that scale, relative to the angular momentum the
        base exchanges (metrics.momentum_drift)."""
        s = self._series
        scale = self._metadata.get("momentum_scale")
        if not isinstance(scale, dict):
            return metrics.momentum_drift(s["total_angular_momentum"], s["body_angular_momentum"])
        out = None
        for name, key in (("total_linear_momentum", "P_N_s"), ("total_angular_momentum", "H_N_m_s")):
            if name in s and scale.get(key):
                a = s[name]
                ratio = float(np.linalg.norm(a - a[0], axis=1).max()) / scale[key]
                out = ratio if out is None else max(out, ratio)
        return out

    @staticmethod
    def _summary_hinge(hinge, H: int) -> int:
        if isinstance(hinge, bool) or not isinstance(hinge, (int, np.integer)):
            raise TypeError(f"hinge must be a hinge index (int) or None, got {type(hinge).__name__}")
        if not 0 <= hinge < H:
            raise ValueError(f"hinge = {hinge} is out of range: must be in [0, {H - 1}]")
        return int(hinge)


#: deg: the settling band of a deployment angle (Result.summary), unless the lock's play is wider.
#: Names a series cannot take: the Result's own attributes (series are attributes too).
_RESERVED_NAMES = frozenset(dir(Result))

SETTLING_ANGLE_TOL_DEG = 0.1


def _angle_band(play_deg) -> float:
    return max(SETTLING_ANGLE_TOL_DEG, float(play_deg)) if play_deg is not None else SETTLING_ANGLE_TOL_DEG


def load(path: PathLike) -> Result:
    """Read a :class:`Result` written by :meth:`Result.save` (arrays bit for bit, same units,
    metadata and series order). Refuses pickled content, and raises ValueError naming the file
    for one that is truncated, altered (its SHA-256 does not match) or not a result file."""
    series, units, metadata = _result_file.read(path)
    try:
        return Result(series, units, metadata)
    except (ValueError, TypeError) as e:
        raise ValueError(f"{path}: {e}") from e


def _columns(name: str, a: np.ndarray, per_hinge: bool = False):
    """(column name, 1-D values) pairs of one series for a DataFrame; ``per_hinge``: a (n, H, ...)
    series, one column per hinge ``name[k]`` (then per component, ``name[k]_x``)."""
    if per_hinge:
        for k in range(a.shape[1]):
            yield from _columns(f"{name}[{k}]", a[:, k])
    elif a.ndim == 1:
        yield name, a
    elif a.shape[1:] == (3,):
        for k, axis in enumerate("xyz"):
            yield f"{name}_{axis}", a[:, k]
    else:
        for index in np.ndindex(*a.shape[1:]):
            yield f"{name}[{','.join(map(str, index))}]", a[(slice(None),) + index]
