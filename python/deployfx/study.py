"""Studies at scale: parameter sweeps and Monte Carlo runs of a scene on Dask, results in an
xarray Dataset stored in zarr, Sobol' sensitivity indices with SALib (issue 26).

>>> from deployfx import study
>>> st = study.Study(dfx.scenes.paper2016, fixed={"layup": 2, "model": "rigid", "nx": 4, "ny": 2},
...                  vary={"tau0": study.Uniform(6.84, 7.56), "friction.mu": study.Uniform(0.15, 0.35)},
...                  samples=16, sampler="saltelli", outputs=["first_lock_time_s", "peak_lock_force_N"],
...                  t_end=5.0, dt=0.01)
>>> ds = st.run("study.zarr", workers=2)   # xarray.Dataset: dim sample, parameter coordinates
>>> ds = study.open("study.zarr")          # the same Dataset, read back
>>> study.sobol(ds)                        # first and total order indices with confidence intervals

- **Base**: a scene factory (``scenes.paper2016``, or any callable returning an object with
  ``.simulate(t_end, dt, ...)`` returning a :class:`~deployfx.Result`), a :class:`~deployfx.Scene`,
  a scene file (path) or a scene file's dict. Parameters are addressed as in
  :mod:`deployfx._study_params`: keyword names of a factory (``"tau0"``), a field inside one
  (``"friction.mu"``, ``"contact.K"``, ``"damping.alpha_M"``), or a dotted path into a scene
  file's dictionary (``"hinges.0.tau0_N_m"``, ``"hinges.0.lock.clearance_m"``).
- **Design**: ``vary`` maps names to distributions (:class:`Uniform`, :class:`LogUniform`,
  :class:`Normal`, truncated with ``low``/``high``) for the samplers ``"sobol"`` (scrambled
  Sobol' points, scipy.stats.qmc; ``samples`` a power of 2), ``"lhs"`` (Latin hypercube),
  ``"random"`` and ``"saltelli"`` (SALib's design for Sobol' indices: ``samples`` = N, a power of
  2, gives N (d + 2) runs), or to :class:`Levels` for ``"grid"`` (full factorial; a list is taken
  as levels). ``seed`` makes the design reproducible.
- **Outputs**: summary keys, reductions of series (``"max(lock_force)"``) or functions of the
  Result (:mod:`deployfx._study_outputs`); ``series`` are stored on a common time grid.
- **Running**: :meth:`Study.run` submits one Dask task per sample to an embedded LocalCluster
  (``workers`` single-threaded processes, default one per core), to ``client=`` or to
  ``scheduler=`` (an address). ``processes=True`` is the default because each sample builds and
  compiles its own model; ``processes=False`` runs the workers as threads of this process (the
  engine releases the GIL while it integrates), the mode in which threads will share one compiled
  model once the engine splits model from data. A failing sample is recorded (``status`` 2,
  ``error``) and the study goes on. Results are written to the zarr store as they arrive; running
  again on the same store resumes: stored samples are not recomputed (see
  :mod:`deployfx._study_store` for the layout).

Study files (TOML/JSON) describe the same study for ``deployfx study run``: :func:`load_study`,
:meth:`Study.save`, format in :mod:`deployfx._study_file` and docs/study.md.
"""
from __future__ import annotations

import dataclasses
import inspect
import math
import numbers
import os
import sys
from pathlib import Path
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _study_outputs, _study_params, _study_sample, _study_store
from ._checks import as_float
from ._study_run import Task, client_for, execute, portable
from ._study_sample import SAMPLERS, Levels, LogUniform, Normal, Uniform
from .integrators import _check_scheme

__all__ = ["Study", "Uniform", "LogUniform", "Normal", "Levels", "SAMPLERS", "open", "sobol",
           "statistics", "load_study"]

PathLike = Union[str, os.PathLike]


def _require(module: str):
    try:
        return __import__(module)
    except ImportError as e:
        raise ImportError(f"deployfx.study needs {module!r}: pip install \"deployfx[study]\" "
                          f"({e})") from e


class Study:
    """A parameter study of one base scene (see the module docstring).

    Parameters
    ----------
    base : a scene factory, a :class:`~deployfx.Scene`, a scene file path or a scene dict.
    fixed : parameters held at a value (same names as ``vary``); for a factory, any keyword
        argument (objects too); for a scene, numbers, strings or booleans at dotted paths.
    vary : {name: distribution or Levels (or a list of levels)}, in the design's column order.
    samples : number of samples (``"saltelli"``: N, giving N (d + 2) runs); None for a grid.
    sampler : one of :data:`SAMPLERS`.
    outputs : scalar outputs: a list of specs, or {name: spec or function of the Result}.
    series : series stored on the ``time`` grid (s; default 0, dt, ..., t_end).
    t_end, dt : simulated time and output step (s). scheme : an integrator
        (``GeneralizedAlpha``, ``HHT``, ``Newmark``; None: the scene's default).
    tolerance : error-controlled steps (m or rad; None: fixed steps), as in ``simulate``.
    seed : the sampler's seed (int >= 0).
    """

    def __init__(self, base, fixed: Optional[Mapping[str, Any]] = None,
                 vary: Optional[Mapping[str, Any]] = None, samples: Optional[int] = None,
                 sampler: str = "sobol",
                 outputs: Union[Sequence[str], Mapping[str, Any]] = ("first_lock_time_s",
                                                                      "peak_lock_force_N"),
                 series: Optional[Sequence[str]] = None, time: Optional[Sequence[float]] = None,
                 t_end: float = 30.0, dt: float = 0.01, scheme=None,
                 tolerance: Optional[float] = None, seed: int = 0):
        self._factory, self._scene, self._base_file = _resolve_base(base)
        self.fixed = dict(fixed or {})
        self.vary = {k: Levels(tuple(v)) if isinstance(v, (list, tuple, np.ndarray)) else v
                     for k, v in dict(vary or {}).items()}
        for k, v in self.vary.items():
            if not isinstance(v, (Levels,) + _study_sample.Distribution):
                raise TypeError(f"vary[{k!r}] must be a study.Uniform, LogUniform, Normal or Levels "
                                f"(or a list of levels), got {type(v).__name__}")
        both = sorted(set(self.fixed) & set(self.vary))
        if both:
            raise ValueError(f"{both} are both fixed and varied: give each parameter once")
        if sampler not in SAMPLERS:
            raise ValueError(f"sampler = {sampler!r} is invalid: must be one of "
                             f"{', '.join(map(repr, SAMPLERS))}")
        self.sampler = sampler
        self.samples = samples
        if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 0:
            raise ValueError(f"seed = {seed!r} is invalid: must be an integer >= 0")
        self.seed = int(seed)
        self.size = _study_sample.check_design(self.vary, sampler, samples)  #: runs in the study
        self._check_names()
        self.outputs = _study_outputs.parse_outputs(outputs)
        self.series = _study_outputs.parse_series(series)
        clash = sorted((set(self.outputs) | set(self.series)) &
                       (set(self.vary) | {"sample", "time", "status", "error"}))
        if clash or set(self.outputs) & set(self.series):
            raise ValueError(f"output names {clash or sorted(set(self.outputs) & set(self.series))} "
                             "clash with a parameter, another output or a reserved name "
                             "(sample, time, status, error)")
        self.t_end, self.dt = as_float("t_end", t_end), as_float("dt", dt)
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ValueError(f"dt = {self.dt!r} is out of range: must be > 0 (s)")
        if not (math.isfinite(self.t_end) and self.t_end > 0):
            raise ValueError(f"t_end = {self.t_end!r} is out of range: must be > 0 (s)")
        self.scheme = None if scheme is None else _check_scheme(scheme)
        self.tolerance = None if tolerance is None else as_float("tolerance", tolerance)
        if self.tolerance is not None and not (math.isfinite(self.tolerance) and self.tolerance > 0):
            raise ValueError(f"tolerance = {self.tolerance!r} is out of range: must be > 0 (m or "
                             "rad) or None")
        if time is None:
            n = int(round(self.t_end / self.dt))
            self.time = np.arange(n + 1) * self.dt  # the engine's output times k dt
        else:
            self.time = np.asarray(time, dtype=float)
            if self.time.ndim != 1 or self.time.size < 1 or not np.all(np.isfinite(self.time)) \
                    or np.any(np.diff(self.time) <= 0):
                raise ValueError("time must be a 1-D, finite, strictly increasing array (s)")
        self._design: Optional[dict] = None

    # ------------------------------------------------------------------------------------------
    def _check_names(self) -> None:
        if self._factory is not None:
            for where, names in (("fixed", self.fixed), ("vary", self.vary)):
                for k in names:
                    _study_params.check_factory_name(self._factory, k, self.fixed, f"{where} key")
            return
        for k, v in self.fixed.items():
            _study_params.check_path(self._scene, k, v, "fixed key")
        for k, v in self.vary.items():
            _study_params.check_path(self._scene, k, v.values[0] if isinstance(v, Levels) else 0.0,
                                     "vary key")

    @property
    def parameters(self) -> list[str]:
        """The varied parameters, in the design's column order."""
        return list(self.vary)

    @property
    def design(self) -> dict[str, np.ndarray]:
        """The value of each varied parameter in each sample (arrays of length :attr:`size`)."""
        if self._design is None:
            self._design = _study_sample.draw(self.vary, self.sampler, self.samples, self.seed)
        return {k: v.copy() for k, v in self._design.items()}

    def values(self, i: int) -> dict[str, Any]:
        """The parameter values of sample ``i`` (Python scalars)."""
        if isinstance(i, bool) or not isinstance(i, numbers.Integral) or not 0 <= i < self.size:
            raise ValueError(f"sample = {i!r} is out of range: must be 0 .. {self.size - 1}")
        return {k: v[int(i)].item() for k, v in self.design.items()}

    def _task(self) -> Task:
        return Task(self._factory, self._scene, portable(self.fixed), self.t_end, self.dt, self.scheme,
                    self.tolerance, self.outputs, tuple(self.series), self.time)

    def scene(self, i: int):
        """Sample ``i``'s scene, built as a worker builds it (the factory's scene, or the
        compiled model of the scene dict): to rerun or inspect one sample."""
        return self._task().build(self.values(i))

    def run_sample(self, i: int):
        """Sample ``i``'s :class:`~deployfx.Result`, run here (its exception propagates)."""
        return self._task().simulate(self.values(i))

    # ------------------------------------------------------------------------------------------
    def run(self, store: PathLike, *, workers: Optional[int] = None, client=None,
            scheduler: Optional[str] = None, processes: bool = True,
            progress: Optional[bool] = None, limit: Optional[int] = None,
            retry_failed: bool = False, flush_s: float = 2.0):
        """Run the study into the zarr store ``store`` and return the Dataset (:func:`open`).

        A new store is created with every sample pending; an existing one must hold this study
        (ValueError naming the first difference otherwise) and only its pending samples run
        (``retry_failed``: its failed ones too). ``limit``: run at most that many pending
        samples, then stop (a time-boxed batch job; the next run resumes).

        Where: ``client`` (a ``distributed.Client``), else ``scheduler`` (an address such as
        ``"tcp://head:8786"``), else an embedded LocalCluster of ``workers`` (default: one per
        core) single-threaded processes, or with ``processes=False`` ``workers`` threads in this
        process. ``progress``: a tqdm bar (default: when standard error is a terminal).
        Finished samples are written at most every ``flush_s`` s (and when the run ends or is
        interrupted)."""
        _require("xarray"), _require("zarr"), _require("distributed")
        from . import __version__

        path = Path(store)
        if workers is not None and (isinstance(workers, bool) or not isinstance(workers, numbers.Integral)
                                    or workers < 1):
            raise ValueError(f"workers = {workers!r} is invalid: must be an integer >= 1")
        if limit is not None and (isinstance(limit, bool) or not isinstance(limit, numbers.Integral)
                                  or limit < 0):
            raise ValueError(f"limit = {limit!r} is invalid: must be an integer >= 0 or None")
        spec = self.to_dict(strict=False)
        if path.exists():
            diff = _study_store.spec_difference(_study_store.stored_spec(path), spec)
            if diff:
                raise ValueError(f"{path} holds a different study ({diff}); give another store "
                                 "or delete this one")
            design, status = _study_store.read_design(path)
        else:
            design = self.design
            _study_store.create(path, spec, design, list(self.outputs), self.series, self.time,
                                __version__)
            status = np.zeros(self.size, dtype=np.int8)
        todo = (status == _study_store.PENDING)
        if retry_failed:
            todo |= (status == _study_store.FAILED)
        pending = np.flatnonzero(todo)
        if limit is not None:
            pending = pending[:limit]
        if pending.size:
            writer = _study_store.Writer(path, list(self.outputs), self.series, flush_s)
            show = sys.stderr.isatty() if progress is None else bool(progress)
            with client_for(workers, client, scheduler, processes) as c:
                execute(c, self._task(), design, pending, writer, show)
        return open(path)

    # ------------------------------------------------------------------------------------------
    def to_dict(self, strict: bool = True) -> dict:
        """The study as a study file's dict (docs/study.md). ``strict``: raise TypeError for
        what a file cannot hold (a factory outside deployfx.scenes given by function, objects in
        ``fixed``, functions as outputs); otherwise those are named (the store's record)."""
        from ._study_file import study_to_dict

        return study_to_dict(self, strict)

    def save(self, path: PathLike) -> Path:
        """Write the study file (``.toml`` or ``.json``) and return its path."""
        from ._study_file import save_study

        return save_study(self, path)

    def __repr__(self) -> str:
        base = (getattr(self._factory, "__name__", repr(self._factory)) if self._factory
                else (str(self._base_file) if self._base_file else "Scene"))
        return (f"Study({base}, vary={self.parameters}, sampler={self.sampler!r}, "
                f"runs={self.size}, outputs={list(self.outputs)})")


def _resolve_base(base) -> tuple:
    """(factory, scene dict, scene file path) of a study's base."""
    from .scene import Scene
    from .scene_file import scene_from_dict, scene_to_dict

    if isinstance(base, Scene):
        d = scene_to_dict(base)
        scene_from_dict(d)  # what a worker will rebuild must read back
        return None, d, None
    if isinstance(base, (str, os.PathLike)):
        from ._study_file import read_scene_dict

        return None, read_scene_dict(Path(base)), Path(base)
    if isinstance(base, Mapping):
        scene_from_dict(base)  # clear errors naming the key now, not in every sample
        return None, dict(base), None
    if hasattr(base, "simulate") and not inspect.isroutine(base) and not isinstance(base, type):
        raise TypeError(f"base is a ready scene ({type(base).__name__}); give its factory and the "
                        "fixed parameters instead (e.g. Study(scenes.paper2016, fixed={...})), or "
                        "its .scene (a deployfx.Scene)")
    if callable(base):
        return base, None, None
    raise TypeError(f"base must be a scene factory, a deployfx.Scene, a scene file path or a scene "
                    f"dict, got {type(base).__name__}")


# ----------------------------------------------------------------------------------------------
# Reading and analysing a store

def open(store: PathLike):
    """The Dataset of a study's zarr store (lazily read; ``.load()`` reads it all)."""
    xr = _require("xarray")
    _require("zarr")
    path = Path(store)
    if not path.exists():
        raise FileNotFoundError(f"{path}: no such study store")
    _study_store.stored_spec(path)  # ValueError if it is not a study store
    return xr.open_zarr(path, consolidated=False, chunks=None)


def load_study(path: PathLike) -> Study:
    """The :class:`Study` of a study file (``.toml`` or ``.json``; docs/study.md), or of a
    study's zarr store (the study it was created for)."""
    from ._study_file import load_study as _load

    return _load(path)


def _outputs(ds, outputs) -> list[str]:
    names = list(ds.attrs.get("outputs", []))
    if outputs is None:
        return names
    outputs = [outputs] if isinstance(outputs, str) else list(outputs)
    bad = [o for o in outputs if o not in names]
    if bad:
        raise ValueError(f"outputs {bad} are not in the study; it has {names}")
    return outputs


def sobol(ds, outputs: Optional[Sequence[str]] = None, conf_level: float = 0.95,
          num_resamples: int = 100, seed: int = 1):
    """First-order and total Sobol' indices of each output (SALib.analyze.sobol: Saltelli 2010's
    first-order and Jansen's total estimators, bootstrap confidence intervals at ``conf_level``).

    Returns an xarray Dataset over (``output``, ``parameter``) with ``S1``, ``S1_conf``, ``ST``,
    ``ST_conf`` (``*_conf``: half-width of the interval). Needs a study sampled with
    ``sampler="saltelli"``, all of whose samples computed to finite values with nonzero variance
    for each output asked for (ValueError naming the output and the samples otherwise).
    ``seed`` (>= 1) seeds the bootstrap, so the intervals are reproducible (SALib leaves a seed
    of 0 unseeded)."""
    xr = _require("xarray")
    from SALib.analyze import sobol as salib_sobol

    if isinstance(seed, bool) or not isinstance(seed, numbers.Integral) or seed < 1:
        raise ValueError(f"seed = {seed!r} is invalid: must be an integer >= 1")
    if ds.attrs.get("sampler") != "saltelli":
        raise ValueError(f"Sobol' indices need a study sampled with sampler='saltelli'; this one "
                         f"was sampled with {ds.attrs.get('sampler')!r}")
    names = list(ds.attrs["parameters"])
    status = np.asarray(ds["status"].values)
    not_done = np.flatnonzero(status != _study_store.DONE)
    if not_done.size:
        raise ValueError(f"Sobol' indices need every sample: {not_done.size} of {status.size} are "
                         f"{'failed or pending'} (samples {not_done[:10].tolist()}"
                         f"{' ...' if not_done.size > 10 else ''}; see ds.error, or run the study on)")
    rows = {k: [] for k in ("S1", "S1_conf", "ST", "ST_conf")}
    outs = _outputs(ds, outputs)
    for out in outs:
        y = np.asarray(ds[out].values, dtype=float)
        bad = np.flatnonzero(~np.isfinite(y))
        if bad.size:
            raise ValueError(f"output {out!r} is undefined (NaN) in {bad.size} samples "
                             f"({bad[:10].tolist()}{' ...' if bad.size > 10 else ''}); Sobol' "
                             "indices need a value in every sample")
        if np.ptp(y) == 0:
            raise ValueError(f"output {out!r} is the same ({y[0]!r}) in every sample: its Sobol' "
                             "indices are undefined (no variance to apportion)")
        r = salib_sobol.analyze(_study_sample._unit_problem(names), y, calc_second_order=False,
                                num_resamples=num_resamples, conf_level=conf_level, seed=seed)
        for k in rows:
            rows[k].append(np.asarray(r[k], dtype=float))
    return xr.Dataset({k: (("output", "parameter"), np.array(v).reshape(len(outs), len(names)))
                       for k, v in rows.items()},
                      coords={"output": outs, "parameter": names},
                      attrs={"conf_level": conf_level, "num_resamples": num_resamples,
                             "estimator": "SALib.analyze.sobol (Saltelli 2010 S1, Jansen ST)"})


def statistics(ds, outputs: Optional[Sequence[str]] = None):
    """A pandas DataFrame, one row per output: ``computed`` (samples), ``undefined`` (NaN among
    them), ``failed``, ``pending``, then mean, std (ddof 1), min, 5 %, median, 95 %, max over the
    computed samples with a value."""
    import pandas as pd

    status = np.asarray(ds["status"].values)
    rows = []
    for out in _outputs(ds, outputs):
        y = np.asarray(ds[out].values, dtype=float)[status == _study_store.DONE]
        v = y[np.isfinite(y)]
        stats = dict(computed=int(y.size), undefined=int(y.size - v.size),
                     failed=int(np.sum(status == _study_store.FAILED)),
                     pending=int(np.sum(status == _study_store.PENDING)))
        if v.size:
            q = np.quantile(v, [0.05, 0.5, 0.95])
            stats.update(mean=float(v.mean()), std=float(v.std(ddof=1)) if v.size > 1 else math.nan,
                         min=float(v.min()), p5=float(q[0]), median=float(q[1]), p95=float(q[2]),
                         max=float(v.max()))
        rows.append(stats)
    cols = ["computed", "undefined", "failed", "pending", "mean", "std", "min", "p5", "median",
            "p95", "max"]
    return pd.DataFrame.from_records(rows, index=_outputs(ds, outputs), columns=cols)
