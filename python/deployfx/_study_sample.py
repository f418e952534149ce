"""Distributions and samplers of a study (deployfx.study): what a varied parameter may take and
how the samples are drawn.

Random samplers draw points u of the unit hypercube [0, 1)^d (scipy.stats.qmc's Sobol' and Latin
hypercube, numpy's generator, or SALib's Saltelli scheme) and map each coordinate through its
distribution's inverse CDF, x = F^-1(u). Sobol' indices are invariant under such a one-to-one map
of each independent input, so the indices SALib computes from the u's design are those of the
x's (Saltelli et al. 2008, Global Sensitivity Analysis: The Primer, Ch. 4).
"""
from __future__ import annotations

import itertools
import math
import numbers
from dataclasses import dataclass
from typing import Any, Mapping, Sequence

import numpy as np

#: Sampler names: "grid" (full factorial of Levels), "sobol" (scrambled Sobol' sequence), "lhs"
#: (Latin hypercube), "random" (plain Monte Carlo), "saltelli" (SALib's design for Sobol' indices).
SAMPLERS = ("grid", "sobol", "lhs", "random", "saltelli")

_U_EDGE = 2.0 ** -53  # u is kept in [edge, 1 - edge]: an unbounded F^-1(0) is -inf


def _real(where: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real) or not math.isfinite(value):
        raise ValueError(f"{where} = {value!r} is invalid: must be a finite real number")
    return float(value)


@dataclass(frozen=True)
class Uniform:
    """Uniform on [low, high) (same units as the parameter)."""

    low: float
    high: float

    def __post_init__(self):
        lo, hi = _real("Uniform.low", self.low), _real("Uniform.high", self.high)
        if not lo < hi:
            raise ValueError(f"Uniform(low={lo!r}, high={hi!r}) is invalid: must have low < high")

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """The inverse CDF at ``u`` in [0, 1): low + (high - low) u."""
        return self.low + (self.high - self.low) * u

    def to_dict(self) -> dict:
        """The study file's table: {distribution = "uniform", low, high}."""
        return {"distribution": "uniform", "low": float(self.low), "high": float(self.high)}


@dataclass(frozen=True)
class LogUniform:
    """Log-uniform on [low, high), 0 < low < high: uniform in log(x) (a stiffness known to a
    decade, say)."""

    low: float
    high: float

    def __post_init__(self):
        lo, hi = _real("LogUniform.low", self.low), _real("LogUniform.high", self.high)
        if not 0 < lo < hi:
            raise ValueError(f"LogUniform(low={lo!r}, high={hi!r}) is invalid: must have "
                             "0 < low < high")

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """The inverse CDF at ``u`` in [0, 1): exp(log low + (log high - log low) u)."""
        a, b = math.log(self.low), math.log(self.high)
        return np.exp(a + (b - a) * u)

    def to_dict(self) -> dict:
        """The study file's table: {distribution = "loguniform", low, high}."""
        return {"distribution": "loguniform", "low": float(self.low), "high": float(self.high)}


@dataclass(frozen=True)
class Normal:
    """Normal with ``mean`` and standard deviation ``std`` > 0; ``low``/``high`` (optional)
    truncate it to [low, high] (scipy.stats.truncnorm), as a tolerance band does."""

    mean: float
    std: float
    low: float = -math.inf
    high: float = math.inf

    def __post_init__(self):
        _real("Normal.mean", self.mean)
        if not _real("Normal.std", self.std) > 0:
            raise ValueError(f"Normal.std = {self.std!r} is out of range: must be > 0")
        for name in ("low", "high"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, numbers.Real) or math.isnan(v):
                raise ValueError(f"Normal.{name} = {v!r} is invalid: must be a real number")
        if not self.low < self.high:
            raise ValueError(f"Normal(low={self.low!r}, high={self.high!r}) is invalid: must have "
                             "low < high")

    def ppf(self, u: np.ndarray) -> np.ndarray:
        """The inverse CDF at ``u`` (clipped to [2^-53, 1 - 2^-53], so an untruncated tail
        stays finite): scipy.stats.norm, or truncnorm between low and high."""
        from scipy import stats

        u = np.clip(u, _U_EDGE, 1.0 - _U_EDGE)
        if math.isinf(self.low) and math.isinf(self.high):
            return stats.norm.ppf(u, self.mean, self.std)
        a, b = (self.low - self.mean) / self.std, (self.high - self.mean) / self.std
        return stats.truncnorm.ppf(u, a, b, self.mean, self.std)

    def to_dict(self) -> dict:
        """The study file's table: {distribution = "normal", mean, std[, low][, high]}."""
        d = {"distribution": "normal", "mean": float(self.mean), "std": float(self.std)}
        d.update({k: float(getattr(self, k)) for k in ("low", "high")
                  if math.isfinite(getattr(self, k))})
        return d


@dataclass(frozen=True)
class Levels:
    """The values of a parameter in a grid study (numbers, strings or booleans, e.g. the lay-up
    or the model's fidelity); the grid is the full factorial of every parameter's levels."""

    values: tuple

    def __post_init__(self):
        values = tuple(v.item() if isinstance(v, np.generic) else v for v in self.values)
        if not values:
            raise ValueError("Levels(values=()) is invalid: give at least one value")
        kinds = {_kind(v) for v in values}
        if None in kinds or len(kinds) > 1:
            raise ValueError(f"Levels(values={list(values)!r}) is invalid: the values must all be "
                             "numbers, all strings or all booleans")
        if kinds == {"number"}:
            for v in values:
                _real("Levels value", v)
        object.__setattr__(self, "values", values)

    def to_dict(self) -> dict:
        """The study file's table: {levels = [...]}."""
        return {"levels": list(self.values)}


def _kind(v: Any):
    if isinstance(v, bool):
        return "bool"
    if isinstance(v, numbers.Real):
        return "number"
    if isinstance(v, str):
        return "str"
    return None


Distribution = (Uniform, LogUniform, Normal)

_DISTRIBUTIONS = {"uniform": (Uniform, ("low", "high"), ()),
                  "loguniform": (LogUniform, ("low", "high"), ()),
                  "normal": (Normal, ("mean", "std"), ("low", "high"))}


def from_dict(where: str, d: Any):
    """A distribution or Levels from its table in a study file ({distribution = "uniform", low,
    high}, ... or {levels = [...]}); ValueError naming ``where`` otherwise."""
    if not isinstance(d, Mapping):
        raise ValueError(f"{where} must be a table such as {{distribution = \"uniform\", low = 1.0, "
                         f"high = 2.0}} or {{levels = [1.0, 2.0]}}, got {d!r}")
    if "levels" in d:
        extra = sorted(set(d) - {"levels"})
        if extra:
            raise ValueError(f"{where} has unknown key(s) {extra}: a grid parameter has only 'levels'")
        if not isinstance(d["levels"], list):
            raise ValueError(f"{where}.levels must be a list, got {d['levels']!r}")
        try:
            return Levels(tuple(d["levels"]))
        except ValueError as e:
            raise ValueError(f"{where}.levels: {e}") from None
    kind = d.get("distribution")
    if kind not in _DISTRIBUTIONS:
        raise ValueError(f"{where}.distribution = {kind!r} is invalid: must be one of "
                         f"{', '.join(map(repr, _DISTRIBUTIONS))} (or give levels = [...] for a grid)")
    cls, required, optional = _DISTRIBUTIONS[kind]
    missing = [k for k in required if k not in d]
    if missing:
        raise ValueError(f"{where} is missing key(s) {', '.join(f'{where}.{k}' for k in missing)}")
    unknown = sorted(set(d) - {"distribution"} - set(required) - set(optional))
    if unknown:
        raise ValueError(f"{where} has unknown key(s) {', '.join(f'{where}.{k}' for k in unknown)}; "
                         f"allowed: distribution, {', '.join(required + optional)}")
    args = {k: d[k] for k in required + optional if k in d}
    for k, v in args.items():
        if isinstance(v, bool) or not isinstance(v, numbers.Real):
            raise ValueError(f"{where}.{k} = {v!r} is invalid: must be a number")
    try:
        return cls(**args)
    except ValueError as e:
        raise ValueError(f"{where}: {e}") from None


def check_design(vary: Mapping[str, Any], sampler: str, samples) -> int:
    """Check the sampler against the varied parameters; return the number of samples (runs)."""
    if sampler not in SAMPLERS:
        raise ValueError(f"sampler = {sampler!r} is invalid: must be one of "
                         f"{', '.join(map(repr, SAMPLERS))}")
    if not vary:
        raise ValueError("vary is empty: give at least one parameter to vary")
    if sampler == "grid":
        bad = [k for k, v in vary.items() if not isinstance(v, Levels)]
        if bad:
            raise ValueError(f"sampler 'grid' needs levels for every parameter; {bad} are "
                             "distributions (use sampler 'sobol', 'lhs', 'random' or 'saltelli')")
        n = math.prod(len(v.values) for v in vary.values())
        if samples is not None and samples != n:
            raise ValueError(f"samples = {samples!r} does not match the grid's {n} points "
                             "(leave samples out for a grid)")
        return n
    bad = [k for k, v in vary.items() if not isinstance(v, Distribution)]
    if bad:
        raise ValueError(f"sampler {sampler!r} needs a distribution (Uniform, LogUniform, Normal) "
                         f"for every parameter; {bad} have levels (use sampler 'grid')")
    if isinstance(samples, bool) or not isinstance(samples, numbers.Integral) or samples < 1:
        raise ValueError(f"samples = {samples!r} is invalid: must be an integer >= 1")
    samples = int(samples)
    if sampler in ("sobol", "saltelli") and samples & (samples - 1):
        lo = 1 << (samples.bit_length() - 1)
        raise ValueError(f"samples = {samples} is invalid for sampler {sampler!r}: must be a power "
                         f"of 2 (the balance properties of Sobol' points), e.g. {lo} or {2 * lo}")
    if sampler == "saltelli":  # SALib: N (d + 2) runs for first and total order indices
        return samples * (len(vary) + 2)
    return samples


def draw(vary: Mapping[str, Any], sampler: str, samples, seed: int) -> dict[str, np.ndarray]:
    """The design: for each varied parameter, its value in each sample (arrays of one length).
    Deterministic for a given ``seed``."""
    names = list(vary)
    if sampler == "grid":
        points = list(itertools.product(*(vary[k].values for k in names)))  # last varies fastest
        return {k: np.array([p[j] for p in points]) for j, k in enumerate(names)}
    d = len(names)
    if sampler == "sobol":
        from scipy.stats import qmc

        u = qmc.Sobol(d, scramble=True, seed=seed).random_base2(int(samples).bit_length() - 1)
    elif sampler == "lhs":
        from scipy.stats import qmc

        u = qmc.LatinHypercube(d, seed=seed).random(samples)
    elif sampler == "random":
        u = np.random.default_rng(seed).random((samples, d))
    else:
        from SALib.sample import sobol as saltelli

        u = saltelli.sample(_unit_problem(names), samples, calc_second_order=False, seed=seed)
    return {k: np.asarray(vary[k].ppf(u[:, j]), dtype=float) for j, k in enumerate(names)}


def _unit_problem(names: Sequence[str]) -> dict:
    """SALib's problem on the unit hypercube (the design's u's; see the module docstring)."""
    return {"num_vars": len(names), "names": list(names), "bounds": [[0.0, 1.0]] * len(names)}
