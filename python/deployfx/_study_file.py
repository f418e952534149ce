"""Study files (deployfx.study): a study written as TOML or JSON, for ``deployfx study run``.

Schema ``deployfx.study`` version 1 (docs/study.md has an annotated example)::

    schema = "deployfx.study"          # required
    version = 1                        # required

    [base]                             # exactly one of:
    scene = "paper2016"                #   a ready scene of deployfx.scenes (paper2016, spin_up_beam)
    factory = "package.module:name"    #   any importable scene factory
    file = "panel.toml"                #   a scene file (relative to this file): dotted-path names
    inline = {...}                     #   a scene file's dict itself (what a store records)

    [fixed]                            # optional: parameters held at a value (numbers, strings,
    model = "rigid"                    #   booleans, lists; lists become tuples for a factory)
    "friction.mu" = 0.3

    [vary]                             # required: one table per varied parameter
    tau0 = {distribution = "uniform", low = 6.84, high = 7.56}
    k_theta = {distribution = "normal", mean = 4.58, std = 0.08, low = 4.35, high = 4.81}
    "contact.K" = {distribution = "loguniform", low = 1e10, high = 1e11}
    # grid studies: clearance = {levels = [1e-4, 2e-4, 3e-4]}

    [sampling]
    sampler = "saltelli"               # grid, sobol, lhs, random, saltelli (default sobol)
    samples = 64                       # required except for a grid
    seed = 0                           # optional (default 0)

    [run]
    t_end_s = 5.0                      # required
    dt_s = 0.01                        # required
    scheme = {type = "generalized-alpha", rho_inf = 0.8}   # optional: or hht {alpha},
                                                           #   newmark {beta, gamma}
    tolerance = 1e-6                   # optional: error-controlled steps (m or rad)

    [outputs]
    metrics = ["first_lock_time_s", "max(node_E_deflection)"]   # or {name = "spec", ...}
    series = ["deployment_angle"]      # optional
    time_step_s = 0.05                 # optional: the series' grid (default dt_s); or time_s = [...]

Every key is checked: an unknown or missing key, a value of the wrong type, an unknown parameter
or distribution raises ValueError naming the key (``vary.tau0.low``), so nothing is silently
dropped; :meth:`Study.save` writes back a study that loads to an equal one.
"""
from __future__ import annotations

import dataclasses
import importlib
import json
import numbers
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from . import _study_sample
from .integrators import HHT, GeneralizedAlpha, Newmark

SCHEMA, VERSION = "deployfx.study", 1
_READY = ("paper2016", "spin_up_beam")


def read_scene_dict(path: Path) -> dict:
    """A scene file's dict, checked by reading it as a scene (errors name the key)."""
    from . import scene_file
    from .scene_file import scene_from_dict

    if not path.exists():
        raise FileNotFoundError(f"scene file {path} does not exist")
    d = scene_file.read_scene_dict(path)  # its content_sha256 checked and removed
    scene_from_dict(d)
    return d


def _table(d: Any, where: str, required: tuple, optional: tuple = ()) -> Mapping[str, Any]:
    if not isinstance(d, Mapping):
        raise ValueError(f"{where} must be a table, got {type(d).__name__} {d!r}"[:200])
    missing = [k for k in required if k not in d]
    if missing:
        raise ValueError(f"{where} is missing key(s) {', '.join(_key(where, k) for k in missing)}")
    unknown = sorted(set(d) - set(required) - set(optional))
    if unknown:
        raise ValueError(f"{where} has unknown key(s) {', '.join(_key(where, k) for k in unknown)}; "
                         f"allowed: {', '.join(required + optional)}")
    return d


def _key(where: str, key: str) -> str:
    return key if where == "study file" else f"{where}.{key}"


def _num(d: Mapping, key: str, where: str, integer: bool = False) -> Any:
    v = d[key]
    kind = numbers.Integral if integer else numbers.Real
    if isinstance(v, bool) or not isinstance(v, kind):
        raise ValueError(f"{where}.{key} = {v!r} is invalid: must be {'an integer' if integer else 'a number'}")
    return v


def _scheme_from(d: Any, where: str):
    if not isinstance(d, Mapping) or d.get("type") not in ("generalized-alpha", "hht", "newmark"):
        raise ValueError(f"{where}.type must be 'generalized-alpha', 'hht' or 'newmark', got "
                         f"{d.get('type') if isinstance(d, Mapping) else d!r}")
    cls, keys = {"generalized-alpha": (GeneralizedAlpha, ("rho_inf",)), "hht": (HHT, ("alpha",)),
                 "newmark": (Newmark, ("beta", "gamma"))}[d["type"]]
    t = _table(d, where, ("type",) + keys)
    return cls(**{k: float(_num(t, k, where)) for k in keys})


def _scheme_to(s) -> dict:
    if isinstance(s, GeneralizedAlpha):
        return {"type": "generalized-alpha", "rho_inf": float(s.rho_inf)}
    if isinstance(s, HHT):
        return {"type": "hht", "alpha": float(s.alpha)}
    return {"type": "newmark", "beta": float(s.beta), "gamma": float(s.gamma)}


def _plain(where: str, v: Any, strict: bool) -> Any:
    """A value of ``fixed`` as a file holds it (numbers, strings, booleans, lists)."""
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, (bool, int, float, str)):
        return v
    if isinstance(v, (list, tuple, np.ndarray)):
        return [_plain(f"{where}[{i}]", x, strict) for i, x in enumerate(v)]
    if not strict and dataclasses.is_dataclass(v):
        return {"type": f"{type(v).__module__}.{type(v).__qualname__}",
                **{f.name: _plain(f"{where}.{f.name}", getattr(v, f.name), False)
                   for f in dataclasses.fields(v) if f.init}}
    if not strict:
        return repr(v)
    raise TypeError(f"{where} = {v!r} cannot be written to a study file (only numbers, strings, "
                    f"booleans and lists); set the fields of an object by dotted names "
                    f"(e.g. 'friction.mu')")


def _function_name(f) -> str:
    return f"{f.__module__}:{f.__qualname__}"


def study_to_dict(st, strict: bool = True) -> dict:
    """The study file's dict of Study ``st`` (see Study.to_dict)."""
    from . import scenes

    if st._factory is not None:
        f = st._factory
        if getattr(scenes, getattr(f, "__name__", ""), None) is f and f.__name__ in _READY:
            base = {"scene": f.__name__}
        elif hasattr(f, "__module__") and hasattr(f, "__qualname__") and "<" not in f.__qualname__:
            base = {"factory": _function_name(f)}
        elif strict:
            raise TypeError(f"base {f!r} cannot be written to a study file: give an importable "
                            "function (module:name)")
        else:
            base = {"factory": repr(f)}
    elif strict and st._base_file is not None:
        base = {"file": str(st._base_file)}
    else:
        base = {"inline": st._scene}
    metrics: Any = {}
    for name, spec in st.outputs.items():
        if callable(spec):
            if strict:
                raise TypeError(f"output {name!r} is a function: a study file holds only summary "
                                "keys and reductions such as 'max(lock_force)'")
            spec = f"function {_function_name(spec) if hasattr(spec, '__qualname__') else repr(spec)}"
        metrics[name] = spec
    if all(k == v for k, v in metrics.items()):
        metrics = list(metrics)
    outputs: dict[str, Any] = {"metrics": metrics}
    if st.series:
        outputs["series"] = list(st.series)
        uniform = np.arange(st.time.size) * (st.time[1] - st.time[0]) if st.time.size > 1 else None
        if uniform is not None and np.array_equal(uniform, st.time):
            if st.time[1] - st.time[0] != st.dt:
                outputs["time_step_s"] = float(st.time[1] - st.time[0])
        else:
            outputs["time_s"] = st.time.tolist()
    run: dict[str, Any] = {"t_end_s": st.t_end, "dt_s": st.dt}
    if st.scheme is not None:
        run["scheme"] = _scheme_to(st.scheme)
    if st.tolerance is not None:
        run["tolerance"] = st.tolerance
    sampling: dict[str, Any] = {"sampler": st.sampler, "seed": st.seed}
    if st.samples is not None:
        sampling["samples"] = int(st.samples)
    return {"schema": SCHEMA, "version": VERSION, "base": base,
            "fixed": {k: _plain(f"fixed[{k!r}]", v, strict) for k, v in st.fixed.items()},
            "vary": {k: v.to_dict() for k, v in st.vary.items()},
            "sampling": sampling, "run": run, "outputs": outputs}


def _base_from(d: Any, base_dir: Path) -> Any:
    from . import scenes
    from .scene_file import scene_from_dict

    t = _table(d, "base", (), ("scene", "factory", "file", "inline"))
    given = [k for k in ("scene", "factory", "file", "inline") if k in t]
    if len(given) != 1:
        raise ValueError(f"base must give exactly one of scene, factory, file, inline; got "
                         f"{given or 'none'}")
    k, v = given[0], t[given[0]]
    if k == "inline":
        if not isinstance(v, Mapping):
            raise ValueError("base.inline must be a table (a scene file's content)")
        try:
            scene_from_dict(v)
        except ValueError as e:
            raise ValueError(f"base.inline: {e}") from None
        return dict(v)
    if not isinstance(v, str):
        raise ValueError(f"base.{k} = {v!r} is invalid: must be a string")
    if k == "scene":
        if v not in _READY:
            raise ValueError(f"base.scene = {v!r} is invalid: must be one of {', '.join(_READY)} "
                             "(or give base.factory = 'module:function')")
        return getattr(scenes, v)
    if k == "file":
        p = Path(v) if Path(v).is_absolute() else base_dir / v
        try:
            read_scene_dict(p)
        except (ValueError, FileNotFoundError) as e:
            raise ValueError(f"base.file = {v!r}: {e}") from None
        return p
    module, _, name = v.partition(":")
    try:
        obj = importlib.import_module(module)
        for part in name.split("."):
            obj = getattr(obj, part)
    except (ImportError, AttributeError, ValueError) as e:
        raise ValueError(f"base.factory = {v!r} cannot be imported (module:function): {e}") from None
    if not callable(obj):
        raise ValueError(f"base.factory = {v!r} is not callable")
    return obj


def study_from_dict(d: Any, base_dir: Path = Path(".")):
    """The :class:`~deployfx.study.Study` of a study file's dict; ValueError naming the key."""
    from .study import Study

    top = _table(d, "study file", ("schema", "version", "base", "vary", "run", "outputs"),
                 ("fixed", "sampling"))
    if top["schema"] != SCHEMA:
        raise ValueError(f"schema = {top['schema']!r} is not a deployfx study (expected {SCHEMA!r})")
    if top["version"] != VERSION or isinstance(top["version"], bool):
        raise ValueError(f"version = {top['version']!r} is an unknown study-file version; this "
                         f"deployfx reads version {VERSION}")
    base = _base_from(top["base"], base_dir)
    fixed = _table(top.get("fixed", {}), "fixed", (), tuple(top.get("fixed", {})))
    for k, v in fixed.items():
        if isinstance(v, Mapping):
            raise ValueError(f"fixed.{k} is a table: set the fields of an object by dotted names "
                             f"(\"{k}.mu\" = ...)")
    if not callable(base):
        fixed = dict(fixed)
    else:  # a factory's sequence arguments are tuples (damping = [0.7, 0.0])
        fixed = {k: tuple(v) if isinstance(v, list) else v for k, v in fixed.items()}
    vary_t = top["vary"]
    if not isinstance(vary_t, Mapping) or not vary_t:
        raise ValueError("vary must be a table with at least one parameter")
    vary = {k: _study_sample.from_dict(f"vary.{k}", v) for k, v in vary_t.items()}
    s = _table(top.get("sampling", {}), "sampling", (), ("sampler", "samples", "seed"))
    sampler = s.get("sampler", "sobol")
    if sampler not in _study_sample.SAMPLERS:
        raise ValueError(f"sampling.sampler = {sampler!r} is invalid: must be one of "
                         f"{', '.join(map(repr, _study_sample.SAMPLERS))}")
    samples = _num(s, "samples", "sampling", integer=True) if "samples" in s else None
    seed = _num(s, "seed", "sampling", integer=True) if "seed" in s else 0
    r = _table(top["run"], "run", ("t_end_s", "dt_s"), ("scheme", "tolerance"))
    scheme = _scheme_from(r["scheme"], "run.scheme") if "scheme" in r else None
    tolerance = _num(r, "tolerance", "run") if "tolerance" in r else None
    o = _table(top["outputs"], "outputs", ("metrics",), ("series", "time_step_s", "time_s"))
    metrics = o["metrics"]
    if not isinstance(metrics, (list, Mapping)) or not metrics:
        raise ValueError(f"outputs.metrics must be a non-empty list (or a table of name = spec), "
                         f"got {metrics!r}")
    if isinstance(metrics, Mapping) and any(isinstance(v, str) and v.startswith("function ")
                                            for v in metrics.values()):
        raise ValueError("outputs.metrics holds Python functions (a study run from Python): "
                         "they cannot be read from a file")
    series = o.get("series")
    if series is not None and not isinstance(series, list):
        raise ValueError(f"outputs.series must be a list of series names, got {series!r}")
    if "time_step_s" in o and "time_s" in o:
        raise ValueError("outputs gives both time_step_s and time_s: give one")
    t_end, dt = _num(r, "t_end_s", "run"), _num(r, "dt_s", "run")
    time = None
    if "time_step_s" in o:
        step = _num(o, "time_step_s", "outputs")
        if not step > 0:
            raise ValueError(f"outputs.time_step_s = {step!r} is out of range: must be > 0 (s)")
        time = np.arange(int(round(t_end / step)) + 1) * step
    elif "time_s" in o:
        time = o["time_s"]
        if not isinstance(time, list) or not all(isinstance(x, numbers.Real) and not isinstance(x, bool)
                                                 for x in time):
            raise ValueError("outputs.time_s must be a list of numbers (s)")
    try:
        return Study(base, fixed=fixed, vary=vary, samples=samples, sampler=sampler,
                     outputs=metrics, series=series, time=time, t_end=t_end, dt=dt, scheme=scheme,
                     tolerance=tolerance, seed=seed)
    except (ValueError, TypeError) as e:
        raise ValueError(f"study file: {e}") from None


def load_study(path) -> Any:
    """The Study of a study file (``.toml``/``.json``) or of a study's zarr store."""
    path = Path(path)
    if path.is_dir():
        from ._study_store import stored_spec

        return study_from_dict(stored_spec(path), path.parent)
    if not path.exists():
        raise FileNotFoundError(f"study file {path} does not exist")
    from .scene_file import read_file

    d = read_file(path)
    try:
        return study_from_dict(d, path.parent)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None


def save_study(st, path) -> Path:
    """Write Study ``st`` as a study file (``.toml`` or ``.json`` by suffix)."""
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".toml", ".json"):
        raise ValueError(f"path = {str(path)!r} must end in .toml or .json (the file format)")
    d = study_to_dict(st, strict=True)
    if suffix == ".json":
        text = json.dumps(d, indent=2) + "\n"
    else:
        import tomli_w

        text = tomli_w.dumps(d)
    path.write_text(text, encoding="utf-8")
    return path
