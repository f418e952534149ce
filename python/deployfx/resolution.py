"""Does a step resolve the scene? The periods a run must follow, and the step that follows them.

The periods (:func:`periods`), estimated at the stowed configuration:

- the rigid bodies swinging on the hinge springs: the modes of the base and the undriven hinge
  angles with every panel held undeformed (the model's mass and stiffness matrices restricted to
  those coordinates; the paper's scene: 9.9 s, the spring-panel oscillator);
- each deforming panel's clamped vibration modes up to the number its fidelity keeps: a reduced
  panel the ``modes`` of its Ritz basis (their Ritz values; on the quadratic manifold those that
  are its bending coordinates, the in-plane ones following them), a full finite-element panel
  the same count of its lowest clamped modes (``Scene.set_appendage(..., modes=)``, default 10), so that a
  scene asks the same of the step at either fidelity. Higher modes of a full panel (thin-plate
  rotations, drilling) are left to the scheme's numerical damping, which is how the engine
  treats them.

A step resolves the scene when it gives each panel mode at least :data:`STEPS_PER_PERIOD` steps a
period and each swing at least :data:`STEPS_PER_SWING`. Why 4 steps a mode's period: generalized-alpha (rho_inf = 0.8, the default) follows a mode sampled 4
times a period with its period 19 % too long and 0.9 % of its amplitude lost a period; with 3
steps the period is 31 % long, with 2 (the sampling limit) 59 %: below 4 the mode is not
followed, only damped or aliased. The limit applies to the highest mode kept, so the modes that
carry the response (the first few) get many more steps (the paper's first mode, 0.80 Hz: 125 a
period at dt = 0.01 s). The swing is the deployment itself, so it is asked for accuracy, not
only to be followed: the scheme lengthens a period sampled N times by about (2 pi / N)^2 / 12
(the trapezoidal rule's period error, which generalized-alpha shares to second order), 0.8 % at
N = 20; the paper's swing (9.9 s) at dt = 1 s (10 steps) is 3 % long, and its first lock comes
70 ms late.

Lock impacts need no step of their own: the engine shortens its steps inside each contact to
resolve it, whatever ``dt`` (``Result.metadata["contact_steps"]`` counts them; see
docs/engine-design.md, "Contacts resolved at the default step").
"""
from __future__ import annotations

import math
from typing import Any, Optional

import numpy as np

from ._checks import as_float

__all__ = ["STEPS_PER_PERIOD", "STEPS_PER_SWING", "periods", "shortest_period", "step_warning", "suggested_dt"]

#: The fewest steps a period at which a panel mode is still followed (module docstring).
STEPS_PER_PERIOD = 4
#: The fewest steps a period of a swing on the hinge springs (the deployment): period error
#: below about 1 % (module docstring).
STEPS_PER_SWING = 20


def _model(model: Any):
    from .animation import _model_of

    return _model_of(model)


def _swing_periods(m) -> list[dict]:
    """The rigid bodies' modes on the hinge springs: the base (free) and the undriven hinge
    angles, panels held undeformed, linearized at the stowed configuration."""
    rows = list(range(6)) if m.base_free else []
    hinges = [k for k in range(m.num_hinges) if m.layout(k)["iv_theta"] >= 0]
    rows += [m.layout(k)["iv_theta"] for k in hinges]
    if not hinges:
        return []
    q0, zero = m.initial_positions(), np.zeros(m.num_velocities)
    ix = np.ix_(rows, rows)
    M = m.newton_matrix(q0, zero, zero, 0.0, 1.0, 0.0, 0.0)[ix]
    K = m.newton_matrix(q0, zero, zero, 0.0, 0.0, 0.0, 1.0)[ix]
    import scipy.linalg

    w2, X = scipy.linalg.eigh(0.5 * (K + K.T), 0.5 * (M + M.T))
    out = []
    scale = max(float(np.abs(w2).max()), np.finfo(float).tiny)
    for j in np.flatnonzero(w2 > 1e-9 * scale):
        x = np.abs(X[len(rows) - len(hinges):, j])  # the mode's hinge angles
        k = hinges[int(np.argmax(x))]
        out.append({"what": f"hinge {k}'s swing on its spring (rigid bodies)", "hinge": k,
                    "period_s": 2 * math.pi / math.sqrt(w2[j]), "steps": STEPS_PER_SWING})
    return out


def _panel_periods(m) -> list[dict]:
    """Each deforming panel's highest clamped mode among those its fidelity keeps."""
    out = []
    for k, L in enumerate(m.links):
        if not m.deforming[k]:
            continue
        a = L.appendage
        if a.fidelity.reduced:
            info = m.basis_info(k)
            n = int(info["modes"])
            if a.fidelity.slaved:  # only the modes that are elastic coordinates (bending) move freely
                n = _highest_free_mode(m, k, n)
                if n == 0:
                    continue
            w2 = float(np.asarray(info["omega2"])[n - 1])  # the modes keep their own Ritz values
            what = f"hinge {k}'s panel, mode {n} of its reduced basis"
        else:
            free = a.shell.num_dofs - len(set(int(i) for i in a.fixed_dofs))
            n = min(int(a.modes), free - 1)
            f, _ = a.shell.modes(n, a.fixed_dofs)
            w2 = float((2 * math.pi * f[-1]) ** 2)
            what = f"hinge {k}'s panel, clamped mode {n}"
        if w2 > 0:
            T = 2 * math.pi / math.sqrt(w2)
            out.append({"what": f"{what} ({1 / T:.4g} Hz)", "hinge": k, "period_s": T, "steps": STEPS_PER_PERIOD})
    return out


def _highest_free_mode(m, k: int, n: int) -> int:
    """The last of the first ``n`` basis vectors of hinge k's panel that is one of its elastic
    coordinates (1-based; 0: none), where the fidelity slaves the others to them: at the
    undeformed panel the map's tangent G (Model.panel_tangent) has a nonzero row exactly for
    those (on the quadratic manifold g(q) = [q; C(q, q)/2], so G(0) = [I; 0])."""
    G0 = m.panel_tangent(m.initial_positions(), k)
    free = np.flatnonzero(np.abs(G0[:n]).max(axis=1) > 0)
    return int(free[-1]) + 1 if free.size else 0


def periods(model: Any) -> list[dict]:
    """The periods a run of ``model`` (a :class:`~deployfx.Model`, or a ready scene with a
    ``.model``) must follow (the module docstring says which), longest first: dicts with
    ``what`` (words), ``hinge``, ``period_s`` (s) and ``steps``, the fewest steps a period it
    needs (:data:`STEPS_PER_SWING` or :data:`STEPS_PER_PERIOD`)."""
    m = _model(model)
    return sorted(_swing_periods(m) + _panel_periods(m), key=lambda p: -p["period_s"])


def shortest_period(model: Any) -> Optional[dict]:
    """The shortest of :func:`periods` (None if the scene has none: no spring, no deforming
    panel)."""
    ps = periods(model)
    return ps[-1] if ps else None


def suggested_dt(period_s: float, steps: int = STEPS_PER_PERIOD) -> float:
    """The largest step of the form 1, 2 or 5 x 10^k (s) that gives ``period_s`` at least
    ``steps`` steps."""
    T = as_float("period_s", period_s)
    if not (math.isfinite(T) and T > 0):
        raise ValueError(f"period_s = {T} is out of range: must be > 0 (s)")
    if isinstance(steps, bool) or not isinstance(steps, int) or steps < 1:
        raise ValueError(f"steps = {steps!r} is out of range: must be an integer >= 1")
    limit = T / steps
    e = math.floor(math.log10(limit))
    for mantissa in (5.0, 2.0, 1.0):
        dt = mantissa * 10.0 ** e
        if dt <= limit * (1 + 1e-12):
            return float(f"{dt:.1g}")
    return float(f"{10.0 ** (e - 1) * 5:.1g}")  # pragma: no cover - 1 x 10^e <= limit always


def step_warning(model: Any, dt: float) -> Optional[str]:
    """A message if the step ``dt`` (s) gives one of the scene's :func:`periods` fewer steps
    than it needs (a swing :data:`STEPS_PER_SWING`, a panel mode :data:`STEPS_PER_PERIOD`),
    naming the most demanding, its period and a step that resolves every one; None if ``dt``
    resolves the scene."""
    dt = as_float("dt", dt)
    if not (math.isfinite(dt) and dt > 0):
        raise ValueError(f"dt = {dt} is out of range: must be > 0 (s)")
    ps = periods(model)
    if not ps:
        return None
    p = min(ps, key=lambda p: p["period_s"] / p["steps"])
    T, steps = p["period_s"], p["steps"]
    if dt <= T / steps:
        return None
    why = ("generalized-alpha no longer follows it" if steps == STEPS_PER_PERIOD else
           f"its period comes out about {100 * (2 * math.pi * dt / T) ** 2 / 12:.2g} % long")
    return (f"dt = {dt:g} s does not resolve the scene: {p['what']} has a period of {T:.4g} s, "
            f"{T / dt:.3g} steps of dt (fewer than {steps}: {why}); use dt <= {suggested_dt(T, steps):g} s")
