"""Fuzz suite of the public API outside the multibody engine (issue 29): materials, plies,
laminates, plates and shell models with their methods, contact laws, friction, the impact, and
scene and result files loaded after random mutations. Every case runs in a child interpreter
(fuzz_harness.py); it must end in a valid finite result or a ValueError/TypeError naming a
parameter. A short derandomized profile runs in the normal ``pytest`` (10 cases per kind, one
child); ``pytest -m fuzz`` runs the long profile, 1000 random cases per kind (11 000 cases)."""
import pytest
from hypothesis import strategies as st

import fuzz_strategies as fs
from fuzz_harness import assert_all_pass, run_cases
from test_fuzz_scene import ENGINE_FINDINGS  # a scene file without its check reaches the builder

KINDS = {
    "isotropic": fs.isotropic_args(),
    "orthotropic": fs.orthotropic_args(),
    "ply": st.fixed_dictionaries({"material": fs.material(), "thickness": fs.number(1e-4, 5e-3),
                                  "angle_deg": fs.number(-180.0, 180.0, log=False)}),
    "laminate": st.fixed_dictionaries({"plies": fs.plies()}),
    "plate": fs.plate_case(),
    "shell": fs.shell_case(),
    "contact_force": fs.contact_force_case(),
    "friction_force": fs.friction_case(),
    "impact": fs.impact_case(),
    "scene_file": fs.scene_file_case(),
    "result_file": fs.result_file_case(),
}
SHORT_PER_KIND = 10
LONG_PER_KIND = 1000  # x 11 kinds (test_fuzz_scene.py adds 2 x 1000)


def test_fuzz_short_profile():
    cases = [c for kind, s in KINDS.items() for c in fs.collect(kind, s, SHORT_PER_KIND)]
    assert_all_pass(run_cases("fuzz_cases_api", cases), ENGINE_FINDINGS)


@pytest.mark.fuzz
@pytest.mark.parametrize("kind", list(KINDS))
def test_fuzz_long_profile(kind):
    cases = fs.collect(kind, KINDS[kind], LONG_PER_KIND, long=True)
    assert_all_pass(run_cases("fuzz_cases_api", cases), ENGINE_FINDINGS)
