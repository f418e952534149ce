"""Reading a scene file's dict (deployfx.scene_file): the file's structure is checked here,
naming the offending key; the builder then checks the values. Versions 1, 2 and 3 of the schema
documented in :mod:`deployfx.scene_file`."""
from __future__ import annotations

import numbers
from contextlib import contextmanager
from typing import Any, Iterator, Mapping

import numpy as np

from ._scene_schema import (_APPENDAGE_FILE_KEYS, _APPENDAGE_OPTIONAL, _HINGE_FILE_KEYS, _HINGE_OPTIONAL,
                            _STRENGTH_KEYS, _STRENGTH_OPTIONAL,
                            _ISOTROPIC, _LOCK_FILE_KEYS, _MATERIAL_UNITS, _OLD_APPENDAGE_OPTIONS, _ORTHOTROPIC,
                            _PART_FILE_KEYS, SCHEMA, VERSIONS_READ, _GROOVE_ELEMENT_KEYS, _GROOVE_FILE_KEYS,
                            _GROOVE_OPTIONAL, _LATCH_FILE_KEYS)
from .contact import ContactLaw, Friction
from .materials import Isotropic, Laminate, Orthotropic, Ply
from .plate import ShellModel
from .scene import Scene
from .strengths import Strengths

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
    if integer:  # a 64-bit index at most (a fuzz case: 99999999999999999999 overflowed the cast)
        big = [x for x in a.ravel() if not -2**63 <= x < 2**63]
        if big:
            raise ValueError(f"{where} holds {big[0]!r}, out of range: must be 64-bit integers"[:300])
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


def _old_options(t: Mapping[str, Any], where: str, allowed: tuple) -> dict:
    """A version-1/2 table's ``options``: only the builder options version 3 names are known."""
    if "options" not in t:
        return {}
    opts = t["options"]
    if not isinstance(opts, Mapping):
        raise ValueError(f"{where}.options must be a table (mapping), got {type(opts).__name__}")
    unknown = sorted(set(opts) - set(allowed))
    if unknown:
        names = ", ".join(f"{where}.options.{k}" for k in unknown)
        raise ValueError(f"{where}.options has unknown key(s) {names}; allowed: {', '.join(allowed) or 'none'}")
    return dict(opts)


def _hinge_args(h: Mapping[str, Any], where: str, R_key: str) -> dict:
    fitting = _rigid(h["fitting"], f"{where}.fitting")
    args = {"point": _array(h["point_m"], f"{where}.point_m", (3,)),
            "axis": _array(h["axis"], f"{where}.axis", (3,)),
            "tau0": _number(h["tau0_N_m"], f"{where}.tau0_N_m"),
            "k_theta": _number(h["k_theta_N_m_per_rad"], f"{where}.k_theta_N_m_per_rad"),
            "c_theta": _number(h["c_theta_N_m_s_per_rad"], f"{where}.c_theta_N_m_s_per_rad"),
            "fitting_inertia": fitting["inertia"], "fitting_mass": fitting["mass"], "fitting_com": fitting["com"],
            "R": _array(h[R_key], f"{where}.{R_key}", (3, 3))}
    if "spin_up" in h:
        s = _table(h["spin_up"], f"{where}.spin_up", ("omega_s_rad_per_s", "t_s_s"))
        args["spin_up"] = (_number(s["omega_s_rad_per_s"], f"{where}.spin_up.omega_s_rad_per_s"),
                           _number(s["t_s_s"], f"{where}.spin_up.t_s_s"))
    if "stowed_angle_deg" in h:
        args["stowed_angle_deg"] = _number(h["stowed_angle_deg"], f"{where}.stowed_angle_deg")
    return args


def _read_shell(s: Any, where: str) -> ShellModel:
    s = _table(s, where, ("nodes_m", "quads", "ref_axis", "plies"))
    plies_in = s["plies"]
    if not isinstance(plies_in, list) or not plies_in:
        raise ValueError(f"{where}.plies must be a non-empty list of tables")
    plies = []
    for i, p in enumerate(plies_in):
        ply = f"{where}.plies[{i}]"
        p = _table(p, ply, ("thickness_m", "angle_deg", "material"))
        with _at(ply):
            plies.append(Ply(_read_material(p["material"], f"{ply}.material"),
                             _number(p["thickness_m"], f"{ply}.thickness_m"),
                             _number(p["angle_deg"], f"{ply}.angle_deg")))
    with _at(where):
        return ShellModel(_array(s["nodes_m"], f"{where}.nodes_m", (None, 3)),
                          _array(s["quads"], f"{where}.quads", (None, 4), integer=True),
                          Laminate(plies), _array(s["ref_axis"], f"{where}.ref_axis", (3,)))


def _read_appendage(scene: Scene, a: Any, where: str, k: int, version: int) -> None:
    if version >= 3:
        a = _table(a, where, _APPENDAGE_FILE_KEYS, _APPENDAGE_OPTIONAL)
        opts = {"modes": a["modes"]}
        for key in ("derivative_modes", "derivative_partners"):
            if key in a:
                opts[key] = a[key]
        table = where
    else:
        a = _table(a, where, ("fidelity", "fixed_dofs", "alpha_M_per_s", "beta_K_s", "shell"), ("options",))
        opts = _old_options(a, where, _OLD_APPENDAGE_OPTIONS)
        table = f"{where}.options"
    for key, value in opts.items():
        if isinstance(value, bool) or not isinstance(value, numbers.Integral):
            raise ValueError(f"{table}.{key} must be an integer, got {value!r}")
    shell = _read_shell(a["shell"], f"{where}.shell")
    if not isinstance(a["fidelity"], str):
        raise ValueError(f"{where}.fidelity must be a string, got {a['fidelity']!r}")
    fixed = _array(a["fixed_dofs"], f"{where}.fixed_dofs", (None,), integer=True)
    damping = (_number(a["alpha_M_per_s"], f"{where}.alpha_M_per_s"),
               _number(a["beta_K_s"], f"{where}.beta_K_s"))
    if "strengths" in a:
        items = _list(a["strengths"], f"{where}.strengths", "one table for all plies, or one per ply")
        strengths = []
        for i, t in enumerate(items):
            w = f"{where}.strengths[{i}]"
            t = _table(t, w, _STRENGTH_KEYS, _STRENGTH_OPTIONAL)
            with _at(w):
                strengths.append(Strengths(
                    **{key[:-3] if key.endswith("_Pa") else key: _number(t[key], f"{w}.{key}") for key in t}))
        opts["strengths"] = strengths
    with _at(where):
        scene.set_appendage(shell, fixed, fidelity=a["fidelity"], damping=damping, hinge=k, **opts)


def _read_law(d: Any, where: str) -> ContactLaw:
    law = _table(d, where, ("kind", "K_N_per_m_n", "n", "D_N_s_per_m", "e"))
    if not isinstance(law["kind"], str):
        raise ValueError(f"{where}.kind must be a string, got {law['kind']!r}")
    with _at(where):
        return ContactLaw(law["kind"], K=_number(law["K_N_per_m_n"], f"{where}.K_N_per_m_n"),
                          n=_number(law["n"], f"{where}.n"), D=_number(law["D_N_s_per_m"], f"{where}.D_N_s_per_m"),
                          e=_number(law["e"], f"{where}.e"))


def _read_friction(d: Any, where: str) -> Friction:
    fr = _table(d, where, ("mu", "v_reg_m_per_s"))
    with _at(where):
        return Friction(_number(fr["mu"], f"{where}.mu"), _number(fr["v_reg_m_per_s"], f"{where}.v_reg_m_per_s"))


def _read_groove(scene: Scene, g: Any, where: str, k: int) -> None:
    """A version-4 pin-groove lock (deployfx.groove.PinGroove)."""
    from .groove import Arc, ArcAbout, GrooveProfile, LatchSpring, Line, PinGroove

    g = _table(g, where, _GROOVE_FILE_KEYS, _GROOVE_OPTIONAL)
    elements = []
    for i, e in enumerate(_list(g["profile"], f"{where}.profile", "the profile's elements in order")):
        at = f"{where}.profile[{i}]"
        kind = e.get("kind") if isinstance(e, Mapping) else None
        if kind not in _GROOVE_ELEMENT_KEYS:
            raise ValueError(f"{at}.kind = {kind!r} is invalid: must be one of {', '.join(_GROOVE_ELEMENT_KEYS)}")
        e = _table(e, at, ("kind",) + _GROOVE_ELEMENT_KEYS[kind])
        start, end = _array(e["start_m"], f"{at}.start_m", (2,)), _array(e["end_m"], f"{at}.end_m", (2,))
        if kind == "line":
            elements.append(Line(start, end))
        elif kind == "arc":
            elements.append(Arc(start, end, _number(e["radius_m"], f"{at}.radius_m")))
        else:
            if not isinstance(e["ccw"], bool):
                raise ValueError(f"{at}.ccw must be true or false, got {e['ccw']!r}")
            elements.append(ArcAbout(start, end, _array(e["centre_m"], f"{at}.centre_m", (2,)), e["ccw"]))
    latch = None
    if "latch" in g:
        L = _table(g["latch"], f"{where}.latch", _LATCH_FILE_KEYS)
        if not isinstance(L["toward_axis"], bool):
            raise ValueError(f"{where}.latch.toward_axis must be true or false, got {L['toward_axis']!r}")
        latch = LatchSpring(_number(L["stop_m"], f"{where}.latch.stop_m"),
                            _number(L["travel_m"], f"{where}.latch.travel_m"),
                            _number(L["preload_N"], f"{where}.latch.preload_N"),
                            _number(L["stiffness_N_per_m"], f"{where}.latch.stiffness_N_per_m"), L["toward_axis"])
    with _at(where):
        groove = PinGroove(GrooveProfile(elements), _number(g["pin_distance_m"], f"{where}.pin_distance_m"),
                           _number(g["pin_angle_rad"], f"{where}.pin_angle_rad"),
                           _number(g["pin_radius_m"], f"{where}.pin_radius_m"),
                           _read_law(g["law"], f"{where}.law"), _read_friction(g["friction"], f"{where}.friction"),
                           latch, play_deg=_number(g["play_deg"], f"{where}.play_deg") if "play_deg" in g else None)
        scene.set_groove(groove, hinge=k)


def _read_lock(scene: Scene, L: Any, where: str, k: int, version: int) -> None:
    L = _table(L, where, _LOCK_FILE_KEYS, ("options",) if version < 3 else ())
    _old_options(L, where, ())
    contact = _read_law(L["law"], f"{where}.law")
    friction = _read_friction(L["friction"], f"{where}.friction")
    with _at(where):
        scene.set_lock(_number(L["theta_lock_rad"], f"{where}.theta_lock_rad"),
                       _number(L["pin_radius_m"], f"{where}.pin_radius_m"),
                       _number(L["clearance_m"], f"{where}.clearance_m"), contact, friction=friction, hinge=k)


def _add_hinge(scene: Scene, parent, args: dict, where: str, R_key: str) -> None:
    """Hinge ``where`` on ``parent``. Version 1's one hinge is Scene.set_hinge's (its errors name
    ``hinge.<parameter>`` and ``hinge.R_BE0``, as the file does); a version-3 file calls the
    rotation ``R_PC0`` where add_hinge's errors say ``R_PE0``."""
    R = args.pop("R")
    with _at(where):
        if R_key == "R_BE0":
            scene.set_hinge(R_BE0=R, **args)
            return
        try:
            scene.add_hinge(parent, R_PE0=R, **args)
        except ValueError as e:
            if R_key == "R_PE0" or f"{where}.R_PE0" not in str(e):
                raise
            raise ValueError(str(e).replace(f"{where}.R_PE0", f"{where}.{R_key}")) from e


def _read_version_1(scene: Scene, top: Mapping[str, Any]) -> None:
    """A version-1 file's one hinge: top-level hinge, appendage and lock (no parts on its body)."""
    top = _table(top, "scene file", ("schema", "version", "base", "hinge", "appendage"),
                 ("units", "parts", "lock"))
    _read_base(scene, top)
    h = _table(top["hinge"], "hinge", ("point_m", "axis", "R_BE0", "tau0_N_m", "k_theta_N_m_per_rad",
                                       "c_theta_N_m_s_per_rad", "fitting"), ("spin_up", "options"))
    _old_options(h, "hinge", ())
    _add_hinge(scene, "base", _hinge_args(h, "hinge", "R_BE0"), "hinge", "R_BE0")
    _read_appendage(scene, top["appendage"], "appendage", 0, 1)
    if "lock" in top:
        _read_lock(scene, top["lock"], "lock", 0, 1)


def _read_hinges(scene: Scene, top: Mapping[str, Any], version: int) -> None:
    """A version-2 (serial chain) or -3 (tree) file's hinges, each with its body's parts,
    appendage and lock."""
    top = _table(top, "scene file", ("schema", "version", "base", "hinges"), ("units", "parts"))
    _read_base(scene, top)
    hinges = _list(top["hinges"], "hinges", "each on the base or an earlier hinge's body")
    if not hinges:
        raise ValueError("hinges must hold at least one hinge")
    for k, h in enumerate(hinges):
        where = f"hinges[{k}]"
        if version == 2:
            if k > 0 and isinstance(h, Mapping) and "spin_up" in h:
                raise ValueError(f"{where}.spin_up is not allowed in a version-2 file: a prescribed hinge angle "
                                 "is for hinge 0 only there")
            h = _table(h, where, ("parent", "point_m", "axis", "R_PE0", "tau0_N_m", "k_theta_N_m_per_rad",
                                  "c_theta_N_m_s_per_rad", "fitting"),
                       (("spin_up",) if k == 0 else ()) + ("options", "parts", "appendage", "lock"))
            _old_options(h, where, ())
        else:
            h = _table(h, where, _HINGE_FILE_KEYS, _HINGE_OPTIONAL)
        parent = h["parent"]
        if version == 2:
            ok = parent == "base" if k == 0 else (isinstance(parent, numbers.Integral)
                                                  and not isinstance(parent, bool) and parent == k - 1)
            allowed = "'base' (hinge 0 is on the base)" if k == 0 else f"{k - 1} (a version-2 file is a serial chain)"
        else:
            ok = parent == "base" or (isinstance(parent, numbers.Integral) and not isinstance(parent, bool)
                                      and 0 <= parent < k)
            allowed = "'base'" + (f" or an earlier hinge's index in [0, {k - 1}]" if k else "")
        if not ok:
            raise ValueError(f"{where}.parent = {parent!r} is out of range: must be {allowed}")
        R_key = "R_PE0" if version == 2 else "R_PC0"
        _add_hinge(scene, parent if isinstance(parent, str) else int(parent), _hinge_args(h, where, R_key), where,
                   R_key)
        _read_parts(scene, h.get("parts", []), f"{where}.parts", k)
        if "appendage" in h:
            _read_appendage(scene, h["appendage"], f"{where}.appendage", k, version)
        if "lock" in h and "groove" in h:
            raise ValueError(f"{where} has both a lock and a groove: a hinge has one lock")
        if "lock" in h:
            _read_lock(scene, h["lock"], f"{where}.lock", k, version)
        if "groove" in h:
            if version < 4:
                raise ValueError(f"{where}.groove is not allowed in a version-{version} file (version 4 and later)")
            _read_groove(scene, h["groove"], f"{where}.groove", k)


def _read_base(scene: Scene, top: Mapping[str, Any]) -> None:
    b = _table(top["base"], "base", ("free",) + _PART_FILE_KEYS)
    if not isinstance(b["free"], bool):
        raise ValueError(f"base.free must be true or false, got {b['free']!r}")
    base = _rigid({k: b[k] for k in _PART_FILE_KEYS}, "base")
    with _at("base"):
        scene.set_base(base["mass"], base["inertia"], com=base["com"], free=b["free"])
    _read_parts(scene, top.get("parts", []), "parts", "base")


def scene_from_dict(d: Mapping[str, Any]) -> Scene:
    """Rebuild a :class:`Scene` from a dict of the schema above, version 3, 2 or 1 (e.g. from
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
                         f"deployfx reads versions {', '.join(map(str, VERSIONS_READ))}")
    scene = Scene()
    if version == 1:
        _read_version_1(scene, d)
    else:
        _read_hinges(scene, d, version)
    return scene
