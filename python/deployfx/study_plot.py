"""Figures of a study (deployfx.study), with matplotlib:

- :func:`sobol_bars`: first-order and total Sobol' indices of each output, with their confidence
  intervals, one panel per output;
- :func:`scatter_matrix`: each output against each varied parameter (rows outputs, columns
  parameters), the samples' values as points;
- :func:`histograms`: the distribution of each output over the computed samples.

Each returns the Figure; failed and pending samples (and NaN values) are left out and counted in
the titles.
"""
from __future__ import annotations

from typing import Optional, Sequence

import numpy as np

from ._study_store import DONE


def _plt():
    import matplotlib.pyplot as plt

    return plt


def sobol_bars(indices, title: Optional[str] = None):
    """Grouped bars of ``S1`` and ``ST`` per parameter, error bars ``S1_conf``/``ST_conf``, one
    panel per output of ``indices`` (:func:`deployfx.study.sobol`'s Dataset)."""
    plt = _plt()
    outputs = [str(o) for o in indices["output"].values]
    params = [str(p) for p in indices["parameter"].values]
    n = len(outputs)
    fig, axes = plt.subplots(1, n, figsize=(max(4.0, 0.9 * len(params) + 2.0) * n, 3.6),
                             squeeze=False, layout="constrained")
    x = np.arange(len(params))
    w = 0.38
    for ax, out in zip(axes[0], outputs):
        s = indices.sel(output=out)
        ax.bar(x - w / 2, s["S1"].values, w, yerr=s["S1_conf"].values, capsize=3,
               label="first order S1")
        ax.bar(x + w / 2, s["ST"].values, w, yerr=s["ST_conf"].values, capsize=3,
               label="total ST")
        ax.set_xticks(x, params, rotation=30, ha="right")
        ax.set_title(out)
        ax.axhline(0.0, color="k", lw=0.6)
        ax.set_ylabel("Sobol' index")
    axes[0][0].legend(loc="best", fontsize="small")
    level = indices.attrs.get("conf_level", 0.95)
    fig.suptitle(title or f"Sobol' indices (bars: {100 * level:g} % confidence intervals)")
    return fig


def _computed(ds):
    return np.asarray(ds["status"].values) == DONE


def scatter_matrix(ds, outputs: Optional[Sequence[str]] = None,
                   parameters: Optional[Sequence[str]] = None):
    """Each output (rows) against each varied parameter (columns), one point per computed
    sample of the study's Dataset ``ds``."""
    plt = _plt()
    outputs = list(outputs or ds.attrs["outputs"])
    parameters = list(parameters or ds.attrs["parameters"])
    ok = _computed(ds)
    fig, axes = plt.subplots(len(outputs), len(parameters),
                             figsize=(2.6 * len(parameters) + 1.0, 2.2 * len(outputs) + 0.8),
                             squeeze=False, sharex="col", sharey="row", layout="constrained")
    for r, out in enumerate(outputs):
        y = np.asarray(ds[out].values, dtype=float)
        for c, p in enumerate(parameters):
            ax = axes[r][c]
            x = np.asarray(ds[p].values)
            keep = ok & np.isfinite(y)
            ax.scatter(x[keep], y[keep], s=8, alpha=0.6)
            if r == len(outputs) - 1:
                ax.set_xlabel(p)
            if c == 0:
                ax.set_ylabel(out)
    fig.suptitle(f"outputs against parameters: {int(ok.sum())} of {ok.size} samples computed")
    return fig


def histograms(ds, outputs: Optional[Sequence[str]] = None, bins: int = 20):
    """A histogram of each output over the computed samples with a value."""
    plt = _plt()
    outputs = list(outputs or ds.attrs["outputs"])
    ok = _computed(ds)
    fig, axes = plt.subplots(1, len(outputs), figsize=(3.6 * len(outputs), 3.0), squeeze=False,
                             layout="constrained")
    for ax, out in zip(axes[0], outputs):
        y = np.asarray(ds[out].values, dtype=float)[ok]
        v = y[np.isfinite(y)]
        ax.hist(v, bins=bins)
        ax.set_xlabel(out)
        ax.set_ylabel("samples")
        ax.set_title(f"{v.size} values" + (f", {y.size - v.size} undefined" if y.size > v.size else ""),
                     fontsize="small")
    return fig
