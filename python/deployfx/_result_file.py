"""The result file (``Result.save``, ``deployfx.load``): one ``.npz`` archive holding the arrays as
they are (lossless), a JSON header (format, version, series order, units, metadata) and a last
entry with the SHA-256 of both; nothing is pickled. Written atomically (a failed save leaves the
previous file)."""
from __future__ import annotations

import hashlib
import json
from pathlib import Path
from typing import Mapping

import numpy as np

from . import _atomic

_FORMAT = "deployfx.Result"
_VERSION = 1
_HEADER = "deployfx_header"  # archive entry of the JSON header
_PREFIX = "series/"  # archive entries of the arrays; never collides with np.savez's parameters
_CHECKSUM = "deployfx_sha256"  # the last archive entry: SHA-256 of the header and the series


def write(path: Path, series: Mapping[str, np.ndarray], units: dict, metadata: dict) -> Path:
    """Write the series (in their order), units and JSON-ready metadata to ``path``; returns it."""
    header = json.dumps({"format": _FORMAT, "version": _VERSION, "series": list(series),
                         "units": units, "metadata": metadata, "checksum": "sha256"}, allow_nan=False)
    entries = {_PREFIX + name: a for name, a in series.items()}
    digest = _digest(header, series)
    with _atomic.atomic_open(path, "wb") as fh:
        np.savez(fh, **{_HEADER: np.array(header)}, **entries, **{_CHECKSUM: np.array(digest)})
    return path


def read(path) -> tuple[dict, dict, dict]:
    """(series, units, metadata) of a result file written by :func:`write`, arrays bit for bit.
    Refuses pickled content, and raises ValueError naming the file for one that is truncated,
    altered (its SHA-256 does not match) or not a result file."""
    # The file is opened here, not by np.load, which leaks its handle on a broken archive.
    with open(Path(path), "rb") as fh:
        # Whatever a damaged archive raises inside zipfile or numpy (BadZipFile, EOFError,
        # NotImplementedError for a garbled compression method, struct.error, ...) is the file's
        # fault: a ValueError naming it, with the cause chained.
        try:
            archive = np.load(fh, allow_pickle=False)
        except Exception as e:  # noqa: BLE001
            raise ValueError(f"{path} is not a readable deployfx result file: "
                             f"{type(e).__name__}: {e}") from e
        if not isinstance(archive, np.lib.npyio.NpzFile):
            raise ValueError(f"{path} is not a deployfx result file (a bare .npy array, not an "
                             "archive)")
        try:
            with archive:
                header, series = _read_archive(archive, path)
        except Exception as e:  # noqa: BLE001 - see above
            if isinstance(e, ValueError) and str(e).startswith(str(path)):
                raise
            raise ValueError(f"{path} is truncated or corrupted: {type(e).__name__}: {e}") from e
    return series, header["units"], header["metadata"]


def _read_archive(archive, path) -> tuple[dict, dict]:
    """The header and the series of an open result archive, checked against its checksum."""
    if _HEADER not in archive.files:
        raise ValueError(f"{path} is not a deployfx result file (no {_HEADER} entry)")
    text = str(archive[_HEADER])
    header = json.loads(text)
    if not isinstance(header, dict) or header.get("format") != _FORMAT or \
            not isinstance(header.get("version"), int):
        raise ValueError(f"{path} is not a deployfx result file (format "
                         f"{header.get('format') if isinstance(header, dict) else header!r})")
    if header["version"] > _VERSION:
        raise ValueError(f"{path} has result format version {header['version']}; this deployfx "
                         f"reads up to version {_VERSION}")
    names, units, metadata = header.get("series"), header.get("units"), header.get("metadata")
    if not (isinstance(names, list) and all(isinstance(n, str) for n in names)
            and isinstance(units, dict) and isinstance(metadata, dict)):
        raise ValueError(f"{path} has a malformed header (series, units, metadata)")
    missing = [name for name in names if _PREFIX + name not in archive.files]
    if missing:
        raise ValueError(f"{path} is missing the series {missing}")
    series = {name: archive[_PREFIX + name] for name in names}
    checksum = header.get("checksum")
    if checksum is not None:  # files written before the checksum have none
        if checksum != "sha256" or _CHECKSUM not in archive.files:
            raise ValueError(f"{path} is truncated or corrupted: its header announces a "
                             f"{checksum!r} checksum and the {_CHECKSUM} entry is missing")
        if str(archive[_CHECKSUM]) != _digest(text, series):
            raise ValueError(f"{path} is corrupted: its content does not match its SHA-256 "
                             f"checksum (altered after it was saved)")
    return header, series


def _digest(header: str, series: Mapping[str, np.ndarray]) -> str:
    """SHA-256 (hex) of the header text and of every series' name, dtype, shape and bytes."""
    h = hashlib.sha256(header.encode("utf-8"))
    for name, a in series.items():
        h.update(json.dumps([name, a.dtype.str, list(a.shape)]).encode("utf-8"))
        h.update(np.ascontiguousarray(a).view(np.uint8).reshape(-1).data if a.size else b"")
    return h.hexdigest()
