"""Running a compiled model: argument checks, the result and its metadata, the divergence check
and the progress bar, shared by :class:`deployfx.Model` and :class:`deployfx.chain.ChainModel`."""
from __future__ import annotations

import math
import sys
import time
from typing import Callable, Optional

import numpy as np

from . import _core
from ._checks import as_float
from .integrators import HHT, Newmark, SimulationError, _check_scheme
from .results import Result


def newton_tolerance_arg(newton_tolerance) -> float:
    """Newton's tolerance for a run (None: the engine's default) checked against the engine's
    range; ValueError or TypeError naming it."""
    if newton_tolerance is None:
        return float(_core.NEWTON_TOLERANCE_DEFAULT)
    tol = as_float("newton_tolerance", newton_tolerance)
    lo, hi = _core.NEWTON_TOLERANCE_RANGE
    if not lo <= tol <= hi:
        raise ValueError(f"newton_tolerance = {tol} is out of range: must be in [{lo:g}, {hi:g}] "
                         f"(relative error of the accelerations)")
    return tol


def _run_arguments(t_end, dt, scheme, tolerance) -> tuple:
    """(t_end, dt, tolerance (0: fixed steps), scheme) checked for a run; ValueError or TypeError
    naming the bad one."""
    t_end, dt = as_float("t_end", t_end), as_float("dt", dt)
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt = {dt} is out of range: must be > 0 (s)")
    if not (math.isfinite(t_end) and t_end >= 0):
        raise ValueError(f"t_end = {t_end} is out of range: must be >= 0 (s)")
    scheme = _check_scheme(scheme)
    tol = 0.0 if tolerance is None else as_float("tolerance", tolerance)
    if not (math.isfinite(tol) and tol >= 0):
        raise ValueError(f"tolerance = {tol} is out of range: must be > 0 (m or rad) or None")
    return t_end, dt, tol, scheme


def _run_result(raw: dict, out: dict, units: dict, meta: dict, scheme, dt: float, t_end: float,
                tolerance, newton_tolerance: float, wall: float, conservative: bool, energy_baseline=None,
                checkpoints=()) -> Result:
    """The :class:`Result` of a run from the engine's ``raw`` dict and the chosen series ``out``,
    with the run's metadata added to ``meta``; raises SimulationError (holding the result) if the
    run stopped early or, for a ``conservative`` scene, its energy grew (_energy_growth;
    ``energy_baseline``: a resumed run's (initial energy, peak kinetic energy so far)).
    ``checkpoints`` become ``result.checkpoints``."""
    meta.update(dt=dt, t_end=t_end, integrator=_scheme_name(scheme),
                steps=int(raw["steps"]), substeps=int(raw["substeps"]), rejected=int(raw["rejected"]),
                events=int(raw["events"]), contact_steps=int(raw["contact_steps"]), tolerance=tolerance,
                newton_tolerance=newton_tolerance,
                newton_iterations=int(sum(raw["newton_iterations"])),  # a list of ints
                factorizations=int(raw["factorizations"]), wall_time_s=wall)
    if conservative:  # report the growth first: it explains a later Newton failure
        raw["failure"] = "; then ".join(m for m in (_energy_growth(raw, energy_baseline), raw["failure"]) if m)
    if raw["failure"]:
        meta["failure"] = raw["failure"]
    result = Result(out, units=units, metadata=meta)
    result.checkpoints = tuple(checkpoints)
    if raw["failure"]:
        raise SimulationError(f"{raw['failure']}; the result up to t = {raw['t'][-1]:.6g} s is in "
                              f"the exception's .result", result)
    return result


#: Energy growth (J, relative to the peak kinetic energy) beyond which an undriven run is
#: declared diverged: the trapezoidal rule's O(dt^2) energy error is orders below it.
ENERGY_GROWTH_LIMIT = 0.1
_TINY = float(np.finfo(float).tiny)


def _energy_growth(raw: dict, baseline=None) -> str:
    """A message if the total energy of an undriven run grew by more than ENERGY_GROWTH_LIMIT of
    the peak kinetic energy (a step beyond a conditionally stable scheme's limit, or too large for a
    stiff contact), else ''. ``baseline``: a resumed run's (initial energy, peak kinetic energy
    before the checkpoint), so that it judges as the uninterrupted run does."""
    E = raw["kinetic_energy"] + raw["potential_energy"]
    if len(E) < 2 and baseline is None:
        return ""
    if not len(E):
        return ""
    E0, peak = (E[0], 0.0) if baseline is None else baseline
    scale = max(raw["kinetic_energy"].max(), peak, _TINY)
    excess = (E - E0) / scale
    over = ~(excess <= ENERGY_GROWTH_LIMIT)  # NaN counts as growth
    if not over.any():
        return ""
    k = int(over.argmax())  # the first
    return (f"diverged: the total energy grew by {excess[k]:.3g} x the peak kinetic energy at "
            f"t = {raw['t'][k]:.6g} s although nothing in the scene adds energy (a step beyond the "
            f"scheme's stability limit, or too large for a stiff contact); use a smaller dt or error-controlled steps "
            f"(tolerance=)")


class _Bar:
    """A tqdm bar over simulated time (s)."""

    def __init__(self, tqdm, t_end: float):
        self._bar = tqdm(total=round(t_end, 6), unit="s", unit_scale=False, desc="deployfx",
                         bar_format="{l_bar}{bar}| {n:.2f}/{total:.2f} s [{elapsed}<{remaining}]")

    def update_to(self, t: float, t_end: float) -> None:
        self._bar.update(max(0.0, round(t, 6) - self._bar.n))

    def close(self) -> None:
        self._bar.close()


def _progress_bar(t_end: float, progress: Optional[bool]) -> Optional[_Bar]:
    if progress is None:
        progress = sys.stderr is not None and sys.stderr.isatty()
    if not progress:
        return None
    from tqdm.auto import tqdm

    return _Bar(tqdm, t_end)


def _timed_run(run: Callable, t_end: float, progress: Optional[bool]) -> tuple:
    """``(run(progress=callback or None), wall time in s)``, with the progress bar of
    :func:`_progress_bar` fed by the engine's ``progress(t, t_end)`` callback and closed after."""
    bar = _progress_bar(t_end, progress)
    start = time.perf_counter()
    try:
        raw = run(progress=None if bar is None else bar.update_to)
        if bar is not None:  # the engine reports every 0.2 s of wall time: show where it ended
            bar.update_to(float(raw["t"][-1]), t_end)
    finally:
        if bar is not None:
            bar.close()
    return raw, time.perf_counter() - start


def base_attitude_deg(q: np.ndarray, base_free: bool) -> np.ndarray:
    """The base's attitude (deg, (n, 3)): the rotation vector of R_WB from the quaternion
    (w, x, y, z) in q[:, 3:7] of a free base; zeros for a fixed base (it has no coordinates).

    The rotation vector of the unit quaternion (w, v) with w >= 0 (the shorter of the two
    rotations): phi = 2 atan2(|v|, w), rotvec = phi / sin(phi / 2) v, the ratio by its Taylor
    series 2 + phi^2/12 + 7 phi^4/2880 for phi <= 1e-3 (as scipy's ``Rotation.as_rotvec``, to
    round-off; vectorised here, a third of its time: part of every run's post-processing)."""
    if not base_free:
        return np.zeros((len(q), 3))
    # As component rows (4, n), contiguous, numpy's loops run along the samples: 2-3x faster than
    # over rows of 4, with the same bits (the squares summed w, x, y, z in order, as np.linalg.norm
    # sums a row); few calls, each costly after the engine's run has evicted numpy from the caches.
    quat = np.ascontiguousarray(q[:, 3:7].T)
    quat = quat / np.sqrt(np.add.reduce(quat * quat, axis=0))
    np.negative(quat, out=quat, where=quat[0] < 0)
    v = quat[1:]
    phi = 2.0 * np.arctan2(np.sqrt(np.add.reduce(v * v, axis=0)), quat[0])
    p2 = phi * phi
    ratio = 2.0 + p2 / 12.0 + 7.0 * p2 * p2 / 2880.0
    np.divide(phi, np.sin(phi / 2.0), out=ratio, where=phi > 1e-3)  # NaN either way for a NaN phi
    return np.degrees(ratio * v).T


def _scheme_name(scheme) -> str:
    if isinstance(scheme, Newmark):
        return f"Newmark(beta={scheme.beta}, gamma={scheme.gamma})"
    if isinstance(scheme, HHT):
        return f"HHT(alpha={scheme.alpha})"
    return f"GeneralizedAlpha(rho_inf={scheme.rho_inf})"
