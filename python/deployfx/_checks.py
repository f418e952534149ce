"""Argument conversion with errors that name the parameter (the C++ core checks ranges)."""
from __future__ import annotations

import numbers

import numpy as np


def as_float(name: str, value: object) -> float:
    """``value`` as a float, or TypeError naming ``name``."""
    if type(value) is float:  # the common case, without the ABC's check
        return value
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    return float(value)


def as_int(name: str, value: object) -> int:
    """``value`` as an int, or TypeError naming ``name``."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    return int(value)


def as_int_sequence(name: str, values: object) -> list:
    """``values`` (a sequence or 1-D array of integers) as a list of ints; TypeError naming
    ``name[k]`` for an entry that is not an integer (1.5 is refused, not truncated to 1)."""
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        raise TypeError(f"{name} must be a sequence of integers, got {type(values).__name__} "
                        f"{values!r}")
    return [as_int(f"{name}[{k}]", v) for k, v in enumerate(values)]


def check_field_types(obj: object) -> None:
    """TypeError naming ``Class.field`` for a dataclass field whose value does not have the
    annotated type: int, float (ints accepted), bool, str, tuple (of real numbers), Optional[X]
    or a class. Annotations of other forms are not checked."""
    import dataclasses
    import typing

    cls = type(obj)
    hints = typing.get_type_hints(cls)
    for f in dataclasses.fields(obj):
        name, value, kind = f"{cls.__name__}.{f.name}", getattr(obj, f.name), hints.get(f.name)
        if typing.get_origin(kind) is typing.Union:
            args = [a for a in typing.get_args(kind) if a is not type(None)]
            if value is None:
                continue
            kind = args[0] if len(args) == 1 else None
        if kind is int:
            as_int(name, value)
        elif kind is float:
            as_float(name, value)
        elif kind is bool:
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{name} must be True or False, got {type(value).__name__} "
                                f"{value!r}")
        elif kind is str:
            if not isinstance(value, str):
                raise TypeError(f"{name} must be a string, got {type(value).__name__} {value!r}")
        elif kind is tuple:
            if isinstance(value, (str, bytes)) or not hasattr(value, "__iter__"):
                raise TypeError(f"{name} must be a sequence of numbers, got "
                                f"{type(value).__name__} {value!r}")
            for k, v in enumerate(value):
                as_float(f"{name}[{k}]", v)
        elif isinstance(kind, type) and not isinstance(value, kind):
            raise TypeError(f"{name} must be a {kind.__name__}, got {type(value).__name__} "
                            f"{value!r}")


def finite_vector(name: str, value: object, n: int) -> np.ndarray:
    """``value`` as ``n`` finite floats, or ValueError naming ``name`` (a state: q0, v0)."""
    a = np.asarray(value, dtype=float)
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be {n} finite numbers, got shape {a.shape}")
    return a
