"""Fuzz suite of the Scene builder, compile() and simulate() on tiny scenes (issue 29), in child
interpreters (fuzz_harness.py): every case ends in a finite result (a run that stops early keeps
finite series) or a ValueError/TypeError naming a parameter. Short profile in the normal run
(26 cases), long profile (1000 random cases of each kind) with ``pytest -m fuzz``. Kept apart from
test_fuzz_api.py: the engine's API is being rewritten and these strategies follow it.

Inputs that the engine's rewrite handles (issue 29, not yet fixed here) are left out of the
strategies and listed in ENGINE_PENDING; put them back when they are fixed."""
import pytest
from hypothesis import strategies as st

import fuzz_strategies as fs
from fuzz_harness import assert_all_pass, run_cases

#: Left out until the engine checks them (issue 29): t_end / dt beyond what can be stored,
#: pin_radius at denormal sizes, an appendage with every dof clamped.
ENGINE_PENDING = ("t_end, dt extremes", "pin_radius < 1e-300", "all dofs clamped")


#: Findings of this fuzzer in the engine's Python layer, matched here so that they stay visible
#: as xfail until fixed: (regex on "outcome: case JSON\ndetail", description); remove an entry
#: when it is fixed. The three it found (a non-number entry of a 3-vector or of the damping pair
#: naming no parameter, damping=True/None, NaN or inf spring parameters) are refused, naming
#: the parameter, by the frozen specs (deployfx.specs): none is left.
ENGINE_FINDINGS = ()


def vector(lo, hi):
    return fs._mostly(st.lists(st.floats(lo, hi), min_size=3, max_size=3),
                      st.one_of(st.lists(fs.number(lo, hi, log=False), min_size=3, max_size=3),
                                st.lists(st.floats(), min_size=0, max_size=4), fs.WRONG))


BASE = st.fixed_dictionaries({"mass": fs.number(10.0, 1e4), "inertia": fs.number(1.0, 1e3),
                              "free": st.one_of(st.booleans(), st.booleans(), fs.WRONG)})
HINGE = st.fixed_dictionaries({
    "point": vector(-1.0, 1.0),
    "axis": fs._mostly(st.sampled_from([[0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.6, 0.8]]),
                       vector(-1.0, 1.0)),
    "tau0": fs.number(0.0, 20.0, log=False), "k_theta": fs.number(0.0, 10.0, log=False),
    "c_theta": fs.number(0.0, 1.0, log=False), "fitting_inertia": fs.number(1e-3, 1.0)})
FIDELITIES = fs._mostly(st.sampled_from(["rigid", "linear", "nonlinear", "reduced-linear",
                                         "reduced-nonlinear", "reduced-manifold"]),
                        st.one_of(st.text(max_size=4), fs.WRONG))
APPENDAGE = fs._mostly(st.fixed_dictionaries({
    "nx": st.integers(1, 2),
    "fixed": st.one_of(st.just("root"), st.just("root"), st.just("root"),
                       st.lists(fs.count(0, 30), min_size=1, max_size=8), fs.WRONG),
    "fidelity": FIDELITIES,
    "damping": fs._mostly(st.tuples(fs.number(0.0, 2.0, log=False),
                                    fs.number(0.0, 1e-3, log=False)), fs.WRONG),
    "modes": fs.count(1, 6)}), st.none())
LOCK = st.one_of(st.none(), st.fixed_dictionaries({
    "theta_lock": fs.number(0.2, 3.0, log=False),
    "pin_radius": st.one_of(st.floats(1e-300, 1.0), fs.number(1e-3, 0.1)).filter(
        lambda r: not isinstance(r, float) or not 0 < abs(r) < 1e-300),
    "clearance": fs.number(0.0, 1e-3, log=False), "K": fs.number(1e6, 1e12),
    "D": fs.number(0.0, 1e4, log=False), "mu": fs.number(0.0, 0.5, log=False)}))


def _simulable(c):
    """Leave out the ENGINE_PENDING inputs."""
    a = c["appendage"]
    return not (a is not None and isinstance(a["fixed"], list) and len(a["fixed"]) >= 18)


BUILD = st.fixed_dictionaries({"base": BASE, "hinge": HINGE, "appendage": APPENDAGE,
                               "lock": LOCK})
SIMULATE = st.fixed_dictionaries({"base": BASE, "hinge": HINGE, "appendage": APPENDAGE,
                                  "lock": LOCK, "t_end": st.floats(0.005, 0.05),
                                  "dt": st.floats(0.005, 0.02)}).filter(_simulable)


def test_fuzz_scene_short_profile():
    cases = fs.collect("scene_build", BUILD, 20) + fs.collect("scene_simulate", SIMULATE, 6)
    assert_all_pass(run_cases("fuzz_cases_scene", cases, timeout_per_case=120), ENGINE_FINDINGS)


@pytest.mark.fuzz
@pytest.mark.parametrize("kind, strategy", [("scene_build", BUILD), ("scene_simulate", SIMULATE)])
def test_fuzz_scene_long_profile(kind, strategy):
    cases = fs.collect(kind, strategy, 1000, long=True)
    assert_all_pass(run_cases("fuzz_cases_scene", cases, batch=100, timeout_per_case=120),
                    ENGINE_FINDINGS)
