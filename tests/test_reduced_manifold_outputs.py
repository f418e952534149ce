"""The Python side of the quadratic-manifold fidelity ``reduced-manifold`` (issue 27): what turns a
manifold panel's elastic coordinates into mesh motion, and where the fidelity is named.

On the manifold the elastic coordinates q are the bending Ritz coordinates only, and the mesh
moves by ``Phi g(q)``, g(q) = [q; C(q, q)/2] (Jain, Tiso, Rutzmoser & Rixen 2017;
docs/research/quadratic-manifold.md, section 3). The references here are independent of the
code under test:
- parity (docs/research/quadratic-manifold.md, "Coordinates and predictors"; fem/parity): on a
  flat panel with a mirror-symmetric lay-up every Ritz vector is purely bending or purely
  in-plane, the in-plane ones with exact zeros in the w, theta_x, theta_y rows; so node E's
  transverse deflection is the bending rows times q alone, and the bending vectors move no node
  in-plane;
- a quadratic map's central difference is exact (its third derivative is zero), so the map's
  tangent and the mode shapes on the mesh are checked by central differences to round-off;
- inextensional bending of a cantilever foreshortens it: the free end moves toward the root by
  int_0^L w_x^2 / 2 dx, 0.58 w_tip^2 / L for the clamped first mode, 0.60 for a tip load
  (closed forms; Euler-Bernoulli shapes);
- the reduced-nonlinear model on the same basis (exact Green strain, in-plane coordinates free)
  as a second model of the same motion.
"""
import json

import numpy as np
import pytest

import deployfx as dfx
from deployfx import Scene, scenes
from deployfx._node_rows import node_translations
from deployfx.cli import main
from deployfx.specs import Fidelity
from deployfx.tradeoff import Case

MANIFOLD = "reduced-manifold"
SMALL = dict(nx=4, ny=2, modes=6)
T_END = 2.8  # past the first lock (2.47 s): node E swings to ~0.4 m at ~2.78 s (README)


def _elastic(model, q, k=0):
    lay = model.layout(k)
    return np.asarray(q)[:, lay["iq_elastic"]:lay["iq_elastic"] + lay["num_elastic"]]


def _bending_columns(Phi):
    """The basis vectors with a nonzero w, theta_x or theta_y row (parity: the others have exact
    zeros there)."""
    rows = Phi.reshape(-1, 6, Phi.shape[1])[:, 2:5, :]
    return np.flatnonzero(np.abs(rows).max(axis=(0, 1)) > 0)


@pytest.fixture(scope="module")
def paper():
    """The paper's scene (lay-up 2, flat and mirror-symmetric) on 4 x 2 with 6 modes, run past
    the first lock with every node recorded; and the reduced-nonlinear run of the same scene."""
    scene = scenes.paper2016(2, MANIFOLD, **SMALL)
    result = scene.simulate(T_END, 0.01, nodes="all")
    ref_scene = scenes.paper2016(2, "reduced-nonlinear", **SMALL)
    return scene, result, ref_scene.simulate(T_END, 0.01, nodes="all"), ref_scene


def test_the_fidelity_parses_and_says_what_it_is():
    f = Fidelity.parse(MANIFOLD)
    assert f is Fidelity.REDUCED_MANIFOLD and f == MANIFOLD and str(f) == MANIFOLD
    assert f.reduced and f.deforms and f.slaved
    assert [g.value for g in Fidelity if g.slaved] == [MANIFOLD]  # no other fidelity maps its coordinates
    for bad in ("manifold", "reduced_manifold", "Reduced-Manifold"):
        with pytest.raises(ValueError, match=rf"appendage.fidelity = '{bad}' is invalid: must be one of .*"
                                             r"'reduced-manifold'"):
            Fidelity.parse(bad, "appendage.fidelity")
    # The reduced fidelities' basis options are checked for it as for reduced-nonlinear.
    plate = dfx.paper2016.appendage_plate(2, 2, 1)
    with pytest.raises(ValueError, match="appendage.modes = 0 is out of range"):
        Scene().set_hinge(point=(0, 0, 0), axis=(0, 1, 0)).set_appendage(
            plate.model, plate.fixed_dofs("CFFF"), fidelity=MANIFOLD, modes=0)
    with pytest.raises(ValueError, match="appendage.derivative_partners = 4 is out of range"):
        Scene().set_hinge(point=(0, 0, 0), axis=(0, 1, 0)).set_appendage(
            plate.model, plate.fixed_dofs("CFFF"), fidelity=MANIFOLD, modes=3, derivative_partners=4)


def test_node_series_are_the_panel_coordinates_through_the_basis(paper):
    # Every node series a run records (the `nodes` series, the tip, node E) is the engine's
    # panel_coordinates(q_el) times the displacement map's rows, computed here from the engine's
    # two functions directly (1e-13 of the largest translation: the same products, another order).
    scene, r, _, _ = paper
    m = scene.model
    q_el = _elastic(m, r["q"])
    Phi = m.core.displacement_map(0)
    lay = m.layout(0)
    assert lay["num_elastic"] < Phi.shape[1] == m.basis_info(0)["size"]  # slaved: fewer coordinates than vectors
    eta = m.core.panel_coordinates(0, np.ascontiguousarray(q_el))
    expected = (eta @ Phi.T).reshape(len(q_el), -1, 6)[:, :, :3]
    got = r["node_displacements_0"]
    scale = np.abs(expected).max()
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(r.tip_displacement[:, 0], expected[:, m.tip_nodes[0]], rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(r.node_E_deflection, expected[:, scene.node_E, 2], rtol=0, atol=1e-13 * scale)
    np.testing.assert_allclose(m.panel_coordinates(r["q"], 0), eta, rtol=0, atol=0)
    # The lift matters: without the slaved in-plane coordinates (eta = [q; 0]) no node would move
    # in-plane, while the run's node E moves toward the root by millimetres (next test).
    linear = np.zeros_like(eta)
    b = _bending_columns(Phi)
    linear[:, b] = q_el
    assert np.abs((linear @ Phi.T).reshape(len(q_el), -1, 6)[:, :, :2]).max() == 0.0
    assert np.abs(got[:, :, :2]).max() > 1e-3


def test_node_E_deflection_is_the_bending_rows_alone(paper):
    # Parity: the in-plane vectors have exact zeros in the w rows, so node E's deflection (the
    # panel frame's z) is Phi_E,w[bending] q_el; and the elastic coordinates are the bending Ritz
    # coordinates themselves (eta[bending] = q_el exactly), in the basis's order.
    scene, r, _, _ = paper
    m = scene.model
    Phi = m.core.displacement_map(0)
    b = _bending_columns(Phi)
    q_el = _elastic(m, r["q"])
    assert len(b) == q_el.shape[1]
    inplane = np.setdiff1d(np.arange(Phi.shape[1]), b)
    assert inplane.size and np.all(Phi.reshape(-1, 6, Phi.shape[1])[:, 2:5][:, :, inplane] == 0.0)
    np.testing.assert_array_equal(m.panel_coordinates(r["q"], 0)[:, b], q_el)
    w_E = q_el @ Phi[6 * scene.node_E + 2, b]
    np.testing.assert_allclose(r.node_E_deflection, w_E, rtol=0, atol=1e-15 * np.abs(w_E).max())
    assert np.abs(w_E).max() > 0.2  # a deflection worth checking (m)


def test_mesh_and_node_displacements_agree(paper):
    # Model.mesh_displacements (every dof) and node_displacements (the translations) are two
    # paths through the panel coordinates: they agree to round-off at every sample, and the
    # rotations are those of the same lift (a bending vector's theta rows times q alone, as w).
    scene, r, _, _ = paper
    m = scene.model
    d = m.mesh_displacements(r["q"], 0)
    assert d.shape == (len(r.t), m.shells[0].num_dofs)
    u = m.node_displacements(r["q"], 0)
    scale = np.abs(u).max()
    np.testing.assert_allclose(d.reshape(len(r.t), -1, 6)[:, :, :3], u, rtol=0, atol=1e-14 * scale)
    # An empty series gives empty arrays of the right widths (no call into the engine).
    assert m.panel_coordinates(r["q"][:0], 0).shape == (0, m.core.displacement_map(0).shape[1])
    assert m.mesh_displacements(r["q"][:0], 0).shape == (0, m.shells[0].num_dofs)
    # Only the slaved fidelity lifts: the other reduced models' node series call nothing per run.
    _, _, _, ref_scene = paper
    assert node_translations(ref_scene.model, 0).lift is None
    assert node_translations(m, 0).lift is not None


def test_the_free_end_foreshortens_as_inextensional_bending(paper):
    # Inextensional bending moves the free end toward the root by int w_x^2/2 dx: 0.58 w^2/L for
    # the clamped first mode, 0.60 for a tip load (module docstring), w the end's deflection, L =
    # 2.0 m. At node E's largest deflection the run's mid-width free-end node must lie in [0.5,
    # 0.7] w^2/L (a 4 x 2 mesh, a shape that is mostly the first mode), and agree with the
    # reduced-nonlinear run, whose in-plane coordinates are free, to 5 % (two models of the same
    # motion: docs/research/quadratic-manifold.md puts the slaving within 0.06 % of eta_m while
    # deploying and 1.6 % after the lock).
    scene, r, ref, _ = paper
    i = int(np.argmax(np.abs(r.node_E_deflection)))
    u = r["node_displacements_0"][i, scene.node_mid]
    w, L = u[2], 2.0
    assert abs(w) > 0.2
    assert 0.5 < -u[0] / (w * w / L) < 0.7
    u_ref = ref["node_displacements_0"][int(np.argmin(np.abs(ref.t - r.t[i]))), scene.node_mid]
    assert u[0] == pytest.approx(u_ref[0], rel=0.05)
    assert w == pytest.approx(u_ref[2], rel=0.05)


def test_mode_shapes_move_the_mesh_along_the_map_tangent(paper):
    # Modes.mesh_shapes is D G s with G = panel_tangent at the state: g is quadratic, so the
    # central difference of mesh_displacements along s is exact up to round-off (1e-9 relative
    # with a unit step on q's scale), and G itself is the central difference of
    # panel_coordinates. The state: the run's sample of largest node E deflection, where G
    # differs from [I; 0] by the in-plane rows C(q, .).
    scene, r, _, _ = paper
    m = scene.model
    i = int(np.argmax(np.abs(r.node_E_deflection)))
    q = r["q"][i]
    lay = m.layout(0)
    G = m.panel_tangent(q, 0)
    n = lay["num_elastic"]
    assert G.shape == (m.core.displacement_map(0).shape[1], n)
    h = 1e-2 * np.abs(_elastic(m, q[None])).max()
    fd = np.empty_like(G)
    for j in range(n):
        dq = np.zeros_like(q)
        dq[lay["iq_elastic"] + j] = h
        fd[:, j] = (m.panel_coordinates(q + dq, 0) - m.panel_coordinates(q - dq, 0))[0] / (2 * h)
    np.testing.assert_allclose(G, fd, rtol=0, atol=1e-9 * np.abs(G).max())
    b = _bending_columns(m.core.displacement_map(0))
    assert np.abs(np.delete(G, b, axis=0)).max() > 1e-3 * np.abs(G).max()  # the slaved rows move

    modes = m.modes(3, q=q)
    shapes = modes.mesh_shapes(0)
    s = modes.shapes[lay["iv_elastic"]:lay["iv_elastic"] + n].real
    for j in range(len(modes)):
        dq = np.zeros_like(q)
        dq[lay["iq_elastic"]:lay["iq_elastic"] + n] = h * s[:, j] / np.abs(s[:, j]).max()
        fd = (m.mesh_displacements(q + dq, 0) - m.mesh_displacements(q - dq, 0))[0] / (2 * h) * np.abs(s[:, j]).max()
        np.testing.assert_allclose(shapes[j], fd, rtol=0, atol=1e-9 * np.abs(shapes[j]).max())


@pytest.mark.parametrize("what", ["unsymmetric lay-up", "curved panel"])
def test_a_panel_without_the_parity_split_is_refused(what):
    # The manifold needs every basis vector purely bending or in-plane: a flat panel with a
    # mirror-symmetric lay-up. A [0/90] lay-up couples membrane and bending (B != 0, classical
    # lamination theory); a faceted cylinder z = 0.05 x^2 (each quad planar: z depends on x only)
    # is not flat. The engine refuses both, naming the fidelity; reduced-nonlinear takes them.
    plate = dfx.paper2016.appendage_plate(2, 4, 2)
    laminate = plate.laminate
    nodes = plate.model.nodes.copy()
    if what == "unsymmetric lay-up":
        plies = laminate.plies
        laminate = dfx.Laminate([plies[0], plies[1]])  # [0/90]
    else:
        nodes[:, 2] = 0.05 * nodes[:, 0] ** 2
    shell = dfx.ShellModel(nodes, plate.model.quads, laminate)
    for fidelity in ("reduced-nonlinear", MANIFOLD):
        scene = (Scene().set_base(100.0, 10.0)
                 .set_hinge(point=(0, 0, 0), axis=(0, 1, 0), k_theta=1.0)
                 .set_appendage(shell, plate.fixed_dofs("CFFF"), fidelity=fidelity, modes=4))
        if fidelity == MANIFOLD:
            with pytest.raises(ValueError, match=r"fidelity = 'reduced-manifold' needs a flat panel"):
                scene.compile()
        else:
            assert scene.compile().fidelities == (Fidelity.REDUCED_NONLINEAR,)


def test_a_trade_case_runs_the_manifold_and_counts_its_coordinates(tmp_path):
    # tradeoff.Case takes the model with the basis's options, like reduced-nonlinear; its row's
    # coordinates are the manifold's elastic coordinates (bending), fewer than the basis size.
    case = Case(MANIFOLD, 2, 1, 0.01, modes=3, derivative_modes=2, derivative_partners=0)
    assert case.name == "reduced-manifold(3, md=2, dp=0) 2x1 dt=0.01 GA(0.8)"
    with pytest.raises(ValueError, match="derivative_modes = 2 is only for the reduced-nonlinear and reduced-manifold"):
        Case("reduced-linear", modes=3, derivative_modes=2)
    ref = Case("reduced-nonlinear", 2, 1, 0.01, modes=3)
    rows = dfx.tradeoff([Case(MANIFOLD, 2, 1, 0.01, modes=3)], ref, 2.6)
    ref_row, row = rows
    assert row["failure"] is None and row["model"] == MANIFOLD and row["modes"] == 3
    assert row["basis_size"] == ref_row["basis_size"] == ref_row["coordinates"]  # the same basis
    model = scenes.paper2016(2, MANIFOLD, nx=2, ny=1, modes=3).model
    assert row["coordinates"] == model.layout(0)["num_elastic"] < row["basis_size"]
    assert row["lock_time_error_s"] < 1e-3  # both lock at the paper's ~2.47 s
    from deployfx.tradeoff_report import plot_work_precision

    fig = plot_work_precision(rows)
    assert MANIFOLD in [t.get_text() for t in fig.axes[0].get_legend().get_texts()]


def test_the_command_line_runs_the_manifold(capsys):
    code = main(["run", "paper2016", "--model", MANIFOLD, "--modes", "4", "--nx", "2", "--ny", "1",
                 "--t-end", "0.3", "--json"])
    assert code == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["steps"] == 30 and summary["momentum_drift"] < 1e-8


def test_a_scene_file_keeps_the_fidelity(tmp_path):
    scene = scenes.paper2016(2, MANIFOLD, nx=2, ny=1, modes=3).scene
    for name in ("s.toml", "s.json"):
        loaded = dfx.load_scene(dfx.save_scene(scene, tmp_path / name))
        model = loaded.compile()
        assert model.fidelities == (Fidelity.REDUCED_MANIFOLD,)
        assert model.layout(0)["num_elastic"] < model.basis_info(0)["size"]


def test_the_step_resolves_the_highest_kept_mode_that_moves_freely():
    # deployfx.resolution asks a step of a reduced panel's highest kept mode; on the manifold the
    # in-plane modes follow the bending ones, so it is the highest kept bending mode. The
    # spin-up strip (10 m x 0.2 m x 77.5 mm, Kane et al. 1987; one element across) has in-plane
    # modes among its first clamped ones: with 5 kept, the fifth is in-plane (its w, theta_x,
    # theta_y rows zero), so the two fidelities ask different periods.
    from deployfx import resolution

    strip = scenes.spin_up_strip(20)
    periods = {}
    for fidelity in ("reduced-nonlinear", MANIFOLD):
        model = (Scene().set_base(1.0, 1.0, free=False)
                 .set_hinge(point=(0, 0, 0), axis=(0, 1, 0), k_theta=1e4)
                 .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity=fidelity, modes=5)).compile()
        (panel,) = [p for p in resolution.periods(model) if "panel" in p["what"]]
        periods[fidelity] = panel
    b = _bending_columns(model.core.displacement_map(0))
    kept = [j for j in range(5) if j in b]
    assert kept[-1] < 4  # the fifth mode is in-plane
    w2 = model.basis_info(0)["omega2"]
    assert periods[MANIFOLD]["period_s"] == pytest.approx(2 * np.pi / np.sqrt(w2[kept[-1]]), rel=1e-12)
    assert f"mode {kept[-1] + 1} of its reduced basis" in periods[MANIFOLD]["what"]
    assert periods["reduced-nonlinear"]["period_s"] == pytest.approx(2 * np.pi / np.sqrt(w2[4]), rel=1e-12)


def test_ply_stresses_take_von_karmans_strain(paper):
    # The manifold's energy is Green strain without the in-plane displacements' own quadratic
    # terms (docs/research/quadratic-manifold.md, "poly"). By parity the membrane Green strain
    # of u = u_b + u_m splits as E_L(u) + E_Q(u_b) + E_Q(u_m), and the stresses are linear in the
    # strain, so the manifold's own stresses are S(u, green) - S(u_m, green) + S(u_m, linear):
    # the recovery's "von-karman" measure (E_Q of the normal displacement alone; the bending
    # vectors move w alone) must give them to round-off (1e-9 of the peak). At node E's largest
    # deflection (0.41 m) they agree with the reduced-nonlinear run's Green stresses (the same
    # motion, exact Green strain) to 2 % of the peak fibre stress (measured 0.56 %: 49.2 MPa
    # against 49.3; the identity 3.5e-14), while Green strain of the manifold's mesh displacements
    # is off by more than 2x the peak (198 MPa).
    # stress.strain_measure names it, and simulate(stresses=True) runs with it.
    from deployfx import stress

    scene, r, ref, ref_scene = paper
    m = scene.model
    i = int(np.argmax(np.abs(r.node_E_deflection)))
    Phi = m.core.displacement_map(0)
    b = _bending_columns(Phi)
    eta = m.panel_coordinates(r["q"][i], 0)[0]
    u = Phi @ eta
    u_m = np.delete(Phi, b, axis=1) @ np.delete(eta, b)
    shell = m.shells[0]

    def S(x, strain):
        return stress.ply_stresses(shell, x, strain=strain).stress[..., 0]  # sigma_1, fibres

    j = int(np.argmin(np.abs(ref.t - r.t[i])))
    truth = S(ref_scene.model.mesh_displacements(ref["q"][j], 0)[0], "green")
    peak = np.abs(truth).max()
    own = S(u, "von-karman")
    np.testing.assert_allclose(own, S(u, "green") - S(u_m, "green") + S(u_m, "linear"), rtol=0, atol=1e-9 * peak)
    assert np.abs(own - truth).max() < 0.02 * peak
    assert np.abs(S(u, "green") - truth).max() > 2 * peak
    assert stress.strain_measure(MANIFOLD) == "von-karman"
    strong = dfx.Strengths(Xt=1.5e9, Xc=1.2e9, Yt=5e7, Yc=2e8, S12=7e7)
    stressed = scenes.paper2016(2, MANIFOLD, nx=2, ny=1, modes=3, strengths=strong)
    run = stressed.simulate(0.05, 0.01, stresses=True)
    assert run.metadata["hinges"][0]["stress"]["strain"] == "von-karman"
    assert np.all(np.isfinite(run["max_failure_index"])) and run["max_failure_index"].max() > 0


