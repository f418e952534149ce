"""Scene files (issue 5): a scene written to JSON or TOML and read back rebuilds a model that gives
bit-identical results, for one hinge, chains and trees of hinges (schema version 3); files of
versions 1 and 2, written here by hand as those versions' writers laid them out, are still read;
bad files raise ValueError naming the key.

The reference of a round trip is the original scene itself: the loaded scene's dict must equal the
original's and its run must give the same bits in every series. A prescribed hinge angle read back
is checked against its closed form (Kane, Ryan & Banerjee 1987).
"""
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
    # The stop-and-latch lock: its [hinges.lock] table is what versions 1-3 wrote (the default
    # groove's [hinges.groove], version 4, is checked in tests/test_groove_lock.py).
    return scenes.paper2016(2, "linear", nx=4, ny=2, lock_geometry="stop-latch")


@pytest.fixture(scope="module")
def paper_run(paper):
    return paper.model.simulate(0.5, 0.01)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_paper_scene_round_trip_gives_identical_results(paper, paper_run, tmp_path, suffix):
    loaded = _round_trip(paper.scene, tmp_path / f"paper{suffix}")
    hinge = scene_file.scene_to_dict(loaded)["hinges"][0]
    assert hinge["stowed_angle_deg"] == 90.0 and hinge["appendage"]["modes"] == 10
    assert "derivative_modes" not in hinge["appendage"]  # None: left out
    run = loaded.compile().simulate(0.5, 0.01)
    assert run.deployment_angle[0, 0] == 90.0  # the stowed angle is read back
    _assert_same_series(run, paper_run)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_lock_law_and_friction_round_trip_through_an_impact(tmp_path, suffix):
    # A rigid panel reaches the lock at ~2.4 s: the contact law and friction act on the result.
    paper = scenes.paper2016(1, "rigid", nx=2, ny=1, friction=Friction(0.3, 2e-4), lock_geometry="stop-latch",
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
            .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="nonlinear",
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
             .set_appendage(shell, strip.fixed_dofs("CFFF"), fidelity="linear"))
    d = scene_file.scene_to_dict(_round_trip(scene, tmp_path / "s.toml"))
    assert d["hinges"][0]["appendage"]["shell"]["ref_axis"] == [1.0, 1.0, 0.0]
    assert [p["mass_kg"] for p in d["parts"]] == [1.0, 2.0]
    assert d["hinges"][0]["fitting"]["mass_kg"] == 0.3 and d["hinges"][0]["parts"] == []


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_reduced_panel_modes_round_trip_by_name(tmp_path, suffix):
    # The Ritz basis' size is part of the model: modes, derivative_modes and derivative_partners
    # are named keys of the appendage (version 3), and the loaded model has the same basis and the
    # same run.
    strip = scenes.spin_up_strip(nx=4)
    scene = (Scene().set_base(1.0, 1.0, free=False)
             .set_hinge(point=(0.0, 0.0, 0.0), axis=(0.0, 1.0, 0.0), spin_up=(2.0, 15.0))
             .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="reduced-nonlinear",
                            modes=4, derivative_modes=2, derivative_partners=1))
    appendage = scene_file.scene_to_dict(scene)["hinges"][0]["appendage"]
    assert (appendage["fidelity"], appendage["modes"], appendage["derivative_modes"],
            appendage["derivative_partners"]) == ("reduced-nonlinear", 4, 2, 1)
    assert "options" not in appendage
    loaded = _round_trip(scene, tmp_path / f"reduced{suffix}")
    model, reference = loaded.compile(), scene.compile()
    info, expected = model.basis_info(0), reference.basis_info(0)
    assert info["modes"] == 4 and info.keys() == expected.keys()
    for key in info:
        np.testing.assert_array_equal(info[key], expected[key], err_msg=key)
    np.testing.assert_array_equal(model.basis(0), reference.basis(0))
    _assert_same_series(model.simulate(0.3, 0.02), reference.simulate(0.3, 0.02))


def test_toml_is_readable_text(paper, tmp_path):
    text = dfx.save_scene(paper.scene, tmp_path / "p.toml").read_text()
    for line in ('schema = "deployfx.scene"', "version = 4", "[base]", "mass_kg = 3000.0",
                 "[[hinges]]", 'parent = "base"', "stowed_angle_deg = 90.0", "modes = 10",
                 "[hinges.appendage.shell]", "[[hinges.appendage.shell.plies]]", "[hinges.lock]"):
        assert line in text
    assert "options" not in text and "R_PE0" not in text


# ------------------------------------------------------------------------------------------------
# Chains and trees of hinges: a yoke and panels, rigid parts on hinges' bodies, two wings

def _panel(length=0.6, width=0.4, offset=0.02, nx=2, ny=1):
    """An aluminium panel (2 mm, nx x ny elements), root edge ``offset`` m from its hinge axis."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    plate = dfx.Plate(length, width, lam, nx=nx, ny=ny)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += offset
    nodes[:, 1] -= width / 2
    return dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")


LAW = ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4)


def _chain_scene(panels=2, fidelity="rigid"):
    """A free base with a part, a yoke (two rigid parts on hinge 0's body, no appendage) and
    ``panels`` panels folded like an accordion, each hinge on the previous one's body; every hinge
    its own spring, damper, fitting and lock (the last panel's hinge without one), a balance mass
    on panel 1's body."""
    shell, root = _panel()
    scene = (Scene().set_base(300.0, np.diag([50.0, 60.0, 40.0]), com=(0.0, 0.0, 0.05))
             .add_rigid_part(5.0, 0.3, (0.2, 0.0, 0.1))
             .add_hinge("base", point=(0.4, 0.0, 0.0), axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2),
                        tau0=4.0, k_theta=0.3, c_theta=0.05, fitting_inertia=0.005)
             .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (0.3, 0.0, 0.0), body=0)
             .add_rigid_part(0.2, 0.001, (0.55, 0.0, 0.0), body=0)
             .set_lock(np.pi / 2, 0.025, 1e-4, LAW, friction=Friction(0.2), hinge=0))
    for k in range(1, panels + 1):
        axis = (0, 1, 0) if k % 2 else (0, -1, 0)
        point = (0.6, 0.0, 0.0) if k == 1 else (0.64, 0.0, 0.0)
        scene.add_hinge(k - 1, point=point, axis=axis, R_PE0=Ry(np.pi), tau0=1.5 / k,
                        k_theta=0.1 * k, c_theta=0.02 * k, fitting_inertia=0.004 + 0.001 * k,
                        fitting_mass=0.05 * k, fitting_com=(0.01, 0.0, 0.0))
        scene.set_appendage(shell, root, fidelity=fidelity, damping=(0.3, 0.0), modes=3)
        if k < panels:
            scene.set_lock(np.pi, 0.025, 1e-4, LAW, friction=Friction(0.1 * k))
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
    assert hinges[2]["axis"] == [0.0, -1.0, 0.0] and hinges[1]["R_PC0"] == Ry(np.pi).tolist()

    loaded = _round_trip(scene, tmp_path / f"array{suffix}")
    model = loaded.compile()
    assert isinstance(model, dfx.Model) and model.num_hinges == panels + 1
    assert model.locks == (True,) * panels + (False,)
    reference = scene.compile().simulate(0.3, 0.01)
    assert np.all(np.abs(reference.deployment_angle[-1]) > 1.0)  # every hinge moved (deg)
    _assert_same_series(model.simulate(0.3, 0.01), reference)


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_paper_scene_with_two_wings_round_trips(tmp_path, suffix):
    # Two hinges on the base (a tree): the second wing is the first's mirror image.
    paper = scenes.paper2016(2, "rigid", nx=2, ny=1, wings=2)
    hinges = scene_file.scene_to_dict(paper.scene)["hinges"]
    assert [h["parent"] for h in hinges] == ["base", "base"]
    assert hinges[0]["axis"] == [0.0, 1.0, 0.0] and hinges[1]["axis"] == [0.0, -1.0, 0.0]
    assert [h["stowed_angle_deg"] for h in hinges] == [90.0, 90.0]
    loaded = _round_trip(paper.scene, tmp_path / f"wings{suffix}")
    model = loaded.compile()
    assert model.num_hinges == 2 and [model.layout(k)["parent"] for k in (0, 1)] == [-1, -1]
    _assert_same_series(model.simulate(0.5, 0.01), paper.model.simulate(0.5, 0.01))


def _tree_scene() -> Scene:
    """Hinges declared out of branch order: two yokes on a free base (hinges 0 and 1), a full
    nonlinear panel on yoke 0 (hinge 2), a linear panel riding on that panel's mesh (hinge 3, a
    tilted axis), a reduced-nonlinear panel on yoke 1 (hinge 4); rigid parts added to earlier
    bodies by index after later hinges."""
    shell, root = _panel(nx=2, ny=2)
    s = (Scene().set_base(300.0, 50 * np.diag([1.0, 1.2, 0.9]), com=(0.1, -0.05, 0.02))
         .add_hinge("base", (0.4, 0.0, 0.0), (0, 1, 0), R_PE0=Ry(-np.pi / 2), tau0=2.0, k_theta=0.3,
                    fitting_inertia=0.01)
         .add_hinge("base", (-0.4, 0.0, 0.1), (0, -1, 0), R_PE0=Ry(np.pi - 0.2), tau0=2.0,
                    k_theta=0.3, fitting_inertia=0.01)
         .add_hinge(0, (0.6, 0.0, 0.0), (0, 1, 0), R_PE0=Ry(np.pi), tau0=1.5, k_theta=0.1,
                    c_theta=0.05, fitting_inertia=0.005)
         .set_appendage(shell, root, fidelity="nonlinear", damping=(0.3, 0.0))
         .set_lock(np.pi, 0.025, 1e-4, LAW, friction=Friction(0.2))
         .add_hinge(2, (0.64, 0.1, 0.0), (0.0, 0.6, 0.8), R_PE0=Ry(0.4), tau0=0.5, k_theta=0.1,
                    fitting_inertia=0.005, fitting_mass=0.05, fitting_com=(0.01, 0.0, 0.0))
         .set_appendage(shell, root, fidelity="linear", damping=(0.3, 1e-4))
         .add_hinge(1, (0.6, 0.0, 0.0), (0, 1, 0), R_PE0=Ry(0.1), tau0=1.0, k_theta=0.1,
                    fitting_inertia=0.005)
         .set_appendage(shell, root, fidelity="reduced-nonlinear", modes=3, derivative_modes=1)
         .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (0.3, 0.0, 0.0), body=0)
         .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (0.3, 0.0, 0.0), body=1)
         .set_lock(np.pi / 2, 0.025, 1e-4, LAW, hinge=0))
    return s


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_tree_with_a_hinge_on_a_full_nonlinear_panel_round_trips(tmp_path, suffix):
    scene = _tree_scene()
    hinges = scene_file.scene_to_dict(scene)["hinges"]
    assert [h["parent"] for h in hinges] == ["base", "base", 0, 2, 1]
    assert [h.get("appendage", {}).get("fidelity") for h in hinges] == [
        None, None, "nonlinear", "linear", "reduced-nonlinear"]
    assert ["lock" in h for h in hinges] == [True, False, True, False, False]
    assert hinges[3]["axis"] == [0.0, 0.6, 0.8]
    loaded = _round_trip(scene, tmp_path / f"tree{suffix}")
    model = loaded.compile()
    assert [model.layout(k)["parent"] for k in range(5)] == [-1, -1, 0, 2, 1]
    assert model.layout(3)["attachment_node"] >= 0  # hinge 3 rides on hinge 2's panel mesh
    assert model.deforming == (False, False, True, True, True)
    reference = scene.compile().simulate(0.2, 0.01)
    assert np.all(np.abs(reference.deployment_angle[-1]) > 0.1)  # every hinge moved (deg)
    _assert_same_series(model.simulate(0.2, 0.01), reference)


def _spin_up_theta(t, omega_s, t_s):
    """Kane, Ryan & Banerjee (1987): the hub angle (rad) of the rate
    (omega_s/t_s)[t - (t_s/2 pi) sin(2 pi t/t_s)], t <= t_s."""
    return omega_s / t_s * (t ** 2 / 2 + (t_s / (2 * np.pi)) ** 2 * (np.cos(2 * np.pi * t / t_s) - 1))


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_a_spin_up_on_a_later_hinge_round_trips(tmp_path, suffix):
    # Hinge 1, on a sprung yoke, is driven; hinge 0 is not. The loaded scene's hinge 1 follows the
    # prescribed angle (closed form, to 1e-12 rad) and gives the original's bits.
    shell, root = _panel()
    scene = (Scene().set_base(1.0, 1.0, free=False)
             .add_hinge("base", (0.0, 0.0, 0.0), (0, 0, 1), tau0=0.2, k_theta=0.5, c_theta=0.1)
             .add_rigid_part(2.0, np.diag([0.01, 0.2, 0.2]), (0.3, 0.0, 0.0), body=0)
             .add_hinge(0, (0.6, 0.0, 0.0), (0, 1, 0), spin_up=(1.0, 2.0), stowed_angle_deg=-30.0)
             .set_appendage(shell, root, fidelity="linear", damping=(0.3, 0.0)))
    hinges = scene_file.scene_to_dict(scene)["hinges"]
    assert "spin_up" not in hinges[0]
    assert hinges[1]["spin_up"] == {"omega_s_rad_per_s": 1.0, "t_s_s": 2.0}
    assert hinges[1]["stowed_angle_deg"] == -30.0
    loaded = _round_trip(scene, tmp_path / f"driven{suffix}")
    model = loaded.compile()
    assert model.layout(1)["iq_theta"] == -1 and model.layout(0)["iq_theta"] >= 0
    assert not model.conservative
    run = model.simulate(0.4, 0.02)
    expected = _spin_up_theta(run.t, 1.0, 2.0)
    np.testing.assert_allclose(np.radians(run.deployment_angle[:, 1] + 30.0), expected, rtol=0, atol=1e-12)
    assert np.abs(run.deployment_angle[-1, 0]) > 0.1  # hinge 0 swings under its spring (deg)
    _assert_same_series(run, scene.compile().simulate(0.4, 0.02))


def _notebook_array(fidelity="reduced-linear", wings=1) -> Scene:
    """The array of notebooks/02_build_your_own_scene.ipynb ("A chain: a yoke and two panels",
    "Two wings: a tree"), as it is built there, without the compile()."""
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
    R_MIRROR = np.array([[0.0, 0.0, 1.0], [0.0, -1.0, 0.0], [1.0, 0.0, 0.0]])

    def add_wing(scene, side):
        k = scene.num_hinges
        return (scene
                .add_hinge("base", point=(0.4 * side, 0.0, 0.0), axis=(0, side, 0),
                           R_PE0=Ry(-np.pi / 2) if side > 0 else R_MIRROR, tau0=4.0, k_theta=0.3,
                           **SPRING)
                .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (YOKE_LENGTH / 2, 0.0, 0.0),
                                body=k)
                .set_lock(np.pi / 2, PIN_RADIUS, CLEARANCE, LAW, friction=FRICTION)
                .add_hinge(k, point=(YOKE_LENGTH, 0.0, 0.0), axis=(0, 1, 0), R_PE0=Ry(np.pi),
                           tau0=1.5, k_theta=0.1, **SPRING)
                .set_appendage(panel, panel_root, fidelity=fidelity, modes=4)
                .set_lock(np.pi, PIN_RADIUS, CLEARANCE, LAW, friction=FRICTION)
                .add_hinge(k + 1, point=(P_LENGTH + 2 * OFFSET, 0.0, 0.0), axis=(0, -1, 0),
                           R_PE0=Ry(np.pi), tau0=0.5, k_theta=0.1, **SPRING)
                .set_appendage(panel, panel_root, fidelity=fidelity, modes=4)
                .set_lock(np.pi, PIN_RADIUS, CLEARANCE, LAW, friction=FRICTION))

    scene = dfx.Scene().set_base(mass=300.0, inertia=50.0)
    for side in (1.0, -1.0)[:wings]:
        add_wing(scene, side)
    return scene


@pytest.mark.parametrize("fidelity, wings", [("reduced-linear", 1), ("nonlinear", 1), ("reduced-linear", 2)])
def test_notebook_arrays_save_and_load(tmp_path, fidelity, wings):
    scene = _notebook_array(fidelity, wings)
    reference = scene.compile().simulate(0.2, 0.01)
    for suffix in SUFFIXES:
        loaded = _round_trip(scene, tmp_path / f"notebook_array{suffix}")
        _assert_same_series(loaded.compile().simulate(0.2, 0.01), reference)
    text = (tmp_path / "notebook_array.toml").read_text()
    assert text.count("[[hinges]]") == 3 * wings and text.count("[[hinges.parts]]") == wings
    assert text.count('parent = "base"') == wings
    assert "parent = 0" in text and "parent = 1" in text
    if wings == 2:
        assert "parent = 3" in text and "parent = 4" in text


@pytest.mark.parametrize("suffix", SUFFIXES)
def test_one_hinge_with_parts_on_its_body_round_trip(tmp_path, suffix):
    # A flexible panel with fittings on its body (merged with the hinge's fitting).
    shell, root = _panel()
    scene = (Scene().set_base(50.0, 8.0)
             .set_hinge(point=(0.3, 0.0, 0.0), axis=(0, 1, 0), R_BE0=Ry(-np.pi / 2), tau0=1.0,
                        k_theta=0.2, fitting_inertia=0.002)
             .add_rigid_part(0.2, 0.001, (0.05, 0.0, 0.0), body=0)
             .set_appendage(shell, root, fidelity="linear", damping=(0.01, 1e-4))
             .add_rigid_part(0.1, np.diag([1e-4, 2e-4, 3e-4]), (0.3, 0.1, 0.0), body=0))
    parts = scene_file.scene_to_dict(scene)["hinges"][0]["parts"]
    assert [p["mass_kg"] for p in parts] == [0.2, 0.1]
    loaded = _round_trip(scene, tmp_path / f"fitted{suffix}")
    model = loaded.compile()
    assert isinstance(model, dfx.Model) and model.fidelities == ("linear",)
    _assert_same_series(model.simulate(0.3, 0.01), scene.compile().simulate(0.3, 0.01))


def test_yoke_alone_round_trip(tmp_path):
    # One hinge carrying rigid parts only, without an appendage.
    scene = (Scene().set_base(1.0, 1.0, free=False)
             .add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0), tau0=0.5, c_theta=0.01)
             .add_rigid_part(2.0, np.diag([0.01, 0.2, 0.2]), (0.3, 0, 0), body=0))
    loaded = _round_trip(scene, tmp_path / "yoke.toml")
    assert "appendage" not in scene_file.scene_to_dict(loaded)["hinges"][0]
    model = loaded.compile()
    assert isinstance(model, dfx.Model) and model.num_hinges == 1 and model.fidelities == (None,)
    _assert_same_series(model.simulate(0.2, 0.01), scene.compile().simulate(0.2, 0.01))


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
            .set_appendage(shell, list(range(6)) + list(range(12, 18)), fidelity="linear",
                           damping=(0.01, 1e-4))
            .set_lock(0.5, 0.02, 1e-4, ContactLaw("hunt-crossley", K=1e9, e=0.8),
                      friction=Friction(0.2)))


def test_version_1_file_is_read(tmp_path):
    path = tmp_path / "old.json"
    path.write_text(VERSION_1_JSON)
    loaded = dfx.load_scene(path)
    scene = _version_1_scene()
    d = scene_file.scene_to_dict(loaded)
    assert d == scene_file.scene_to_dict(scene) and d["version"] == 4
    assert d["hinges"][0]["stowed_angle_deg"] == 0.0  # version 1 has none: theta is the angle
    reference = scene.compile().simulate(0.3, 0.01)
    assert reference.lock_force.max() > 0  # the lock law and friction act
    _assert_same_series(loaded.compile().simulate(0.3, 0.01), reference)


def _older(d: dict) -> tuple[dict, dict]:
    """A current dict of a serial chain in version 2's layout (``R_PE0``; the appendage's modes
    under ``options``; no stowed angle), and the current dict that layout reads back to (the
    stowed angles 0)."""
    d = copy.deepcopy(d)
    for h in d["hinges"]:
        h["R_PE0"] = h.pop("R_PC0")
        h.pop("stowed_angle_deg")
        a = h.get("appendage")
        if a is not None:
            a["options"] = {k: a.pop(k) for k in ("modes", "derivative_modes") if k in a}
    d["version"] = 2
    expected = copy.deepcopy(d)
    for h in expected["hinges"]:
        h["R_PC0"] = h.pop("R_PE0")
        h["stowed_angle_deg"] = 0.0
        a = h.get("appendage")
        if a is not None:
            a.update(a.pop("options"))
    expected["version"] = scene_file.VERSION
    return d, expected


def _as_version_1(d: dict) -> tuple[dict, dict]:
    """A one-hinge version-3 dict (no parts on the hinge's body) in version 1's layout, and the
    version-3 dict it reads back to."""
    d2, expected = _older(d)
    d1 = copy.deepcopy(d2)
    (h,) = d1.pop("hinges")
    assert h.pop("parent") == "base" and h.pop("parts") == []
    h["R_BE0"] = h.pop("R_PE0")
    d1.update(version=1, hinge=h, appendage=h.pop("appendage"))
    if "lock" in h:
        d1["lock"] = h.pop("lock")
    return d1, expected


def test_version_1_spin_up_and_paper_dicts_are_read(paper):
    for scene in (_spin_up_scene(), paper.scene):
        d1, expected = _as_version_1(scene_file.scene_to_dict(scene))
        assert scene_file.scene_to_dict(scene_file.scene_from_dict(d1)) == expected


@pytest.mark.parametrize("edit, match", [
    (lambda d: d["hinge"].pop("axis"), r"^hinge is missing key\(s\) hinge.axis$"),
    (lambda d: d["hinge"].update(R_PE0=d["hinge"].pop("R_BE0")),
     r"^hinge is missing key\(s\) hinge.R_BE0$"),
    (lambda d: d["hinge"].update(axis=[0.0, 2.0, 0.0]),
     r"^hinge.axis = \[0.0, 2.0, 0.0\] must be a unit vector$"),
    (lambda d: d["hinge"].update(R_BE0=[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
     r"^hinge.R_BE0 must be a rotation matrix$"),
    (lambda d: d["hinge"].update(stowed_angle_deg=90.0),
     r"^hinge has unknown key\(s\) hinge.stowed_angle_deg; allowed:"),
    (lambda d: d["hinge"].update(options={"stowed_angle_deg": 90.0}),
     r"^hinge.options has unknown key\(s\) hinge.options.stowed_angle_deg; allowed: none$"),
    (lambda d: d["appendage"].update(fidelity="stiff"),
     r"^appendage.fidelity = 'stiff' is invalid: must be one of 'rigid', 'linear', 'nonlinear'"),
    (lambda d: d["appendage"]["options"].update(modes=2.5),
     r"^appendage.options.modes must be an integer, got 2.5$"),
    # a fuzz case: an index past 64 bits overflowed numpy's cast instead of naming the key
    (lambda d: d["appendage"].update(fixed_dofs=[0, 99999999999999999999]),
     r"^appendage.fixed_dofs holds 99999999999999999999, out of range: must be 64-bit integers$"),
    (lambda d: d["appendage"]["options"].update(study_tag=7),
     r"^appendage.options has unknown key\(s\) appendage.options.study_tag; allowed: modes, "
     r"derivative_modes$"),
    (lambda d: d["lock"]["law"].pop("K_N_per_m_n"), r"lock.law.K_N_per_m_n$"),
    (lambda d: d.update(hinges=[]), r"^scene file has unknown key\(s\) hinges; allowed: schema"),
])
def test_bad_version_1_files_name_the_key(edit, match):
    d = json.loads(VERSION_1_JSON)
    edit(d)
    with pytest.raises(ValueError, match=match):
        scene_file.scene_from_dict(d)


# ------------------------------------------------------------------------------------------------
# Version 2 (serial chains; written by deployfx before trees) is still read

# A version-2 file as that version's writer laid it out (written by hand, compactly): a free base,
# a yoke on it (a rigid part, a lock), a reduced panel on the yoke (its modes under "options").
VERSION_2_JSON = """{
  "schema": "deployfx.scene",
  "version": 2,
  "units": "SI: m, kg, s, rad, N, Pa",
  "base": {"free": true, "mass_kg": 200.0, "com_m": [0.0, 0.0, 0.0],
           "inertia_kg_m2": [[30.0, 0.0, 0.0], [0.0, 40.0, 0.0], [0.0, 0.0, 35.0]]},
  "parts": [],
  "hinges": [
    {"parent": "base", "point_m": [0.4, 0.0, 0.0], "axis": [0.0, 1.0, 0.0],
     "R_PE0": [[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]],
     "tau0_N_m": 2.0, "k_theta_N_m_per_rad": 0.3, "c_theta_N_m_s_per_rad": 0.05,
     "fitting": {"mass_kg": 0.0, "com_m": [0.0, 0.0, 0.0],
                 "inertia_kg_m2": [[0.005, 0.0, 0.0], [0.0, 0.005, 0.0], [0.0, 0.0, 0.005]]},
     "parts": [{"mass_kg": 1.5, "com_m": [0.3, 0.0, 0.0],
                "inertia_kg_m2": [[0.002, 0.0, 0.0], [0.0, 0.045, 0.0], [0.0, 0.0, 0.045]]}],
     "lock": {"theta_lock_rad": 1.5, "pin_radius_m": 0.025, "clearance_m": 0.0001,
              "law": {"kind": "kelvin-voigt-hertz", "K_N_per_m_n": 1000000000.0, "n": 1.5,
                      "D_N_s_per_m": 10000.0, "e": 1.0},
              "friction": {"mu": 0.2, "v_reg_m_per_s": 0.0001}}},
    {"parent": 0, "point_m": [0.6, 0.0, 0.0], "axis": [0.0, 1.0, 0.0],
     "R_PE0": [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]],
     "tau0_N_m": 1.0, "k_theta_N_m_per_rad": 0.1, "c_theta_N_m_s_per_rad": 0.02,
     "fitting": {"mass_kg": 0.05, "com_m": [0.01, 0.0, 0.0],
                 "inertia_kg_m2": [[0.004, 0.0, 0.0], [0.0, 0.004, 0.0], [0.0, 0.0, 0.004]]},
     "parts": [],
     "appendage": {
       "fidelity": "reduced-nonlinear",
       "fixed_dofs": [0, 1, 2, 3, 4, 5, 18, 19, 20, 21, 22, 23],
       "alpha_M_per_s": 0.3, "beta_K_s": 0.0,
       "shell": {
         "nodes_m": [[0.02, -0.1, 0.0], [0.17, -0.1, 0.0], [0.32, -0.1, 0.0],
                     [0.02, 0.1, 0.0], [0.17, 0.1, 0.0], [0.32, 0.1, 0.0]],
         "quads": [[0, 1, 4, 3], [1, 2, 5, 4]],
         "ref_axis": [1.0, 0.0, 0.0],
         "plies": [{"thickness_m": 0.002, "angle_deg": 0.0,
                    "material": {"type": "isotropic", "E_Pa": 70000000000.0, "nu": 0.33,
                                 "rho_kg_per_m3": 2700.0}}]
       },
       "options": {"modes": 3, "derivative_modes": 2}
     }}
  ]
}
"""


def _version_2_scene() -> Scene:
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    nodes = [[0.02, -0.1, 0.0], [0.17, -0.1, 0.0], [0.32, -0.1, 0.0],
             [0.02, 0.1, 0.0], [0.17, 0.1, 0.0], [0.32, 0.1, 0.0]]
    shell = dfx.ShellModel(nodes, [[0, 1, 4, 3], [1, 2, 5, 4]], lam)
    return (Scene().set_base(200.0, np.diag([30.0, 40.0, 35.0]))
            .add_hinge("base", (0.4, 0.0, 0.0), (0.0, 1.0, 0.0),
                       R_PE0=[[0.0, 0.0, -1.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0]], tau0=2.0,
                       k_theta=0.3, c_theta=0.05, fitting_inertia=0.005)
            .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (0.3, 0.0, 0.0), body=0)
            .set_lock(1.5, 0.025, 1e-4, LAW, friction=Friction(0.2))
            .add_hinge(0, (0.6, 0.0, 0.0), (0.0, 1.0, 0.0),
                       R_PE0=[[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]], tau0=1.0,
                       k_theta=0.1, c_theta=0.02, fitting_inertia=0.004, fitting_mass=0.05,
                       fitting_com=(0.01, 0.0, 0.0))
            .set_appendage(shell, list(range(6)) + list(range(18, 24)), fidelity="reduced-nonlinear",
                           damping=(0.3, 0.0), modes=3, derivative_modes=2))


def test_version_2_file_is_read(tmp_path):
    path = tmp_path / "chain_v2.json"
    path.write_text(VERSION_2_JSON)
    loaded = dfx.load_scene(path)
    scene = _version_2_scene()
    d = scene_file.scene_to_dict(loaded)
    assert d == scene_file.scene_to_dict(scene) and d["version"] == 4
    appendage = d["hinges"][1]["appendage"]
    assert (appendage["modes"], appendage["derivative_modes"]) == (3, 2)
    assert [h["stowed_angle_deg"] for h in d["hinges"]] == [0.0, 0.0]
    model = loaded.compile()
    assert model.basis_info(1)["modes"] == 3
    reference = scene.compile().simulate(0.5, 0.01)
    assert np.all(np.abs(reference.deployment_angle[-1]) > 1.0)  # both hinges moved (deg)
    _assert_same_series(model.simulate(0.5, 0.01), reference)


def test_version_2_chain_spin_up_and_paper_dicts_are_read(paper):
    # The layout of version 2 of scenes this version expresses: serial chains, a spin-up on hinge 0.
    for scene in (_chain_scene(3), _spin_up_scene(), paper.scene):
        d2, expected = _older(scene_file.scene_to_dict(scene))
        assert scene_file.scene_to_dict(scene_file.scene_from_dict(d2)) == expected


@pytest.fixture(scope="module")
def good_chain():
    return scene_file.scene_to_dict(_chain_scene(2))


@pytest.fixture(scope="module")
def good_v2(good_chain):
    return _older(good_chain)[0]


def _broken(good, edit):
    d = copy.deepcopy(good)
    edit(d)
    return d


def _h(d, k=0):
    return d["hinges"][k]


@pytest.mark.parametrize("edit, match", [
    # options: only the appendage's modes and derivative_modes (what version 3 names)
    (lambda d: _h(d, 1)["appendage"]["options"].update(warp=9),
     (r"^hinges\[1\].appendage.options has unknown key\(s\) hinges\[1\].appendage.options.warp; "
      r"allowed: modes, derivative_modes$")),
    (lambda d: _h(d, 1)["appendage"]["options"].update(modes="4"),
     r"^hinges\[1\].appendage.options.modes must be an integer, got '4'$"),
    (lambda d: _h(d, 1)["appendage"]["options"].update(derivative_modes=True),
     r"^hinges\[1\].appendage.options.derivative_modes must be an integer, got True$"),
    (lambda d: _h(d, 1)["appendage"].update(options=[3]),
     r"^hinges\[1\].appendage.options must be a table \(mapping\), got list$"),
    (lambda d: _h(d, 1)["appendage"].update(modes=3),
     r"^hinges\[1\].appendage has unknown key\(s\) hinges\[1\].appendage.modes; allowed:"),
    (lambda d: _h(d, 2).update(options={"spin_up": [1.0, 1.0]}),
     r"^hinges\[2\].options has unknown key\(s\) hinges\[2\].options.spin_up; allowed: none$"),
    (lambda d: _h(d, 0)["lock"].update(options={"hinge": 0}),
     r"^hinges\[0\].lock.options has unknown key\(s\) hinges\[0\].lock.options.hinge; allowed: none$"),
    # a serial chain: hinge k on hinge k - 1, a spin-up on hinge 0 only, no version-3 keys
    (lambda d: _h(d, 2).update(parent=0),
     r"^hinges\[2\].parent = 0 is out of range: must be 1 \(a version-2 file is a serial chain\)$"),
    (lambda d: _h(d, 0).update(parent=0),
     r"^hinges\[0\].parent = 0 is out of range: must be 'base' \(hinge 0 is on the base\)$"),
    (lambda d: _h(d, 1).update(parent="base"),
     r"^hinges\[1\].parent = 'base' is out of range: must be 0"),
    (lambda d: _h(d, 1).update(spin_up={"omega_s_rad_per_s": 1.0, "t_s_s": 1.0}),
     r"^hinges\[1\].spin_up is not allowed in a version-2 file: a prescribed hinge angle is for hinge 0"),
    (lambda d: _h(d, 1).update(stowed_angle_deg=90.0),
     r"^hinges\[1\] has unknown key\(s\) hinges\[1\].stowed_angle_deg; allowed:"),
    (lambda d: _h(d, 0).update(R_PC0=_h(d, 0).pop("R_PE0")),
     r"^hinges\[0\] is missing key\(s\) hinges\[0\].R_PE0$"),
    (lambda d: _h(d, 2).update(R_PE0=[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
     r"^hinges\[2\].R_PE0 must be a rotation matrix$"),
])
def test_bad_version_2_files_name_the_key(good_v2, edit, match):
    scene_file.scene_from_dict(good_v2)  # the unbroken file reads
    with pytest.raises(ValueError, match=match):
        scene_file.scene_from_dict(_broken(good_v2, edit))


# ------------------------------------------------------------------------------------------------
# Bad files (version 3)

@pytest.fixture(scope="module")
def good(paper):
    return scene_file.scene_to_dict(paper.scene)


@pytest.mark.parametrize("edit, match", [
    (lambda d: d.update(version=5), (r"^version = 5 is an unknown scene-file schema version; "
                                     r"this deployfx reads versions 1, 2, 3, 4$")),
    (lambda d: d.update(version="3"), r"^version = '3' is an unknown"),
    (lambda d: d.update(version=3.0), r"^version = 3.0 is an unknown"),
    (lambda d: d.update(schema="other"), r"^schema = 'other' is not a deployfx scene"),
    (lambda d: d.pop("version"), r"^scene file is missing key\(s\) version$"),
    (lambda d: d.pop("hinges"), r"^scene file is missing key\(s\) hinges$"),
    (lambda d: d.update(hinge={}), (r"^scene file has unknown key\(s\) hinge; allowed: schema, "
                                    r"version, base, hinges, units, parts$")),
    (lambda d: _h(d).pop("axis"), r"^hinges\[0\] is missing key\(s\) hinges\[0\].axis$"),
    (lambda d: _h(d).pop("R_PC0"), r"^hinges\[0\] is missing key\(s\) hinges\[0\].R_PC0$"),
    (lambda d: d["base"].update(mas_kg=1.0), r"base.mas_kg"),
    (lambda d: _h(d)["appendage"]["shell"]["nodes_m"].__setitem__(0, [0.0, 0.0]),
     r"^hinges\[0\].appendage.shell.nodes_m must be n x 3 numbers"),
    (lambda d: _h(d)["appendage"]["shell"]["quads"].__setitem__(0, [0, 1, 2, 3.5]),
     r"^hinges\[0\].appendage.shell.quads must be n x 4 integers"),
    (lambda d: _h(d).update(R_PC0=[1.0, 0.0, 0.0]), r"^hinges\[0\].R_PC0 must be 3 x 3 numbers"),
    (lambda d: _h(d).update(R_PC0=[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
     r"^hinges\[0\].R_PC0 must be a rotation matrix$"),
    (lambda d: d["base"].update(mass_kg="heavy"), r"^base.mass_kg must be a number, got str"),
    (lambda d: d["base"].update(free="yes"), r"^base.free must be true or false"),
    (lambda d: _h(d)["lock"]["law"].pop("K_N_per_m_n"),
     r"^hinges\[0\].lock.law is missing key\(s\) hinges\[0\].lock.law.K_N_per_m_n$"),
    (lambda d: _h(d)["appendage"]["shell"]["plies"][1]["material"].update(type="steel"),
     r"^hinges\[0\].appendage.shell.plies\[1\].material.type must be 'isotropic' or 'orthotropic'"),
    (lambda d: _h(d)["appendage"]["shell"]["plies"][0]["material"].pop("G13_Pa"), "G13_Pa"),
    # version 3 has no options: the appendage's modes are keys of their own
    (lambda d: _h(d)["appendage"].update(options={"modes": 4}),
     r"^hinges\[0\].appendage has unknown key\(s\) hinges\[0\].appendage.options; allowed:"),
    (lambda d: _h(d)["appendage"].pop("modes"),
     r"^hinges\[0\].appendage is missing key\(s\) hinges\[0\].appendage.modes$"),
    (lambda d: _h(d)["appendage"].update(modes=4.0),
     r"^hinges\[0\].appendage.modes must be an integer, got 4.0$"),
    (lambda d: _h(d)["appendage"].update(derivative_modes=11),
     r"^hinges\[0\].appendage: appendage.derivative_modes = 11 is out of range: must be in \[0, modes = 10\]"),
    (lambda d: _h(d).update(stowed_angle_deg="90"),
     r"^hinges\[0\].stowed_angle_deg must be a number, got str '90'$"),
    (lambda d: _h(d).update(spin_up={"omega_s_rad_per_s": 1.0}),
     r"^hinges\[0\].spin_up is missing key\(s\) hinges\[0\].spin_up.t_s_s$"),
    (lambda d: _h(d).update(spin_up={"omega_s_rad_per_s": 1.0, "t_s_s": 0.0}),
     r"^hinges\[0\]: spin_up.t_s = 0.0 is out of range: must be > 0 \(s\)$"),
    # the builder's checks, prefixed with the file's table when they do not name it
    (lambda d: _h(d).update(axis=[0.0, 2.0, 0.0]),
     r"^hinges\[0\].axis = \[0.0, 2.0, 0.0\] must be a unit vector$"),
    (lambda d: _h(d)["appendage"]["shell"]["plies"][0]["material"].update(E1_Pa=-1.0),
     r"^hinges\[0\].appendage.shell.plies\[0\]: Orthotropic.E1 = -1 is out of range"),
])
def test_bad_files_name_the_key(good, edit, match):
    with pytest.raises(ValueError, match=match):
        scene_file.scene_from_dict(_broken(good, edit))


@pytest.mark.parametrize("edit, match", [
    (lambda d: d.update(hinges=[]), r"^hinges must hold at least one hinge$"),
    (lambda d: d.update(hinges={"0": {}}), r"^hinges must be a list of tables"),
    # a parent is the base or an earlier hinge
    (lambda d: _h(d).update(parent=0), r"^hinges\[0\].parent = 0 is out of range: must be 'base'$"),
    (lambda d: _h(d, 1).update(parent=1),
     r"^hinges\[1\].parent = 1 is out of range: must be 'base' or an earlier hinge's index in \[0, 0\]$"),
    (lambda d: _h(d, 1).update(parent=2),
     r"^hinges\[1\].parent = 2 is out of range: must be 'base' or an earlier hinge's index in \[0, 0\]$"),
    (lambda d: _h(d, 2).update(parent=-1),
     r"^hinges\[2\].parent = -1 is out of range: must be 'base' or an earlier hinge's index in \[0, 1\]$"),
    (lambda d: _h(d, 1).update(parent=True), r"^hinges\[1\].parent = True is out of range"),
    (lambda d: _h(d, 1).update(parent=0.0), r"^hinges\[1\].parent = 0.0 is out of range"),
    (lambda d: _h(d, 1).update(parent="yoke"), r"^hinges\[1\].parent = 'yoke' is out of range"),
    (lambda d: _h(d, 1).pop("parent"), r"^hinges\[1\] is missing key\(s\) hinges\[1\].parent$"),
    (lambda d: _h(d, 1).update(yoke=1.0),
     (r"^hinges\[1\] has unknown key\(s\) hinges\[1\].yoke; allowed: parent, point_m, axis, "
      r"R_PC0, tau0_N_m, k_theta_N_m_per_rad, c_theta_N_m_s_per_rad, fitting, stowed_angle_deg, "
      r"spin_up, parts, appendage, lock, groove$")),
    (lambda d: _h(d, 1).update(options={"parent": 0}),
     r"^hinges\[1\] has unknown key\(s\) hinges\[1\].options; allowed:"),
    (lambda d: _h(d, 0)["lock"].update(options={}),
     r"^hinges\[0\].lock has unknown key\(s\) hinges\[0\].lock.options; allowed:"),
    (lambda d: _h(d, 0)["parts"][1].pop("com_m"),
     r"^hinges\[0\].parts\[1\] is missing key\(s\) hinges\[0\].parts\[1\].com_m$"),
    (lambda d: _h(d, 0)["parts"][0].update(mass_kg=-1.0),
     r"^hinges\[0\].parts\[0\]: part.mass = -1.0 is out of range: must be finite, >= 0 and <= 1e50 \(kg\)$"),
    (lambda d: _h(d, 1).update(parts={}), r"^hinges\[1\].parts must be a list of tables"),
    (lambda d: d["parts"][0].update(inertia_kg_m2=[[1.0, 2.0, 0.0], [0.0, 1.0, 0.0],
                                                   [0.0, 0.0, 1.0]]),
     r"^parts\[0\]: part.inertia must be symmetric positive semidefinite"),
    (lambda d: _h(d, 1)["fitting"].update(mass_kg=-1.0),
     r"^hinges\[1\].fitting.mass = -1.0 is out of range"),
    (lambda d: _h(d, 1).update(axis=[0.0, 2.0, 0.0]),
     r"^hinges\[1\].axis = \[0.0, 2.0, 0.0\] must be a unit vector$"),
    (lambda d: _h(d, 2).update(R_PC0=[[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]),
     r"^hinges\[2\].R_PC0 must be a rotation matrix$"),
    (lambda d: _h(d, 1)["appendage"].update(fidelity="stiff"),
     r"^hinges\[1\].appendage: appendage.fidelity = 'stiff' is invalid: must be one of 'rigid'"),
    (lambda d: _h(d, 1)["lock"]["law"].update(kind="bogus"),
     r"^hinges\[1\].lock.law: contact.kind = 'bogus' is not one of"),
    (lambda d: _h(d, 0)["lock"]["friction"].update(mu=-0.1),
     r"^hinges\[0\].lock.friction: friction.mu = -0.1 is out of range: must be >= 0$"),
    (lambda d: _h(d, 1)["lock"].update(clearance_m=-1.0),
     r"^hinges\[1\].lock: lock.clearance = -1.0 is out of range"),
])
def test_bad_tree_files_name_the_key(good_chain, edit, match):
    scene_file.scene_from_dict(good_chain)  # the unbroken file reads
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


@pytest.mark.parametrize("suffix", [".json", ".toml"])
def test_ply_strengths_round_trip(tmp_path, suffix):
    """Reference: the scene as built. A panel's strength allowables (one for all plies, and one
    per ply with the optional S13, S23) are written by name and read back equal."""
    one = dfx.Strengths(Xt=2.0e9, Xc=1.5e9, Yt=50e6, Yc=200e6, S12=100e6)
    per_ply = [dfx.Strengths(Xt=2.0e9 + i, Xc=1.5e9, Yt=50e6, Yc=200e6, S12=100e6, S13=90e6, S23=40e6,
                             F12_star=-0.3) for i in range(4)]
    for strengths in (one, per_ply):
        sc = dfx.scenes.paper2016(2, "reduced-nonlinear", nx=2, ny=1, strengths=strengths)
        loaded = dfx.load_scene(dfx.save_scene(sc, tmp_path / f"s{suffix}"))
        expected = (strengths,) if isinstance(strengths, dfx.Strengths) else tuple(strengths)
        assert loaded.links[0].appendage.strengths == expected
