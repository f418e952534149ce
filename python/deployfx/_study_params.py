"""Addressing a study's parameters (deployfx.study): how a name such as ``"tau0"``,
``"friction.mu"`` or ``"hinges.0.lock.clearance_m"`` becomes a change of the base scene.

- A scene factory (``scenes.paper2016`` or any callable returning an object with
  ``.simulate(t_end, dt, ...)``): a name is a keyword argument; a dotted name changes one field
  inside the argument's value: a dataclass field (``"friction.mu"``, ``"contact.K"``), a tuple
  entry by position (``"damping.0"``) or by its documented name (:data:`COMPONENTS`:
  ``"damping.alpha_M"``), a mapping's key. The value being changed comes from ``fixed`` or else
  from the factory's default (its signature, or for ``scenes.paper2016`` the fields of
  ``Paper2016Parameters``).
- A :class:`~deployfx.Scene`, a scene file or a scene dict: a name is a dotted path into the scene
  file's dictionary (:func:`deployfx.scene_file.scene_to_dict`, schema in
  :mod:`deployfx.scene_file`), list entries by index: ``"hinges.0.tau0_N_m"``,
  ``"hinges.0.lock.friction.mu"``, ``"hinges.0.appendage.alpha_M_per_s"``.
"""
from __future__ import annotations

import copy
import dataclasses
import inspect
import numbers
from typing import Any, Callable, Mapping, Optional

#: Names of the entries of tuple-valued factory parameters, for dotted names.
COMPONENTS = {"damping": ("alpha_M", "beta_K"), "yoke_inertia": ("Jxx", "Jyy", "Jzz")}


def factory_defaults(factory: Callable) -> tuple[Optional[dict], bool]:
    """(defaults by parameter name, whether the factory takes any further keyword): the
    signature's defaults and, for ``scenes.paper2016``, Paper2016Parameters' fields."""
    from . import scenes

    defaults, var_kw = {}, False
    try:
        params = inspect.signature(factory).parameters
    except (TypeError, ValueError):  # a builtin without a signature: anything goes
        return None, True
    for p in params.values():
        if p.kind is inspect.Parameter.VAR_KEYWORD:
            var_kw = True
        elif p.kind is not inspect.Parameter.VAR_POSITIONAL:
            defaults[p.name] = p.default
    if factory is scenes.paper2016:
        defaults.update({f.name: f.default for f in dataclasses.fields(scenes.Paper2016Parameters)})
        var_kw = False  # paper2016 rejects any other keyword
    return defaults, var_kw


def check_factory_name(factory: Callable, name: str, fixed: Mapping[str, Any], where: str) -> None:
    """ValueError naming ``where`` if ``name`` cannot address a parameter of ``factory``."""
    defaults, var_kw = factory_defaults(factory)
    head, *rest = name.split(".")
    label = getattr(factory, "__name__", repr(factory))
    if defaults is not None and head not in defaults and not var_kw:
        raise ValueError(f"{where} = {name!r}: {label}() has no parameter {head!r}; allowed: "
                         f"{', '.join(sorted(defaults))}")
    if rest:
        if head in fixed:
            base = fixed[head]
        elif defaults is not None and head in defaults and defaults[head] is not inspect._empty:
            base = defaults[head]
        else:
            raise ValueError(f"{where} = {name!r}: {label}() has no default for {head!r} to change "
                             f"a field of; give one in fixed (e.g. fixed={{{head!r}: ...}})")
        replace(base, rest, 0.0, name, head, check_only=True)


def factory_kwargs(factory: Callable, fixed: Mapping[str, Any], values: Mapping[str, Any]) -> dict:
    """The factory's keyword arguments for one sample: ``fixed`` updated with ``values``, dotted
    names applied in order (fixed ones first)."""
    kw = {k: v for k, v in fixed.items() if "." not in k}
    kw.update({k: v for k, v in values.items() if "." not in k})
    dotted = [(k, v) for k, v in fixed.items() if "." in k] + \
             [(k, v) for k, v in values.items() if "." in k]
    if dotted:
        defaults, _ = factory_defaults(factory)
        for name, v in dotted:
            head, *rest = name.split(".")
            base = kw[head] if head in kw else (defaults or {})[head]
            kw[head] = replace(base, rest, v, name, head)
    return kw


def replace(obj: Any, path: list, value: Any, name: str, head: str, check_only: bool = False) -> Any:
    """``obj`` with the entry at ``path`` replaced by ``value`` (a new object: dataclasses by
    dataclasses.replace, tuples and lists rebuilt, mappings copied)."""
    if not path:
        if check_only and not (isinstance(obj, numbers.Real) or obj is None):
            raise ValueError(f"parameter {name!r} addresses a {type(obj).__name__}, not a number")
        return value
    key, rest = path[0], path[1:]
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        fields = [f.name for f in dataclasses.fields(obj) if f.init and not f.name.startswith("_")]
        if key not in fields:
            raise ValueError(f"parameter {name!r}: {type(obj).__name__} has no field {key!r}; "
                             f"fields: {', '.join(fields)}")
        new = replace(getattr(obj, key), rest, value, name, head, check_only)
        return obj if check_only else dataclasses.replace(obj, **{key: new})
    if isinstance(obj, (tuple, list)):
        names = COMPONENTS.get(head, ()) if len(path) == len(name.split(".")) - 1 else ()
        if key in names:
            k = names.index(key)
        elif key.isdigit() and int(key) < len(obj):
            k = int(key)
        else:
            allowed = [str(i) for i in range(len(obj))] + list(names)
            raise ValueError(f"parameter {name!r}: {key!r} is not an entry of a {len(obj)}-entry "
                             f"{type(obj).__name__}; use one of {', '.join(allowed)}")
        new = replace(obj[k], rest, value, name, head, check_only)
        if check_only:
            return obj
        out = list(obj)
        out[k] = new
        return type(obj)(out)
    if isinstance(obj, Mapping):
        if key not in obj:
            raise ValueError(f"parameter {name!r}: no key {key!r}; keys: {', '.join(map(str, obj))}")
        new = replace(obj[key], rest, value, name, head, check_only)
        if check_only:
            return obj
        out = dict(obj)
        out[key] = new
        return out
    raise ValueError(f"parameter {name!r}: cannot address {key!r} inside a "
                     f"{type(obj).__name__} ({obj!r})")


def check_path(scene: Mapping[str, Any], name: str, value: Any, where: str) -> None:
    """ValueError naming ``where`` unless ``name`` is a dotted path to a value of ``value``'s kind
    (number, string or boolean) in the scene dict."""
    node: Any = scene
    parts = name.split(".")
    for i, key in enumerate(parts):
        at = ".".join(parts[:i]) or "the scene file"
        if isinstance(node, Mapping):
            if key not in node:
                raise ValueError(f"{where} = {name!r}: {at} has no key {key!r}; keys: "
                                 f"{', '.join(map(str, node))}")
            node = node[key]
        elif isinstance(node, list):
            if not (key.isdigit() and int(key) < len(node)):
                raise ValueError(f"{where} = {name!r}: {at} is a list of {len(node)}; {key!r} must "
                                 f"be an index from 0 to {len(node) - 1}")
            node = node[int(key)]
        else:
            raise ValueError(f"{where} = {name!r}: {at} is a value, not a table or list")
    if isinstance(node, (Mapping, list)):
        raise ValueError(f"{where} = {name!r} is a {'table' if isinstance(node, Mapping) else 'list'}"
                         f"; address one number inside it (e.g. {name}.{next(iter(node), 0)})")
    if type(node) is bool or isinstance(value, bool) or isinstance(node, str) or isinstance(value, str):
        if type(node) is not type(value):
            raise ValueError(f"{where} = {name!r} holds {node!r}; it cannot take {value!r}")


def set_paths(scene: Mapping[str, Any], values: Mapping[str, Any]) -> dict:
    """A deep copy of the scene dict with each dotted path set to its value."""
    d = copy.deepcopy(dict(scene))
    for name, v in values.items():
        node: Any = d
        parts = name.split(".")
        for key in parts[:-1]:
            node = node[int(key)] if isinstance(node, list) else node[key]
        last = parts[-1]
        if isinstance(node, list):
            node[int(last)] = v
        else:
            node[last] = v
    return d
