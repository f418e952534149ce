"""The failure envelope over a displacement series (deployfx.stress.envelope), its plots and
VTK cell data.

A planted maximum: a plate under a uniform curvature that rises and falls in time, plus, at one
sample, a rotation of the corner node that only the corner element feels. The expected element,
time, ply and index come from hand lamination theory (tests/clt_reference.py; Jones 1999) and
hand criteria (maximum stress, Jones 1999 Sec. 2.9.1; Tsai & Wu 1971), and the whole envelope is
checked against a brute-force pass over the per-sample fields.

The strengths are round numbers for the test, not a material's allowables.
"""
import numpy as np
import pytest

import clt_reference as clt
import deployfx as dfx
from deployfx import stress, stress_plot

MPa = 1e6
PLY = dfx.Orthotropic(E1=177e9, E2=10.8e9, G12=7.6e9, G13=7.6e9, G23=8.504e9, nu12=0.27, rho=1600)
Q = clt.lamina_Q(177e9, 10.8e9, 7.6e9, 0.27)
ANGLES = [0, 90, 90, 0]
ST = dfx.Strengths(Xt=1500 * MPa, Xc=1200 * MPa, Yt=50 * MPa, Yc=200 * MPa, S12=70 * MPa)
NX, NY, A, B = 4, 3, 0.2, 0.2  # elements of A x B m
KAPPA0, THETA_BUMP, K_PEAK, K_PLANT = 0.5, 1.0, 10, 14


def hand_max_stress(s):
    s1, s2, t12 = s
    return max(s1 / 1500e6 if s1 >= 0 else -s1 / 1200e6, s2 / 50e6 if s2 >= 0 else -s2 / 200e6,
               abs(t12) / 70e6)


def hand_tsai_wu(s):
    s1, s2, t12 = s
    F1, F2 = 1 / 1500e6 - 1 / 1200e6, 1 / 50e6 - 1 / 200e6
    F11, F22, F66 = 1 / (1500e6 * 1200e6), 1 / (50e6 * 200e6), 1 / 70e6**2
    F12 = -0.5 * np.sqrt(F11 * F22)
    a = F11 * s1**2 + F22 * s2**2 + F66 * t12**2 + 2 * F12 * s1 * s2
    b = F1 * s1 + F2 * s2
    if a == 0 and b == 0:
        return 0.0  # no stress
    R = max(np.roots([a, b, -1]).real)  # the positive root of a R^2 + b R = 1
    return 1 / R


HAND = {"max_stress": hand_max_stress, "tsai_wu": hand_tsai_wu}


@pytest.fixture(scope="module")
def run():
    plate = dfx.Plate(NX * A, NY * B, dfx.Laminate.from_angles(PLY, 0.5e-3, ANGLES), NX, NY)
    x, y = plate.model.nodes[:, 0], plate.model.nodes[:, 1]
    t = np.linspace(0.0, 1.0, 21)
    U = np.zeros((len(t), plate.model.num_dofs))
    for i, ti in enumerate(t):  # uniform kappa_x: w = -k x^2 / 2, beta_x = theta_y = k x
        k = KAPPA0 * np.sin(np.pi * ti)
        U[i, 2::6] = -k * x**2 / 2
        U[i, 4::6] = k * x
    corner = int(np.argmax(x + y))
    U[K_PLANT, 6 * corner + 4] += THETA_BUMP  # theta_y of the corner node
    element = int(np.flatnonzero((plate.model.quads == corner).any(axis=1))[0])
    return plate, t, U, element


def hand_index(criterion, kappa):
    """(plies,) the largest index over each ply's faces for a centroid curvature kappa."""
    h = 2e-3
    return np.array([max(HAND[criterion](clt.ply_stress(Q, a, np.zeros(3), kappa, z))
                         for z in (-h / 2 + k * 0.5e-3, -h / 2 + (k + 1) * 0.5e-3))
                     for k, a in enumerate(ANGLES)])


@pytest.mark.parametrize("criterion", ["max_stress", "tsai_wu"])
def test_envelope_finds_the_planted_maximum(run, criterion):
    plate, t, U, element = run
    env = stress.envelope(plate.model, ST, t, U, criteria=[criterion], impact_times=[0.3, 0.7])
    # The corner element at the planted sample: at its centroid the bump's bilinear rotation
    # beta_x = theta N_corner adds kappa_x = theta / (2 A) and kappa_xy = theta / (2 B).
    kappa = np.array([KAPPA0 * np.sin(np.pi * t[K_PLANT]) + THETA_BUMP / (2 * A), 0.0,
                      THETA_BUMP / (2 * B)])
    planted = hand_index(criterion, kappa)
    assert env.critical_element == element
    assert env.critical_sample == K_PLANT and env.critical_time_s == t[K_PLANT]
    assert env.critical_ply == int(np.argmax(planted))
    assert env.max_failure_index == pytest.approx(planted.max(), rel=1e-9)
    assert env.min_failure_margin == pytest.approx(1 / planted.max() - 1, rel=1e-9)
    assert env.critical_criterion == criterion
    # Every other element peaks with the background, at t = 0.5 s, at its hand value.
    background = hand_index(criterion, np.array([KAPPA0, 0.0, 0.0]))
    others = [e for e in range(NX * NY) if e != element]
    np.testing.assert_allclose(env.index[0, others], np.tile(background, (len(others), 1)),
                               rtol=1e-9)
    assert np.all(env.sample[0, others] == K_PEAK)
    np.testing.assert_allclose(env.time_s[0, others], 0.5)
    assert env.summary() == {"min_failure_margin": env.min_failure_margin,
                             "max_failure_index": env.max_failure_index,
                             "critical_criterion": criterion, "critical_ply": env.critical_ply,
                             "critical_element": element, "critical_time_s": float(t[K_PLANT])}
    np.testing.assert_array_equal(env.impact_times, [0.3, 0.7])


@pytest.mark.parametrize("where", ["centroid", "gauss"])
@pytest.mark.parametrize("strain", ["linear", "green"])
def test_envelope_equals_a_brute_force_pass_over_the_samples(run, where, strain):
    # The streaming kernel against failure_index(ply_stresses(u_i)) sample by sample (1e-12).
    plate, t, U, _ = run
    criteria = ("max_stress", "tsai_wu", "hashin_fibre")
    env = stress.envelope(plate, ST, t, U, criteria=["max_stress", "tsai_wu", "hashin_fibre"],
                          where=where, strain=strain)
    assert env.criteria == criteria
    fields = [stress.ply_stresses(plate, u, where=where, strain=strain) for u in U]
    per_sample = np.array([[stress.failure_index(f, ST, c).max(axis=(1, 3)) for c in criteria]
                           for f in fields])
    np.testing.assert_allclose(env.index, per_sample.max(axis=0), rtol=1e-12)
    np.testing.assert_array_equal(env.sample, per_sample.argmax(axis=0))
    np.testing.assert_allclose(env.peak_index, per_sample.max(axis=(2, 3)), rtol=1e-12)
    c = criteria.index(env.critical_criterion)
    e, k = env.critical_element, env.critical_ply
    np.testing.assert_allclose(env.critical_history, per_sample[:, c, e, k], rtol=1e-12)
    np.testing.assert_allclose(env.critical_field, per_sample[env.critical_sample, c, :, k],
                               rtol=1e-12)
    assert env.where == where and env.strain_measure == strain


def test_default_criteria_follow_the_strengths(run):
    plate, t, U, _ = run
    assert stress.envelope(plate, ST, t, U).criteria == ("max_stress", "tsai_wu", "hashin_fibre")
    full = dfx.Strengths(Xt=1500 * MPa, Xc=1200 * MPa, Yt=50 * MPa, Yc=200 * MPa, S12=70 * MPa,
                         S23=60 * MPa)
    env = stress.envelope(plate, [full] * 4, t, U, criteria=["hashin"])
    assert env.criteria == ("hashin_fibre", "hashin_matrix")
    assert stress.envelope(plate, full, t, U).criteria == stress.CRITERIA


def test_fields_at_chosen_times(run):
    plate, t, U, _ = run
    fields = stress.fields_at(plate, t, U, [0.52, 0.7])
    assert [f.time_s for f in fields] == [t[K_PEAK], t[K_PLANT]]
    np.testing.assert_array_equal(fields[1].stress, stress.ply_stresses(plate, U[K_PLANT]).stress)
    with pytest.raises(ValueError, match=r"times = \[1.5\] is out of range"):
        stress.fields_at(plate, t, U, [0.2, 1.5])


def test_critical_ply_plot_colours_the_critical_field(run):
    plate, t, U, element = run
    env = stress.envelope(plate, ST, t, U, criteria=["tsai_wu"], impact_times=[0.3, 0.7])
    fig = stress_plot.critical_ply(plate, env)
    ax = fig.axes[0]
    filled = [c for c in ax.collections if c.get_array() is not None]
    assert len(filled) == 1
    np.testing.assert_array_equal(filled[0].get_array(), env.critical_field)
    outline = [c for c in ax.collections if c.get_array() is None][0]
    np.testing.assert_allclose(outline.get_paths()[0].vertices[:4],
                               plate.model.nodes[plate.model.quads[element], :2])
    fig = stress_plot.critical_history(env)
    ax = fig.axes[0]
    curve = [ln for ln in ax.lines if ln.get_label().startswith("element")][0]
    np.testing.assert_array_equal(curve.get_ydata(), env.critical_history)
    vertical = [ln for ln in ax.lines if np.ptp(np.asarray(ln.get_xdata(), dtype=float)) == 0]
    assert sorted(ln.get_xdata()[0] for ln in vertical) == [0.3, 0.7]  # the impacts marked
    assert [ln.get_label() for ln in vertical][0] == "lock impact"
    with pytest.raises(ValueError, match="elements"):
        stress_plot.critical_ply(dfx.Plate(1.0, 1.0, plate.laminate, 2, 2), env)


def test_cell_data_round_trips_through_meshio(run, tmp_path):
    meshio = pytest.importorskip("meshio")
    plate, t, U, _ = run
    s = stress.ply_stresses(plate, U[K_PLANT], where="gauss")
    data = stress.cell_data(s, ST)
    assert set(data) >= {f"ply{k}_{c}" for k in range(4) for c in stress.COMPONENTS}
    np.testing.assert_allclose(data["ply3_sigma_1"][0], s.stress[:, :, 3, 1, 0].mean(axis=1))
    fi = stress.failure_index(s, ST, "tsai_wu")
    np.testing.assert_allclose(data["ply2_tsai_wu"][0], fi[:, :, 2, :].max(axis=(1, 2)))
    np.testing.assert_allclose(data["tsai_wu_max"][0], fi.max(axis=(1, 2, 3)))
    env = stress.envelope(plate, ST, t, U, criteria=["tsai_wu"])
    data.update(env.cell_data())
    mesh = meshio.Mesh(plate.model.nodes, [("quad", np.asarray(plate.model.quads))], cell_data=data)
    meshio.write(tmp_path / "plies.vtu", mesh)
    back = meshio.read(tmp_path / "plies.vtu")
    for name in ("ply0_sigma_1", "ply1_tau_23", "ply3_tsai_wu_max"):
        np.testing.assert_allclose(back.cell_data[name][0], data[name][0], rtol=1e-12)


def test_bad_input_is_named(run):
    plate, t, U, _ = run
    shell = plate.model
    with pytest.raises(ValueError, match=r"u must have shape \(120,\)"):
        stress.ply_stresses(shell, np.zeros(7))
    with pytest.raises(ValueError, match="u has non-finite"):
        stress.ply_stresses(shell, np.full(shell.num_dofs, np.nan))
    with pytest.raises(ValueError, match=r"u_series must have shape \(20, 120\)"):
        stress.envelope(shell, ST, t[:-1], U)
    with pytest.raises(ValueError, match="strengths must give one Strengths per ply"):
        stress.envelope(shell, [ST, ST], t, U)
    with pytest.raises(ValueError, match="S23 is required"):
        stress.envelope(shell, ST, t, U, criteria=["hashin_matrix"])
    with pytest.raises(ValueError, match="where = 'nodes' is invalid"):
        stress.ply_stresses(shell, U[0], where="nodes")
    with pytest.raises(ValueError, match="strain = 'almansi' is invalid"):
        stress.ply_stresses(shell, U[0], strain="almansi")
    with pytest.raises(TypeError, match="shell must be a deployfx.ShellModel"):
        stress.ply_stresses("plate", U[0])
    fidelities = ("linear", "nonlinear", "reduced-linear", "reduced-nonlinear")
    assert [stress.strain_measure(f) for f in fidelities] == ["linear", "green", "linear", "green"]
    with pytest.raises(ValueError, match="fidelity = 'rigid' has no ply stresses"):
        stress.strain_measure("rigid")
    other = dfx.Laminate.from_angles(PLY, 0.5e-3, [90, 0, 0, 90])  # same A, different D
    with pytest.raises(ValueError, match="laminate is not the shell model's section: its D"):
        dfx._core.PlyRecovery(shell._impl, other._impl, False)


def test_a_runs_envelope_is_the_envelope_of_its_mesh_displacements():
    """Reference: deployfx.stress.envelope on the run's mesh displacements, formed here from the
    recorded Ritz coordinates and the panel's basis (d = Phi eta), with Green strain for the
    reduced-nonlinear panel; the summary's margin is 1/FI - 1 of the largest index (the margin's
    definition), its critical ply, element and time those of the envelope, exactly."""
    st = dfx.Strengths(Xt=2.0e9, Xc=1.5e9, Yt=50e6, Yc=200e6, S12=100e6)
    sc = dfx.scenes.paper2016(2, "reduced-nonlinear", nx=4, ny=2, strengths=st)
    r = sc.simulate(2.6, 0.01, stresses=True)
    model = sc.model
    lay = model.layout(0)
    eta = r.q[:, lay["iq_elastic"]:lay["iq_elastic"] + lay["num_elastic"]]
    U = eta @ model.basis(0).T
    env = dfx.stress.envelope(model.shells[0], st, r.t, U, strain="green")
    s = r.summary(hinge=0)
    assert s["min_failure_margin"] == pytest.approx(1 / env.max_failure_index - 1, rel=1e-12)
    assert (s["critical_ply"], s["critical_element"], s["critical_time_s"]) == (
        env.critical_ply, env.critical_element, env.critical_time_s)
    np.testing.assert_allclose(r.max_failure_index[:, 0], env.peak_index.max(axis=1), rtol=1e-12)
    assert s["first_lock_time_s"] < s["critical_time_s"]  # the panel is loaded hardest after the lock
    with pytest.raises(ValueError, match="strengths"):
        dfx.scenes.paper2016(2, "reduced-nonlinear", nx=4, ny=2).simulate(0.1, 0.01, stresses=True)
