"""Hypothesis strategies of the fuzz suite (issue 29): values that are mostly plausible (so that
cases reach deep into the solvers), often extreme (0, denormals, 1e+-300, NaN, inf) and sometimes
of the wrong type. Two profiles: the short one runs in the normal ``pytest`` (a few seconds), the
long one (``pytest -m fuzz``) runs ~10^4 cases (docs/reliability.md)."""
from __future__ import annotations

import math

from hypothesis import HealthCheck, Phase, given, settings
from hypothesis import strategies as st

def collect(kind: str, args: st.SearchStrategy, n: int, long: bool = False) -> list:
    """``n`` cases ``{"kind": kind, "args": ...}`` drawn by hypothesis (no test body: the cases
    run later, many per child interpreter). The short profile is derandomized (the same cases
    every run); the long one (``long=True``) random."""
    out = []

    @settings(max_examples=n, derandomize=not long, deadline=None, database=None,
              suppress_health_check=list(HealthCheck), phases=[Phase.explicit, Phase.generate])
    @given(args)
    def draw(a):
        out.append({"kind": kind, "args": a})

    draw()
    return out


# A plausible value 9 times in 10 (hypothesis favours the edges of what it draws, so the odds
# are set by hand): a case with 15 parameters is then valid in ~1 of 5 draws and reaches the
# solvers; the others test the checks, mostly one parameter at a time.
TYPICAL = 0.9


def _mostly(typical, other):
    return st.floats(0.0, 1.0).flatmap(lambda u: typical if u < TYPICAL else other)
SPECIAL = [0.0, -0.0, 1.0, -1.0, 5e-324, 2.2250738585072014e-308, 1e-300, 1e-100, 1e100,
           1e300, 1.7976931348623157e308, -1.7976931348623157e308, math.nan, math.inf, -math.inf]
WRONG = st.sampled_from(["1.0", None, True, [1.0], {"a": 1}, [[]]])


def number(lo: float, hi: float, *, log: bool = True) -> st.SearchStrategy:
    """A float, mostly in [lo, hi] (log-uniform if ``log`` and lo > 0), else special values, any
    double, big ints or a wrong type."""
    if log and lo > 0:
        typical = st.floats(math.log10(lo), math.log10(hi)).map(lambda e: 10.0 ** e)
    else:
        typical = st.floats(lo, hi)
    return _mostly(typical, st.one_of(st.sampled_from(SPECIAL), st.floats(),
                                      st.integers(-2 ** 70, 2 ** 70), WRONG))


def count(lo: int, hi: int) -> st.SearchStrategy:
    """An int, mostly in [lo, hi], else extreme ints, floats or a wrong type."""
    typical = st.integers(lo, hi)
    return _mostly(typical, st.one_of(
        st.sampled_from([0, -1, 2 ** 31, 2 ** 31 - 1, 2 ** 63, -2 ** 63, 2 ** 32 + 3]),
        st.floats(), WRONG))


def isotropic_args():
    return st.fixed_dictionaries({"E": number(1e6, 1e12), "nu": number(-0.9, 0.49, log=False),
                                  "rho": number(1.0, 2e4)})


def orthotropic_args():
    return st.fixed_dictionaries({
        "E1": number(1e9, 5e11), "E2": number(1e9, 5e10), "G12": number(1e9, 2e10),
        "G13": number(1e9, 2e10), "G23": number(1e9, 2e10), "nu12": number(-0.5, 0.6, log=False),
        "rho": number(1e3, 3e3)})


def material():
    return st.one_of(isotropic_args().map(lambda a: {"type": "isotropic", **a}),
                     orthotropic_args().map(lambda a: {"type": "orthotropic", **a}),
                     st.sampled_from([{"type": "isotropic", "E": 70e9, "nu": 0.33, "rho": 2700.0},
                                      {"type": "orthotropic", "E1": 177e9, "E2": 10.8e9,
                                       "G12": 7.6e9, "G13": 7.6e9, "G23": 8.504e9, "nu12": 0.27,
                                       "rho": 1600.0}]))


def plies(max_plies: int = 4):
    ply = st.fixed_dictionaries({"material": material(), "thickness": number(1e-4, 5e-3),
                                 "angle_deg": number(-180.0, 180.0, log=False)})
    return st.one_of(st.lists(ply, min_size=1, max_size=max_plies),
                     st.lists(ply, min_size=1, max_size=max_plies),
                     st.lists(ply, min_size=1, max_size=max_plies), st.just([]), WRONG)


BOUNDARIES = st.one_of(st.sampled_from(["CFFF", "FFFF", "SSSS", "CCCC", "CSFS", "cfff"]),
                       st.text(max_size=6), WRONG)


def plate_case():
    return st.fixed_dictionaries({
        "length": number(0.1, 5.0), "width": number(0.1, 5.0), "nx": count(1, 4),
        "ny": count(1, 3), "plies": plies(3),
        "method": st.sampled_from(["frequencies", "modes", "static", "fixed_dofs", "matrices"]),
        "n": count(1, 80), "boundary": BOUNDARIES, "pressure": number(1.0, 1e5)})


def shell_case():
    edit = st.one_of(st.none(), st.none(), st.tuples(st.integers(0, 50), st.integers(0, 2),
                                                     number(-5.0, 5.0, log=False)))
    quad_edit = st.one_of(st.none(), st.none(), st.tuples(
        st.integers(0, 20), st.integers(0, 3),
        st.one_of(st.integers(-3, 30), st.sampled_from([2 ** 31, 2 ** 32 + 3, -2 ** 31 - 1]))))
    axis = st.one_of(st.just([1.0, 0.0, 0.0]), st.just([1.0, 0.0, 0.0]),
                     st.lists(number(-1.0, 1.0, log=False), min_size=3, max_size=3),
                     st.lists(st.floats(), min_size=0, max_size=4))
    return st.fixed_dictionaries({
        "length": st.floats(0.1, 3.0), "width": st.floats(0.1, 3.0), "nx": st.integers(1, 3),
        "ny": st.integers(1, 3), "node_edit": edit, "quad_edit": quad_edit, "ref_axis": axis,
        "plies": plies(2),
        "method": st.sampled_from(["pressure_load", "static", "internal_force", "strain_energy",
                                   "geometric_stiffness", "geometric_stiffness_from", "modes",
                                   "inertia", "matrices"]),
        "scale": number(1e-6, 1e3), "n": count(1, 30),
        "fixed": st.one_of(st.just(list(range(12))), st.lists(count(0, 100), max_size=14),
                           WRONG)})


KINDS = st.one_of(st.sampled_from(["kelvin-voigt-hertz", "paper", "hunt-crossley",
                                   "lankarani-nikravesh", "flores"]), st.text(max_size=5), WRONG)


def law_args():
    return {"kind": KINDS, "K": number(1e4, 1e12), "n": number(1.0, 2.5, log=False),
            "D": st.one_of(st.just(0.0), st.just(0.0), number(1.0, 1e6)),
            "e": st.one_of(st.just(1.0), st.just(1.0), number(0.05, 1.0, log=False))}


def contact_force_case():
    return st.fixed_dictionaries({**law_args(), "delta": number(1e-9, 1e-2),
                                  "delta_dot": number(-1.0, 1.0, log=False),
                                  "v0": st.one_of(st.none(), number(1e-3, 10.0))})


def friction_case():
    return st.fixed_dictionaries({"mu": number(0.0, 1.0, log=False), "v_reg": number(1e-6, 1e-2),
                                  "v_t": number(-1.0, 1.0, log=False),
                                  "F_n": number(-10.0, 1e4, log=False)})


def impact_case():
    return st.fixed_dictionaries({**law_args(), "mass_kg": number(1e-3, 1e3),
                                  "v0_m_s": number(1e-3, 10.0),
                                  "dt_s": st.one_of(st.none(), st.none(), st.none(),
                                                    number(1e-9, 1e-4)),
                                  "record": st.booleans()})


def text_ops():
    op = st.one_of(
        st.tuples(st.just("truncate"), st.floats(0, 1)),
        st.tuples(st.just("insert"), st.floats(0, 1),
                  st.sampled_from(["\n[hinges.lock]\n", "x", "]", "\"", "= 1", "\n", "\x00",
                                   "nan", "inf", "[[hinges]]\n", "{", ","])),
        st.tuples(st.just("delete"), st.floats(0, 1), st.integers(1, 40)),
        st.tuples(st.just("lines"), st.floats(0, 1), st.sampled_from(["drop", "dup", "swap"])),
        st.tuples(st.just("number"), st.floats(0, 1),
                  st.sampled_from(["nan", "inf", "-inf", "1e400", "-1", "0", "1e-320", "0.5",
                                   "99999999999999999999", "1.5", "-0.0", "2147483648"])))
    return st.lists(op, min_size=1, max_size=3)


def scene_file_case():
    return st.fixed_dictionaries({"suffix": st.sampled_from([".toml", ".json"]), "ops": text_ops(),
                                  "keep_check": st.booleans()})


def byte_ops():
    op = st.one_of(
        st.tuples(st.just("truncate"), st.floats(0, 1)),
        st.tuples(st.just("flip"), st.floats(0, 1), st.integers(1, 255)),
        st.tuples(st.just("flip"), st.floats(0.95, 1), st.integers(1, 255)),  # the directory
        st.tuples(st.just("delete"), st.floats(0, 1), st.integers(1, 64)),
        st.tuples(st.just("insert"), st.floats(0, 1), st.sampled_from(["x", "PK\x03\x04", "\x00"])))
    return st.lists(op, min_size=1, max_size=3)


def result_file_case():
    return st.fixed_dictionaries({"ops": byte_ops()})
