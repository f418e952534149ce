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

import inspect
import json
import numbers
import os
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, Mapping, Union

import numpy as np

from .contact import ContactLaw, Friction
from .materials import Isotropic, Laminate, Orthotropic, Ply
from .plate import ShellModel
from .scene import RigidPart, Scene

PathLike = Union[str, os.PathLike]

SCHEMA = "deployfx.scene"
#: The schema version written.
VERSION = 2
#: The schema versions read.
VERSIONS_READ = (1, 2)
_UNITS = ("SI: m, kg, s, rad, N, Pa; each dimensional key ends with its unit (K_N_per_m_n: "
          "N/m^n, n the contact law's exponent); ply angles in degrees; unsuffixed numbers are "
          "dimensionless")

# Keys of Scene's private dicts that this module writes by name; any other key is an "option".
_HINGE_KEYS = {"point", "axis", "R_BE0", "tau0", "k_theta", "c_theta", "fitting", "spin_up"}
_APPENDAGE_KEYS = {"shell", "fixed", "fidelity", "alpha_M", "beta_K"}
_LOCK_KEYS = {"theta_lock", "pin_radius", "clearance", "law", "friction"}

# The keyword arguments this module passes to each builder method itself: never options.
_GIVEN = {
    "set_hinge": {"point", "axis", "R_BE0", "tau0", "k_theta", "c_theta", "fitting_inertia",
                  "fitting_mass", "fitting_com", "spin_up"},
    "add_hinge": {"parent", "point", "axis", "R_PE0", "tau0", "k_theta", "c_theta",
                  "fitting_inertia", "fitting_mass", "fitting_com"},
    "set_appendage": {"shell", "fixed_dofs", "fidelity", "damping", "hinge"},
    "set_lock": {"theta_lock", "pin_radius", "clearance", "law", "friction", "hinge"},
}

# A hinge's keys in the file (version 2; version 1 has R_BE0 for R_PE0 and no parent or parts).
_HINGE_FILE_KEYS = ("point_m", "axis", "R_PE0", "tau0_N_m", "k_theta_N_m_per_rad",
                    "c_theta_N_m_s_per_rad", "fitting")
_PART_FILE_KEYS = ("mass_kg", "com_m", "inertia_kg_m2")

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


def _given(method, key: str) -> bool:
    """Whether this module passes ``key`` to ``method`` itself (then it is never an option)."""
    return key in _GIVEN.get(method.__name__, ())


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


@contextmanager
def _at(where: str) -> Iterator[None]:
    """Prefix ``where`` (the file's table) to a ValueError raised inside that does not start with
    it (the builder's and the materials' checks name their own parameters)."""
    try:
        yield
    except ValueError as e:
        if str(e).startswith(where):
            raise
        raise ValueError(f"{where}: {e}") from e


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


def _list(value: Any, where: str, what: str) -> list:
    if not isinstance(value, list):
        raise ValueError(f"{where} must be a list of tables ({what}), got {type(value).__name__}")
    return value


def _rigid(d: Any, where: str) -> dict:
    t = _table(d, where, _PART_FILE_KEYS)
    return {"mass": _number(t["mass_kg"], f"{where}.mass_kg"),
            "com": _array(t["com_m"], f"{where}.com_m", (3,)),
            "inertia": _array(t["inertia_kg_m2"], f"{where}.inertia_kg_m2", (3, 3))}


def _read_parts(scene: Scene, parts: Any, where: str, body) -> None:
    """Rigid parts on ``body`` ("base" or a hinge index), in the file's order (the order they are
    merged in, so a loaded scene sums them as the original did)."""
    for i, p in enumerate(_list(parts, where, "mass_kg, com_m, inertia_kg_m2")):
        with _at(f"{where}[{i}]"):
            p = _rigid(p, f"{where}[{i}]")
            scene.add_rigid_part(p["mass"], p["inertia"], p["com"], body=body)


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
        if _given(method, key):
            raise ValueError(f"{where}.options.{key} is not an option: the file gives {key!r} "
                             "itself (by a key of its own or by the hinge's place in the file)")
        if not _accepts(method, key):
            raise ValueError(f"{where}.options.{key}: Scene.{method.__name__} has no parameter "
                             f"{key!r} (a newer deployfx may have written this file)")
    return dict(opts)


def _read_hinge(scene: Scene, h: Mapping[str, Any], where: str, k: int, R_key: str) -> None:
    """Hinge k from its checked table ``h`` (hinge 0: Scene.set_hinge; k > 0: add_hinge on the
    body of hinge k - 1)."""
    fitting = _rigid(h["fitting"], f"{where}.fitting")
    args = {"point": _array(h["point_m"], f"{where}.point_m", (3,)),
            "axis": _array(h["axis"], f"{where}.axis", (3,)),
            "tau0": _number(h["tau0_N_m"], f"{where}.tau0_N_m"),
            "k_theta": _number(h["k_theta_N_m_per_rad"], f"{where}.k_theta_N_m_per_rad"),
            "c_theta": _number(h["c_theta_N_m_s_per_rad"], f"{where}.c_theta_N_m_s_per_rad"),
            "fitting_inertia": fitting["inertia"], "fitting_mass": fitting["mass"],
            "fitting_com": fitting["com"]}
    R = _array(h[R_key], f"{where}.{R_key}", (3, 3))
    if k > 0:
        opts = _read_options(h, where, Scene.add_hinge)
        with _at(where):
            scene.add_hinge(k - 1, R_PE0=R, **args, **opts)
        return
    spin_up = None
    if "spin_up" in h:
        s = _table(h["spin_up"], f"{where}.spin_up", ("omega_s_rad_per_s", "t_s_s"))
        spin_up = (_number(s["omega_s_rad_per_s"], f"{where}.spin_up.omega_s_rad_per_s"),
                   _number(s["t_s_s"], f"{where}.spin_up.t_s_s"))
    opts = _read_options(h, where, Scene.set_hinge)
    with _at(where):
        scene.set_hinge(R_BE0=R, spin_up=spin_up, **args, **opts)


def _read_appendage(scene: Scene, a: Any, where: str, k: int) -> None:
    a = _table(a, where, ("fidelity", "fixed_dofs", "alpha_M_per_s", "beta_K_s", "shell"),
               ("options",))
    s = _table(a["shell"], f"{where}.shell", ("nodes_m", "quads", "ref_axis", "plies"))
    plies_in = s["plies"]
    if not isinstance(plies_in, list) or not plies_in:
        raise ValueError(f"{where}.shell.plies must be a non-empty list of tables")
    plies = []
    for i, p in enumerate(plies_in):
        ply = f"{where}.shell.plies[{i}]"
        p = _table(p, ply, ("thickness_m", "angle_deg", "material"))
        with _at(ply):
            plies.append(Ply(_read_material(p["material"], f"{ply}.material"),
                             _number(p["thickness_m"], f"{ply}.thickness_m"),
                             _number(p["angle_deg"], f"{ply}.angle_deg")))
    with _at(f"{where}.shell"):
        shell = ShellModel(_array(s["nodes_m"], f"{where}.shell.nodes_m", (None, 3)),
                           _array(s["quads"], f"{where}.shell.quads", (None, 4), integer=True),
                           Laminate(plies), _array(s["ref_axis"], f"{where}.shell.ref_axis", (3,)))
    if not isinstance(a["fidelity"], str):
        raise ValueError(f"{where}.fidelity must be a string, got {a['fidelity']!r}")
    fixed = _array(a["fixed_dofs"], f"{where}.fixed_dofs", (None,), integer=True)
    damping = (_number(a["alpha_M_per_s"], f"{where}.alpha_M_per_s"),
               _number(a["beta_K_s"], f"{where}.beta_K_s"))
    opts = _read_options(a, where, Scene.set_appendage)
    with _at(where):
        scene.set_appendage(shell, fixed, a["fidelity"], damping=damping, hinge=k, **opts)


def _read_lock(scene: Scene, L: Any, where: str, k: int) -> None:
    L = _table(L, where, ("theta_lock_rad", "pin_radius_m", "clearance_m", "law", "friction"),
               ("options",))
    law = _table(L["law"], f"{where}.law", ("kind", "K_N_per_m_n", "n", "D_N_s_per_m", "e"))
    if not isinstance(law["kind"], str):
        raise ValueError(f"{where}.law.kind must be a string, got {law['kind']!r}")
    fr = _table(L["friction"], f"{where}.friction", ("mu", "v_reg_m_per_s"))
    with _at(f"{where}.law"):
        contact = ContactLaw(law["kind"], K=_number(law["K_N_per_m_n"], f"{where}.law.K_N_per_m_n"),
                             n=_number(law["n"], f"{where}.law.n"),
                             D=_number(law["D_N_s_per_m"], f"{where}.law.D_N_s_per_m"),
                             e=_number(law["e"], f"{where}.law.e"))
    with _at(f"{where}.friction"):
        friction = Friction(_number(fr["mu"], f"{where}.friction.mu"),
                            _number(fr["v_reg_m_per_s"], f"{where}.friction.v_reg_m_per_s"))
    args = (_number(L["theta_lock_rad"], f"{where}.theta_lock_rad"),
            _number(L["pin_radius_m"], f"{where}.pin_radius_m"),
            _number(L["clearance_m"], f"{where}.clearance_m"), contact, friction)
    opts = _read_options(L, where, Scene.set_lock)
    with _at(where):
        scene.set_lock(*args, hinge=k, **opts)


def _read_version_1(scene: Scene, top: Mapping[str, Any]) -> None:
    """A version-1 file's one hinge: top-level hinge, appendage and lock (no parts on its body)."""
    top = _table(top, "scene file", ("schema", "version", "base", "hinge", "appendage"),
                 ("units", "parts", "lock"))
    _read_base(scene, top)
    h = _table(top["hinge"], "hinge", ("point_m", "axis", "R_BE0") + _HINGE_FILE_KEYS[3:],
               ("spin_up", "options"))
    _read_hinge(scene, h, "hinge", 0, "R_BE0")
    _read_appendage(scene, top["appendage"], "appendage", 0)
    if "lock" in top:
        _read_lock(scene, top["lock"], "lock", 0)


def _read_version_2(scene: Scene, top: Mapping[str, Any]) -> None:
    """A version-2 file: the hinges in chain order, each with its body's parts, appendage, lock."""
    top = _table(top, "scene file", ("schema", "version", "base", "hinges"), ("units", "parts"))
    _read_base(scene, top)
    hinges = _list(top["hinges"], "hinges", "hinge 0 on the base, hinge k on hinge k - 1's body")
    if not hinges:
        raise ValueError("hinges must hold at least one hinge (hinge 0, on the base)")
    for k, h in enumerate(hinges):
        where = f"hinges[{k}]"
        if k > 0 and isinstance(h, Mapping) and "spin_up" in h:
            raise ValueError(f"{where}.spin_up is not allowed: a prescribed hinge angle is for "
                             "hinge 0 only (Scene.set_hinge)")
        h = _table(h, where, ("parent",) + _HINGE_FILE_KEYS,
                   (("spin_up",) if k == 0 else ()) + ("options", "parts", "appendage", "lock"))
        parent = h["parent"]
        if k == 0:
            ok = isinstance(parent, str) and parent == "base"
        else:
            ok = (isinstance(parent, numbers.Integral) and not isinstance(parent, bool)
                  and parent == k - 1)
        if not ok:
            allowed = ("'base' (hinge 0 is on the base)" if k == 0 else
                       f"{k - 1} (hinge {k} is on the body of hinge {k - 1}: deployfx builds "
                       "serial chains)")
            raise ValueError(f"{where}.parent = {parent!r} is out of range: must be {allowed}")
        _read_hinge(scene, h, where, k, "R_PE0")
        _read_parts(scene, h.get("parts", []), f"{where}.parts", k)
        if "appendage" in h:
            _read_appendage(scene, h["appendage"], f"{where}.appendage", k)
        if "lock" in h:
            _read_lock(scene, h["lock"], f"{where}.lock", k)


def _read_base(scene: Scene, top: Mapping[str, Any]) -> None:
    b = _table(top["base"], "base", ("free",) + _PART_FILE_KEYS)
    if not isinstance(b["free"], bool):
        raise ValueError(f"base.free must be true or false, got {b['free']!r}")
    base = _rigid({k: b[k] for k in _PART_FILE_KEYS}, "base")
    with _at("base"):
        scene.set_base(base["mass"], base["inertia"], base["com"], free=b["free"])
    _read_parts(scene, top.get("parts", []), "parts", "base")


def scene_from_dict(d: Mapping[str, Any]) -> Scene:
    """Rebuild a :class:`Scene` from a dict of the schema above, version 2 or 1 (e.g. from
    :func:`scene_to_dict`). Raises ValueError naming the key for an unknown schema or version, a
    missing or unknown key, or a value of the wrong type or shape; the builder's own checks
    follow."""
    if not isinstance(d, Mapping):
        raise ValueError(f"scene file must be a table (mapping), got {type(d).__name__}")
    missing = [k for k in ("schema", "version") if k not in d]
    if missing:
        raise ValueError(f"scene file is missing key(s) {', '.join(missing)}")
    if d["schema"] != SCHEMA:
        raise ValueError(f"schema = {d['schema']!r} is not a deployfx scene "
                         f"(expected {SCHEMA!r})")
    version = d["version"]
    if isinstance(version, bool) or not isinstance(version, int) or version not in VERSIONS_READ:
        raise ValueError(f"version = {version!r} is an unknown scene-file schema version; this "
                         f"deployfx reads versions {' and '.join(map(str, VERSIONS_READ))}")
    scene = Scene()
    (_read_version_1 if version == 1 else _read_version_2)(scene, d)
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
