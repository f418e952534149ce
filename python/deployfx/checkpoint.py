"""Checkpoints of a run: everything the run loop carries from one output instant to the next,
so that a run resumed from one is bit-identical to the uninterrupted run.

``Model.simulate(..., checkpoint_at=[t1, ...])`` takes a :class:`Checkpoint` at the end of each
listed output instant (``result.checkpoints``); ``Model.resume(checkpoint, t_end)`` (or
``simulate(..., resume=checkpoint)``) goes on from it with the checkpointed run's dt, scheme,
tolerance and Newton tolerance. A checkpoint holds the state (q, v), the integrator's accelerations and its predictor's
history, the step control's next sizes, the lock histories (contact modes, impact trackers) and
the impact records so far, the energy check's baseline, and the model's fingerprint; and the
integrator's Newton matrix as last built or refreshed, factorized afresh on resuming, so that the
modified Newton iteration goes on with the very matrix the uninterrupted run reuses. Taking
checkpoints changes nothing in a run.

File format (:meth:`Checkpoint.save`): the line ``deployfx-checkpoint 1``, an 8-byte
little-endian length and a JSON header (the run's settings, the model's fingerprint), an 8-byte
length and the engine's binary image, then the SHA-256 of everything before it. Written
atomically; :func:`load_checkpoint` refuses a truncated or altered file. The engine's image holds
numbers in the writing machine's representation: resume on the same kind of machine.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import os
import struct
from pathlib import Path
from typing import Optional, Union

import numpy as np

from . import _atomic, _core, integrators

_MAGIC = b"deployfx-checkpoint 1\n"


def _scheme_spec(scheme) -> dict:
    return {"kind": type(scheme).__name__, **dataclasses.asdict(scheme)}


def _scheme_from(spec: dict):
    fields = dict(spec)
    kind = fields.pop("kind")
    if kind not in ("Newmark", "HHT", "GeneralizedAlpha"):
        raise ValueError(f"checkpoint: unknown scheme {kind!r}")
    return getattr(integrators, kind)(**fields)


def model_fingerprint(model) -> str:
    """SHA-256 of a compiled model: its description, sizes, stowed configuration, and its residual
    and Newton matrix at a probe state there (masses, stiffnesses, springs, locks)."""
    core = model.core
    q = np.asarray(core.initial_positions(), dtype=float)
    nv = core.num_velocities
    v = 0.01 * (np.arange(nv) + 1.0) / max(nv, 1)
    a = np.zeros(nv)
    h = hashlib.sha256()
    h.update(json.dumps(model.description, sort_keys=True, default=str).encode())
    h.update(struct.pack("<4q", core.num_positions, nv, core.num_hinges, int(core.base_free)))
    for x in (q, core.residual(q, v, a, 0.0), core.newton_matrix(q, v, a, 0.0, 1.0, 0.1, 0.01)):
        h.update(np.ascontiguousarray(x, dtype="<f8").tobytes())
    return h.hexdigest()


class Checkpoint:
    """A run at one output instant (see the module docstring). ``t`` (s), ``q``, ``v`` (the
    state), ``impacts`` (the impact records so far, the last possibly still open), ``dt``,
    ``scheme``, ``tolerance``, ``newton_tolerance`` (the run's settings, which a resumed run
    takes)."""

    def __init__(self, core: "_core.Checkpoint", *, model_id: str, dt: float, scheme, tolerance: float,
                 newton_tolerance: float, energy0: float, kinetic_peak: float):
        self._core = core
        self.model_id = model_id
        self.dt = float(dt)
        self.scheme = scheme
        self.tolerance = float(tolerance)
        self.newton_tolerance = float(newton_tolerance)
        self.energy0 = float(energy0)
        self.kinetic_peak = float(kinetic_peak)

    @property
    def t(self) -> float:
        """The instant, s."""
        return self._core.t

    @property
    def q(self) -> np.ndarray:
        """The positions at ``t`` (Model.layout)."""
        return self._core.q

    @property
    def v(self) -> np.ndarray:
        """The velocities at ``t``."""
        return self._core.v

    @property
    def impacts(self) -> dict:
        """The impact records so far as a dict of arrays (the last may still be open)."""
        return self._core.impacts

    def __repr__(self) -> str:
        return f"Checkpoint(t={self.t:.6g} s, dt={self.dt:g} s, scheme={self.scheme!r}, tolerance={self.tolerance:g})"

    def _header(self) -> dict:
        return {"model": self.model_id, "t": self.t, "dt": self.dt, "scheme": _scheme_spec(self.scheme),
                "tolerance": self.tolerance, "newton_tolerance": self.newton_tolerance,
                "energy0": self.energy0, "kinetic_peak": self.kinetic_peak}

    def to_bytes(self) -> bytes:
        """The file's content (see :meth:`save`)."""
        header = json.dumps(self._header(), allow_nan=False).encode()
        body = self._core.to_bytes()
        data = _MAGIC + struct.pack("<Q", len(header)) + header + struct.pack("<Q", len(body)) + body
        return data + hashlib.sha256(data).digest()

    @classmethod
    def from_bytes(cls, data: bytes) -> "Checkpoint":
        """The inverse of :meth:`to_bytes`; ValueError for anything else (a truncated or altered
        image included)."""
        if not isinstance(data, (bytes, bytearray)):
            raise TypeError(f"data must be bytes, got {type(data).__name__}")
        data = bytes(data)
        if not data.startswith(_MAGIC):
            raise ValueError("not a deployfx checkpoint (or of another format version)")
        if len(data) < len(_MAGIC) + 16 + 32 or hashlib.sha256(data[:-32]).digest() != data[-32:]:
            raise ValueError("the checkpoint is truncated or corrupt (its SHA-256 does not match)")
        at = len(_MAGIC)
        (n,) = struct.unpack_from("<Q", data, at)
        header = json.loads(data[at + 8: at + 8 + n].decode())
        at += 8 + n
        (m,) = struct.unpack_from("<Q", data, at)
        body = data[at + 8: at + 8 + m]
        if at + 8 + m != len(data) - 32:
            raise ValueError("the checkpoint is truncated or corrupt (its lengths do not add up)")
        return cls(_core.Checkpoint.from_bytes(body), model_id=header["model"], dt=header["dt"],
                   scheme=_scheme_from(header["scheme"]), tolerance=header["tolerance"],
                   # files of 0.x before the knob: every run had the engine's default
                   newton_tolerance=header.get("newton_tolerance", _core.NEWTON_TOLERANCE_DEFAULT),
                   energy0=header["energy0"], kinetic_peak=header["kinetic_peak"])

    def save(self, path: Union[str, os.PathLike]) -> Path:
        """Write the checkpoint to ``path`` atomically (the previous file survives a failed save);
        returns the path."""
        path = Path(path)
        _atomic.write_bytes(path, self.to_bytes())
        return path

    def __reduce__(self):
        return (Checkpoint.from_bytes, (self.to_bytes(),))


def check_resume(model, resume, *, dt: float, scheme, tolerance: float, newton_tolerance: float, t_end: float,
                 q0, v0) -> None:
    """ValueError or TypeError unless ``resume`` can continue a run of ``model`` with these settings
    (the checkpointed run's), from its time to ``t_end`` (s), taking no q0, v0."""
    if not isinstance(resume, Checkpoint):
        raise TypeError(f"resume must be a deployfx Checkpoint, got {type(resume).__name__}")
    if q0 is not None or v0 is not None:
        raise ValueError("resume: q0 and v0 are the checkpoint's; do not pass them")
    if resume.model_id != model.fingerprint:
        raise ValueError("resume: the checkpoint was taken on another model (its fingerprint differs)")
    if dt != resume.dt:
        raise ValueError(f"resume: dt = {dt:g} s, but the checkpoint's run had dt = {resume.dt:g} s")
    if _scheme_spec(scheme) != _scheme_spec(resume.scheme):
        raise ValueError(f"resume: scheme = {scheme!r}, but the checkpoint's run had {resume.scheme!r}")
    if tolerance != resume.tolerance:
        raise ValueError(f"resume: tolerance = {tolerance or None}, but the checkpoint's run had "
                         f"{resume.tolerance or None}")
    if newton_tolerance != resume.newton_tolerance:
        raise ValueError(f"resume: newton_tolerance = {newton_tolerance:g}, but the checkpoint's run had "
                         f"{resume.newton_tolerance:g}")
    if not t_end >= resume.t:
        raise ValueError(f"t_end = {t_end:g} s is out of range: must be >= the checkpoint's t = {resume.t:g} s")
    resume._core.check(model.core)


def from_run(model, raw: dict, *, dt: float, scheme, tolerance: float, newton_tolerance: float, baseline) -> tuple:
    """The checkpoints the engine took in a run of ``model`` (``raw``: its dict), with the run's
    settings and the energy check's baseline up to each (``baseline``: a resumed run's)."""
    if not raw["checkpoints"]:
        return ()
    E = raw["kinetic_energy"] + raw["potential_energy"]
    out = []
    for c in raw["checkpoints"]:
        i = int(np.flatnonzero(raw["t"] == c.t)[-1])
        peak = float(np.max(raw["kinetic_energy"][: i + 1]))
        e0, peak = (float(E[0]), peak) if baseline is None else (baseline[0], max(baseline[1], peak))
        out.append(Checkpoint(c, model_id=model.fingerprint, dt=dt, scheme=scheme, tolerance=tolerance,
                              newton_tolerance=newton_tolerance, energy0=e0, kinetic_peak=peak))
    return tuple(out)


def load_checkpoint(path: Union[str, os.PathLike]) -> Checkpoint:
    """A checkpoint written by :meth:`Checkpoint.save`; ValueError naming the file if it is not
    one, or is truncated or altered."""
    data = Path(path).read_bytes()
    try:
        return Checkpoint.from_bytes(data)
    except ValueError as e:
        raise ValueError(f"{path}: {e}") from None


def _steps(checkpoint_at, t_end: float, dt: float, after: Optional["Checkpoint"] = None) -> list:
    """The output steps k (t = k dt, the last one t_end) of the times ``checkpoint_at``; ValueError
    naming the parameter for a time off the output grid or outside (0, t_end] (after the resumed
    checkpoint's time for a resumed run)."""
    if checkpoint_at is None:
        return []
    if isinstance(checkpoint_at, (str, bytes)) or not np.iterable(checkpoint_at):
        raise TypeError(f"checkpoint_at must be a sequence of times (s), got {type(checkpoint_at).__name__}")
    last = int(np.ceil(t_end / dt - 1e-9))
    steps = set()
    for t in checkpoint_at:
        if isinstance(t, bool) or not isinstance(t, (int, float, np.integer, np.floating)):
            raise TypeError(f"checkpoint_at: {t!r} is not a time (s)")
        t = float(t)
        start = 0.0 if after is None else after.t
        if not (np.isfinite(t) and start < t <= t_end * (1 + 1e-12)):
            raise ValueError(f"checkpoint_at: t = {t} s is out of range: must be in ({start:g}, t_end = {t_end:g}] s")
        if abs(t - t_end) <= 1e-9 * max(1.0, t_end):
            k = last
        else:
            k = int(round(t / dt))
            if not abs(k * dt - t) <= 1e-9 * max(1.0, abs(t)):
                raise ValueError(f"checkpoint_at: t = {t} s is not an output time (a multiple of dt = {dt:g} s, "
                                 f"or t_end)")
        steps.add(k)
    return sorted(steps)
