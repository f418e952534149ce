"""Scene files (issue 5): a scene written to JSON or TOML and read back rebuilds a model that gives
bit-identical results, for one hinge and for chains of hinges (schema version 2; version-1 files
are still read); bad files raise ValueError naming the key."""
import copy
import json

import numpy as np
import pytest

import deployfx as dfx
from deployfx import scene_file, scenes
from deployfx.chain import ChainModel
from deployfx.contact import ContactLaw, Friction
from deployfx.scene import Scene

SUFFIXES = (".json", ".toml")


def _assert_same_series(a, b):
    assert a.series == b.series
    for name in a.series:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


def _round_trip(scene, path):
    """The scene saved to ``path`` and loaded back; its dict must be the original's."""
    loaded = dfx.load_scene(dfx.save_scene(scene, path))
    assert scene_file.scene_to_dict(loaded) == scene_file.scene_to_dict(scene)
    return loaded


def Ry(angle):
    """Rotation by ``angle`` (rad) about y."""
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@pytest.fixture(scope="module")
def paper():
    return scenes.paper2016(2, "linear", nx=4, ny=2)


@pytest.fixture(scope="module")
def paper_run(paper):
    return paper.model.simulate(0.5, 0.01)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_paper_scene_round_trip_gives_identical_results(paper, paper_run, tmp_path, suffix):
    loaded = _round_trip(paper.scene, tmp_path / f"paper{suffix}")
    _assert_same_series(loaded.compile().simulate(0.5, 0.01), paper_run)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_lock_law_and_friction_round_trip_through_an_impact(tmp_path, suffix):
    # A rigid panel reaches the lock at ~2.4 s: the contact law and friction act on the result.
    paper = scenes.paper2016(1, "rigid", nx=2, ny=1, friction=Friction(0.3, 2e-4),
                             contact=ContactLaw("hunt-crossley", K=3e10, n=1.5, e=0.7))
    reference = paper.model.simulate(3.0, 0.01)
    assert reference.lock_force.max() > 0
    loaded = _round_trip(paper.scene, tmp_path / f"rigid{suffix}")
    lock = scene_file.scene_to_dict(loaded)["hinges"][0]["lock"]
    assert lock["law"] == {"kind": "hunt-crossley", "K_N_per_m_n": 3e10, "n": 1.5,
                           "D_N_s_per_m": 0.0, "e": 0.7}
    assert lock["friction"] == {"mu": 0.3, "v_reg_m_per_s": 2e-4}
    _assert_same_series(loaded.compile().simulate(3.0, 0.01), reference)


def _spin_up_scene() -> Scene:
    strip = scenes.spin_up_strip(nx=4)
    return (Scene().set_base(1.0, 1.0, free=False)
            .set_hinge(point=(0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0), spin_up=(2.0, 15.0))
            .set_appendage(strip.model, strip.fixed_dofs("CFFF"), "nonlinear",
                           damping=(0.01, 1e-4)))


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_fixed_base_driven_hinge_isotropic_round_trip(tmp_path, suffix):
    scene = _spin_up_scene()
    d = scene_file.scene_to_dict(scene)
    hinge = d["hinges"][0]
    assert "lock" not in hinge and d["base"]["free"] is False
    assert hinge["spin_up"] == {"omega_s_rad_per_s": 2.0, "t_s_s": 15.0}
    assert hinge["appendage"]["shell"]["plies"][0]["material"]["type"] == "isotropic"
    loaded = _round_trip(scene, tmp_path / f"beam{suffix}")
    _assert_same_series(loaded.compile().simulate(0.2, 0.02), scene.compile().simulate(0.2, 0.02))


def test_ref_axis_and_rigid_parts_are_kept(tmp_path):
    strip = scenes.spin_up_strip(nx=2)
    shell = dfx.ShellModel(strip.model.nodes, strip.model.quads, strip.laminate,
                           ref_axis=(1.0, 1.0, 0.0))
    scene = (Scene().set_base(10.0, np.diag([1.0, 2.0, 3.0]), com=(0.1, 0.0, 0.0))
             .add_rigid_part(1.0, 0.5, (0.2, 0.0, 0.0)).add_rigid_part(2.0, 0.1, (0.0, 0.3, 0.0))
             .set_hinge(point=(0.4, 0.0, 0.0), axis=(0.0, 0.0, 1.0), tau0=1.0, k_theta=0.5,
                        c_theta=0.1, fitting_inertia=np.diag([0.01, 0.02, 0.03]), fitting_mass=0.3,
                        fitting_com=(0.01, 0.0, 0.0))
             .set_appendage(shell, strip.fixed_dofs("CFFF"), "linear"))
    d = scene_file.scene_to_dict(_round_trip(scene, tmp_path / "s.toml"))
    assert d["hinges"][0]["appendage"]["shell"]["ref_axis"] == [1.0, 1.0, 0.0]
    assert [p["mass_kg"] for p in d["parts"]] == [1.0, 2.0]
    assert d["hinges"][0]["fitting"]["mass_kg"] == 0.3 and d["hinges"][0]["parts"] == []


def test_unknown_appendage_options_round_trip(tmp_path, monkeypatch):
    # A builder option this module does not know (as "modes" for a reduced fidelity would be)
    # is written generically and passed back to set_appendage by keyword.
    original = Scene.set_appendage

    def set_appendage(self, shell, fixed_dofs, fidelity="nonlinear", damping=(0.0, 0.0),
                      study_tag=None, **others):
        original(self, shell, fixed_dofs, fidelity, damping, **others)
        self._appendage["study_tag"] = study_tag
        return self

    monkeypatch.setattr(Scene, "set_appendage", set_appendage)
    strip = scenes.spin_up_strip(nx=2)
    scene = (Scene().set_base(1.0, 1.0, free=False).set_hinge((0.0, 0.0, 0.0), (0.0, 1.0, 0.0))
             .set_appendage(strip.model, strip.fixed_dofs("CFFF"), "linear", study_tag=7))
    assert scene_file.scene_to_dict(scene)["hinges"][0]["appendage"]["options"]["study_tag"] == 7
    for suffix in SUFFIXES:
        loaded = _round_trip(scene, tmp_path / f"o{suffix}")
        assert loaded._appendage["study_tag"] == 7
    # None is the default: not written.
    scene.set_appendage(strip.model, strip.fixed_dofs("CFFF"), "linear")
    appendage = scene_file.scene_to_dict(scene)["hinges"][0]["appendage"]
    assert "study_tag" not in appendage.get("options", {})


def test_an_option_the_builder_cannot_read_back_is_refused(paper):
    scene = copy.copy(paper.scene)
    scene._appendage = dict(paper.scene._appendage, not_a_parameter=3)
    with pytest.raises(TypeError, match=r"hinges\[0\].appendage.not_a_parameter cannot be written: "
                                        r"Scene.set_appendage has no parameter 'not_a_parameter'"):
        scene_file.scene_to_dict(scene)
    # hinge= is given by the hinge's place in the file, never as an option.
    scene._lock = dict(paper.scene._lock, hinge=0)
    scene._appendage = paper.scene._appendage
    with pytest.raises(TypeError, match=r"hinges\[0\].lock.hinge cannot be written: the file gives "
                                        r"Scene.set_lock's 'hinge' itself"):
        scene_file.scene_to_dict(scene)


def test_toml_is_readable_text(paper, tmp_path):
    text = dfx.save_scene(paper.scene, tmp_path / "p.toml").read_text()
    for line in ('schema = "deployfx.scene"', "version = 2", "[base]", "mass_kg = 3000.0",
                 "[[hinges]]", 'parent = "base"', "[hinges.appendage.shell]",
                 "[[hinges.appendage.shell.plies]]", "[hinges.lock]"):
        assert line in text


# ------------------------------------------------------------------------------------------------
# Chains of hinges: a yoke and panels, rigid parts on hinges' bodies

def _panel(length=0.6, width=0.4, offset=0.02):
    """An aluminium panel (2 mm, 2 x 1 elements), root edge ``offset`` m from its hinge axis."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    plate = dfx.Plate(length, width, lam, nx=2, ny=1)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += offset
    nodes[:, 1] -= width / 2
    return dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")


LAW = ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4)


def _chain_scene(panels=2, fidelity="rigid"):
    """A free base with a part, a yoke (two rigid parts on hinge 0's body, no appendage) and
    ``panels`` panels folded like an accordion; every hinge its own spring, damper, fitting and
    lock (the last panel's hinge without one), a balance mass on panel 1's body."""
    shell, root = _panel()
    scene = (Scene().set_base(300.0, np.diag([50.0, 60.0, 40.0]), com=(0.0, 0.0, 0.05))
             .add_rigid_part(5.0, 0.3, (0.2, 0.0, 0.1))
             .add_hinge("base", point=(0.4, 0.0, 0.0), axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2),
                        tau0=4.0, k_theta=0.3, c_theta=0.05, fitting_inertia=0.005)
             .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (0.3, 0.0, 0.0), body=0)
             .add_rigid_part(0.2, 0.001, (0.55, 0.0, 0.0), body=0)
             .set_lock(np.pi / 2, 0.025, 1e-4, LAW, Friction(0.2), hinge=0))
    for k in range(1, panels + 1):
        axis = (0, 1, 0) if k % 2 else (0, -1, 0)
        point = (0.6, 0.0, 0.0) if k == 1 else (0.64, 0.0, 0.0)
        scene.add_hinge(k - 1, point=point, axis=axis, R_PE0=Ry(np.pi), tau0=1.5 / k,
                        k_theta=0.1 * k, c_theta=0.02 * k, fitting_inertia=0.004 + 0.001 * k,
                        fitting_mass=0.05 * k, fitting_com=(0.01, 0.0, 0.0))
        scene.set_appendage(shell, root, fidelity)
        if k < panels:
            scene.set_lock(np.pi, 0.025, 1e-4, LAW, Friction(0.1 * k))
    scene.add_rigid_part(0.3, 0.002, (0.3, 0.1, 0.0), body=1)  # after hinge 2: by index
    return scene


@pytest.mark.parametrize("panels", [2, 3])
@pytest.mark.parametrize("suffix", SUFFIXES)
def test_chain_round_trip_gives_identical_results(tmp_path, suffix, panels):
    scene = _chain_scene(panels)
    d = scene_file.scene_to_dict(scene)
    hinges = d["hinges"]
    assert [h["parent"] for h in hinges] == ["base"] + list(range(panels))
    assert [len(h["parts"]) for h in hinges] == [2, 1] + [0] * (panels - 1)
    assert "appendage" not in hinges[0]
    assert all(h["appendage"]["fidelity"] == "rigid" for h in hinges[1:])
    mu = [h["lock"]["friction"]["mu"] for h in hinges[:-1]]
    assert mu == [0.2] + [0.1 * k for k in range(1, panels)]
    assert "lock" not in hinges[-1]
    assert [h["tau0_N_m"] for h in hinges] == [4.0] + [1.5 / k for k in range(1, panels + 1)]
    assert hinges[2]["axis"] == [0.0, -1.0, 0.0] and hinges[1]["R_PE0"] == Ry(np.pi).tolist()

    loaded = _round_trip(scene, tmp_path / f"array{suffix}")
    model = loaded.compile()
    assert isinstance(model, ChainModel) and model.num_hinges == panels + 1
    assert model.locks == (True,) * panels + (False,)
    reference = scene.compile().simulate(0.3, 0.01)
    assert np.all(np.abs(reference.deployment_angle[-1]) > 1.0)  # every hinge moved (deg)
    _assert_same_series(model.simulate(0.3, 0.01), reference)


def _notebook_chain() -> Scene:
    """The chain of notebooks/02_build_your_own_scene.ipynb ("A chain: a yoke and two panels"),
    as it is built there, without the compile()."""
    laminate = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 3e-3)])
    P_LENGTH, P_WIDTH, OFFSET, YOKE_LENGTH = 0.6, 0.4, 0.02, 0.6
    small = dfx.Plate(P_LENGTH, P_WIDTH, laminate, nx=4, ny=2)
    panel_nodes = small.model.nodes.copy()
    panel_nodes[:, 0] += OFFSET
    panel_nodes[:, 1] -= P_WIDTH / 2
    panel = dfx.ShellModel(panel_nodes, small.model.quads, laminate)
    panel_root = small.fixed_dofs("CFFF")
    PIN_RADIUS, CLEARANCE, FRICTION = 0.025, 0.1e-3, Friction(0.2)
    SPRING = {"c_theta": 0.05, "fitting_inertia": 0.005}
    return (Scene()
            .set_base(mass=300.0, inertia=50.0)
            .add_hinge("base", point=(0.4, 0.0, 0.0), axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2),
                       tau0=4.0, k_theta=0.3, **SPRING)
            .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (YOKE_LENGTH / 2, 0.0, 0.0),
                            body=0)
            .set_lock(np.pi / 2, PIN_RADIUS, CLEARANCE, LAW, FRICTION)
            .add_hinge(0, point=(YOKE_LENGTH, 0.0, 0.0), axis=(0, 1, 0), R_PE0=Ry(np.pi),
                       tau0=1.5, k_theta=0.1, **SPRING)
            .set_appendage(panel, panel_root, "rigid")
            .set_lock(np.pi, PIN_RADIUS, CLEARANCE, LAW, FRICTION)
            .add_hinge(1, point=(P_LENGTH + 2 * OFFSET, 0.0, 0.0), axis=(0, -1, 0), R_PE0=Ry(np.pi),
                       tau0=0.5, k_theta=0.1, **SPRING)
            .set_appendage(panel, panel_root, "rigid")
            .set_lock(np.pi, PIN_RADIUS, CLEARANCE, LAW, FRICTION))


def test_notebook_chain_saves_and_loads(tmp_path):
    scene = _notebook_chain()
    reference = scene.compile().simulate(0.4, 0.01)
    for suffix in SUFFIXES:
        loaded = _round_trip(scene, tmp_path / f"notebook_array{suffix}")
        _assert_same_series(loaded.compile().simulate(0.4, 0.01), reference)
    text = (tmp_path / "notebook_array.toml").read_text()
    assert text.count("[[hinges]]") == 3 and text.count("[[hinges.parts]]") == 1
    assert "parent = 0" in text and "parent = 1" in text


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_one_hinge_with_parts_on_its_body_round_trip(tmp_path, suffix):
    # A flexible panel with fittings on its body (merged with the hinge's fitting): a Model.
    shell, root = _panel()
    scene = (Scene().set_base(50.0, 8.0)
             .set_hinge(point=(0.3, 0.0, 0.0), axis=(0, 1, 0), R_BE0=Ry(-np.pi / 2), tau0=1.0,
                        k_theta=0.2, fitting_inertia=0.002)
             .add_rigid_part(0.2, 0.001, (0.05, 0.0, 0.0), body=0)
             .set_appendage(shell, root, "linear", damping=(0.01, 1e-4))
             .add_rigid_part(0.1, np.diag([1e-4, 2e-4, 3e-4]), (0.3, 0.1, 0.0), body=0))
    parts = scene_file.scene_to_dict(scene)["hinges"][0]["parts"]
    assert [p["mass_kg"] for p in parts] == [0.2, 0.1]
    loaded = _round_trip(scene, tmp_path / f"fitted{suffix}")
    model = loaded.compile()
    assert isinstance(model, dfx.Model) and model.fidelity == "linear"
    _assert_same_series(model.simulate(0.3, 0.01), scene.compile().simulate(0.3, 0.01))


def test_yoke_alone_round_trip(tmp_path):
    # One hinge carrying rigid parts only: a chain of one, without an appendage.
    scene = (Scene().set_base(1.0, 1.0, free=False)
             .add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0), tau0=0.5, c_theta=0.01)
             .add_rigid_part(2.0, np.diag([0.01, 0.2, 0.2]), (0.3, 0, 0), body=0))
    loaded = _round_trip(scene, tmp_path / "yoke.toml")
    assert "appendage" not in scene_file.scene_to_dict(loaded)["hinges"][0]
    model = loaded.compile()
    assert isinstance(model, ChainModel) and model.num_hinges == 1
    _assert_same_series(model.simulate(0.2, 0.01), scene.compile().simulate(0.2, 0.01))


def test_a_chain_compile_refuses_is_written_and_refused_alike(tmp_path):
    # The builder expresses a flexible panel in a chain; compile() refuses it, before and after.
    scene = _chain_scene(2, fidelity="linear")
    loaded = _round_trip(scene, tmp_path / "flexible_chain.json")
    message = r"hinges\[1\] appendage fidelity = 'linear' is not supported in a chain"
    for s in (scene, loaded):
        with pytest.raises(ValueError, match=message):
            s.compile()


def test_a_spin_up_on_a_chain_hinge_cannot_be_written():
    scene = _chain_scene(2)
    link = scene._links[1]
    scene._links[1] = dict(link, hinge=dict(link["hinge"], spin_up=(1.0, 2.0)))
    with pytest.raises(ValueError, match=(r"hinges\[1\].spin_up cannot be written: a prescribed "
                                          r"hinge angle is for hinge 0 \(Scene.set_hinge\) only")):
        scene_file.scene_to_dict(scene)


# ------------------------------------------------------------------------------------------------
# Version 1 (one hinge; written by deployfx before chains) is still read

# What the version-1 scene_file module wrote for the scene of _version_1_scene() (its JSON, laid out
# more compactly; the informative units string shortened).
VERSION_1_JSON = """{
  "schema": "deployfx.scene",
  "version": 1,
  "units": "SI: m, kg, s, rad, N, Pa",
  "base": {"free": true, "mass_kg": 50.0, "com_m": [0.01, 0.0, 0.0],
           "inertia_kg_m2": [[5.0, 0.0, 0.0], [0.0, 6.0, 0.0], [0.0, 0.0, 7.0]]},
  "parts": [{"mass_kg": 1.5, "com_m": [0.1, 0.0, 0.0],
             "inertia_kg_m2": [[0.02, 0.0, 0.0], [0.0, 0.02, 0.0], [0.0, 0.0, 0.02]]}],
  "hinge": {
    "point_m": [0.2, 0.0, 0.0], "axis": [0.0, 1.0, 0.0],
    "R_BE0": [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    "tau0_N_m": 0.5, "k_theta_N_m_per_rad": 0.1, "c_theta_N_m_s_per_rad": 0.01,
    "fitting": {"mass_kg": 0.1, "com_m": [0.01, 0.0, 0.0],
                "inertia_kg_m2": [[0.001, 0.0, 0.0], [0.0, 0.001, 0.0], [0.0, 0.0, 0.001]]}
  },
  "appendage": {
    "fidelity": "linear",
    "fixed_dofs": [0, 1, 2, 3, 4, 5, 12, 13, 14, 15, 16, 17],
    "alpha_M_per_s": 0.01, "beta_K_s": 0.0001,
    "shell": {
      "nodes_m": [[0.02, -0.1, 0.0], [0.32, -0.1, 0.0], [0.02, 0.1, 0.0], [0.32, 0.1, 0.0]],
      "quads": [[0, 1, 3, 2]],
      "ref_axis": [1.0, 0.0, 0.0],
      "plies": [{"thickness_m": 0.002, "angle_deg": 0.0,
                 "material": {"type": "isotropic", "E_Pa": 70000000000.0, "nu": 0.33,
                              "rho_kg_per_m3": 2700.0}}]
    },
    "options": {"modes": 10}
  },
  "lock": {
    "theta_lock_rad": 0.5, "pin_radius_m": 0.02, "clearance_m": 0.0001,
    "law": {"kind": "hunt-crossley", "K_N_per_m_n": 1000000000.0, "n": 1.5, "D_N_s_per_m": 0.0,
            "e": 0.8},
    "friction": {"mu": 0.2, "v_reg_m_per_s": 0.0001}
  }
}
"""


def _version_1_scene() -> Scene:
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    nodes = [[0.02, -0.1, 0.0], [0.32, -0.1, 0.0], [0.02, 0.1, 0.0], [0.32, 0.1, 0.0]]
    shell = dfx.ShellModel(nodes, [[0, 1, 3, 2]], lam)
    return (Scene().set_base(50.0, np.diag([5.0, 6.0, 7.0]), com=(0.01, 0.0, 0.0))
            .add_rigid_part(1.5, 0.02, (0.1, 0.0, 0.0))
            .set_hinge(point=(0.2, 0.0, 0.0), axis=(0.0, 1.0, 0.0), tau0=0.5, k_theta=0.1,
                       c_theta=0.01, fitting_inertia=0.001, fitting_mass=0.1,
                       fitting_com=(0.01, 0.0, 0.0))
            .set_appendage(shell, list(range(6)) + list(range(12, 18)), "linear",
                           damping=(0.01, 1e-4))
            .set_lock(0.5, 0.02, 1e-4, ContactLaw("hunt-crossley", K=1e9, e=0.8), Friction(0.2)))


def test_version_1_file_is_read(tmp_path):
    path = tmp_path / "old.json"
    path.write_text(VERSION_1_JSON)
    loaded = dfx.load_scene(path)
    scene = _version_1_scene()
    d = scene_file.scene_to_dict(loaded)
    assert d == scene_file.scene_to_dict(scene) and d["version"] == 2
    reference = scene.compile().simulate(0.3, 0.01)
    assert reference.lock_force.max() > 0  # the lock law and friction act
    _assert_same_series(loaded.compile().simulate(0.3, 0.01), reference)


def _as_version_1(d: dict) -> dict:
    """A one-hinge version-2 dict (no parts on the hinge's body) in version 1's layout."""
    d = copy.deepcopy(d)
    (h,) = d.pop("hinges")
    assert h.pop("parent") == "base" and h.pop("parts") == []
    h["R_BE0"] = h.pop("R_PE0")
    d.update(version=1, hinge=h, appendage=h.pop("appendage"))
    if "lock" in h:
        d["lock"] = h.pop("lock")
    return d


def test_version_1_spin_up_and_paper_dicts_are_read(paper):
    for scene in (_spin_up_scene(), paper.scene):
        d = scene_file.scene_to_dict(scene)
        assert scene_file.scene_to_dict(scene_file.scene_from_dict(_as_version_1(d))) == d


@pytest.mark.parametrize("edit, match", [
    (lambda d: d["hinge"].pop("axis"), r"hinge is missing key\(s\) hinge.axis$"),
    (lambda d: d["hinge"].update(R_PE0=d["hinge"].pop("R_BE0")),
     r"hinge is missing key\(s\) hinge.R_BE0$"),
    (lambda d: d["hinge"].update(axis=[0.0, 2.0, 0.0]),
     r"^hinge.axis = \[0.0, 2.0, 0.0\] must be a unit vector$"),
    (lambda d: d["appendage"].update(fidelity="stiff"),
     r"^appendage: fidelity = 'stiff' is invalid: must be one of rigid, linear, nonlinear"),
    (lambda d: d["lock"]["law"].pop("K_N_per_m_n"), r"lock.law.K_N_per_m_n$"),
    (lambda d: d.update(hinges=[]), r"scene file has unknown key\(s\) hinges; allowed: schema"),
])
def test_bad_version_1_files_name_the_key(edit, match):
    d = json.loads(VERSION_1_JSON)
    edit(d)
    with pytest.raises(ValueError, match=match):
        scene_file.scene_from_dict(d)


# ------------------------------------------------------------------------------------------------
# Bad files

@pytest.fixture(scope="module")
def good(paper):
    return scene_file.scene_to_dict(paper.scene)


@pytest.fixture(scope="module")
def good_chain():
    return scene_file.scene_to_dict(_chain_scene(2))


def _broken(good, edit):
    d = copy.deepcopy(good)
    edit(d)
    return d


def _h(d, k=0):
    return d["hinges"][k]


@pytest.mark.parametrize("edit, match", [
    (lambda d: d.update(version=3), (r"^version = 3 is an unknown scene-file schema version; "
                                     r"this deployfx reads versions 1 and 2$")),
    (lambda d: d.update(version="2"), r"^version = '2' is an unknown"),
    (lambda d: d.update(schema="other"), r"^schema = 'other' is not a deployfx scene"),
    (lambda d: d.pop("version"), r"^scene file is missing key\(s\) version$"),
    (lambda d: d.pop("hinges"), r"^scene file is missing key\(s\) hinges$"),
    (lambda d: d.update(hinge={}), (r"^scene file has unknown key\(s\) hinge; allowed: schema, "
                                    r"version, base, hinges, units, parts$")),
    (lambda d: _h(d).pop("axis"), r"^hinges\[0\] is missing key\(s\) hinges\[0\].axis$"),
    (lambda d: d["base"].update(mas_kg=1.0), r"base.mas_kg"),
    (lambda d: _h(d)["appendage"]["shell"]["nodes_m"].__setitem__(0, [0.0, 0.0]),
     r"^hinges\[0\].appendage.shell.nodes_m must be n x 3 numbers"),
    (lambda d: _h(d)["appendage"]["shell"]["quads"].__setitem__(0, [0, 1, 2, 3.5]),
     r"^hinges\[0\].appendage.shell.quads must be n x 4 integers"),
    (lambda d: _h(d).update(R_PE0=[1.0, 0.0, 0.0]), r"^hinges\[0\].R_PE0 must be 3 x 3 numbers"),
    (lambda d: d["base"].update(mass_kg="heavy"), r"^base.mass_kg must be a number, got str"),
    (lambda d: d["base"].update(free="yes"), r"^base.free must be true or false"),
    (lambda d: _h(d)["lock"]["law"].pop("K_N_per_m_n"),
     r"^hinges\[0\].lock.law is missing key\(s\) hinges\[0\].lock.law.K_N_per_m_n$"),
    (lambda d: _h(d)["appendage"]["shell"]["plies"][1]["material"].update(type="steel"),
     r"^hinges\[0\].appendage.shell.plies\[1\].material.type must be 'isotropic' or 'orthotropic'"),
    (lambda d: _h(d)["appendage"]["shell"]["plies"][0]["material"].pop("G13_Pa"), "G13_Pa"),
    (lambda d: _h(d)["appendage"].update(options={"warp": 9}),
     r"^hinges\[0\].appendage.options.warp: Scene.set_appendage has no parameter 'warp'"),
    # the builder's checks, prefixed with the file's table
    (lambda d: _h(d).update(axis=[0.0, 2.0, 0.0]),
     r"^hinges\[0\]: hinge.axis = \[0.0, 2.0, 0.0\] must be a unit vector$"),
    (lambda d: _h(d)["appendage"]["shell"]["plies"][0]["material"].update(E1_Pa=-1.0),
     r"^hinges\[0\].appendage.shell.plies\[0\]: Orthotropic.E1 = -1 is out of range"),
])
def test_bad_files_name_the_key(good, edit, match):
    with pytest.raises(ValueError, match=match):
        scene_file.scene_from_dict(_broken(good, edit))


@pytest.mark.parametrize("edit, match", [
    (lambda d: d.update(hinges=[]),
     r"^hinges must hold at least one hinge \(hinge 0, on the base\)$"),
    (lambda d: d.update(hinges={"0": {}}), r"^hinges must be a list of tables"),
    (lambda d: _h(d).update(parent=0), r"^hinges\[0\].parent = 0 is out of range: must be 'base'"),
    (lambda d: _h(d, 2).update(parent=0),
     (r"^hinges\[2\].parent = 0 is out of range: must be 1 \(hinge 2 is on the body of hinge 1: "
      r"deployfx builds serial chains\)$")),
    (lambda d: _h(d, 1).update(parent="base"),
     r"^hinges\[1\].parent = 'base' is out of range: must be 0"),
    (lambda d: _h(d, 1).update(parent=True), r"^hinges\[1\].parent = True is out of range"),
    (lambda d: _h(d, 1).pop("parent"), r"^hinges\[1\] is missing key\(s\) hinges\[1\].parent$"),
    (lambda d: _h(d, 2).update(spin_up={"omega_s_rad_per_s": 1.0, "t_s_s": 1.0}),
     r"^hinges\[2\].spin_up is not allowed: a prescribed hinge angle is for hinge 0 only"),
    (lambda d: _h(d, 1).update(yoke=1.0),
     (r"^hinges\[1\] has unknown key\(s\) hinges\[1\].yoke; allowed: parent, point_m, axis, "
      r"R_PE0, tau0_N_m, k_theta_N_m_per_rad, c_theta_N_m_s_per_rad, fitting, options, parts, "
      r"appendage, lock$")),
    (lambda d: _h(d, 0)["parts"][1].pop("com_m"),
     r"^hinges\[0\].parts\[1\] is missing key\(s\) hinges\[0\].parts\[1\].com_m$"),
    (lambda d: _h(d, 0)["parts"][0].update(mass_kg=-1.0),
     r"^hinges\[0\].parts\[0\]: part.mass = -1.0 is out of range: must be >= 0 \(kg\)$"),
    (lambda d: _h(d, 1).update(parts={}), r"^hinges\[1\].parts must be a list of tables"),
    (lambda d: d["parts"][0].update(inertia_kg_m2=[[1.0, 2.0, 0.0], [0.0, 1.0, 0.0],
                                                   [0.0, 0.0, 1.0]]),
     r"^parts\[0\]: part.inertia must be symmetric positive semidefinite"),
    (lambda d: _h(d, 1).update(axis=[0.0, 2.0, 0.0]),
     r"^hinges\[1\].axis = \[0.0, 2.0, 0.0\] must be a unit vector$"),
    (lambda d: _h(d, 2).update(R_PE0=[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
     r"^hinges\[2\].R_PE0 must be a rotation matrix$"),
    (lambda d: _h(d, 1)["appendage"].update(fidelity="stiff"),
     r"^hinges\[1\].appendage: fidelity = 'stiff' is invalid: must be one of rigid, linear"),
    (lambda d: _h(d, 1)["lock"]["law"].update(kind="bogus"),
     r"^hinges\[1\].lock.law: contact.kind = 'bogus' is not one of"),
    (lambda d: _h(d, 0)["lock"]["friction"].update(mu=-0.1),
     r"^hinges\[0\].lock.friction: friction.mu = -0.1 is out of range: must be >= 0$"),
    (lambda d: _h(d, 1)["appendage"].update(options={"hinge": 0}),
     r"^hinges\[1\].appendage.options.hinge is not an option: the file gives 'hinge' itself"),
    (lambda d: _h(d, 1).update(options={"parent": 0}),
     r"^hinges\[1\].options.parent is not an option: the file gives 'parent' itself"),
    (lambda d: _h(d, 2).update(options={"spin_up": [1.0, 1.0]}),
     r"^hinges\[2\].options.spin_up: Scene.add_hinge has no parameter 'spin_up'"),
])
def test_bad_chain_files_name_the_key(good_chain, edit, match):
    with pytest.raises(ValueError, match=match):
        scene_file.scene_from_dict(_broken(good_chain, edit))


def test_bad_paths_and_text(paper, tmp_path):
    with pytest.raises(ValueError, match="path"):
        dfx.save_scene(paper.scene, tmp_path / "scene.yaml")
    with pytest.raises(ValueError, match="path"):
        dfx.load_scene(tmp_path / "scene.txt")
    (tmp_path / "bad.toml").write_text("version = = 1\n")
    with pytest.raises(ValueError, match="not a valid TOML"):
        dfx.load_scene(tmp_path / "bad.toml")
    (tmp_path / "bad.json").write_text(json.dumps([1, 2]))
    with pytest.raises(ValueError, match="must be a table"):
        dfx.load_scene(tmp_path / "bad.json")
    with pytest.raises(TypeError, match="scene"):
        scene_file.scene_to_dict(paper.model)
    assert scene_file.scene_to_dict(paper) == scene_file.scene_to_dict(paper.scene)
    with pytest.raises(ValueError, match=r"^the scene has no hinge: call set_hinge\(\)"):
        scene_file.scene_to_dict(Scene().set_base(1.0, 1.0))
    with pytest.raises(ValueError, match=r"^the scene has no base: call set_base\(\) first$"):
        scene_file.scene_to_dict(Scene())
