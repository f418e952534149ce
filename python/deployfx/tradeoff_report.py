"""Reports of :func:`deployfx.tradeoff.tradeoff`'s rows: CSV, markdown and text tables, a pandas
DataFrame (pandas is optional, as for :meth:`Result.to_dataframe`) and the work-precision plot."""
from __future__ import annotations

import csv
import math
from pathlib import Path
from typing import Any, Mapping, Optional, Sequence

from .results import PathLike
from .tradeoff import COLUMNS, ERRORS, _positive

#: Marker and colour of each fidelity family in :func:`plot_work_precision`.
FAMILY_STYLE = {"rigid": ("s", "tab:gray"), "reduced-linear": ("v", "tab:green"),
                "reduced-nonlinear": ("^", "tab:orange"), "reduced-manifold": ("P", "tab:purple"),
                "linear": ("o", "tab:blue"), "nonlinear": ("D", "tab:red")}

def to_dataframe(rows: Sequence[Mapping[str, Any]]):
    """The rows as a pandas DataFrame (columns :data:`COLUMNS`; None becomes NaN in numeric
    columns). Needs pandas (``pip install pandas``; it is in ``deployfx[test]``)."""
    try:
        import pandas as pd
    except ImportError as exc:
        raise ImportError("deployfx.tradeoff_report.to_dataframe needs pandas: pip install pandas "
                          "(or pip install 'deployfx[test]')") from exc
    return pd.DataFrame([dict(r) for r in rows], columns=list(COLUMNS))


def write_csv(rows: Sequence[Mapping[str, Any]], path: PathLike) -> Path:
    """Write the rows to a CSV file (header :data:`COLUMNS`, then any other keys the rows carry;
    None and NaN as empty cells, floats with 6 significant digits); returns the path."""
    names = list(COLUMNS)
    for r in rows:
        names += [k for k in r if k not in names]
    path = Path(path)
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(names)
        for r in rows:
            w.writerow([_cell(r.get(c)) for c in names])
    return path


def _cell(v: Any) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return ""
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


#: Columns of the short table (:func:`to_markdown`, the bench's printout): name -> format.
SHORT = {"label": "{}", "coordinates": "{}", "wall_time_s": "{:.3g}", "ms_per_step": "{:.3g}",
         "newton_iterations": "{}", "lock_time_s": "{:.4f}", "lock_time_error_s": "{:.1e}",
         "peak_lock_force_N": "{:.3g}", "peak_lock_force_rel_error": "{:.1e}",
         "node_E_rms_rel_error": "{:.1e}"}


def _fmt(v: Any, fmt: str) -> str:
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "-"
    if isinstance(v, float) and math.isinf(v):
        return "inf"
    return fmt.format(v)


def to_markdown(rows: Sequence[Mapping[str, Any]], columns: Mapping[str, str] = SHORT) -> str:
    """The rows as a GitHub-markdown table of ``columns`` (name -> format string), one line per
    row; failed runs get their message in a last column."""
    names = list(columns)
    head = "| " + " | ".join(names) + " | failure |"
    lines = [head, "|" + "---|" * (len(names) + 1)]
    for r in rows:
        cells = [_fmt(r.get(c), f) for c, f in columns.items()]
        lines.append("| " + " | ".join(cells) + f" | {r.get('failure') or ''} |")
    return "\n".join(lines)


def to_text(rows: Sequence[Mapping[str, Any]], columns: Mapping[str, str] = SHORT) -> str:
    """The rows as an aligned plain-text table of ``columns`` (as :func:`to_markdown`)."""
    table = [list(columns) + ["failure"]]
    for r in rows:
        table.append([_fmt(r.get(c), f) for c, f in columns.items()]
                     + [(r.get("failure") or "")[:60]])
    widths = [max(len(row[k]) for row in table) for k in range(len(table[0]))]
    return "\n".join("  ".join(c.ljust(w) if k == 0 else c.rjust(w) for k, (c, w) in
                               enumerate(zip(row, widths))).rstrip() for row in table)


def plot_work_precision(rows: Sequence[Mapping[str, Any]], errors: Sequence[str] = tuple(ERRORS),
                        title: Optional[str] = None):
    """Work-precision diagram: each error in ``errors`` (columns of :data:`ERRORS`) against wall
    time (s), log-log, one panel per error, one marker and colour per fidelity family
    (:data:`FAMILY_STYLE`). The reference's wall time is a dotted vertical line; rows with a zero,
    NaN or infinite error (the reference itself, failed runs) have no point in that panel.
    Returns a :class:`matplotlib.figure.Figure` (built without pyplot; save with ``savefig``)."""
    from matplotlib.figure import Figure

    unknown = [e for e in errors if e not in ERRORS]
    if unknown or not errors:
        raise ValueError(f"errors must be a non-empty subset of {list(ERRORS)}, got {list(errors)}")
    fig = Figure(figsize=(4.2 * len(errors), 4.0), layout="constrained")
    axes = fig.subplots(1, len(errors), squeeze=False)[0]
    ref_wall = [r["wall_time_s"] for r in rows if r.get("is_reference") and r.get("wall_time_s")]
    for ax, err in zip(axes, errors):
        for family, (marker, colour) in FAMILY_STYLE.items():
            pts = [(r["wall_time_s"], r[err]) for r in rows
                   if r.get("model") == family and not r.get("is_reference")
                   and _positive(r.get("wall_time_s")) and _positive(r.get(err))]
            if pts:
                x, y = zip(*pts)
                ax.plot(x, y, linestyle="none", marker=marker, color=colour, label=family,
                        markeredgecolor="k", markeredgewidth=0.5)
        for w in ref_wall:
            ax.axvline(w, color="k", linestyle=":", linewidth=1.0, label="reference wall time")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel(ERRORS[err])
        ax.grid(True, which="both", linewidth=0.3)
    handles, labels = axes[0].get_legend_handles_labels()
    if handles:
        seen = dict(zip(labels, handles))
        axes[0].legend(seen.values(), seen.keys(), fontsize="small")
    if title:
        fig.suptitle(title)
    return fig
