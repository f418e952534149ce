"""Reading a scene file's dict (deployfx.scene_file): the file's structure is checked here,
naming the offending key; the builder then checks the values. Versions 1 and 2 of the schema
documented in :mod:`deployfx.scene_file`."""
from __future__ import annotations

import numbers
from contextlib import contextmanager
from typing import Any, Iterator, Mapping

import numpy as np

from ._scene_schema import (_HINGE_FILE_KEYS, _ISOTROPIC, _MATERIAL_UNITS, _ORTHOTROPIC, _PART_FILE_KEYS,
                            SCHEMA, VERSIONS_READ, _accepts, _given)
from .contact import ContactLaw, Friction
from .materials import Isotropic, Laminate, Orthotropic, Ply
from .plate import ShellModel
from .scene import Scene

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
