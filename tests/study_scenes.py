"""Scene factories for the study tests (tests/test_study*.py), importable by Dask workers.

- :func:`ishigami`: the Ishigami function as a one-sample 'scene' (Ishigami & Homma 1990),
  y = sin x1 + a sin^2 x2 + b x3^4 sin x1, x_i uniform on [-pi, pi), a = 7, b = 0.1; its Sobol'
  indices in closed form are :data:`ISHIGAMI_S1` and :data:`ISHIGAMI_ST` (Sobol' & Levitan 1999;
  Saltelli et al. 2008, Global Sensitivity Analysis: The Primer, Sec. 4.8).
- :func:`logged_paper2016`: ``scenes.paper2016`` that first appends the worker's process id and
  its arguments to a file (which process built which sample).
"""
from __future__ import annotations

import math
import os

import deployfx as dfx

A, B = 7.0, 0.1
_PI = math.pi
_V1 = 0.5 * (1 + B * _PI ** 4 / 5) ** 2                     # V[E(y | x1)]
_V2 = A ** 2 / 8                                              # V[E(y | x2)]
_V13 = B ** 2 * _PI ** 8 * (1 / 18 - 1 / 50)                 # the x1-x3 interaction
_V = _V1 + _V2 + _V13                                         # = a^2/8 + b pi^4/5 + b^2 pi^8/18 + 1/2
#: First-order and total Sobol' indices of x1, x2, x3.
ISHIGAMI_S1 = (_V1 / _V, _V2 / _V, 0.0)
ISHIGAMI_ST = ((_V1 + _V13) / _V, _V2 / _V, _V13 / _V)


def ishigami_value(x1: float, x2: float, x3: float) -> float:
    return math.sin(x1) + A * math.sin(x2) ** 2 + B * x3 ** 4 * math.sin(x1)


class _Ishigami:
    def __init__(self, x1, x2, x3, log, fail_above):
        self.x = (x1, x2, x3)
        self.log, self.fail_above = log, fail_above

    def simulate(self, t_end, dt):
        if self.log:
            with open(self.log, "a") as f:
                f.write(f"{os.getpid()} {self.x[0]!r}\n")
        if self.fail_above is not None and self.x[0] > self.fail_above:
            raise ValueError(f"x1 = {self.x[0]} is out of range: must be <= {self.fail_above}")
        y = ishigami_value(*self.x)
        return dfx.Result({"t": [0.0, t_end], "y": [y, y]})


def ishigami(x1: float = 0.0, x2: float = 0.0, x3: float = 0.0, log: str = "",
             fail_above=None) -> _Ishigami:
    """The Ishigami function at (x1, x2, x3) as a scene whose run records ``y`` (constant in
    time); ``log``: a file that gets one line per run; ``fail_above``: runs with x1 above it
    raise ValueError (a failing sample)."""
    return _Ishigami(x1, x2, x3, log, fail_above)


def logged_paper2016(log: str = "", **kw):
    """``scenes.paper2016(**kw)``, after appending this process's id to ``log``."""
    with open(log, "a") as f:
        f.write(f"{os.getpid()}\n")
    return dfx.scenes.paper2016(**kw)
