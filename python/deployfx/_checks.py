"""Argument conversion with errors that name the parameter (the C++ core checks ranges)."""
from __future__ import annotations

import numbers


def as_float(name: str, value: object) -> float:
    """``value`` as a float, or TypeError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r}")
    return float(value)


def as_int(name: str, value: object) -> int:
    """``value`` as an int, or TypeError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name} must be an integer, got {type(value).__name__} {value!r}")
    return int(value)
