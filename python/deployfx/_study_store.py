"""A study's zarr store (deployfx.study): created whole, with every sample pending, then filled
in place as samples finish, so an interrupted study resumes where it stopped.

Layout (an xarray Dataset written with ``xarray.Dataset.to_zarr``):

- dimension ``sample`` (coordinate: 0 .. n-1) and, with series, ``time`` (coordinate: s);
- one coordinate per varied parameter along ``sample`` (its value in each sample: the design,
  written when the store is created);
- one float64 variable per output along ``sample``, one per series along (``sample``, ``time``):
  NaN until the sample is computed, and for a failed sample;
- ``status`` (int8): 0 pending, 1 computed, 2 failed; ``error``: the failed sample's error
  ("" otherwise);
- attributes: ``deployfx_study`` (the study as JSON, :meth:`deployfx.study.Study.to_dict`),
  ``sampler``, ``parameters``, ``outputs``, ``series``, ``deployfx_version``.

A sample's values are written before its status, so a store interrupted between the two shows
the sample pending and it is computed again, overwriting the same values. Nothing in the store
depends on when or where a sample ran, so a resumed store equals one run through.
"""
from __future__ import annotations

import json
import time as _time
from pathlib import Path
from typing import Any, Mapping, Sequence

import numpy as np

PENDING, DONE, FAILED = 0, 1, 2
_ATTR = "deployfx_study"


def create(path: Path, spec: dict, design: Mapping[str, np.ndarray], outputs: Sequence[str],
           series: Sequence[str], time: np.ndarray, version: str) -> None:
    """Write the empty store (every sample pending); FileExistsError if ``path`` exists."""
    import xarray as xr

    n = len(next(iter(design.values())))
    coords: dict[str, Any] = {"sample": ("sample", np.arange(n, dtype=np.int64))}
    for k, v in design.items():
        coords[k] = ("sample", v.astype(object) if v.dtype.kind == "U" else v)
    data: dict[str, Any] = {}
    chunk = min(n, 4096)
    encoding: dict[str, dict] = {}
    for k in outputs:
        data[k] = ("sample", np.full(n, np.nan))
        encoding[k] = {"chunks": (chunk,)}
    if series:
        coords["time"] = ("time", np.asarray(time, dtype=float), {"units": "s"})
        rows = max(1, min(n, (1 << 17) // max(len(time), 1)))  # chunks of about 1 MB
        for k in series:
            data[k] = (("sample", "time"), np.full((n, len(time)), np.nan))
            encoding[k] = {"chunks": (rows, len(time))}
    data["status"] = ("sample", np.zeros(n, dtype=np.int8),
                      {"flag_values": [PENDING, DONE, FAILED], "flag_meanings": "pending computed failed"})
    data["error"] = ("sample", np.full(n, "", dtype=object))
    encoding["status"] = {"chunks": (chunk,)}
    encoding["error"] = {"chunks": (chunk,)}
    ds = xr.Dataset(data, coords=coords)
    ds.attrs.update({_ATTR: json.dumps(spec, sort_keys=True), "sampler": spec["sampling"]["sampler"],
                     "parameters": list(design), "outputs": list(outputs), "series": list(series),
                     "deployfx_version": version})
    ds.to_zarr(path, mode="w-", encoding=encoding, consolidated=False)


def stored_spec(path: Path) -> dict:
    """The study a store was created for (its ``deployfx_study`` attribute); ValueError if the
    path is not a deployfx study store."""
    import zarr

    try:
        g = zarr.open_group(str(path), mode="r")
        return json.loads(g.attrs[_ATTR])
    except (KeyError, FileNotFoundError, ValueError, TypeError) as e:
        raise ValueError(f"{path} is not a deployfx study store (no {_ATTR!r} attribute: {e})") from None


def spec_difference(a: Any, b: Any, where: str = "") -> str:
    """The first key at which two study dicts differ, with both values ('' if equal)."""
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            sub = f"{where}.{k}" if where else k
            if k not in a or k not in b:
                return f"{sub} is {'only in the store' if k in a else 'only in this study'}"
            d = spec_difference(a[k], b[k], sub)
            if d:
                return d
        return ""
    if a != b:
        return f"{where}: the store has {str(a)[:120]}, this study {str(b)[:120]}"
    return ""


def read_design(path: Path) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """(the stored design by parameter, the status of every sample)."""
    import zarr

    g = zarr.open_group(str(path), mode="r")
    names = list(g.attrs["parameters"])
    return {k: np.asarray(g[k][:]) for k in names}, np.asarray(g["status"][:])


class Writer:
    """Buffers finished samples and writes them in batches (one write per touched chunk), at
    most every ``flush_s`` seconds, values first and ``status`` last."""

    def __init__(self, path: Path, outputs: Sequence[str], series: Sequence[str],
                 flush_s: float = 2.0):
        import zarr

        self._g = zarr.open_group(str(path), mode="r+")
        self._outputs, self._series = list(outputs), list(series)
        self._flush_s = flush_s
        self._buffer: list[tuple[int, dict]] = []
        self._last = _time.monotonic()

    def add(self, i: int, record: Mapping[str, Any]) -> None:
        self._buffer.append((int(i), dict(record)))
        if _time.monotonic() - self._last >= self._flush_s:
            self.flush()

    def flush(self) -> None:
        self._last = _time.monotonic()
        if not self._buffer:
            return
        self._buffer.sort(key=lambda item: item[0])
        idx = np.array([i for i, _ in self._buffer])
        recs = [r for _, r in self._buffer]
        nan = np.nan
        for k in self._outputs:
            self._g[k].oindex[idx] = np.array([r["outputs"].get(k, nan) for r in recs], dtype=float)
        for k in self._series:
            n_t = self._g[k].shape[1]
            rows = np.array([r["series"].get(k, np.full(n_t, nan)) for r in recs], dtype=float)
            self._g[k].oindex[idx, :] = rows
        self._g["error"].oindex[idx] = np.array([r["error"] for r in recs], dtype=object)
        self._g["status"].oindex[idx] = np.array([r["status"] for r in recs], dtype=np.int8)
        self._buffer.clear()
