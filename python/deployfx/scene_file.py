"""Scene files: a :class:`~deployfx.scene.Scene` written to and read from plain text (JSON or TOML),
so that a study can be shared and rebuilt exactly.

``save_scene(scene, "study.toml")`` / ``load_scene("study.toml")`` (or ``.json``);
:func:`scene_to_dict` / :func:`scene_from_dict` give the same content as a plain dict. Floats are
written with Python's shortest round-trip representation, so a loaded scene compiles to a model
that gives bit-identical results.

Schema ``deployfx.scene`` version 1. SI units throughout; every dimensional key ends with its unit
(``_m``, ``_kg``, ``_kg_m2``, ``_N_m``, ``_per_s``, ...; ``_n`` in ``K_N_per_m_n`` is the law's
exponent: N/m^n); unsuffixed numbers are dimensionless. Optional parts are simply left out
(TOML has no null)::

    schema = "deployfx.scene"            # required
    version = 1                          # required: the schema version
    units = "SI ..."                     # informative only

    [base]                               # Scene.set_base
    free = true                          # false: fixed to the ground
    mass_kg = 3000.0
    inertia_kg_m2 = [[...], [...], [...]]    # 3 x 3, about the centre of mass, B axes
    com_m = [0.0, 0.0, 0.0]              # centre of mass in B

    [[parts]]                            # Scene.add_rigid_part, zero or more (list)
    mass_kg, inertia_kg_m2 (3 x 3), com_m (3)

    [hinge]                              # Scene.set_hinge
    point_m = [...]                      # 3, a point of the axis in B
    axis = [...]                         # 3, unit vector in B
    R_BE0 = [[...], [...], [...]]        # 3 x 3 rotation: E's axes at theta = 0
    tau0_N_m, k_theta_N_m_per_rad, c_theta_N_m_s_per_rad
    fitting = {mass_kg, com_m (3, E), inertia_kg_m2 (3 x 3, E axes)}
    spin_up = {omega_s_rad_per_s, t_s_s}  # optional: prescribed hinge angle
    options = {...}                      # optional: further set_hinge keywords (see below)

    [appendage]                          # Scene.set_appendage
    fidelity = "linear"                  # "rigid", "linear", "nonlinear", ...
    fixed_dofs = [...]                   # dof indices (6 per node) clamped to E
    alpha_M_per_s, beta_K_s              # Rayleigh damping
    options = {...}                      # optional: further set_appendage keywords, e.g. modes
    [appendage.shell]                    # the ShellModel
    nodes_m = [[x, y, z], ...]           # (n, 3), in E
    quads = [[i, j, k, l], ...]          # (e, 4), 0-based node indices
    ref_axis = [1.0, 0.0, 0.0]           # the laminate's 0-degree direction
    [[appendage.shell.plies]]            # bottom first
    thickness_m, angle_deg
    material = {type = "orthotropic", E1_Pa, E2_Pa, G12_Pa, G13_Pa, G23_Pa, nu12, rho_kg_per_m3}
            or {type = "isotropic", E_Pa, nu, rho_kg_per_m3}

    [lock]                               # optional: Scene.set_lock
    theta_lock_rad, pin_radius_m, clearance_m
    law = {kind, K_N_per_m_n, n, D_N_s_per_m, e}     # deployfx.contact.ContactLaw
    friction = {mu, v_reg_m_per_s}                    # deployfx.contact.Friction
    options = {...}                      # optional: further set_lock keywords

``options``: entries of the scene's hinge, appendage or lock that this module does not name (new
builder options, e.g. an appendage's number of modes for a reduced fidelity) are written as they
are (scalars, or lists of them; None is left out) and passed back to the matching ``set_*`` method
as keyword arguments. Each must be a parameter of that method.

Loading checks the file: an unknown schema or version, a missing or unknown key, a value of the
wrong type or shape raises ``ValueError`` naming the key (e.g. ``appendage.shell.nodes_m``); the
builder then checks the values themselves.
"""
from __future__ import annotations

import inspect
import json
import numbers
import os
from pathlib import Path
from typing import Any, Mapping, Union

import numpy as np

from .contact import ContactLaw, Friction
from .materials import Isotropic, Laminate, Orthotropic, Ply
from .plate import ShellModel
from .scene import RigidPart, Scene

PathLike = Union[str, os.PathLike]

SCHEMA = "deployfx.scene"
#: The schema version written, and the only one read.
VERSION = 1
_UNITS = ("SI: m, kg, s, rad, N, Pa; each dimensional key ends with its unit (K_N_per_m_n: "
          "N/m^n, n the contact law's exponent); ply angles in degrees; unsuffixed numbers are "
          "dimensionless")

# Keys of Scene's private dicts that this module writes by name; any other key is an "option".
_HINGE_KEYS = {"point", "axis", "R_BE0", "tau0", "k_theta", "c_theta", "fitting", "spin_up"}
_APPENDAGE_KEYS = {"shell", "fixed", "fidelity", "alpha_M", "beta_K"}
_LOCK_KEYS = {"theta_lock", "pin_radius", "clearance", "law", "friction"}

_ISOTROPIC = ("E", "nu", "rho")
_ORTHOTROPIC = ("E1", "E2", "G12", "G13", "G23", "nu12", "rho")
_MATERIAL_UNITS = {"E": "E_Pa", "E1": "E1_Pa", "E2": "E2_Pa", "G12": "G12_Pa", "G13": "G13_Pa",
                   "G23": "G23_Pa", "nu": "nu", "nu12": "nu12", "rho": "rho_kg_per_m3"}


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


def _accepts(method, key: str) -> bool:
    """Whether ``method`` takes the keyword argument ``key``."""
    params = inspect.signature(method).parameters
    return (key != "self" and key in params) or any(
        p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values())


def _options(section: str, stored: Mapping[str, Any], known: set, method) -> dict:
    """The entries of ``stored`` not in ``known``: the builder's newer keyword options."""
    out = {}
    for key in sorted(set(stored) - known):
        if stored[key] is None:   # TOML has no null; None is taken to be the default
            continue
        if not _accepts(method, key):
            raise TypeError(f"{section}.{key} cannot be written: Scene.{method.__name__} has no "
                            f"parameter {key!r} to read it back")
        out[key] = _option_value(f"{section}.options.{key}", stored[key])
    return out


def scene_to_dict(scene: Scene) -> dict:
    """The scene as a plain dict of the schema above (str keys; bool, int, float, str, lists, dicts;
    no None), ready for JSON or TOML. ``scene``: a :class:`Scene`, or a ready scene keeping one as
    ``.scene`` (``scenes.paper2016(...)``). Raises TypeError for anything else and ValueError for
    a scene without a base, hinge or appendage, or with several hinges (a chain: not yet in
    the schema)."""
    if not isinstance(scene, Scene) and isinstance(getattr(scene, "scene", None), Scene):
        scene = scene.scene
    if not isinstance(scene, Scene):
        raise TypeError(f"scene must be a deployfx.Scene, got {type(scene).__name__}")
    if scene.num_hinges > 1 or scene._links[0]["parts"]:
        raise ValueError(f"scene files hold one-hinge scenes (schema version {VERSION}): this scene has "
                         f"{scene.num_hinges} hinges or rigid parts on a hinge's body, which cannot be "
                         "written yet")
    for name in ("base", "hinge", "appendage"):
        if getattr(scene, f"_{name}") is None:
            raise ValueError(f"the scene has no {name}: call set_{name}() first")
    base, free = scene._base
    h, a = scene._hinge, scene._appendage
    shell: ShellModel = a["shell"]
    out: dict = {"schema": SCHEMA, "version": VERSION, "units": _UNITS,
                 "base": {"free": bool(free), **_part(base)},
                 "parts": [_part(p) for p in scene._parts]}

    hinge = {"point_m": _floats(h["point"]), "axis": _floats(h["axis"]),
             "R_BE0": _floats(h["R_BE0"]),
             "tau0_N_m": float(h["tau0"]), "k_theta_N_m_per_rad": float(h["k_theta"]),
             "c_theta_N_m_s_per_rad": float(h["c_theta"]), "fitting": _part(h["fitting"])}
    if h["spin_up"] is not None:
        omega_s, t_s = h["spin_up"]
        hinge["spin_up"] = {"omega_s_rad_per_s": float(omega_s), "t_s_s": float(t_s)}
    opts = _options("hinge", h, _HINGE_KEYS, Scene.set_hinge)
    if opts:
        hinge["options"] = opts
    out["hinge"] = hinge

    plies = [{"thickness_m": float(p.thickness), "angle_deg": float(p.angle_deg),
              "material": _material(p.material)} for p in shell.laminate.plies]
    appendage = {"fidelity": str(a["fidelity"]), "fixed_dofs": [int(i) for i in a["fixed"]],
                 "alpha_M_per_s": float(a["alpha_M"]), "beta_K_s": float(a["beta_K"]),
                 "shell": {"nodes_m": _floats(shell.nodes),
                           "quads": np.asarray(shell.quads, dtype=int).tolist(),
                           "ref_axis": _floats(getattr(shell, "ref_axis", (1.0, 0.0, 0.0))),
                           "plies": plies}}
    opts = _options("appendage", a, _APPENDAGE_KEYS, Scene.set_appendage)
    if opts:
        appendage["options"] = opts
    out["appendage"] = appendage

    if scene._lock is not None:
        L = scene._lock
        law, fr = L["law"], L["friction"]
        lock = {"theta_lock_rad": float(L["theta_lock"]), "pin_radius_m": float(L["pin_radius"]),
                "clearance_m": float(L["clearance"]),
                "law": {"kind": law.kind, "K_N_per_m_n": float(law.K), "n": float(law.n),
                        "D_N_s_per_m": float(law.D), "e": float(law.e)},
                "friction": {"mu": float(fr.mu), "v_reg_m_per_s": float(fr.v_reg)}}
        opts = _options("lock", L, _LOCK_KEYS, Scene.set_lock)
        if opts:
            lock["options"] = opts
        out["lock"] = lock
    return out


# ------------------------------------------------------------------------------------------------
# dict -> Scene (with the file's structure checked; the builder checks the values)

def _table(d: Any, where: str, required: tuple, optional: tuple = ()) -> Mapping[str, Any]:
    if not isinstance(d, Mapping):
        raise ValueError(f"{where} must be a table (mapping), got {type(d).__name__}")
    missing = [k for k in required if k not in d]
    if missing:
        raise ValueError(f"{where} is missing key(s) {', '.join(_key(where, k) for k in missing)}")
    unknown = sorted(set(d) - set(required) - set(optional))
    if unknown:
        names = ", ".join(_key(where, k) for k in unknown)
        raise ValueError(f"{where} has unknown key(s) {names}; "
                         f"allowed: {', '.join(list(required) + list(optional))}")
    return d


def _key(where: str, key: str) -> str:
    return key if where == "scene file" else f"{where}.{key}"


def _number(value: Any, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ValueError(f"{where} must be a number, got {type(value).__name__} {value!r}")
    return float(value)


def _array(value: Any, where: str, shape: tuple, integer: bool = False) -> np.ndarray:
    """``value`` as an array of ``shape`` (None: any length), or ValueError naming ``where``."""
    what = "integers" if integer else "numbers"
    kind = numbers.Integral if integer else numbers.Real
    dims = " x ".join("n" if s is None else str(s) for s in shape)
    try:
        a = np.array(value, dtype=object)
    except ValueError:  # ragged
        a = None
    ok = (a is not None and a.ndim == len(shape)
          and all(s is None or s == n for s, n in zip(shape, a.shape))
          and all(not isinstance(x, bool) and isinstance(x, kind) for x in a.ravel()))
    if not ok:
        raise ValueError(f"{where} must be {dims} {what}, got {value!r}"[:300])
    return a.astype(int if integer else float)


def _rigid(d: Any, where: str) -> dict:
    t = _table(d, where, ("mass_kg", "com_m", "inertia_kg_m2"))
    return {"mass": _number(t["mass_kg"], f"{where}.mass_kg"),
            "com": _array(t["com_m"], f"{where}.com_m", (3,)),
            "inertia": _array(t["inertia_kg_m2"], f"{where}.inertia_kg_m2", (3, 3))}


def _read_material(d: Any, where: str):
    if not isinstance(d, Mapping) or d.get("type") not in ("isotropic", "orthotropic"):
        raise ValueError(f"{where}.type must be 'isotropic' or 'orthotropic'")
    names = _ISOTROPIC if d["type"] == "isotropic" else _ORTHOTROPIC
    keys = tuple(_MATERIAL_UNITS[k] for k in names)
    t = _table(d, where, ("type",) + keys)
    args = {k: _number(t[key], f"{where}.{key}") for k, key in zip(names, keys)}
    return Isotropic(**args) if d["type"] == "isotropic" else Orthotropic(**args)


def _read_options(t: Mapping[str, Any], where: str, method) -> dict:
    if "options" not in t:
        return {}
    opts = t["options"]
    if not isinstance(opts, Mapping):
        raise ValueError(f"{where}.options must be a table (mapping), got {type(opts).__name__}")
    for key in opts:
        if not _accepts(method, key):
            raise ValueError(f"{where}.options.{key}: Scene.{method.__name__} has no parameter "
                             f"{key!r} (a newer deployfx may have written this file)")
    return dict(opts)


def scene_from_dict(d: Mapping[str, Any]) -> Scene:
    """Rebuild a :class:`Scene` from a dict of the schema above (e.g. from :func:`scene_to_dict`).
    Raises ValueError naming the key for an unknown schema or version, a missing or unknown key,
    or a value of the wrong type or shape; the builder's own checks follow."""
    top = _table(d, "scene file", ("schema", "version", "base", "hinge", "appendage"),
                 ("units", "parts", "lock"))
    if top["schema"] != SCHEMA:
        raise ValueError(f"schema = {top['schema']!r} is not a deployfx scene "
                         f"(expected {SCHEMA!r})")
    version = top["version"]
    if isinstance(version, bool) or not isinstance(version, int) or version != VERSION:
        raise ValueError(f"version = {version!r} is an unknown scene-file schema version; this "
                         f"deployfx reads version {VERSION}")
    scene = Scene()

    b = _table(top["base"], "base", ("free", "mass_kg", "com_m", "inertia_kg_m2"))
    if not isinstance(b["free"], bool):
        raise ValueError(f"base.free must be true or false, got {b['free']!r}")
    base = _rigid({k: b[k] for k in ("mass_kg", "com_m", "inertia_kg_m2")}, "base")
    scene.set_base(base["mass"], base["inertia"], base["com"], free=b["free"])

    parts = top.get("parts", [])
    if not isinstance(parts, list):
        raise ValueError(f"parts must be a list of tables, got {type(parts).__name__}")
    for i, p in enumerate(parts):
        p = _rigid(p, f"parts[{i}]")
        scene.add_rigid_part(p["mass"], p["inertia"], p["com"])

    h = _table(top["hinge"], "hinge",
               ("point_m", "axis", "R_BE0", "tau0_N_m", "k_theta_N_m_per_rad",
                "c_theta_N_m_s_per_rad", "fitting"), ("spin_up", "options"))
    fitting = _rigid(h["fitting"], "hinge.fitting")
    spin_up = None
    if "spin_up" in h:
        s = _table(h["spin_up"], "hinge.spin_up", ("omega_s_rad_per_s", "t_s_s"))
        spin_up = (_number(s["omega_s_rad_per_s"], "hinge.spin_up.omega_s_rad_per_s"),
                   _number(s["t_s_s"], "hinge.spin_up.t_s_s"))
    scene.set_hinge(point=_array(h["point_m"], "hinge.point_m", (3,)),
                    axis=_array(h["axis"], "hinge.axis", (3,)),
                    R_BE0=_array(h["R_BE0"], "hinge.R_BE0", (3, 3)),
                    tau0=_number(h["tau0_N_m"], "hinge.tau0_N_m"),
                    k_theta=_number(h["k_theta_N_m_per_rad"], "hinge.k_theta_N_m_per_rad"),
                    c_theta=_number(h["c_theta_N_m_s_per_rad"], "hinge.c_theta_N_m_s_per_rad"),
                    fitting_inertia=fitting["inertia"], fitting_mass=fitting["mass"],
                    fitting_com=fitting["com"], spin_up=spin_up,
                    **_read_options(h, "hinge", Scene.set_hinge))

    a = _table(top["appendage"], "appendage",
               ("fidelity", "fixed_dofs", "alpha_M_per_s", "beta_K_s", "shell"), ("options",))
    s = _table(a["shell"], "appendage.shell", ("nodes_m", "quads", "ref_axis", "plies"))
    plies_in = s["plies"]
    if not isinstance(plies_in, list) or not plies_in:
        raise ValueError("appendage.shell.plies must be a non-empty list of tables")
    plies = []
    for i, p in enumerate(plies_in):
        where = f"appendage.shell.plies[{i}]"
        p = _table(p, where, ("thickness_m", "angle_deg", "material"))
        plies.append(Ply(_read_material(p["material"], f"{where}.material"),
                         _number(p["thickness_m"], f"{where}.thickness_m"),
                         _number(p["angle_deg"], f"{where}.angle_deg")))
    shell = ShellModel(_array(s["nodes_m"], "appendage.shell.nodes_m", (None, 3)),
                       _array(s["quads"], "appendage.shell.quads", (None, 4), integer=True),
                       Laminate(plies), _array(s["ref_axis"], "appendage.shell.ref_axis", (3,)))
    if not isinstance(a["fidelity"], str):
        raise ValueError(f"appendage.fidelity must be a string, got {a['fidelity']!r}")
    fixed = _array(a["fixed_dofs"], "appendage.fixed_dofs", (None,), integer=True)
    scene.set_appendage(shell, fixed, a["fidelity"],
                        damping=(_number(a["alpha_M_per_s"], "appendage.alpha_M_per_s"),
                                 _number(a["beta_K_s"], "appendage.beta_K_s")),
                        **_read_options(a, "appendage", Scene.set_appendage))

    if "lock" in top:
        L = _table(top["lock"], "lock", ("theta_lock_rad", "pin_radius_m", "clearance_m", "law",
                                         "friction"), ("options",))
        law = _table(L["law"], "lock.law", ("kind", "K_N_per_m_n", "n", "D_N_s_per_m", "e"))
        if not isinstance(law["kind"], str):
            raise ValueError(f"lock.law.kind must be a string, got {law['kind']!r}")
        fr = _table(L["friction"], "lock.friction", ("mu", "v_reg_m_per_s"))
        scene.set_lock(_number(L["theta_lock_rad"], "lock.theta_lock_rad"),
                       _number(L["pin_radius_m"], "lock.pin_radius_m"),
                       _number(L["clearance_m"], "lock.clearance_m"),
                       ContactLaw(law["kind"],
                                  K=_number(law["K_N_per_m_n"], "lock.law.K_N_per_m_n"),
                                  n=_number(law["n"], "lock.law.n"),
                                  D=_number(law["D_N_s_per_m"], "lock.law.D_N_s_per_m"),
                                  e=_number(law["e"], "lock.law.e")),
                       Friction(_number(fr["mu"], "lock.friction.mu"),
                                _number(fr["v_reg_m_per_s"], "lock.friction.v_reg_m_per_s")),
                       **_read_options(L, "lock", Scene.set_lock))
    return scene


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


def save_scene(scene: Scene, path: PathLike) -> Path:
    """Write ``scene`` (a :class:`Scene`, or a ready scene with ``.scene``) to ``path``
    (``.json`` or ``.toml``, by suffix; UTF-8) in the schema above and return the path. TOML is
    written with the ``tomli-w`` package."""
    fmt = _format(path)
    d = scene_to_dict(scene)
    if fmt == "json":
        text = _json(d) + "\n"
    else:
        import tomli_w

        text = tomli_w.dumps(d)
    path = Path(path)
    path.write_text(text, encoding="utf-8")
    return path


def load_scene(path: PathLike) -> Scene:
    """Read a scene written by :func:`save_scene` (or by hand) from ``path`` (``.json`` or
    ``.toml``). Raises ValueError naming the bad key or parameter (see :func:`scene_from_dict`),
    or for a file that is not valid JSON/TOML."""
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
    except (json.JSONDecodeError, ValueError) as e:  # TOMLDecodeError is a ValueError
        raise ValueError(f"{path} is not a valid {fmt.upper()} file: {e}") from e
    return scene_from_dict(d)
