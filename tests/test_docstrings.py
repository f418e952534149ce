"""Every public name of deployfx has a docstring (issue: "docstrings on every public name").

The public API walked here: the package and each public module (``deployfx.<name>``, names not
starting with ``_``), the names each exports (``__all__`` if it has one, else every name not
starting with ``_``), and of each exported class its public methods, class and static methods,
properties and nested classes. A docstring is a non-empty ``__doc__`` of the object itself or of
the same name on a deployfx base class; docstrings Python makes up (a dataclass's signature, a
pybind11 signature line) or inherits from ``object`` and the builtins do not count. Data (constants,
dataclass fields, type aliases) cannot hold a docstring and is not checked. Objects defined outside
deployfx (numpy, typing, ...) are not deployfx's API and are skipped. No engine run: imports only.
"""
import dataclasses
import importlib
import inspect
import pkgutil
import re
import types

import deployfx
import pytest

PACKAGE = deployfx.__name__
# pybind11's generated signature lines, e.g. "modes(self: ..., n: int) -> ..." or "1. f(x: float)".
_SIGNATURE = re.compile(r"^(\d+\. )?[A-Za-z_][\w.]*\(.*\)( -> .*)?$")


def public_modules() -> list[types.ModuleType]:
    """The package and its public submodules, imported (not ``_core``, ``_run``, ``__main__``)."""
    mods = [deployfx]
    for info in pkgutil.iter_modules(deployfx.__path__):
        if not info.name.startswith("_"):
            mods.append(importlib.import_module(f"{PACKAGE}.{info.name}"))
    return mods


def exported(module: types.ModuleType) -> list[str]:
    """The public names of ``module``: its ``__all__``, else every name not starting with ``_``."""
    names = getattr(module, "__all__", None)
    if names is None:
        names = [n for n in vars(module) if not n.startswith("_")]
    return list(names)


def _ours(obj: object) -> bool:
    return (getattr(obj, "__module__", None) or "").split(".")[0] == PACKAGE


def _core(obj: object) -> bool:
    """True for the compiled module's objects (pybind11 makes up signature docstrings)."""
    return (getattr(obj, "__module__", None) or "").startswith(f"{PACKAGE}._core")


def _text(doc: object, obj: object, core: bool = False) -> str:
    """The docstring's own text: empty if missing, blank, or made up by Python or pybind11
    (``core``: ``obj`` is, or belongs to, a name of the compiled module)."""
    if not isinstance(doc, str):
        return ""
    doc = doc.strip()
    if inspect.isclass(obj) and dataclasses.is_dataclass(obj):
        # A dataclass without a docstring gets "Name(field: type, ...)".
        auto = obj.__name__ + str(inspect.signature(obj)).replace(" -> None", "")
        if doc == auto:
            return ""
    if core or _core(obj):
        lines = [ln for ln in doc.splitlines() if ln.strip()]
        lines = [ln for ln in lines if ln.strip() != "Overloaded function."
                 and not _SIGNATURE.match(ln.strip())]
        doc = "\n".join(lines)
    return doc


def _member_doc(cls: type, name: str, member: object) -> str:
    """The docstring of ``cls.<name>``, or of the same name on a deployfx base class."""
    for klass in inspect.getmro(cls):
        if not _ours(klass) or name not in vars(klass):
            continue
        m = vars(klass)[name]
        if isinstance(m, (staticmethod, classmethod)):
            m = m.__func__
        text = _text(getattr(m, "__doc__", None), m, _core(klass))
        if text:
            return text
    return ""


def _is_documentable(member: object) -> bool:
    """Methods, properties and classes hold docstrings; data does not."""
    if isinstance(member, (staticmethod, classmethod, property)):
        return True
    if type(member).__name__ == "_tuplegetter":  # a namedtuple's field: data
        return False
    return inspect.isroutine(member) or inspect.isclass(member) or inspect.isdatadescriptor(member)


def missing_docstrings() -> list[str]:
    """Qualified names of every public module, class, function, method and property that has no
    docstring of its own, sorted; each object once, under the name it was defined with."""
    missing: set[str] = set()
    seen: set[int] = set()

    def check_class(cls: type, qualname: str) -> None:
        if not _text(cls.__doc__, cls):
            missing.add(qualname)
        for name, member in vars(cls).items():
            if name.startswith("_") or not _is_documentable(member):
                continue
            if inspect.isclass(member):
                if _ours(member) and id(member) not in seen:
                    seen.add(id(member))
                    check_class(member, f"{qualname}.{name}")
                continue
            if not _member_doc(cls, name, member):
                missing.add(f"{qualname}.{name}")

    for module in public_modules():
        if not _text(module.__doc__, module):
            missing.add(f"{module.__name__} (module)")
        for name in exported(module):
            obj = getattr(module, name)
            if isinstance(obj, types.ModuleType) or not _ours(obj):
                continue  # submodules are walked themselves; numpy, typing etc. are not ours
            if not (inspect.isclass(obj) or inspect.isroutine(obj)):
                continue  # data: constants, instances, type aliases
            if id(obj) in seen:
                continue
            seen.add(id(obj))
            qualname = f"{obj.__module__}.{getattr(obj, '__qualname__', name)}"
            if inspect.isclass(obj):
                check_class(obj, qualname)
            elif not _text(obj.__doc__, obj):
                missing.add(qualname)
    return sorted(missing)


def test_every_public_name_has_a_docstring():
    missing = missing_docstrings()
    assert not missing, (f"{len(missing)} public name(s) without a docstring:\n  "
                         + "\n  ".join(missing))


def test_the_walk_covers_the_api():
    # Guards the test against walking nothing: the package's exports and a few known members.
    names = set(exported(deployfx))
    assert {"Scene", "Model", "Result", "Laminate", "Plate", "load"} <= names
    assert {m.__name__ for m in public_modules()} >= {
        "deployfx", "deployfx.scene", "deployfx.results", "deployfx.plot", "deployfx.tradeoff"}


def test_a_missing_docstring_is_reported(monkeypatch):
    # The check must be able to fail: blank a method's, a property's and a function's docstring.
    monkeypatch.setattr(deployfx.Result.save, "__doc__", None)
    monkeypatch.setattr(deployfx.Laminate, "A", property(lambda self: None, doc="  "))
    monkeypatch.setattr(deployfx.metrics.max_abs, "__doc__", "")
    missing = missing_docstrings()
    assert {"deployfx.results.Result.save", "deployfx.materials.Laminate.A",
            "deployfx.metrics.max_abs"} <= set(missing)


def test_a_dataclass_signature_is_not_a_docstring():
    @dataclasses.dataclass
    class Point:
        x: float

    @dataclasses.dataclass
    class Documented:
        """A point, m."""

        x: float

    assert Point.__doc__ and _text(Point.__doc__, Point) == ""
    assert _text(Documented.__doc__, Documented) == "A point, m."


@pytest.mark.parametrize("doc, expected", [
    ("modes(self: deployfx._core.ShellModel, n: int) -> tuple", ""),
    ("Overloaded function.\n\n1. f(x: float) -> float\n\n2. f(x: int) -> int", ""),
    ("mass(self: deployfx._core.ShellModel) -> float\n\nTotal mass, kg.", "Total mass, kg."),
])
def test_pybind11_signatures_are_not_docstrings(doc, expected):
    assert _text(doc, None, core=True) == expected
