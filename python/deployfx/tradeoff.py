"""The speed-accuracy trade of the paper's scene, measured (issue 6).

:func:`tradeoff` runs a list of :class:`Case` (fidelity, modes and modal derivatives, mesh, step,
integrator) of the paper's scene (You et al. 2016, :func:`deployfx.scenes.paper2016`) and a
reference case, times each run and measures its error against the reference in the three
quantities the paper reports:

- ``lock_time_error_s`` (s): |first lock time - the reference's| (the first output sample with a
  lock force > 0, :func:`deployfx.metrics.first_lock_time`);
- ``peak_lock_force_rel_error``: |peak lock force - the reference's| / the reference's (the
  largest located peak among the run's impact records in [0, t_end], ``Result.impacts``; for a
  result without records, the largest output sample);
- ``node_E_rms_rel_error``: the RMS over [0, t_end] of the node E deflection history minus the
  reference's (linearly interpolated onto the case's output times; time-weighted by the
  trapezoidal rule, so samples added at contact events do not weigh more), divided by the
  reference's max |deflection| over [0, t_end].

The rows are plain dicts (keys :data:`COLUMNS`, units in the names), so the table needs nothing
beyond numpy; :mod:`deployfx.tradeoff_report` writes it out (CSV, markdown, pandas) and draws
the work-precision plot. ``bench/tradeoff.py`` runs the
issue's sweep from the command line.

Wall times are those of ``simulate()`` (``wall_time_s``, the median of ``repeat`` runs); the cost
of building the scene (mesh, matrices, the reduced basis) is reported apart as ``setup_s``.
"""
from __future__ import annotations

import math
import statistics
import time
from dataclasses import dataclass, fields
from typing import Any, Callable, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from . import impacts
from . import paper2016 as _paper
from . import scenes
from ._checks import as_float, as_int
from ._run import newton_tolerance_arg
from .integrators import HHT, GeneralizedAlpha, Newmark, Scheme, SimulationError, _check_scheme
from .results import Result
from .scene import FIDELITIES

#: The fidelities whose basis has modal derivatives (Case.derivative_modes, derivative_partners).
_DERIVATIVE_MODELS = ("reduced-nonlinear", "reduced-manifold")

#: Error metrics, in the order of the plot's panels: column name -> axis label.
ERRORS = {"lock_time_error_s": "|first lock time error| (s)",
          "peak_lock_force_rel_error": "peak lock force, relative error",
          "node_E_rms_rel_error": "node E deflection, RMS error / max |ref|"}

#: Columns of a row, in order. Units in the names: s, N, m; ``*_rel_error`` are fractions.
COLUMNS = ("label", "model", "modes", "modal_derivatives", "basis_size", "mesh", "coordinates",
           "dt_s", "tolerance", "newton_tolerance", "integrator", "setup_s", "wall_time_s", "steps", "substeps",
           "newton_iterations", "ms_per_step", "t_reached_s", "lock_time_s", "peak_lock_force_N",
           "max_node_E_deflection_m",
           "lock_time_error_s", "peak_lock_force_rel_error", "node_E_rms_rel_error",
           "ref_lock_time_s", "ref_peak_lock_force_N", "ref_max_node_E_deflection_m",
           "is_reference", "failure")


def scheme_label(scheme: Scheme) -> str:
    """Short name of an integrator: ``GA(0.8)`` (rho_inf), ``HHT(-0.05)`` (alpha),
    ``Newmark(0.25,0.5)`` (beta, gamma)."""
    if isinstance(scheme, GeneralizedAlpha):
        return f"GA({scheme.rho_inf:g})"
    if isinstance(scheme, HHT):
        return f"HHT({scheme.alpha:g})"
    if isinstance(scheme, Newmark):
        return f"Newmark({scheme.beta:g},{scheme.gamma:g})"
    raise TypeError(f"scheme must be Newmark, HHT or GeneralizedAlpha, got {type(scheme).__name__}")


@dataclass(frozen=True)
class Case:
    """One run of the paper's scene: what it costs and how accurate it is depend on these.

    - ``model``: fidelity, one of ``rigid``, ``linear``, ``nonlinear``, ``reduced-linear``,
      ``reduced-nonlinear``, ``reduced-manifold`` (:class:`~deployfx.specs.Fidelity`);
    - ``nx``, ``ny``: elements along the 2.0 m length and the 1.3 m width (the paper: 15 x 10);
    - ``dt`` (s): output step, the fixed integration step unless ``tolerance`` is set;
    - ``scheme``: the integrator (``GeneralizedAlpha``, ``HHT`` or ``Newmark``);
    - ``modes``: clamped modes of a reduced model (None: the scene's default, 10); must be None
      for the full fidelities;
    - ``derivative_modes``: the reduced-nonlinear (or reduced-manifold) basis's modal derivatives
      are those of every pair among its first ``derivative_modes`` modes (None: min(modes, 3);
      fewer: a smaller basis, cheaper per step, whose node E deflection drifts from the full
      model's); must be None for the other fidelities;
    - ``derivative_partners``: and those of each of its first ``derivative_partners`` modes with
      every mode and static correction (None: the scene's default, 1; 0: the pairs above only;
      docs/research/undamped-stability.md); reduced-nonlinear and reduced-manifold only, like
      ``derivative_modes``;
    - ``tolerance`` (m or rad): error-controlled steps of at most ``dt``
      (:meth:`deployfx.scene.Model.simulate`); None: fixed steps;
    - ``newton_tolerance``: Newton's convergence test on the accelerations' relative error
      (:meth:`deployfx.scene.Model.simulate`); None: the engine's default, 1e-10;
    - ``label``: the row's name (None: made from the fields, see :attr:`name`).
    """

    model: str = "nonlinear"
    nx: int = _paper.NX
    ny: int = _paper.NY
    dt: float = 0.01
    scheme: Scheme = GeneralizedAlpha(0.8)
    modes: Optional[int] = None
    derivative_modes: Optional[int] = None
    derivative_partners: Optional[int] = None
    tolerance: Optional[float] = None
    newton_tolerance: Optional[float] = None
    label: Optional[str] = None

    def __post_init__(self):
        if self.model not in FIDELITIES:
            raise ValueError(f"model = {self.model!r} is invalid: must be one of "
                             f"{', '.join(FIDELITIES)}")
        for name in ("nx", "ny"):
            if as_int(name, getattr(self, name)) < 1:
                raise ValueError(f"{name} = {getattr(self, name)} is out of range: must be >= 1")
        dt = as_float("dt", self.dt)
        if not (math.isfinite(dt) and dt > 0):
            raise ValueError(f"dt = {dt} is out of range: must be > 0 (s)")
        _check_scheme(self.scheme)
        if self.modes is not None:
            if not self.model.startswith("reduced"):
                raise ValueError(f"modes = {self.modes} is only for the reduced models, "
                                 f"not {self.model!r}")
            if as_int("modes", self.modes) < 1:
                raise ValueError(f"modes = {self.modes} is out of range: must be >= 1")
        for name in ("derivative_modes", "derivative_partners"):  # the reduced basis's derivatives
            value = getattr(self, name)
            if value is None:
                continue
            if self.model not in _DERIVATIVE_MODELS:
                raise ValueError(f"{name} = {value} is only for the {' and '.join(_DERIVATIVE_MODELS)} "
                                 f"models, not {self.model!r}")
            if as_int(name, value) < 0:
                raise ValueError(f"{name} = {value} is out of range: must be >= 0 (and <= modes)")
        if self.tolerance is not None:
            tol = as_float("tolerance", self.tolerance)
            if not (math.isfinite(tol) and tol > 0):
                raise ValueError(f"tolerance = {tol} is out of range: must be > 0 (m or rad) "
                                 "or None")
        if self.newton_tolerance is not None:
            newton_tolerance_arg(self.newton_tolerance)
        if self.label is not None and not isinstance(self.label, str):
            raise TypeError(f"label must be a string or None, got {type(self.label).__name__}")

    @property
    def mesh(self) -> str:
        """``"NXxNY"``."""
        return f"{self.nx}x{self.ny}"

    @property
    def name(self) -> str:
        """The label, or one made from the fields, e.g. ``reduced-nonlinear(10) 15x10 dt=0.01
        GA(0.8)``, or ``reduced-nonlinear(10, md=3) ...`` with ``derivative_modes = 3``, ending
        in `` newton=1e-08`` with a Newton tolerance."""
        if self.label is not None:
            return self.label
        size = [] if self.modes is None else [str(self.modes)]
        if self.derivative_modes is not None:
            size.append(f"md={self.derivative_modes}")
        if self.derivative_partners is not None:
            size.append(f"dp={self.derivative_partners}")
        model = f"{self.model}({', '.join(size)})" if size else self.model
        mesh = "" if self.model == "rigid" else f" {self.mesh}"
        step = f"dt<={self.dt:g} tol={self.tolerance:g}" if self.tolerance else f"dt={self.dt:g}"
        newton = "" if self.newton_tolerance is None else f" newton={self.newton_tolerance:g}"
        return f"{model}{mesh} {step} {scheme_label(self.scheme)}{newton}"


CaseLike = Union[Case, Mapping[str, Any]]


def _as_case(case: CaseLike, what: str) -> Case:
    if isinstance(case, Case):
        return case
    if isinstance(case, Mapping):
        names = {f.name for f in fields(Case)}
        unknown = sorted(set(case) - names)
        if unknown:
            raise TypeError(f"{what} has unknown fields {unknown}; allowed: {sorted(names)}")
        return Case(**case)
    raise TypeError(f"{what} must be a Case or a mapping of its fields, got {type(case).__name__}")


def tradeoff(cases: Iterable[CaseLike], reference: Union[CaseLike, Result], t_end: float = 3.0, *,
             layup: int = 2, repeat: int = 1, scene_overrides: Optional[Mapping[str, Any]] = None,
             callback: Optional[Callable[[dict, Optional[Result]], None]] = None) -> list[dict]:
    """Run each case of the paper's scene to ``t_end`` (s), time it and measure its error
    against ``reference``; returns one row (a dict, keys :data:`COLUMNS`) per case, after a first
    row for the reference itself (``is_reference`` True, errors 0).

    Parameters
    ----------
    cases
        :class:`Case` objects, or mappings of their fields (``{"model": "rigid", "dt": 0.02}``).
    reference
        The run taken as the truth: a :class:`Case` (or mapping), run first, or a
        :class:`~deployfx.results.Result` already computed (e.g. a saved reference loaded with
        :func:`deployfx.load`; it needs ``t``, ``lock_force`` and ``node_E_deflection`` up to
        ``t_end``). It should be the finest run of the sweep (nonlinear, finest mesh, smallest
        step): the errors measure distance to it, not to the exact solution.
    t_end
        Simulated time (s) of every run; errors are measured over [0, t_end]. The paper's
        appendage first locks at about 2.46 s, so 3 s covers the deployment and the first impact.
    layup
        The paper's lay-up, 1 or 2.
    repeat
        Timed runs per case (>= 1; the reference runs once); ``wall_time_s`` is their median
        (the runs are deterministic, the first one's series are used).
    scene_overrides
        Further :class:`~deployfx.scenes.Paper2016Parameters` fields for every run (e.g.
        ``{"clearance": 1e-4}``), applied to the reference case too.
    callback
        Called as ``callback(row, result)`` after each run (the reference first), e.g. to print
        progress or save the series; ``result`` is None if the scene could not be built.

    A case whose run stops early (:class:`~deployfx.integrators.SimulationError`) or whose
    scene cannot be built is kept with its message in ``failure``; its lock time error is given
    if it locked before stopping, its other errors are NaN. The reference must complete.
    Undefined values (no lock, a rigid model's basis size) are None or NaN.
    """
    t_end = as_float("t_end", t_end)
    if not (math.isfinite(t_end) and t_end > 0):
        raise ValueError(f"t_end = {t_end} is out of range: must be > 0 (s)")
    if layup not in _paper.LAYUPS:
        raise ValueError(f"layup = {layup!r} is out of range: must be 1 or 2")
    repeat = as_int("repeat", repeat)
    if repeat < 1:
        raise ValueError(f"repeat = {repeat} is out of range: must be >= 1")
    overrides = dict(scene_overrides or {})
    for key in ("model", "nx", "ny", "modes", "derivative_modes", "derivative_partners", "layup"):
        if key in overrides:
            raise ValueError(f"scene_overrides must not set {key!r}: it is a Case field or an "
                             "argument")
    cases = [_as_case(c, f"cases[{k}]") for k, c in enumerate(cases)]

    if isinstance(reference, Result):
        ref_result, ref_case, ref_setup = reference, None, math.nan
        ref_wall = reference.metadata.get("wall_time_s", math.nan)
        for name in ("lock_force", "node_E_deflection"):
            if name not in ref_result:
                raise ValueError(f"the reference result has no series {name!r}")
        if ref_result.failure is not None:
            raise ValueError(f"the reference result stopped early: {ref_result.failure}")
    else:
        ref_case = _as_case(reference, "reference")
        ref_result, ref_setup, failure, ref_wall = _run(ref_case, t_end, layup, 1, overrides)
        if ref_result is None:
            raise ValueError(f"the reference {ref_case.name} cannot be built: {failure}")
        if failure:
            raise SimulationError(f"the reference run {ref_case.name} failed: {failure}",
                                  ref_result)
    if ref_result.t[-1] < t_end * (1 - 1e-9):
        raise ValueError(f"the reference ends at t = {ref_result.t[-1]:g} s, before "
                         f"t_end = {t_end:g} s")
    ref = _Reference(ref_result, t_end)

    rows = []
    row = _row(ref_case, ref_result, ref_setup, ref_wall, "", ref, True)
    rows.append(row)
    if callback is not None:
        callback(row, ref_result)
    for case in cases:
        result, setup, failure, wall = _run(case, t_end, layup, repeat, overrides)
        row = _row(case, result, setup, wall, failure, ref, False)
        rows.append(row)
        if callback is not None:
            callback(row, result)
    return rows


def _run(case: Case, t_end: float, layup: int, repeat: int,
         overrides: dict) -> tuple[Optional[Result], float, str, float]:
    """(result or None, setup time s, failure message or "", median wall time s)."""
    kwargs = dict(overrides, nx=case.nx, ny=case.ny)
    if case.modes is not None:
        kwargs["modes"] = case.modes
    for key in ("derivative_modes", "derivative_partners"):
        if getattr(case, key) is not None:
            kwargs[key] = getattr(case, key)
    start = time.perf_counter()
    try:
        scene = scenes.paper2016(layup, case.model, **kwargs)
    except (ValueError, RuntimeError) as e:  # e.g. more modes than the mesh has dofs
        return None, math.nan, f"scene: {e}", math.nan
    setup = time.perf_counter() - start
    result, walls, failure = None, [], ""
    for _ in range(repeat):
        try:
            r = scene.simulate(t_end, case.dt, scheme=case.scheme, tolerance=case.tolerance,
                               newton_tolerance=case.newton_tolerance, progress=False)
        except SimulationError as e:
            r, failure = e.result, str(e)
        walls.append(r.metadata["wall_time_s"])
        result = result or r
        if failure:
            break
    return result, setup, failure, statistics.median(walls)


class _Reference:
    """The reference's series on [0, t_end] and its summary values."""

    def __init__(self, result: Result, t_end: float):
        keep = result.t <= t_end * (1 + 1e-12)
        self.t = np.asarray(result.t[keep])
        self.force = np.asarray(result.lock_force[keep]).reshape(int(keep.sum()), -1)[:, 0]
        self.deflection = np.asarray(result.node_E_deflection[keep])
        self.t_end = t_end
        self.lock_time = _lock_time(self.t, self.force)
        self.peak_force = _peak_force(result, self.force, t_end)
        self.max_deflection = float(np.abs(self.deflection).max())
        if self.lock_time is None:
            raise ValueError(f"the reference never locks within t_end = {t_end:g} s: lock time and "
                             "peak force errors are undefined; use a longer t_end")


def _peak_force(result: Result, force: np.ndarray, t_end: float) -> float:
    """The run's located peak lock force up to t_end (its impact records), or for a result
    without records the largest sample of ``force``."""
    located = impacts.peak_force(result, 0, t_end)
    return float(force.max()) if located is None else located


def _lock_time(t: np.ndarray, force: np.ndarray) -> Optional[float]:
    hit = np.flatnonzero(force > 0.0)
    return float(t[hit[0]]) if hit.size else None


def _nan(x: Optional[float]) -> float:
    return math.nan if x is None else float(x)


def _row(case: Optional[Case], result: Optional[Result], setup: float, wall: float, failure: str,
         ref: _Reference, is_reference: bool) -> dict:
    meta = result.metadata if result is not None else {}
    hinge = (meta.get("hinges") or [{}])[0]  # the paper scene's one hinge: its panel's basis
    row: dict[str, Any] = dict.fromkeys(COLUMNS)
    if case is not None:
        row.update(label=("reference: " if is_reference else "") + case.name, model=case.model,
                   modes=case.modes, mesh=case.mesh, dt_s=case.dt, tolerance=case.tolerance,
                   newton_tolerance=meta.get("newton_tolerance", case.newton_tolerance), integrator=scheme_label(case.scheme))
        if case.model.startswith("reduced") and case.modes is None:
            row["modes"] = hinge.get("modes")
    else:  # a given reference Result
        row.update(label="reference (given result)", model=meta.get("model"),
                   modes=hinge.get("modes"), mesh=meta.get("mesh"), dt_s=meta.get("dt"),
                   tolerance=meta.get("tolerance"), newton_tolerance=meta.get("newton_tolerance"),
                   integrator=meta.get("integrator"))
    row.update(basis_size=hinge.get("basis_size"), modal_derivatives=hinge.get("modal_derivatives"),
               setup_s=setup, wall_time_s=wall,
               steps=meta.get("steps"), substeps=meta.get("substeps"),
               newton_iterations=meta.get("newton_iterations"),
               ref_lock_time_s=ref.lock_time, ref_peak_lock_force_N=ref.peak_force,
               ref_max_node_E_deflection_m=ref.max_deflection, is_reference=is_reference,
               failure=failure or None)
    if _positive(wall) and row["substeps"]:
        row["ms_per_step"] = 1e3 * row["wall_time_s"] / row["substeps"]
    if result is not None and meta.get("model") is not None:
        row["coordinates"] = _coordinates(case, meta)
    for key in ERRORS:
        row[key] = math.nan
    if result is None:
        return row
    t = np.asarray(result.t)
    keep = t <= ref.t_end * (1 + 1e-12)
    t, force = t[keep], np.asarray(result.lock_force[keep]).reshape(int(keep.sum()), -1)[:, 0]
    deflection = np.asarray(result.node_E_deflection[keep])
    row["t_reached_s"] = float(t[-1])
    lock = _lock_time(t, force)
    row["lock_time_s"] = lock
    if lock is not None:
        row["lock_time_error_s"] = abs(lock - ref.lock_time)
    elif not failure:  # never locked within t_end, while the reference did: off by more than
        row["lock_time_error_s"] = math.inf  # the record; inf, so it is not mistaken for small
    if failure:
        return row
    row["peak_lock_force_N"] = _peak_force(result, force, ref.t_end)
    row["max_node_E_deflection_m"] = float(np.abs(deflection).max())
    row["peak_lock_force_rel_error"] = (abs(row["peak_lock_force_N"] - ref.peak_force)
                                        / ref.peak_force)
    row["node_E_rms_rel_error"] = history_error(t, deflection, ref.t, ref.deflection)
    return row


def _coordinates(case: Optional[Case], meta: dict) -> Optional[int]:
    # Elastic coordinates: those a reduced panel's metadata gives (the basis size, or on the
    # quadratic manifold its bending part; older results give the basis size only), the free dofs
    # (full), 0 (rigid).
    hinges = meta.get("hinges") or [{}]
    for key in ("elastic_coordinates", "basis_size"):
        if hinges[0].get(key) is not None:
            return int(hinges[0][key])
    model = meta.get("model")
    if model == "rigid":
        return 0
    mesh = case.mesh if case is not None else meta.get("mesh")
    if not mesh:
        return None
    nx, ny = (int(v) for v in str(mesh).split("x"))
    return 6 * (nx + 1) * (ny + 1) - 6 * (ny + 1)  # clamped root edge: ny + 1 nodes


def history_error(t: Sequence[float], x: Sequence[float], t_ref: Sequence[float],
                  x_ref: Sequence[float]) -> float:
    """RMS of ``x - x_ref`` over the case's times ``t`` (s), relative to max |``x_ref``|.

    ``x_ref`` is interpolated linearly onto ``t`` (which must lie within ``t_ref``'s span); the
    mean square is time-weighted (trapezoidal rule over ``t``), so unevenly spaced samples (event
    times, adaptive steps) weigh by the time they stand for. Zero exactly when the two histories
    are the same samples; NaN if max |``x_ref``| is zero.
    """
    t, x = np.asarray(t, float), np.asarray(x, float)
    t_ref, x_ref = np.asarray(t_ref, float), np.asarray(x_ref, float)
    if t.shape != x.shape or t_ref.shape != x_ref.shape or t.ndim != 1 or t_ref.ndim != 1:
        raise ValueError(f"t, x and t_ref, x_ref must be 1-D pairs of equal length, got "
                         f"{t.shape}, {x.shape}, {t_ref.shape}, {x_ref.shape}")
    span = t_ref[-1] - t_ref[0]
    if t[0] < t_ref[0] - 1e-9 * span or t[-1] > t_ref[-1] + 1e-9 * span:
        raise ValueError(f"t spans [{t[0]:g}, {t[-1]:g}] s, outside the reference's "
                         f"[{t_ref[0]:g}, {t_ref[-1]:g}] s")
    scale = float(np.abs(x_ref).max())
    if scale == 0.0:
        return math.nan
    e2 = (x - np.interp(t, t_ref, x_ref)) ** 2
    if t.size < 2:
        return float(np.sqrt(e2.mean())) / scale
    mean_square = float(np.sum(0.5 * (e2[1:] + e2[:-1]) * np.diff(t)) / (t[-1] - t[0]))
    return math.sqrt(mean_square) / scale


def _positive(v: Any) -> bool:
    return v is not None and isinstance(v, (int, float)) and math.isfinite(v) and v > 0
