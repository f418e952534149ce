"""Scene files: a :class:`~deployfx.scene.Scene` written to and read from plain text (JSON or TOML),
so that a study can be shared and rebuilt exactly.

``save_scene(scene, "study.toml")`` / ``load_scene("study.toml")`` (or ``.json``);
:func:`scene_to_dict` / :func:`scene_from_dict` give the same content as a plain dict. Floats are
written with Python's shortest round-trip representation, so a loaded scene compiles to a model
that gives bit-identical results. Every scene the builder expresses is written: one hinge, or a
chain of hinges (``Scene.add_hinge``: a yoke and panels), each with its spring, damper, fitting,
lock, appendage and rigid parts.

Schema ``deployfx.scene`` version 2 (written; versions 1 and 2 are read). SI units throughout;
every dimensional key ends with its unit (``_m``, ``_kg``, ``_kg_m2``, ``_N_m``, ``_per_s``, ...;
``_n`` in ``K_N_per_m_n`` is the law's exponent: N/m^n); unsuffixed numbers are dimensionless.
Optional parts are simply left out (TOML has no null)::

    schema = "deployfx.scene"            # required
    version = 2                          # required: the schema version
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

    [[hinges]]                           # one or more, in chain order: hinges[k] is hinge k
    parent = "base"                      # "base" for hinge 0, k - 1 for hinge k (a serial chain)
    point_m = [...]                      # 3, a point of the axis in the parent's frame P
    axis = [...]                         # 3, unit vector in P
    R_PE0 = [[...], [...], [...]]        # 3 x 3 rotation: E_k's axes at theta = 0 in P's
                                         #   (hinge 0: P = B, set_hinge's R_BE0)
    tau0_N_m, k_theta_N_m_per_rad, c_theta_N_m_s_per_rad
    fitting = {mass_kg, com_m (3, E_k), inertia_kg_m2 (3 x 3, E_k axes)}
    spin_up = {omega_s_rad_per_s, t_s_s}  # optional, hinge 0 only: prescribed hinge angle
    options = {...}                      # optional: further set_hinge (hinge 0) or add_hinge
                                         #   (hinge k > 0) keywords (see below)

    [[hinges.parts]]                     # Scene.add_rigid_part(body=k), zero or more (list):
    mass_kg, inertia_kg_m2, com_m        #   rigid parts on this hinge's body, in E_k (a yoke)

    [hinges.appendage]                   # optional: Scene.set_appendage(hinge=k)
    fidelity = "linear"                  # "rigid", "linear", "nonlinear", ...
    fixed_dofs = [...]                   # dof indices (6 per node) clamped to E_k
    alpha_M_per_s, beta_K_s              # Rayleigh damping
    options = {...}                      # optional: further set_appendage keywords, e.g. modes
    [hinges.appendage.shell]             # the ShellModel
    nodes_m = [[x, y, z], ...]           # (n, 3), in E_k
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
    options = {...}                      # optional: further set_lock keywords

In TOML, a ``[hinges.appendage]``, ``[[hinges.parts]]``, ``[hinges.lock]``, ... header belongs to
the hinge of the last ``[[hinges]]`` header above it (in JSON: ``"hinges": [{..., "parts": [...],
"appendage": {...}, "lock": {...}}, ...]``).

Version 1 (one hinge, read only) has, instead of ``hinges``, top-level tables ``[hinge]`` (the
keys above without ``parent`` and ``parts``, ``R_BE0`` for ``R_PE0``), ``[appendage]`` and,
optionally, ``[lock]``, with the same keys as ``hinges[0]``'s.

``options``: entries of the scene's hinge, appendage or lock that this module does not name (new
builder options, e.g. an appendage's number of modes for a reduced fidelity) are written as they
are (scalars, or lists of them; None is left out) and passed back to the matching builder method
as keyword arguments. Each must be a parameter of that method that the file does not already give
(``parent`` and the appendage's and lock's ``hinge=`` come from the hinge's place in ``hinges``).

Loading checks the file: an unknown schema or version, a missing or unknown key, a value of the
wrong type or shape raises ``ValueError`` naming the key (e.g.
``hinges[1].appendage.shell.nodes_m``); the builder then checks the values themselves, and its
errors are prefixed with the file's table when they do not name it (``hinges[0]: hinge.axis =
...``).
"""
from __future__ import annotations

import hashlib
import json
import numbers
import os
from pathlib import Path
from typing import Any, Mapping, Union

import numpy as np

from . import _atomic
from ._scene_read import scene_from_dict
from ._scene_schema import (_APPENDAGE_KEYS, _HINGE_KEYS, _ISOTROPIC, _LOCK_KEYS, _MATERIAL_UNITS,
                            _ORTHOTROPIC, _UNITS, SCHEMA, VERSION, VERSIONS_READ, _accepts, _given)
from .materials import Isotropic, Orthotropic
from .plate import ShellModel
from .scene import RigidPart, Scene

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


def _option_value(where: str, value: Any) -> Any:
    """A scalar or a (nested) list of scalars as plain Python types, or TypeError."""
    if isinstance(value, np.generic):
        value = value.item()
    if isinstance(value, (bool, str)):
        return value
    if isinstance(value, numbers.Integral):
        return int(value)
    if isinstance(value, numbers.Real):
        if not np.isfinite(value):
            raise ValueError(f"{where} = {value!r} cannot be written: must be finite")
        return float(value)
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_option_value(f"{where}[{i}]", v) for i, v in enumerate(value)]
    raise TypeError(f"{where} of type {type(value).__name__} cannot be written to a scene file "
                    f"(only numbers, strings, booleans and lists of them)")


def _options(section: str, stored: Mapping[str, Any], known: set, method) -> dict:
    """The entries of ``stored`` not in ``known``: the builder's newer keyword options."""
    out = {}
    for key in sorted(set(stored) - known):
        if stored[key] is None:   # TOML has no null; None is taken to be the default
            continue
        if _given(method, key):
            raise TypeError(f"{section}.{key} cannot be written: the file gives "
                            f"Scene.{method.__name__}'s {key!r} itself")
        if not _accepts(method, key):
            raise TypeError(f"{section}.{key} cannot be written: Scene.{method.__name__} has no "
                            f"parameter {key!r} to read it back")
        out[key] = _option_value(f"{section}.options.{key}", stored[key])
    return out


def _write_appendage(where: str, a: Mapping[str, Any]) -> dict:
    shell: ShellModel = a["shell"]
    plies = [{"thickness_m": float(p.thickness), "angle_deg": float(p.angle_deg),
              "material": _material(p.material)} for p in shell.laminate.plies]
    appendage = {"fidelity": str(a["fidelity"]), "fixed_dofs": [int(i) for i in a["fixed"]],
                 "alpha_M_per_s": float(a["alpha_M"]), "beta_K_s": float(a["beta_K"]),
                 "shell": {"nodes_m": _floats(shell.nodes),
                           "quads": np.asarray(shell.quads, dtype=int).tolist(),
                           "ref_axis": _floats(getattr(shell, "ref_axis", (1.0, 0.0, 0.0))),
                           "plies": plies}}
    opts = _options(where, a, _APPENDAGE_KEYS, Scene.set_appendage)
    if opts:
        appendage["options"] = opts
    return appendage


def _write_lock(where: str, L: Mapping[str, Any]) -> dict:
    law, fr = L["law"], L["friction"]
    lock = {"theta_lock_rad": float(L["theta_lock"]), "pin_radius_m": float(L["pin_radius"]),
            "clearance_m": float(L["clearance"]),
            "law": {"kind": law.kind, "K_N_per_m_n": float(law.K), "n": float(law.n),
                    "D_N_s_per_m": float(law.D), "e": float(law.e)},
            "friction": {"mu": float(fr.mu), "v_reg_m_per_s": float(fr.v_reg)}}
    opts = _options(where, L, _LOCK_KEYS, Scene.set_lock)
    if opts:
        lock["options"] = opts
    return lock


def _write_hinge(k: int, link: Mapping[str, Any]) -> dict:
    """Entry k of the scene's hinge list (its hinge, rigid parts, appendage and lock)."""
    where = f"hinges[{k}]"
    h = link["hinge"]
    hinge = {"parent": "base" if k == 0 else k - 1,
             "point_m": _floats(h["point"]), "axis": _floats(h["axis"]),
             "R_PE0": _floats(h["R_BE0"]),
             "tau0_N_m": float(h["tau0"]), "k_theta_N_m_per_rad": float(h["k_theta"]),
             "c_theta_N_m_s_per_rad": float(h["c_theta"]), "fitting": _part(h["fitting"])}
    if h["spin_up"] is not None:
        if k > 0:  # add_hinge cannot set it; only a scene changed by hand has it
            raise ValueError(f"{where}.spin_up cannot be written: a prescribed hinge angle is for "
                             "hinge 0 (Scene.set_hinge) only")
        omega_s, t_s = h["spin_up"]
        hinge["spin_up"] = {"omega_s_rad_per_s": float(omega_s), "t_s_s": float(t_s)}
    opts = _options(where, h, _HINGE_KEYS, Scene.set_hinge if k == 0 else Scene.add_hinge)
    if opts:
        hinge["options"] = opts
    hinge["parts"] = [_part(p) for p in link["parts"]]
    if link["appendage"] is not None:
        hinge["appendage"] = _write_appendage(f"{where}.appendage", link["appendage"])
    if link["lock"] is not None:
        hinge["lock"] = _write_lock(f"{where}.lock", link["lock"])
    return hinge


def scene_to_dict(scene: Scene) -> dict:
    """The scene as a plain dict of the schema above (version 2; str keys; bool, int, float, str,
    lists, dicts; no None), ready for JSON or TOML. ``scene``: a :class:`Scene`, or a ready scene
    keeping one as ``.scene`` (``scenes.paper2016(...)``): one hinge or a chain of hinges. Raises
    TypeError for anything else and ValueError for a scene without a base or a hinge (what else
    it lacks, e.g. an appendage, is written as it is and reported by ``compile()``)."""
    if not isinstance(scene, Scene) and isinstance(getattr(scene, "scene", None), Scene):
        scene = scene.scene
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a deployfx.Scene, got {type(scene).__name__}")
    if scene._base is None:
        raise ValueError("the scene has no base: call set_base() first")
    if scene.num_hinges == 0:
        raise ValueError("the scene has no hinge: call set_hinge() or add_hinge(parent='base') "
                         "first")
    base, free = scene._base
    return {"schema": SCHEMA, "version": VERSION, "units": _UNITS,
            "base": {"free": bool(free), **_part(base)},
            "parts": [_part(p) for p in scene._parts],
            "hinges": [_write_hinge(k, link) for k, link in enumerate(scene._links)]}


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
    fmt = _format(path)
    path = Path(path)
    try:
        if fmt == "json":
            d = json.loads(path.read_text(encoding="utf-8"))
        else:
            try:
                import tomllib
            except ModuleNotFoundError:  # Python < 3.11
                import tomli as tomllib
            with path.open("rb") as f:
                d = tomllib.load(f)
    except (json.JSONDecodeError, ValueError) as e:  # TOMLDecodeError, UnicodeDecodeError too
        raise ValueError(f"{path} is not a valid {fmt.upper()} file: {e}") from e
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
    return scene_from_dict(d)
