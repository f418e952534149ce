"""The words figures and animations share (deployfx.plot, deployfx.animation): axis labels
"quantity (unit)" and the caption line that says how the runs were made (Result.settings)."""
from __future__ import annotations

import json
from typing import Any, Sequence

#: Time and the deployment angle, as the plots' axes and the animation's frames name them.
TIME = "time"
DEPLOYMENT_ANGLE = "deployment angle"


#: Characters in a caption line (x-small text across a 6.4 in figure).
WIDTH = 90


def label(quantity: str, unit: str) -> str:
    """An axis label: ``quantity (unit)``, or the quantity alone without a unit."""
    return f"{quantity} ({unit})" if unit else quantity


def _text(value: Any) -> str:
    return value if isinstance(value, str) else json.dumps(value, separators=(",", ":"))


def _mesh(mesh: Any) -> Any:
    """Per-hinge ``{"nodes", "quads"}`` as "150 quads" (hinges without a panel left out)."""
    if not isinstance(mesh, list):
        return mesh
    quads = [str(m["quads"]) for m in mesh if isinstance(m, dict) and "quads" in m]
    return " + ".join(quads) + " quads" if quads else None


def caption(results: Sequence) -> str:
    """One line of the runs' settings (:meth:`deployfx.Result.settings`): scene, mesh, dt,
    scheme, tolerance, deployfx version and the first run's start time; a setting the runs differ in lists each
    run's value (``a / b``); lines of at most :data:`WIDTH` characters; '' when no run has
    settings (results made by hand)."""
    settings = [r.settings() for r in results]
    engine = any(s["dt"] is not None for s in settings)
    fields = [("scene", lambda v: f"scene {_text(v)}"), ("mesh", lambda v: f"mesh {v}")]
    if engine:
        fields += [("dt", lambda v: f"dt {v:g} s" if isinstance(v, (int, float)) else f"dt {v}"),
                   ("scheme", _text),
                   ("tolerance", lambda v: "fixed steps" if v is None else f"tolerance {v:g}")]
    fields += [("deployfx_version", lambda v: f"deployfx {v}"),
               ("run_started_utc", lambda v: f"run {v[:16].replace('T', ' ')} UTC")]
    parts = []
    for key, fmt in fields:
        values = [_mesh(s[key]) if key == "mesh" else s[key] for s in settings]
        if key == "run_started_utc":  # the first run's start (ISO 8601 sorts as time)
            values = [min((v for v in values if v is not None), default=None)]
        if key != "tolerance" and all(v is None for v in values):
            continue
        shown = list(dict.fromkeys(fmt(v) for v in values))
        parts.append(" / ".join(shown))
    lines = [""]
    for part in parts:  # lines of at most WIDTH characters, broken between settings
        if lines[-1] and len(lines[-1]) + 3 + len(part) > WIDTH:
            lines.append("")
        lines[-1] += (" · " if lines[-1] else "") + part
    return "\n".join(lines)
