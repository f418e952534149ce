"""Scene files: a :class:`~deployfx.scene.Scene` written to and read from plain text (JSON or TOML),
so that a study can be shared and rebuilt exactly.

``save_scene(scene, "study.toml")`` / ``load_scene("study.toml")`` (or ``.json``);
:func:`scene_to_dict` / :func:`scene_from_dict` give the same content as a plain dict. Floats are
written with Python's shortest round-trip representation, so a loaded scene compiles to a model
that gives bit-identical results. Every scene the builder expresses is written: one hinge, a
chain, or a tree of hinges (two wings), each with its spring, damper, fitting, prescribed angle,
lock, panel and rigid parts.

Schema ``deployfx.scene`` version 4 (written; versions 1 to 4 are read). SI units throughout;
every dimensional key ends with its unit (``_m``, ``_kg``, ``_kg_m2``, ``_N_m``, ``_per_s``, ...;
``_n`` in ``K_N_per_m_n`` is the law's exponent: N/m^n); unsuffixed numbers are dimensionless.
Optional parts are simply left out (TOML has no null)::

    schema = "deployfx.scene"            # required
    version = 4                          # required: the schema version
    units = "SI ..."                     # informative only
    content_sha256 = "..."               # written by save_scene: SHA-256 of the rest in
                                         #   canonical JSON; load_scene refuses a file that does
                                         #   not match (truncated or changed); optional

    [base]                               # Scene.set_base
    free = true                          # false: fixed to the ground
    mass_kg = 3000.0
    inertia_kg_m2 = [[...], [...], [...]]    # 3 x 3, about the centre of mass, B axes
    com_m = [0.0, 0.0, 0.0]              # centre of mass in B

    [[parts]]                            # Scene.add_rigid_part(body="base"), zero or more (list)
    mass_kg, inertia_kg_m2 (3 x 3, B axes), com_m (3, B)

    [[hinges]]                           # one or more: hinges[k] is hinge k
    parent = "base"                      # "base", or the index of an earlier hinge (a tree)
    point_m = [...]                      # 3, a point of the axis in the parent's frame P
    axis = [...]                         # 3, unit vector in P
    R_PC0 = [[...], [...], [...]]        # 3 x 3 rotation: the body frame's axes at theta = 0 in P
    tau0_N_m, k_theta_N_m_per_rad, c_theta_N_m_s_per_rad
    fitting = {mass_kg, com_m (3, C_k), inertia_kg_m2 (3 x 3, C_k axes)}
    stowed_angle_deg = 90.0              # optional: the deployment angle reported at theta = 0
    spin_up = {omega_s_rad_per_s, t_s_s}  # optional: a prescribed hinge angle

    [[hinges.parts]]                     # Scene.add_rigid_part(body=k), zero or more (list):
    mass_kg, inertia_kg_m2, com_m        #   rigid parts on this hinge's body, in C_k (a yoke)

    [hinges.appendage]                   # optional: Scene.set_appendage(hinge=k)
    fidelity = "linear"                  # "rigid", "linear", "nonlinear", "reduced-linear",
                                         #   "reduced-nonlinear" or "reduced-manifold"
    fixed_dofs = [...]                   # dof indices (6 per node) clamped to C_k
    alpha_M_per_s, beta_K_s              # Rayleigh damping
    modes = 10                           # reduced fidelities: clamped modes kept
    derivative_modes = 3                 # optional (left out: min(modes, 3))
    derivative_partners = 1              # optional (left out: 1)
    strengths = [{Xt_Pa, Xc_Pa, Yt_Pa, Yc_Pa, S12_Pa, F12_star, S13_Pa, S23_Pa}]
                                         # optional: the plies' allowables (deployfx.Strengths),
                                         #   one for all plies or one per ply; S13, S23 optional
    [hinges.appendage.shell]             # the ShellModel
    nodes_m = [[x, y, z], ...]           # (n, 3), in C_k
    quads = [[i, j, k, l], ...]          # (e, 4), 0-based node indices
    ref_axis = [1.0, 0.0, 0.0]           # the laminate's 0-degree direction
    [[hinges.appendage.shell.plies]]     # bottom first
    thickness_m, angle_deg
    material = {type = "orthotropic", E1_Pa, E2_Pa, G12_Pa, G13_Pa, G23_Pa, nu12, rho_kg_per_m3}
            or {type = "isotropic", E_Pa, nu, rho_kg_per_m3}

    [hinges.lock]                        # optional: Scene.set_lock(hinge=k)
    theta_lock_rad, pin_radius_m, clearance_m
    law = {kind, K_N_per_m_n, n, D_N_s_per_m, e}     # deployfx.contact.ContactLaw
    friction = {mu, v_reg_m_per_s}                    # deployfx.contact.Friction

    [hinges.groove]                      # optional, instead of a lock: Scene.set_groove(hinge=k)
    pin_distance_m, pin_angle_rad, pin_radius_m       # deployfx.groove.PinGroove
    law = {...}, friction = {...}                     # as the lock's
    latch = {stop_m, travel_m, preload_N, stiffness_N_per_m, toward_axis}   # optional
    play_deg                                          # optional: the free play once held
    [[hinges.groove.profile]]            # the profile's elements in order, in P's hinge plane:
    kind = "line", start_m = [x, y], end_m = [x, y]                 # deployfx.groove.Line
    kind = "arc", start_m, end_m, radius_m                          #   Arc
    kind = "arc_about", start_m, end_m, centre_m, ccw = true        #   ArcAbout

In TOML, a ``[hinges.appendage]``, ``[[hinges.parts]]``, ``[hinges.lock]``, ... header belongs to
the hinge of the last ``[[hinges]]`` header above it (in JSON: ``"hinges": [{..., "parts": [...],
"appendage": {...}, "lock": {...}}, ...]``).

Older versions (read only): version 3 is version 4 without grooves; version 2 is a serial chain (hinge k's parent is k - 1), with
``R_PE0`` for ``R_PC0``, a spin-up on hinge 0 only, no ``stowed_angle_deg``, and the appendage's
``modes`` and ``derivative_modes`` under ``options``; version 1 has one hinge in top-level tables
``[hinge]`` (``R_BE0``), ``[appendage]`` and ``[lock]``.

Loading checks the file: an unknown schema or version, a missing or unknown key, a value of the
wrong type or shape raises ``ValueError`` naming the key (e.g.
``hinges[1].appendage.shell.nodes_m``); the builder then checks the values themselves, and its
errors are prefixed with the file's table when they do not name it (``hinges[0].lock: lock.clearance
= ...``).
"""
from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path
from typing import Any, Union

import numpy as np

from . import _atomic
from ._scene_read import scene_from_dict
from ._scene_schema import _ISOTROPIC, _MATERIAL_UNITS, _ORTHOTROPIC, _UNITS, SCHEMA, VERSION, VERSIONS_READ
from .materials import Isotropic, Orthotropic
from .scene import Scene
from .specs import Appendage, Link, Lock, RigidPart

__all__ = ["SCHEMA", "VERSION", "VERSIONS_READ", "load_scene", "save_scene", "scene_from_dict", "scene_to_dict"]

PathLike = Union[str, os.PathLike]

# ------------------------------------------------------------------------------------------------
# Scene -> dict

def _floats(a) -> Any:
    """A float, or nested lists of floats, from an array-like (plain Python types)."""
    return np.asarray(a, dtype=float).tolist()


def _part(p: RigidPart) -> dict:
    return {"mass_kg": float(p.mass), "com_m": _floats(p.com), "inertia_kg_m2": _floats(p.inertia)}


def _material(m) -> dict:
    if isinstance(m, Isotropic):
        return {"type": "isotropic",
                **{_MATERIAL_UNITS[k]: float(getattr(m, k)) for k in _ISOTROPIC}}
    if isinstance(m, Orthotropic):
        return {"type": "orthotropic",
                **{_MATERIAL_UNITS[k]: float(getattr(m, k)) for k in _ORTHOTROPIC}}
    raise TypeError(f"ply material must be deployfx.Isotropic or deployfx.Orthotropic, "
                    f"got {type(m).__name__}")


def _write_appendage(a: Appendage) -> dict:
    shell = a.shell
    plies = [{"thickness_m": float(p.thickness), "angle_deg": float(p.angle_deg),
              "material": _material(p.material)} for p in shell.laminate.plies]
    out = {"fidelity": a.fidelity.value, "fixed_dofs": [int(i) for i in a.fixed_dofs],
           "alpha_M_per_s": float(a.alpha_M), "beta_K_s": float(a.beta_K), "modes": int(a.modes)}
    if a.derivative_modes is not None:
        out["derivative_modes"] = int(a.derivative_modes)
    if a.derivative_partners is not None:
        out["derivative_partners"] = int(a.derivative_partners)
    if a.strengths is not None:
        out["strengths"] = [{**{f"{k}_Pa": float(getattr(s, k)) for k in ("Xt", "Xc", "Yt", "Yc", "S12")},
                             "F12_star": float(s.F12_star),
                             **{f"{k}_Pa": float(getattr(s, k)) for k in ("S13", "S23") if getattr(s, k) is not None}}
                            for s in a.strengths]
    out["shell"] = {"nodes_m": _floats(shell.nodes), "quads": np.asarray(shell.quads, dtype=int).tolist(),
                    "ref_axis": _floats(getattr(shell, "ref_axis", (1.0, 0.0, 0.0))), "plies": plies}
    return out


def _write_law(law) -> dict:
    return {"kind": law.kind, "K_N_per_m_n": float(law.K), "n": float(law.n), "D_N_s_per_m": float(law.D),
            "e": float(law.e)}


def _write_friction(fr) -> dict:
    return {"mu": float(fr.mu), "v_reg_m_per_s": float(fr.v_reg)}


def _write_lock(L: Lock) -> dict:
    return {"theta_lock_rad": float(L.theta_lock), "pin_radius_m": float(L.pin_radius),
            "clearance_m": float(L.clearance), "law": _write_law(L.law), "friction": _write_friction(L.friction)}


def _write_groove(g) -> dict:
    """A pin-groove lock (deployfx.groove.PinGroove): its profile's elements in order, the pin,
    the law, the friction and the latch spring."""
    from .groove import ArcAbout, Line

    elements = []
    for e in g.profile.elements:
        if isinstance(e, Line):
            elements.append({"kind": "line", "start_m": _floats(e.start), "end_m": _floats(e.end)})
        elif isinstance(e, ArcAbout):
            elements.append({"kind": "arc_about", "start_m": _floats(e.start), "end_m": _floats(e.end),
                             "centre_m": _floats(e.centre), "ccw": bool(e.ccw)})
        else:
            elements.append({"kind": "arc", "start_m": _floats(e.start), "end_m": _floats(e.end),
                             "radius_m": float(e.radius)})
    out = {"profile": elements, "pin_distance_m": float(g.pin_distance), "pin_angle_rad": float(g.pin_angle),
           "pin_radius_m": float(g.pin_radius), "law": _write_law(g.law), "friction": _write_friction(g.friction)}
    if g.latch is not None:
        L = g.latch
        out["latch"] = {"stop_m": float(L.stop), "travel_m": float(L.travel), "preload_N": float(L.preload),
                        "stiffness_N_per_m": float(L.stiffness), "toward_axis": bool(L.toward_axis)}
    if g.play_deg is not None:
        out["play_deg"] = float(g.play_deg)
    return out


def _write_hinge(link: Link) -> dict:
    """One entry of the scene's hinge list (its hinge, rigid parts, appendage and lock)."""
    h = link.hinge
    hinge = {"parent": h.parent if isinstance(h.parent, str) else int(h.parent),
             "point_m": _floats(h.point), "axis": _floats(h.axis), "R_PC0": _floats(h.R_PC0),
             "tau0_N_m": float(h.tau0), "k_theta_N_m_per_rad": float(h.k_theta),
             "c_theta_N_m_s_per_rad": float(h.c_theta), "fitting": _part(h.fitting),
             "stowed_angle_deg": float(h.stowed_angle_deg)}
    if h.spin_up is not None:
        hinge["spin_up"] = {"omega_s_rad_per_s": float(h.spin_up.omega_s), "t_s_s": float(h.spin_up.t_s)}
    hinge["parts"] = [_part(p) for p in link.parts]
    if link.appendage is not None:
        hinge["appendage"] = _write_appendage(link.appendage)
    if isinstance(link.lock, Lock):
        hinge["lock"] = _write_lock(link.lock)
    elif link.lock is not None:
        hinge["groove"] = _write_groove(link.lock)
    return hinge


def scene_to_dict(scene: Scene) -> dict:
    """The scene as a plain dict of the schema above (version 3; str keys; bool, int, float, str,
    lists, dicts; no None), ready for JSON or TOML. ``scene``: a :class:`Scene`, or a ready scene
    keeping one as ``.scene`` (``scenes.paper2016(...)``). Raises TypeError for anything else and
    ValueError for a scene without a base or a hinge."""
    if not isinstance(scene, Scene) and isinstance(getattr(scene, "scene", None), Scene):
        scene = scene.scene
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a deployfx.Scene, got {type(scene).__name__}")
    if scene.base is None:
        raise ValueError("the scene has no base: call set_base() first")
    if scene.num_hinges == 0:
        raise ValueError("the scene has no hinge: call set_hinge() or add_hinge() first")
    return {"schema": SCHEMA, "version": VERSION, "units": _UNITS,
            "base": {"free": bool(scene.base.free), **_part(scene.base.part)},
            "parts": [_part(p) for p in scene.base_parts],
            "hinges": [_write_hinge(link) for link in scene.links]}


# ------------------------------------------------------------------------------------------------
# Files

def _format(path: PathLike) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in (".json", ".toml"):
        raise ValueError(f"path = {str(path)!r} must end in .json or .toml (the file format)")
    return suffix[1:]


def _json(value: Any, indent: str = "") -> str:
    """JSON with one line per innermost list of numbers (a mesh stays readable)."""
    inner = indent + "  "
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = (f"{inner}{json.dumps(k)}: {_json(v, inner)}" for k, v in value.items())
        return "{\n" + ",\n".join(items) + "\n" + indent + "}"
    if isinstance(value, list) and any(isinstance(v, (list, dict)) for v in value):
        return "[\n" + ",\n".join(inner + _json(v, inner) for v in value) + "\n" + indent + "]"
    return json.dumps(value, allow_nan=False)


_CHECK_KEY = "content_sha256"


def _content_digest(d: Mapping[str, Any]) -> str:
    """SHA-256 (hex) of a scene dict without its check, in a canonical JSON form that JSON and
    TOML files give back identically (floats in shortest round-trip form, keys sorted)."""
    body = {k: v for k, v in d.items() if k != _CHECK_KEY}
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), allow_nan=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def save_scene(scene: Scene, path: PathLike) -> Path:
    """Write ``scene`` (a :class:`Scene`, or a ready scene with ``.scene``) to ``path``
    (``.json`` or ``.toml``, by suffix; UTF-8) in the schema above and return the path. TOML is
    written with the ``tomli-w`` package.

    The file carries ``content_sha256`` (a top-level key, after ``version``): the SHA-256 of its
    content in canonical JSON, which :func:`load_scene` checks. The write is atomic (a temporary
    file beside ``path``, fsync'ed and renamed over it): a failed or killed save leaves the
    previous file as it was."""
    fmt = _format(path)
    d = scene_to_dict(scene)
    head = {k: d[k] for k in ("schema", "version", "units")}
    d = {**head, _CHECK_KEY: _content_digest(d), **{k: v for k, v in d.items() if k not in head}}
    if fmt == "json":
        text = _json(d) + "\n"
    else:
        import tomli_w

        text = tomli_w.dumps(d)
    path = Path(path)
    _atomic.write_text(path, text, encoding="utf-8")
    return path


def load_scene(path: PathLike) -> Scene:
    """Read a scene written by :func:`save_scene` (or by hand) from ``path`` (``.json`` or
    ``.toml``). Raises ValueError naming the bad key or parameter (see :func:`scene_from_dict`),
    or naming the file if it is not valid UTF-8 JSON/TOML or its content does not match its
    ``content_sha256`` (truncated, e.g. cut at a table boundary, or edited after it was saved:
    after an intended edit by hand, delete the ``content_sha256`` line). A file without
    ``content_sha256`` (written by hand, or before deployfx wrote the check) is read unchecked."""
    return scene_from_dict(read_scene_dict(path))


def read_scene_dict(path: PathLike) -> Any:
    """A scene file's content as read (:func:`read_file`), its ``content_sha256`` checked and
    removed (ValueError naming the file on a mismatch); not yet validated as a scene."""
    path = Path(path)
    d = read_file(path)
    if isinstance(d, dict) and _CHECK_KEY in d:
        stored = d.pop(_CHECK_KEY)
        try:
            actual = _content_digest(d)
        except (TypeError, ValueError):  # content JSON cannot hold (TOML dates, inf)
            actual = None
        if stored != actual:
            raise ValueError(f"{path} is truncated or was changed after it was saved: its content "
                             f"does not match its {_CHECK_KEY} (if you edited it on purpose, "
                             f"delete the {_CHECK_KEY} line)")
    return d


def read_file(path: PathLike) -> Any:
    """The content of a ``.json`` or ``.toml`` file (by suffix; UTF-8), with ValueError naming the
    file if it is not valid."""
    fmt = _format(path)
    path = Path(path)
    try:
        if fmt == "json":
            return json.loads(path.read_text(encoding="utf-8"))
        try:
            import tomllib
        except ModuleNotFoundError:  # Python < 3.11
            import tomli as tomllib
        with path.open("rb") as f:
            return tomllib.load(f)
    except (json.JSONDecodeError, ValueError) as e:  # TOMLDecodeError, UnicodeDecodeError too
        raise ValueError(f"{path} is not a valid {fmt.upper()} file: {e}") from e
