"""Time integrators of the generalized-alpha family (Arnold & Bruls 2007 form of Chung & Hulbert
1993): Newmark, HHT-alpha and generalized-alpha, each with Newton iterations.

Schemes are small immutable descriptions; the stepping runs in C++ with the GIL released.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Union

import numpy as np

from . import _core
from ._checks import as_float


@dataclass(frozen=True)
class Newmark:
    """Newmark's method; beta = 1/4, gamma = 1/2 is the average-acceleration (trapezoidal) rule,
    second order and energy conserving for linear systems."""

    beta: float = 0.25
    gamma: float = 0.5

    def _params(self) -> _core.AlphaParameters:
        return _core.AlphaParameters.newmark(as_float("beta", self.beta), as_float("gamma", self.gamma))


@dataclass(frozen=True)
class HHT:
    """Hilber-Hughes-Taylor alpha method, alpha in [-1/3, 0] (0: average acceleration)."""

    alpha: float = -0.05

    def _params(self) -> _core.AlphaParameters:
        return _core.AlphaParameters.hht(as_float("alpha", self.alpha))


@dataclass(frozen=True)
class GeneralizedAlpha:
    """Chung-Hulbert generalized-alpha with spectral radius rho_inf in [0, 1] at infinite
    frequency (1: no numerical dissipation)."""

    rho_inf: float = 0.9

    def _params(self) -> _core.AlphaParameters:
        return _core.AlphaParameters.generalized_alpha(as_float("rho_inf", self.rho_inf))


Scheme = Union[Newmark, HHT, GeneralizedAlpha]


class SimulationError(RuntimeError):
    """A run that stopped early; ``result`` holds what was computed up to the failure."""

    def __init__(self, message: str, result: "Trajectory"):
        super().__init__(message)
        self.result = result


@dataclass(frozen=True)
class Trajectory:
    """Recorded states: ``t`` (n,) in s, ``q`` (n, nq), ``v`` (n, nv), Newton iterations per step."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    newton_iterations: np.ndarray


def _check_scheme(scheme: object) -> Scheme:
    if not isinstance(scheme, (Newmark, HHT, GeneralizedAlpha)):
        raise TypeError(f"scheme must be Newmark, HHT or GeneralizedAlpha, got {type(scheme).__name__}")
    return scheme


def simulate_linear(M, C, K, q0, v0, t_end: float, dt: float, scheme: Scheme = Newmark()) -> Trajectory:
    """Integrate ``M a + C v + K q = 0`` from ``(q0, v0)`` at t = 0 to ``t_end`` (s) with step
    ``dt`` (s). Raises :class:`SimulationError` (with the partial trajectory) if a step fails."""
    d = _core.simulate_linear(np.atleast_2d(np.asarray(M, float)), np.atleast_2d(np.asarray(C, float)),
                              np.atleast_2d(np.asarray(K, float)), np.atleast_1d(np.asarray(q0, float)),
                              np.atleast_1d(np.asarray(v0, float)), as_float("t_end", t_end),
                              as_float("dt", dt), _check_scheme(scheme)._params())
    tr = Trajectory(d["t"], d["q"], d["v"], np.asarray(d["newton_iterations"]))
    if d["failure"]:
        raise SimulationError(d["failure"], tr)
    return tr
