"""What a :class:`~deployfx.results.Result` accepts, checked and frozen: its series (names,
dtypes, leading dimension, finite values, copied into read-only buffers), units and metadata
(JSON values). Each error names the series or the metadata entry."""
from __future__ import annotations

import functools
import keyword
import math
from typing import Any, Mapping, Optional

import numpy as np

from . import metrics


def frozen(a: np.ndarray) -> np.ndarray:
    """``a``, made read-only."""
    a.flags.writeable = False
    return a


def checked_arrays(series: Mapping[str, Any], n: int,
                   reserved: frozenset) -> list[tuple[str, np.ndarray]]:
    """(name, array) of each series but ``t``, in order, its name (check_name, against
    ``reserved``), dtype and leading dimension ``n`` checked (ValueError naming it); not yet
    copied, nor checked finite. A series that fails after one holding NaN or inf reports that
    one's error, as a check of one series after the other would."""
    out = []
    for name, value in series.items():
        if name == "t":
            continue
        try:
            check_name(name, reserved)
            a = np.asarray(value)
            if a.dtype.kind not in "biuf":
                raise ValueError(f"series {name!r} must hold real numbers, got dtype {a.dtype}")
            if a.ndim == 0 or a.shape[0] != n:
                raise ValueError(f"series {name!r} must have leading dimension len(t) = {n}, "
                                 f"got shape {a.shape}")
        except ValueError:
            check_finite(out)
            raise
        out.append((name, a))
    return out


def check_finite(arrays: list[tuple[str, np.ndarray]]) -> None:
    """ValueError naming the first of ``arrays`` ((name, array)) holding NaN or inf."""
    for name, a in arrays:
        metrics._check_finite(f"series {name!r}", a)


def frozen_copies(arrays: list[tuple[str, np.ndarray]]) -> dict[str, np.ndarray]:
    """Read-only copies of ``arrays`` ((name, array), checked by checked_arrays) by name, in
    order; ValueError naming the first holding NaN or inf. The copies of one dtype are views of
    one read-only buffer: one copy and one finiteness test a dtype, not one a series."""
    groups: dict[np.dtype, list] = {}
    for name, a in arrays:
        groups.setdefault(a.dtype, []).append((name, a))
    views = {}
    for dtype, group in groups.items():
        buffer = np.empty(sum([a.size for _, a in group]), dtype=dtype)
        np.concatenate([a.ravel() for _, a in group], out=buffer)
        if not np.isfinite(buffer).all():
            check_finite(arrays)
        buffer.flags.writeable = False
        start = 0
        for name, a in group:
            views[name] = buffer[start:start + a.size].reshape(a.shape)
            start += a.size
    return {name: views[name] for name, _ in arrays}


@functools.lru_cache(maxsize=256)
def check_name(name: object, reserved: frozenset) -> None:
    """ValueError unless ``name`` is an identifier, not private and not in ``reserved`` (the
    Result's own attribute names)."""
    if not isinstance(name, str) or not name.isidentifier() or keyword.iskeyword(name):
        raise ValueError(f"series names must be Python identifiers, got {name!r}")
    if name.startswith("_") or name in reserved:
        raise ValueError(f"series name {name!r} is reserved (leading underscore or an attribute "
                         "of Result)")


def check_units(units: Optional[Mapping[str, str]], arrays: Mapping[str, np.ndarray]) -> dict:
    """The units by series name, in the series' order, ``t`` in s; ValueError for a unit of no
    series, TypeError for one that is not a string."""
    out = {"t": "s"}
    for name, unit in dict(units or {}).items():
        if name not in arrays:
            raise ValueError(f"units names {name!r}, which is not a series; series: {list(arrays)}")
        if not isinstance(unit, str):
            raise TypeError(f"units[{name!r}] must be a string, "
                            f"got {type(unit).__name__} {unit!r}")
        out[name] = unit
    return {name: out[name] for name in arrays if name in out}


#: The JSON values a container's walk keeps as they are, by exact type (with finite floats: most
#: of a run's metadata), without a call each.
PLAIN_JSON_TYPES = frozenset((str, int, bool, type(None)))


def to_json_value(value: Any, where: Any) -> Any:
    """``value`` in the form JSON gives back (tuples as lists, numpy as Python); TypeError for
    what JSON cannot hold, ValueError for NaN or inf. ``where`` names ``value`` in the error: a
    string, or (the container's ``where``, key or index), formatted only when raising."""
    kind = type(value)
    if kind is dict:
        return json_dict(value, where)
    if kind is list or kind is tuple:
        return json_list(value, where)
    if isinstance(value, np.ndarray):
        value = value.tolist()
    elif isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"{where_text(where)} must be finite, got {value!r}")
        return value
    if isinstance(value, (list, tuple)):
        return json_list(value, where)
    if isinstance(value, Mapping):
        return json_dict(value, where)
    raise TypeError(f"{where_text(where)} must be JSON-compatible (None, bool, int, float, str, list, "
                    f"dict), got {type(value).__name__}")


def json_list(values: Any, where: Any) -> list:
    """to_json_value of a list or tuple's items: plain values (the test repeated in json_dict)
    kept without a call each."""
    return [v if type(v) in PLAIN_JSON_TYPES or (type(v) is float and math.isfinite(v))
            else to_json_value(v, (where, k)) for k, v in enumerate(values)]


def json_dict(mapping: Mapping, where: Any) -> dict:
    """to_json_value of a mapping's values, its keys checked to be strings (as json_list)."""
    out = {}
    for key, v in mapping.items():
        if not isinstance(key, str):
            raise TypeError(f"{where_text(where)} keys must be strings, got {key!r}")
        out[key] = (v if type(v) in PLAIN_JSON_TYPES or (type(v) is float and math.isfinite(v))
                    else to_json_value(v, (where, key)))
    return out


def where_text(where: Any) -> str:
    """The name of to_json_value's ``where``: ``metadata['hinges'][0]``."""
    keys = []
    while isinstance(where, tuple):
        where, key = where
        keys.append(f"[{key!r}]" if isinstance(key, str) else f"[{key}]")
    return where + "".join(reversed(keys))
