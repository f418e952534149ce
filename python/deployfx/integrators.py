"""Time integrators of the generalized-alpha family (Arnold & Bruls 2007 form of Chung & Hulbert
1993): Newmark, HHT-alpha and generalized-alpha, each with Newton iterations.

Schemes are small immutable descriptions; the stepping runs in C++ with the GIL released.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Sequence, Union

import numpy as np
import scipy.sparse

from . import _core
from ._checks import as_float, as_int_sequence


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


def _square(name: str, A, n: Optional[int]) -> np.ndarray:
    """``A`` (a numpy array, an array-like or any scipy.sparse matrix) as a dense float (n x n)
    array; ValueError naming ``name`` for another shape or a non-finite entry."""
    if scipy.sparse.issparse(A):
        A = A.toarray()
    try:
        a = np.atleast_2d(np.asarray(A, dtype=float))
    except (TypeError, ValueError) as e:
        raise TypeError(f"{name} must be a real matrix (numpy array or scipy.sparse), "
                        f"got {type(A).__name__}: {e}") from None
    if a.ndim != 2 or a.shape[0] != a.shape[1] or (n is not None and a.shape[0] != n):
        want = "square (n x n)" if n is None else f"({n} x {n}), the size of M"
        raise ValueError(f"{name} must be {want}, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got NaN or inf")
    return a


def _vector(name: str, x, n: int) -> np.ndarray:
    a = np.atleast_1d(np.asarray(x, dtype=float))
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be {n} finite numbers (one per row of M), got shape {a.shape}")
    return a


def simulate_linear(M, C, K, q0, v0, t_end: float, dt: float, scheme: Scheme = Newmark(), *,
                    fixed_dofs: Optional[Sequence[int]] = None) -> Trajectory:
    """Integrate ``M a + C v + K q = 0`` from ``(q0, v0)`` at t = 0 to ``t_end`` (s) with step
    ``dt`` (s), holding the dofs ``fixed_dofs`` at zero.

    ``M``, ``C``, ``K``: (n x n) matrices, numpy arrays or any scipy.sparse format (what
    :meth:`deployfx.ShellModel.stiffness_matrix` and ``mass_matrix`` return); ``q0``, ``v0``: n
    values. ``fixed_dofs``: dof indices in [0, n) held at zero (e.g. ``Plate.fixed_dofs("CFFF")``):
    their rows and columns are removed before the run and their entries of ``q0`` and ``v0`` must
    be zero. The returned :class:`Trajectory` has all n columns (zeros at the fixed dofs). The
    solve is dense (the matrices of the free dofs are copied into dense arrays): meant for systems
    of up to a few thousand dofs. Raises ValueError or TypeError naming a bad argument, and
    :class:`SimulationError` (with the partial trajectory) if a step fails."""
    M = _square("M", M, None)
    n = M.shape[0]
    C, K = _square("C", C, n), _square("K", K, n)
    q0, v0 = _vector("q0", q0, n), _vector("v0", v0, n)
    free = np.arange(n)
    if fixed_dofs is not None:
        fixed = np.asarray(as_int_sequence("fixed_dofs", fixed_dofs), dtype=int)
        bad = fixed[(fixed < 0) | (fixed >= n)]
        if bad.size:
            raise ValueError(f"fixed_dofs = {int(bad[0])} is out of range: must be in [0, {n - 1}] (the rows of M)")
        for name, x in (("q0", q0), ("v0", v0)):
            moved = fixed[x[fixed] != 0]
            if moved.size:
                raise ValueError(f"{name}[{int(moved[0])}] = {float(x[moved[0]])!r}: a fixed dof must start at 0")
        free = np.setdiff1d(free, fixed)
    ix = np.ix_(free, free)
    d = _core.simulate_linear(M[ix], C[ix], K[ix], q0[free], v0[free], as_float("t_end", t_end),
                              as_float("dt", dt), _check_scheme(scheme)._params())
    q, v = (np.zeros((len(d["t"]), n)) for _ in range(2))
    q[:, free], v[:, free] = d["q"], d["v"]
    tr = Trajectory(d["t"], q, v, np.asarray(d["newton_iterations"]))
    if d["failure"]:
        raise SimulationError(d["failure"], tr)
    return tr
