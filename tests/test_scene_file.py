"""Scene files (issue 5): a scene written to JSON or TOML and read back rebuilds a model that gives
bit-identical results; bad files raise ValueError naming the key."""
import copy
import json

import numpy as np
import pytest

import deployfx as dfx
from deployfx import scene_file, scenes
from deployfx.contact import ContactLaw, Friction
from deployfx.scene import Scene

SUFFIXES = (".json", ".toml")


def _assert_same_series(a, b):
    assert a.series == b.series
    for name in a.series:
        np.testing.assert_array_equal(a[name], b[name], err_msg=name)


@pytest.fixture(scope="module")
def paper():
    return scenes.paper2016(2, "linear", nx=4, ny=2)


@pytest.fixture(scope="module")
def paper_run(paper):
    return paper.model.simulate(0.5, 0.01)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_paper_scene_round_trip_gives_identical_results(paper, paper_run, tmp_path, suffix):
    path = dfx.save_scene(paper.scene, tmp_path / f"paper{suffix}")
    loaded = dfx.load_scene(path)
    assert scene_file.scene_to_dict(loaded) == scene_file.scene_to_dict(paper.scene)
    _assert_same_series(loaded.compile().simulate(0.5, 0.01), paper_run)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_lock_law_and_friction_round_trip_through_an_impact(tmp_path, suffix):
    # A rigid panel reaches the lock at ~2.4 s: the contact law and friction act on the result.
    paper = scenes.paper2016(1, "rigid", nx=2, ny=1, friction=Friction(0.3, 2e-4),
                             contact=ContactLaw("hunt-crossley", K=3e10, n=1.5, e=0.7))
    reference = paper.model.simulate(3.0, 0.01)
    assert reference.lock_force.max() > 0
    loaded = dfx.load_scene(dfx.save_scene(paper.scene, tmp_path / f"rigid{suffix}"))
    d = scene_file.scene_to_dict(loaded)
    assert d["lock"]["law"] == {"kind": "hunt-crossley", "K_N_per_m_n": 3e10, "n": 1.5,
                                "D_N_s_per_m": 0.0, "e": 0.7}
    assert d["lock"]["friction"] == {"mu": 0.3, "v_reg_m_per_s": 2e-4}
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
    assert "lock" not in d and d["base"]["free"] is False
    assert d["hinge"]["spin_up"] == {"omega_s_rad_per_s": 2.0, "t_s_s": 15.0}
    assert d["appendage"]["shell"]["plies"][0]["material"]["type"] == "isotropic"
    loaded = dfx.load_scene(dfx.save_scene(scene, tmp_path / f"beam{suffix}"))
    assert scene_file.scene_to_dict(loaded) == d
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
    loaded = dfx.load_scene(dfx.save_scene(scene, tmp_path / "s.toml"))
    d = scene_file.scene_to_dict(loaded)
    assert d["appendage"]["shell"]["ref_axis"] == [1.0, 1.0, 0.0]
    assert len(d["parts"]) == 2 and d["hinge"]["fitting"]["mass_kg"] == 0.3
    assert d == scene_file.scene_to_dict(scene)


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
    assert scene_file.scene_to_dict(scene)["appendage"]["options"]["study_tag"] == 7
    for suffix in SUFFIXES:
        loaded = dfx.load_scene(dfx.save_scene(scene, tmp_path / f"o{suffix}"))
        assert loaded._appendage["study_tag"] == 7
        assert scene_file.scene_to_dict(loaded) == scene_file.scene_to_dict(scene)
    # None is the default: not written.
    scene.set_appendage(strip.model, strip.fixed_dofs("CFFF"), "linear")
    assert "study_tag" not in scene_file.scene_to_dict(scene)["appendage"].get("options", {})


def test_an_option_the_builder_cannot_read_back_is_refused(paper):
    scene = copy.copy(paper.scene)
    scene._appendage = dict(paper.scene._appendage, not_a_parameter=3)
    with pytest.raises(TypeError, match="appendage.not_a_parameter"):
        scene_file.scene_to_dict(scene)


def test_toml_is_readable_text(paper, tmp_path):
    text = dfx.save_scene(paper.scene, tmp_path / "p.toml").read_text()
    for line in ('schema = "deployfx.scene"', "version = 1", "[base]", "mass_kg = 3000.0",
                 "[hinge]", "[appendage.shell]", "[[appendage.shell.plies]]", "[lock]"):
        assert line in text


@pytest.fixture(scope="module")
def good(paper):
    return scene_file.scene_to_dict(paper.scene)


def _broken(good, edit):
    d = copy.deepcopy(good)
    edit(d)
    return d


@pytest.mark.parametrize("edit, match", [
    (lambda d: d.update(version=2), "version = 2 is an unknown"),
    (lambda d: d.update(schema="other"), "schema"),
    (lambda d: d.pop("hinge"), "missing key.*hinge"),
    (lambda d: d["hinge"].pop("axis"), "hinge.axis"),
    (lambda d: d["base"].update(mas_kg=1.0), "base.mas_kg"),
    (lambda d: d["appendage"]["shell"]["nodes_m"].__setitem__(0, [0.0, 0.0]),
     "appendage.shell.nodes_m"),
    (lambda d: d["appendage"]["shell"]["quads"].__setitem__(0, [0, 1, 2, 3.5]),
     "appendage.shell.quads"),
    (lambda d: d["hinge"].update(R_BE0=[1.0, 0.0, 0.0]), "hinge.R_BE0"),
    (lambda d: d["base"].update(mass_kg="heavy"), "base.mass_kg"),
    (lambda d: d["base"].update(free="yes"), "base.free"),
    (lambda d: d["lock"]["law"].pop("K_N_per_m_n"), "lock.law.K_N_per_m_n"),
    (lambda d: d["appendage"]["shell"]["plies"][1]["material"].update(type="steel"),
     r"plies\[1\].material.type"),
    (lambda d: d["appendage"]["shell"]["plies"][0]["material"].pop("G13_Pa"), "G13_Pa"),
    (lambda d: d["appendage"].update(options={"warp": 9}), "appendage.options.warp"),
    (lambda d: d["hinge"].update(axis=[0.0, 2.0, 0.0]), "hinge.axis"),  # the builder's check
])
def test_bad_files_name_the_key(good, edit, match):
    with pytest.raises(ValueError, match=match):
        scene_file.scene_from_dict(_broken(good, edit))


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
    with pytest.raises(ValueError, match="no hinge"):
        scene_file.scene_to_dict(Scene().set_base(1.0, 1.0))
