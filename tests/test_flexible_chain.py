"""Flexible panels in a chain of hinges (system::HingeChain with reduced panels; issue 5).

Each test names its independent reference:
- one hinge: the single-hinge engine (system::HingedSystem, its own code for the same equations);
- a free-floating yoke and two flexible panels, the second hinge riding on the first panel:
  conservation of momentum (round-off) and energy (the trapezoidal rule's truncation error);
- the stiff limit: the rigid chain (the panels' mass distribution as rigid bodies);
- the attachment: the child hinge's frame from the parent node's displacement and rotation
  (computed here from the basis), and the parent's static deflection under the child's
  centrifugal load from a full finite-element solve (numpy, the mesh's own K and M);
- the Newton and momentum Jacobians: central finite differences.
"""
import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import deployfx as dfx
from deployfx import _core
from deployfx.chain import ChainModel, compile_chain
from deployfx.integrators import GeneralizedAlpha

from test_hinge_chain import Ry, check_jacobians, random_state, rod

Y = np.array([0.0, 1.0, 0.0])


def aluminium_panel(E=70e9, nx=4, ny=2):
    """A 1 m x 0.5 m aluminium panel (2 mm) on an nx x ny mesh, root edge 0.02 m from its hinge
    axis, centred on the hinge point; and its clamped root dofs."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=E, nu=0.33, rho=2700.0), 2e-3)])
    plate = dfx.Plate(1.0, 0.5, lam, nx=nx, ny=ny)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += 0.02
    nodes[:, 1] -= 0.25
    return dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")


def array_scene(fidelity="reduced-linear", modes=3, E=70e9, damping=(0.0, 0.0)):
    """A free base, a yoke on hinge 0 and two panels; hinge 2 sits on panel 1 (past its free edge,
    tilted: a 3-D motion), so a flexible panel 1 carries it on its deforming mesh."""
    shell, root = aluminium_panel(E)
    return (dfx.Scene().set_base(200.0, np.diag([30.0, 35.0, 40.0]))
            .add_hinge("base", point=(0.5, 0, 0), axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2), tau0=2.0, k_theta=0.3,
                       fitting_inertia=0.01)
            .add_rigid_part(2.0, np.diag([0.01, 0.1, 0.1]), (0.4, 0, 0), body=0)
            .add_hinge(0, point=(0.8, 0, 0), axis=(0, 1, 0), R_PE0=Ry(np.pi), tau0=1.5, k_theta=0.2,
                       fitting_inertia=0.01)
            .set_appendage(shell, root, fidelity, modes=modes, damping=damping)
            .add_hinge(1, point=(1.04, 0, 0.01), axis=(0, 0.6, 0.8), R_PE0=Ry(-np.pi), tau0=1.0, k_theta=0.2,
                       fitting_inertia=0.01)
            .set_appendage(shell, root, fidelity, modes=modes, damping=damping))


# ------------------------------------------------------------------------------------------------
# (a) One hinge: the single-hinge engine

def engine_chain_of_one(scene):
    """The engine's chain of one hinge for a one-hinge Scene, any fidelity (compile_chain's
    assembly without its refusal of the full models, which the engine runs too)."""
    body, free = scene._base
    for p in scene._parts:
        body = body + p
    h, a = scene._hinge, scene._appendage
    spec = _core.ChainHingeSpec(h["point"], h["axis"], h["R_BE0"], h["tau0"], h["k_theta"], h["c_theta"],
                                h["fitting"].mass, h["fitting"].com, h["fitting"].inertia, shell=a["shell"]._impl,
                                fixed_dofs=list(a["fixed"]), fidelity=a["fidelity"], alpha_M=a["alpha_M"],
                                beta_K=a["beta_K"], modes=a["modes"])
    return _core.HingeChain(free, body.mass, body.inertia, base_com=body.com, hinges=[spec])


@pytest.mark.parametrize("fidelity", ["reduced-linear", "reduced-nonlinear", "linear", "nonlinear"])
def test_one_hinge_chain_residual_matches_hinged_system(fidelity):
    """Reference: HingedSystem with the same panel (same basis, same Rayleigh damping): a chain of
    one hinge has its coordinates, so the residuals, momenta and energies agree to round-off
    (1e-12 relative; measured 1e-18 (residual), 4e-16 (momentum), 2e-16 (energies)) and the Newton
    matrices to the chain's differences (1e-8; measured 1e-12). The full models too: the engine
    runs them (Scene refuses them in a chain for their cost, test_hinge_chain.py)."""
    p = dfx.scenes.Paper2016Parameters(model=fidelity, nx=4, ny=2, modes=4, damping=(0.3, 1e-3), lock=False)
    sc = dfx.scenes.Paper2016Scene(p)
    hs = sc.model.system
    ch = engine_chain_of_one(sc.scene)
    assert (ch.num_positions, ch.num_velocities) == (hs.num_positions, hs.num_velocities)
    for seed in range(2):
        q, v, a = random_state(hs.num_positions, hs.num_velocities, seed)
        q[8:] *= 0.01  # elastic coordinates of a few cm
        r = hs.residual(q, v, a, 0.0)
        assert np.abs(ch.residual(q, v, a, 0.0) - r).max() <= 1e-12 * np.abs(r).max()
        P = hs.momentum(q, v)
        assert np.abs(ch.momentum(q, v) - P).max() <= 1e-12 * np.abs(P).max()
        o, oc = hs.outputs(q, v, 0.0), ch.outputs(q, v, 0.0)
        for key in ("kinetic_energy", "potential_energy"):
            assert oc[key] == pytest.approx(o[key], rel=1e-12)
        S = hs.iteration_matrix(q, v, a, 0.0, 1.0, 0.05, 0.01)
        assert np.abs(ch.iteration_matrix(q, v, a, 0.0, 1.0, 0.05, 0.01) - S).max() <= 1e-8 * np.abs(S).max()


@pytest.mark.parametrize("fidelity, tol", [("reduced-linear", 1e-9), ("reduced-nonlinear", 1e-9)])
def test_one_hinge_chain_run_matches_hinged_system(fidelity, tol):
    """Reference: HingedSystem's run of the paper's scene (4 x 2 mesh, 6 modes, alpha_M = 0.7 1/s,
    the paper's lock) to past the first lock (3 s, dt = 10 ms): the two engines take the same
    steps and switches, so lock time (s), deployment angle (deg) and node deflections (m) agree to
    `tol`, the trace of Newton's tolerance (1e-10 of the accelerations per step): the two Newton
    matrices differ at truncation level (differenced vs analytic), so the iterates, and which
    step reuses a matrix, differ within that tolerance (measured: reduced-linear 6e-11 deg;
    reduced-nonlinear, nodes and output times below that)."""
    sc = dfx.scenes.Paper2016Scene(dfx.scenes.Paper2016Parameters(model=fidelity, nx=4, ny=2, modes=6))
    chain = compile_chain(sc.scene._base, sc.scene._parts, sc.scene._links, None)
    assert isinstance(chain, ChainModel) and chain.flexible == (True,)
    ref, run = sc.model.simulate(3.0, 0.01), chain.simulate(3.0, 0.01)
    np.testing.assert_allclose(run.t, ref.t, rtol=0, atol=tol)
    lock_ref, lock = ref.summary()["first_lock_time_s"], run.summary()["first_lock_time_s"][0]
    assert 2.3 < lock_ref < 2.6 and abs(lock - lock_ref) <= tol
    assert np.abs(run.deployment_angle[:, 0] - np.degrees(ref.theta)).max() <= tol
    u_ref = ref.node_displacements
    assert np.abs(u_ref).max() > 0.1  # the panel really did bend (m)
    assert np.abs(run.node_displacements_0 - u_ref).max() <= tol
    tip = chain.tip_nodes[0]
    np.testing.assert_allclose(run.tip_displacement[:, 0], u_ref[:, tip], rtol=0, atol=tol)
    np.testing.assert_allclose(run.tip_deflection[:, 0], u_ref[:, tip, 2], rtol=0, atol=tol)  # normal: E's z


# ------------------------------------------------------------------------------------------------
# (b) Conservation: free base, yoke, two flexible panels, the second hinge on the first panel

def test_free_chain_conserves_momentum_and_energy():
    """Reference: no external load and no dissipation (undamped panels, no locks, rho_inf = 1).
    The total momentum (linear, and angular about W's origin) is constant to round-off (1e-12 of
    its size; measured 5e-15: the base rows are solved as Pi_n+1 = Pi_n). The energy (kinetic +
    springs + strain) is conserved by the exact flow only (the attachment's kinematics are exact
    derivatives); the trapezoidal rule leaves its O(dt^2) truncation error, here a few 1e-5 of the
    peak kinetic energy at dt = 2 ms (measured 8.8e-5 at 2 ms, 3.1e-5 at 1 ms, 6.7e-4 at 4 ms;
    stiff static-correction vectors up to 3.5e4 rad/s keep the ratio from a clean 4): within 2e-4
    at 2 ms, and at least halved at 1 ms."""
    model = array_scene().compile()
    assert model.flexible == (False, True, True) and model.attachment_nodes[2] >= 0
    v0 = np.zeros(model.system.num_velocities)
    v0[:6] = [0.01, -0.02, 0.005, 0.02, -0.05, 0.03]  # m/s, rad/s: the base moves and tumbles
    error = {}
    for dt in (2e-3, 1e-3):
        r = model.simulate(1.0, dt, GeneralizedAlpha(1.0), v0=v0)
        Pi = np.hstack([r.total_linear_momentum, r.total_angular_momentum])
        scale = np.abs(Pi).max()
        assert np.abs(Pi - Pi[0]).max() <= 1e-12 * scale
        assert np.abs(r.body_angular_momentum - r.body_angular_momentum[0]).max() > 0.1 * scale  # traded
        assert r.strain_energy.max() > 0.01 * r.kinetic_energy.max()  # the panels really did bend
        E = r.kinetic_energy + r.potential_energy
        error[dt] = np.abs(E - E[0]).max() / r.kinetic_energy.max()
    assert error[2e-3] <= 2e-4
    assert error[1e-3] <= 0.5 * error[2e-3]


# ------------------------------------------------------------------------------------------------
# (c) The stiff limit: the rigid chain

def test_stiff_panels_converge_to_the_rigid_chain():
    """Reference: the same chain with rigid panels (their meshes' mass distributions). The elastic
    deflection under the deployment's inertial loads scales as 1/E, so does the hinge angles'
    departure from the rigid chain's: measured 4.9e-2, 4.7e-4, 5.2e-6 rad for E = 70 GPa x 1, 1e2,
    1e4 over 1.5 s (rho_inf = 1, dt = 2.5 ms: generalized-alpha's numerical dissipation, rho_inf <
    1, would add an O(dt^2) error of its own to the stiff panels' constrained limit). Asserted:
    each hundredfold stiffening cuts it at least fiftyfold, and 1e-5 rad at 1e4."""
    dt = 2.5e-3
    rigid = array_scene("rigid").compile().simulate(1.5, dt, GeneralizedAlpha(1.0))
    assert np.ptp(rigid.theta, axis=0).min() > 0.9  # every hinge swings
    gap = []
    for scale in (1.0, 1e2, 1e4):
        r = array_scene(E=70e9 * scale).compile().simulate(1.5, dt, GeneralizedAlpha(1.0))
        gap.append(np.abs(r.theta - rigid.theta).max())
    assert gap[0] > 1e-2  # flexibility matters at the real stiffness
    assert gap[1] < gap[0] / 50 and gap[2] < gap[1] / 50 and gap[2] < 1e-5


# ------------------------------------------------------------------------------------------------
# (d) The attachment: a child hinge on a loaded panel

OMEGA, CHILD_MASS, CHILD_LENGTH = 0.5, 5.0, 0.6  # rad/s, kg, m
CHILD_POINT = np.array([1.04, 0.0, 0.0])         # hinge 1, m, in the panel's frame E_0


def spinning_panel_with_a_child():
    """A fixed base; hinge 0 (axis y, a 100 kg m^2 flywheel fitting, no spring) carries a reduced
    panel, heavily damped; hinge 1, 2 cm past the panel's free edge, carries a 5 kg rod folded
    normal to the panel (along E_0's z) and held there by a stiff spring. Spun at OMEGA about hinge
    0, the rod's centrifugal load bends the panel through the attachment."""
    shell, root = aluminium_panel()
    m, com, J = rod(CHILD_MASS, CHILD_LENGTH)
    scene = (dfx.Scene().set_base(1.0, 1.0, free=False)
             .add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0), fitting_inertia=100.0)
             .set_appendage(shell, root, "reduced-linear", modes=4, damping=(40.0, 0.0))
             .add_hinge(0, point=CHILD_POINT, axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2), k_theta=400.0, c_theta=5.0)
             .add_rigid_part(m, J, com, body=1))
    return scene.compile(), shell, root, (m, com, J)


def static_reference(shell, root, child, node, omega, theta1):
    """The panel's static deflection (all mesh dofs, m and rad) in its frame E_0 turning steadily at
    `omega` (rad/s, E_0 axes, the axis through E_0's origin), by a full finite-element solve with
    the mesh's own K and consistent M: K u = f_c(X + u) + the child's d'Alembert wrench at the
    attachment node. f_c = -M A (X + u) is the panel's centrifugal load, A x = w x (w x x) on each
    node's translation (the linear model's softening included); the child (mass, com, inertia in
    its frame) sits at hinge angle `theta1` on a rigid arm from `node` to CHILD_POINT, turned by
    the node's rotation (fixed-point iterations: its load depends on u)."""
    m, com, J = child
    A = np.outer(omega, omega) - omega @ omega * np.eye(3)
    K, M = shell.stiffness_matrix().toarray(), shell.mass_matrix().toarray()
    n_dof = shell.num_dofs
    free = np.setdiff1d(np.arange(n_dof), root)

    def translations(x):  # A applied to each node's translation; rotations untouched (zero)
        y = np.zeros(n_dof)
        y.reshape(-1, 6)[:, :3] = x.reshape(-1, 6)[:, :3] @ A.T
        return y

    X_all = np.zeros(n_dof)
    X_all.reshape(-1, 6)[:, :3] = shell.nodes
    G = M @ np.column_stack([translations(e) for e in np.eye(n_dof)])
    X = shell.nodes[node]
    u = np.zeros(n_dof)
    for _ in range(6):
        un, psi = u.reshape(-1, 6)[node, :3], u.reshape(-1, 6)[node, 3:]
        R_att = Rotation.from_rotvec(psi).as_matrix()
        o = X + un + R_att @ (CHILD_POINT - X)
        R_PC = R_att @ Rotation.from_rotvec(theta1 * Y).as_matrix() @ Ry(-np.pi / 2)
        c, J_E = o + R_PC @ com, R_PC @ J @ R_PC.T
        F = -m * (A @ c)                                        # on the panel, at o
        M_o = np.cross(c - o, F) - np.cross(omega, J_E @ omega)
        f = -M @ translations(X_all)
        f[6 * node:6 * node + 3] += F
        f[6 * node + 3:6 * node + 6] += M_o + np.cross(o - (X + un), F)
        u = np.zeros(n_dof)
        u[free] = np.linalg.solve((K + G)[np.ix_(free, free)], f[free])
    return u.reshape(-1, 6)


def test_child_hinge_rides_on_the_loaded_parent_panel():
    """(i) Kinematics, reference: the child hinge's origin and axes in W (the engine's frames())
    equal those placed here from the parent's frame and its attachment node's displacement u and
    rotation psi (read from the Ritz basis): o = o_0 + R_W0 (X + u + exp(psi~) (point - X)),
    R_W1 = R_W0 exp(psi~) Rot(y, theta_1) R_PE0 (1e-12; round-off measured).
    (ii) Statics, reference: a full finite-element solve of the panel under the settled spin's
    loads (static_reference; the reduced basis holds the static responses to unit loads at the
    attachment node, so only the residual transient and the modal softening separate them):
    the node's deflection and rotation within 1e-3 (measured 6e-5 and 5e-5 after 5 s, alpha_M =
    40 1/s)."""
    model, shell, root, child = spinning_panel_with_a_child()
    node = model.attachment_nodes[1]
    assert node >= 0 and np.allclose(shell.nodes[node], [1.02, 0.0, 0.0])  # the nearest node
    v0 = np.zeros(model.system.num_velocities)
    v0[0] = OMEGA
    r = model.simulate(5.0, 0.01, GeneralizedAlpha(0.8), v0=v0)
    q = r.q[-1]
    start, n = model.system.elastic_position(0), model.system.num_elastic(0)
    d = (q[start:start + n] @ model.system.displacement_map(0).T).reshape(-1, 6)[node]
    u, psi = d[:3], d[3:]
    np.testing.assert_array_equal(u, model.node_displacements(q, 0)[0, node])
    R, o = model.system.frames(q)
    R_W0, o_0, R_W1 = R[:, 0:3], o[:, 0], R[:, 3:6]
    R_att = Rotation.from_rotvec(psi).as_matrix()
    X = shell.nodes[node]
    np.testing.assert_allclose(o[:, 1], o_0 + R_W0 @ (X + u + R_att @ (CHILD_POINT - X)), rtol=0, atol=1e-12)
    expected = R_W0 @ R_att @ Rotation.from_rotvec(q[1] * Y).as_matrix() @ Ry(-np.pi / 2)
    np.testing.assert_allclose(R_W1, expected, rtol=0, atol=1e-12)

    assert abs(r.theta_rate[-1, 0] - OMEGA) < 1e-3 and abs(r.theta_rate[-1, 1]) < 1e-5  # settled spin
    assert abs(u[2]) > 1e-3 and abs(psi[1]) > 5e-3  # the child's load bends the panel (m, rad)
    ref = static_reference(shell, root, child, node, r.theta_rate[-1, 0] * Y, q[1])[node]
    assert abs(u[2] - ref[2]) <= 1e-3 * abs(ref[2])
    assert abs(psi[1] - ref[4]) <= 1e-3 * abs(ref[4])


@pytest.mark.parametrize("free", [False, True], ids=["fixed base", "free base"])
def test_locks_with_friction_on_a_flexible_chain(free):
    """Reference: dissipation. notebooks/02's array (a yoke and two flexible aluminium panels,
    hinge 2 riding on panel 1), every hinge locking with the Kelvin-Voigt-Hertz law and Coulomb
    friction (mu = 0.2), undamped panels: nothing adds energy, so kinetic + spring + strain energy
    never rises above its start by more than 1e-6 of the peak kinetic energy (the contact's own
    stored energy only makes it dip), and the run goes through every lock's first impact. Before
    joint::friction_step_limit, exact Newton cycled across the friction's stick band here (hinge
    2's effective inertia is 1500 x below its own) and the runs stopped at t = 0.78 / 1.09 s."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 3e-3)])
    plate = dfx.Plate(0.6, 0.4, lam, nx=4, ny=2)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += 0.02
    nodes[:, 1] -= 0.2
    panel, root = dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")
    law, friction = dfx.contact.ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4), dfx.contact.Friction(0.2)
    spring = dict(c_theta=0.05, fitting_inertia=0.005)
    lock = dict(pin_radius=0.025, clearance=1e-4, law=law, friction=friction)
    array = (dfx.Scene().set_base(mass=300.0, inertia=50.0, free=free)
             .add_hinge("base", point=(0.4, 0, 0), axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2), tau0=4.0, k_theta=0.3,
                        **spring)
             .add_rigid_part(1.5, np.diag([0.002, 0.045, 0.045]), (0.3, 0, 0), body=0)
             .set_lock(np.pi / 2, **lock)
             .add_hinge(0, point=(0.6, 0, 0), axis=(0, 1, 0), R_PE0=Ry(np.pi), tau0=1.5, k_theta=0.1, **spring)
             .set_appendage(panel, root, "reduced-linear", modes=4)
             .set_lock(np.pi, **lock)
             .add_hinge(1, point=(0.64, 0, 0), axis=(0, -1, 0), R_PE0=Ry(np.pi), tau0=0.5, k_theta=0.1, **spring)
             .set_appendage(panel, root, "reduced-linear", modes=4)
             .set_lock(np.pi, **lock)
             .compile())
    r = array.simulate(1.9, 0.01)
    locks = r.summary()["first_lock_time_s"]
    assert all(t is not None for t in locks), locks  # every hinge reached its lock
    E = r.kinetic_energy + r.potential_energy
    assert np.max(E - E[0]) <= 1e-6 * r.kinetic_energy.max()
    assert np.abs(r.tip_deflection[:, 1:]).max() > 1e-2  # the panels really bend (m)


# ------------------------------------------------------------------------------------------------
# Jacobians and the results' series

@pytest.mark.parametrize("fidelity", ["reduced-linear", "reduced-nonlinear"])
def test_jacobians_match_finite_differences(fidelity):
    """Reference: central differences. dr/da = M exactly (r is affine in a; 1e-12); dPi/dv = A(q)
    (Pi is linear in v; 1e-12); dr/dv, dr/dq (along retract) and dPi/dq to the differences' 1e-6,
    at a state with the panels deformed and the second hinge riding on the first panel. Damping
    the matrix carries exactly: mass-proportional, and stiffness-proportional for linear strain
    (with Green strain the matrix drops beta_K dK_T/dq d', as HingedSystem's does)."""
    beta_K = 1e-3 if fidelity == "reduced-linear" else 0.0
    ch = array_scene(fidelity, damping=(0.3, beta_K)).compile().system
    nq, n = ch.num_positions, ch.num_velocities
    q, v, a = random_state(nq, n, 3)
    q[10:] *= 0.02
    v[9:] *= 0.1
    check_jacobians(ch, q, v, a, mass_tol=1e-12)


def test_results_animation_export_and_scene_file(tmp_path):
    """The series of a flexible chain (units, shapes), the deformed panels in W (animation's
    world_points: the mesh plus its node displacements placed with the body frames), the VTK
    export, and a saved scene that runs bit for bit alike."""
    scene = array_scene("reduced-nonlinear", damping=(0.5, 0.0))
    for k, angle in enumerate((np.pi / 2, np.pi, np.pi)):
        scene.set_lock(angle, 0.03, 1e-4, dfx.contact.ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4), hinge=k)
    model = scene.compile()
    assert model.fidelities == (None, "reduced-nonlinear", "reduced-nonlinear")
    assert model.basis_info(0) is None
    assert model.basis_info(1)["static_corrections"] == 12 and model.basis_info(2)["static_corrections"] == 6
    r = model.simulate(0.3, 0.01)
    n, nodes = len(r.t), model.shells[1].nodes.shape[0]
    assert r.metadata["model"] == "flexible chain"
    assert r.tip_deflection.shape == r.strain_energy.shape == (n, 3) and r.tip_displacement.shape == (n, 3, 3)
    assert r.node_displacements_1.shape == r.node_displacements_2.shape == (n, nodes, 3)
    assert "node_displacements_0" not in r
    assert r.units["tip_deflection"] == "m" and r.units["node_displacements_2"] == "m"
    assert r.units["strain_energy"] == "J"
    assert np.all(r.tip_deflection[:, 0] == 0) and np.abs(r.tip_deflection[:, 1:]).max() > 1e-4
    np.testing.assert_allclose(r.potential_energy, r.strain_energy.sum(axis=1) + sum(
        -t0 * th + 0.5 * k * th**2 for t0, k, th in zip((2.0, 1.5, 1.0), (0.3, 0.2, 0.2), r.theta.T)), rtol=1e-12)

    from deployfx import animation, export
    R_WE, o_W = animation.body_frames(model, r)
    for k in (1, 2):
        X = model.shells[k].nodes + r[f"node_displacements_{k}"]
        expected = o_W[:, k, None, :] + np.einsum("kij,knj->kni", R_WE[:, k], X)
        np.testing.assert_allclose(animation.world_points(model, r, hinge=k), expected, rtol=0, atol=1e-14)
        rigid = animation.world_points(model, r, hinge=k, scale=0.0)
        assert np.abs(rigid - expected).max() > 1e-4  # the drawing is the deformed panel
    R, o = model.system.frames(r.q[-1])  # the engine's frames, hinges riding on deformed panels
    np.testing.assert_allclose(o_W[-1].T, o, rtol=0, atol=1e-14)
    np.testing.assert_allclose(np.hstack(list(R_WE[-1])), R, rtol=0, atol=1e-14)
    paths = export.write_vtk_series(r, None, tmp_path / "vtk", every=10, model=model)
    import meshio
    mesh = meshio.read(paths[-1])
    k = (len(r.t) - 1) // 10 * 10
    np.testing.assert_allclose(mesh.points[:nodes], animation.world_points(model, r, hinge=1)[k], atol=1e-12)
    np.testing.assert_allclose(mesh.point_data["displacement"][:nodes],
                               np.einsum("ij,nj->ni", R_WE[k, 1], r.node_displacements_1[k]), atol=1e-12)

    loaded = dfx.load_scene(dfx.save_scene(scene, tmp_path / "flexible_array.toml"))
    again = loaded.compile()
    assert again.fidelities == model.fidelities
    np.testing.assert_array_equal(again.simulate(0.3, 0.01).q, r.q)


# ------------------------------------------------------------------------------------------------
# Bad input

def test_bad_flexible_chain_input_raises_value_error_naming_it():
    shell, root = aluminium_panel()
    base = dict(point=np.zeros(3), axis=Y, R_PC0=np.eye(3), tau0=0.0, k_theta=1.0, c_theta=0.0, mass=0.0,
                com=np.zeros(3), inertia=0.01 * np.eye(3))
    panel = dict(shell=shell._impl, fixed_dofs=list(root), fidelity="reduced-linear", modes=3)
    for change, message in [
        (dict(alpha_M=-1.0), r"hinges\[1\]\.appendage\.alpha_M = -1 is out of range: must be finite and >= 0"),
        (dict(beta_K=np.nan), r"hinges\[1\]\.appendage\.beta_K = nan is out of range"),
        (dict(modes=0), r"hinges\[1\]\.appendage\.modes = 0 is out of range: must be in \[1, 72\]"),
        (dict(modes=3, derivative_modes=4, fidelity="reduced-nonlinear"),
         r"hinges\[1\]\.appendage\.derivative_modes = 4 is out of range"),
        (dict(fidelity="wobbly"), r"appendage\.fidelity = 'wobbly' is invalid: must be 'rigid', 'linear'"),
    ]:
        with pytest.raises(ValueError, match=message):
            spec = _core.ChainHingeSpec(**dict(base, point=np.array([1.04, 0, 0])), **dict(panel, **change))
            _core.HingeChain(False, 1.0, np.eye(3), hinges=[_core.ChainHingeSpec(**base, **panel), spec])

    with pytest.raises(ValueError, match=r"appendage.modes = 0 is out of range: must be in \[1, 72\]"):
        dfx.Scene().set_base(1.0, 1.0).add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0)).set_appendage(
            shell, root, "reduced-linear", modes=0)
    model = array_scene().compile()
    r = model.simulate(0.02, 0.01)
    with pytest.raises(ValueError, match=r"hinge = 0 carries no panel"):
        model.node_displacements(r.q, 0)
    with pytest.raises(ValueError, match=r"hinge = 3 is out of range: must be in \[0, 2\]"):
        model.node_displacements(r.q, 3)
    with pytest.raises(ValueError, match=rf"q has 5 coordinates per sample, the model {model.system.num_positions}"):
        model.node_displacements(np.zeros((1, 5)), 1)
    with pytest.raises(ValueError, match=r"hinge = -1 is out of range"):
        model.system.num_elastic(-1)


def test_a_hinge_on_the_clamped_root_of_a_flexible_panel():
    """A child hinge whose nearest node is on the parent's clamped root edge: the attachment does
    not move with the panel (its node's dofs are fixed), the unit-load corrections there vanish and
    are dropped; the chain compiles and runs (reference: the child then rides on E_1 rigidly)."""
    shell, root = aluminium_panel()
    model = (dfx.Scene().set_base(50.0, 5.0)
             .add_hinge("base", point=(0.3, 0, 0), axis=(0, 1, 0), tau0=1.0, fitting_inertia=0.01)
             .set_appendage(shell, root, "reduced-linear", modes=3)
             .add_hinge(0, point=(0.0, 0.3, 0.0), axis=(1, 0, 0), tau0=0.5, fitting_inertia=0.01)
             .add_rigid_part(1.0, 0.01, (0, 0.2, 0), body=1)).compile()
    node = model.attachment_nodes[1]
    assert node >= 0 and shell.nodes[node][0] == pytest.approx(0.02)  # on the root edge
    info = model.basis_info(0)
    assert info["static_corrections"] == 12  # proposed: E's six, the node's six (zero: dropped)
    assert info["size"] == array_scene().compile().basis_info(2)["size"]  # as the same panel without a child
    r = model.simulate(0.5, 0.01)
    assert np.all(np.isfinite(r.q)) and np.abs(r.theta).max() > 0.01
    R, o = model.system.frames(r.q[-1])
    np.testing.assert_allclose(o[:, 1], o[:, 0] + R[:, 0:3] @ np.array([0.0, 0.3, 0.0]), atol=1e-12)
