"""Ply strength allowables for the failure criteria of :mod:`deployfx.stress`.

deployfx ships no strength values: the paper (You et al. 2016) gives none for its IM6/SC1081
plies, and allowables depend on the material batch, the environment and the design basis
(A- or B-basis). Supply your own, in Pa, with their source.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from . import _core
from ._checks import as_float

__all__ = ["Strengths"]


@dataclass(frozen=True)
class Strengths:
    """Strength allowables of a unidirectional ply in its material axes (1 along the fibres), Pa.

    Parameters
    ----------
    Xt, Xc : tensile and compressive strength along the fibres, Pa (> 0; Xc a magnitude).
    Yt, Yc : tensile and compressive strength across the fibres, Pa (> 0; Yc a magnitude).
    S12 : in-plane (axial) shear strength, Pa (> 0).
    S13 : interlaminar shear strength in the 1-3 plane, Pa (> 0), optional. When given, the
        maximum-stress and Tsai-Wu criteria include ``tau_13``.
    S23 : transverse shear strength in the 2-3 plane, Pa (> 0), optional; Hashin's matrix modes
        need it (his S_T). When given, maximum stress and Tsai-Wu include ``tau_23``.
    F12_star : the Tsai-Wu interaction ``F12 / sqrt(F11 F22)``, in (-1, 1); default -1/2
        (Tsai & Hahn, *Introduction to Composite Materials*, 1980).

    Raises ValueError naming the field for a value out of range, TypeError for a non-number.
    """

    Xt: float
    Xc: float
    Yt: float
    Yc: float
    S12: float
    S13: Optional[float] = None
    S23: Optional[float] = None
    F12_star: float = -0.5
    _impl: _core.Strengths = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        args = {k: as_float(f"Strengths.{k}", getattr(self, k))
                for k in ("Xt", "Xc", "Yt", "Yc", "S12", "F12_star")}
        for k in ("S13", "S23"):
            v = getattr(self, k)
            args[k] = None if v is None else as_float(f"Strengths.{k}", v)
        object.__setattr__(self, "_impl", _core.Strengths(**args))
