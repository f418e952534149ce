"""Flexible panels in a chain of hinges (the engine's tree of hinged bodies with deforming panels;
issue 5).

Each test names its independent reference:
- one hinge: the same spacecraft described in a base frame turned by 90 deg about the hinge axis
  (the equations and the Lie-group scheme are equivariant under a change of the base's axes, so
  every run and residual agrees to round-off), and the power balance of the Rayleigh damping
  along the exact flow (dE/dt = -d'^T (alpha_M M + beta_K K_T) d', from the mesh's own matrices);
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
from deployfx import _core, scenes
from deployfx import paper2016 as paper
from deployfx.groove import PinGroove
from deployfx.integrators import GeneralizedAlpha

import chain_scenes  # tests/: scenes shared by tests
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
            .set_appendage(shell, root, fidelity=fidelity, modes=modes, damping=damping)
            .add_hinge(1, point=(1.04, 0, 0.01), axis=(0, 0.6, 0.8), R_PE0=Ry(-np.pi), tau0=1.0, k_theta=0.2,
                       fitting_inertia=0.01)
            .set_appendage(shell, root, fidelity=fidelity, modes=modes, damping=damping))


def thetas(model, result):
    """The undriven hinges' angles (rad, (n, H)) from a run's q (Model.layout)."""
    return result.q[:, [model.layout(k)["iq_theta"] for k in range(model.num_hinges)]]


# ------------------------------------------------------------------------------------------------
# (a) One hinge: the same spacecraft in turned base axes; the damping's power

R0 = Ry(np.pi / 2)  # B' = B turned by 90 deg about the hinge axis y: a signed permutation of x, z


def paper_scene_in_turned_axes(p, R=R0):
    """The paper's scene (scenes.Paper2016Scene, parameters ``p``) with every base-fixed vector
    and tensor given in the axes of B' (B's axes turned by R: x_B' = R^T x_B): the same
    spacecraft, whose base starts at the attitude R_WB' = I instead of R_WB = I."""
    plate = paper.appendage_plate(p.layup, p.nx, p.ny)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += p.root_offset
    nodes[:, 1] -= paper.WIDTH / 2
    shell = dfx.ShellModel(nodes, plate.model.quads, plate.laminate)
    scene = (dfx.Scene().set_base(p.body_mass, R.T @ (p.body_inertia * np.eye(3)) @ R)
             .add_rigid_part(p.yoke_mass, R.T @ np.diag(p.yoke_inertia) @ R, R.T @ np.array([p.yoke_com_x, 0, 0]))
             .set_hinge(R.T @ np.array([p.hinge_x, 0, 0]), R.T @ Y, R_BE0=R.T @ Ry(-np.pi / 2), tau0=p.tau0,
                        k_theta=p.k_theta, c_theta=p.c_theta, fitting_inertia=p.fitting_inertia, stowed_angle_deg=90.0)
             .set_appendage(shell, plate.fixed_dofs("CFFF"), fidelity=p.model, damping=p.damping, modes=p.modes))
    if p.lock and p.lock_geometry == "groove":  # the lock lives in the hinge's plane: unturned
        scene.set_groove(PinGroove.paper(p.contact, p.friction, seat=p.pin_radius, clearance=p.clearance))
    elif p.lock:
        scene.set_lock(np.pi / 2, p.pin_radius, p.clearance, p.contact, friction=p.friction)
    return scene.compile()


def turned_state(q, v, a, R=R0):
    """(q, v, a) of the paper's scene in B' axes: r_W and v_W, w_B and the attitude R_W'B' =
    R^T R_WB R expressed in W' = R^T W (the world turned with the base); the rest unchanged."""
    T = np.eye(len(v))
    T[:3, :3] = T[3:6, 3:6] = R.T
    qb = q.copy()
    qb[:3] = R.T @ q[:3]
    x = Rotation.from_matrix(R.T @ Rotation.from_quat(q[[4, 5, 6, 3]]).as_matrix() @ R).as_quat()
    qb[3:7] = x[[3, 0, 1, 2]]
    return qb, T @ v, T @ a, T


@pytest.mark.parametrize("fidelity", ["reduced-linear", "reduced-nonlinear", "linear", "nonlinear"])
def test_one_hinge_residual_is_equivariant_under_turned_base_axes(fidelity):
    """Reference: the same spacecraft in B' axes (paper_scene_in_turned_axes) at the same state
    (turned_state): the base's rows and momenta turn with the axes (r' = T r, Pi' = R^T Pi,
    S' = T S T^T), everything else is equal (same panel, same basis, same Rayleigh damping):
    residual, momenta and energies to round-off (1e-12 relative; measured 2e-18, 2e-16, 2e-16) and
    the Newton matrices to 1e-8 (measured 1e-18)."""
    p = scenes.Paper2016Parameters(model=fidelity, nx=4, ny=2, modes=4, damping=(0.3, 1e-3), lock=False)
    hs = scenes.Paper2016Scene(p).model.core
    ch = paper_scene_in_turned_axes(p).core
    assert (ch.num_positions, ch.num_velocities) == (hs.num_positions, hs.num_velocities)
    for seed in range(2):
        q, v, a = random_state(hs.num_positions, hs.num_velocities, seed)
        q[8:] *= 0.01  # elastic coordinates of a few cm
        qb, vb, ab, T = turned_state(q, v, a)
        r = hs.residual(q, v, a, 0.0)
        assert np.abs(ch.residual(qb, vb, ab, 0.0) - T @ r).max() <= 1e-12 * np.abs(r).max()
        P = hs.momentum(q, v)
        assert np.abs(ch.momentum(qb, vb) - np.r_[R0.T @ P[:3], R0.T @ P[3:]]).max() <= 1e-12 * np.abs(P).max()
        o, oc = hs.outputs(q, v, a, 0.0), ch.outputs(qb, vb, ab, 0.0)
        for key in ("kinetic_energy", "potential_energy"):
            assert oc[key] == pytest.approx(o[key], rel=1e-12)
        S = hs.newton_matrix(q, v, a, 0.0, 1.0, 0.05, 0.01)
        assert np.abs(ch.newton_matrix(qb, vb, ab, 0.0, 1.0, 0.05, 0.01) - T @ S @ T.T).max() <= 1e-8 * np.abs(S).max()


@pytest.mark.parametrize("fidelity", ["reduced-linear", "reduced-nonlinear", "linear", "nonlinear"])
def test_one_hinge_damping_dissipates_the_rayleigh_power_along_the_flow(fidelity):
    """Reference: along the exact flow (accelerations from r(q, v, a) = 0) the total energy falls
    at the rate the Rayleigh damping dissipates, dE/dt = -d'^T (alpha_M M + beta_K K_T(d)) d'
    (Clough & Penzien 1993, Sec. 12-4; K_T = K for linear strain), with d, d' the mesh dofs of the
    elastic coordinates (Model's displacement map) and M, K_T the mesh's own matrices; the other
    forces (springs, strain) are conservative. Central differences with step 1e-6 s: within 1e-5
    of the power exchanged between kinetic and potential energy (their truncation error;
    measured 4e-7), as test_hinged_system's undamped flow."""
    alpha_M, beta_K = 0.3, 1e-3
    p = scenes.Paper2016Parameters(model=fidelity, nx=4, ny=2, modes=4, damping=(alpha_M, beta_K), lock=False)
    model = scenes.Paper2016Scene(p).model
    sys, shell = model.core, model.shells[0]
    lay, D = sys.layout(0), sys.displacement_map(0)
    n, ne = sys.num_velocities, lay["num_elastic"]
    rng = np.random.default_rng(1)
    q = sys.initial_positions()
    q[3:7] = np.array([0.9, 0.1, -0.3, 0.2]) / np.linalg.norm([0.9, 0.1, -0.3, 0.2])
    q[lay["iq_theta"]] = 0.3
    scale = 1e-3 / np.abs(D).max(axis=0)  # ~1 mm of displacement per coordinate
    q[lay["iq_elastic"]:] = scale * rng.normal(size=ne)
    v = 0.1 * rng.normal(size=n)
    v[lay["iv_elastic"]:] = 3 * scale * rng.normal(size=ne)
    a = np.zeros(n)
    for _ in range(3):
        a -= np.linalg.solve(sys.newton_matrix(q, v, a, 0.0, 1, 0, 0), sys.residual(q, v, a, 0.0))
    eps = 1e-6
    plus = sys.outputs(sys.retract(q, eps * v), v + eps * a, a, 0.0)
    minus = sys.outputs(sys.retract(q, -eps * v), v - eps * a, a, 0.0)
    E = lambda o: o["kinetic_energy"] + o["potential_energy"]
    d, dd = D @ q[lay["iq_elastic"]:], D @ v[lay["iv_elastic"]:]
    K_T = shell.internal_force(d)[1] if "nonlinear" in fidelity else shell.stiffness_matrix()
    dissipated = alpha_M * dd @ (shell.mass_matrix() @ dd) + beta_K * dd @ (K_T @ dd)
    power = abs(plus["kinetic_energy"] - minus["kinetic_energy"]) / (2 * eps)
    assert dissipated > 1e-4 * power  # the damping is not negligible here
    assert abs((E(plus) - E(minus)) / (2 * eps) + dissipated) < 1e-5 * power


@pytest.mark.parametrize("fidelity, tol", [("reduced-linear", 1e-9), ("reduced-nonlinear", 1e-9)])
def test_one_hinge_run_is_equivariant_under_turned_base_axes(fidelity, tol):
    """Reference: the run of the same spacecraft in B' axes (above) of the paper's scene (4 x 2
    mesh, 6 modes, alpha_M = 0.7 1/s, the paper's lock) to past the first lock (3 s, dt = 10 ms):
    the scheme is equivariant too (exp(R^T w~ R) = R^T exp(w~) R, and B' only permutes the base's
    components with signs, so Newton's norms and steps are the same), so lock time (s),
    deployment angle (deg) and node deflections (m) agree to `tol` (measured 6e-13 deg, 1e-12 m),
    and the base's attitude is the turned one, R_W'B' = R^T R_WB R."""
    p = scenes.Paper2016Parameters(model=fidelity, nx=4, ny=2, modes=6)
    sc = scenes.Paper2016Scene(p)
    turned = paper_scene_in_turned_axes(p)
    ref, run = sc.model.simulate(3.0, 0.01), turned.simulate(3.0, 0.01)
    np.testing.assert_allclose(run.t, ref.t, rtol=0, atol=tol)
    lock_ref, lock = ref.summary(hinge=0)["first_lock_time_s"], run.summary(hinge=0)["first_lock_time_s"]
    assert 2.3 < lock_ref < 2.6 and abs(lock - lock_ref) <= tol
    assert np.abs(run.deployment_angle - ref.deployment_angle).max() <= tol
    u_ref, u = sc.model.node_displacements(ref.q, 0), turned.node_displacements(run.q, 0)
    assert np.abs(u_ref).max() > 0.1  # the panel really did bend (m)
    assert np.abs(u - u_ref).max() <= tol
    R_ref = Rotation.from_quat(ref.q[:, [4, 5, 6, 3]]).as_matrix()
    R_run = Rotation.from_quat(run.q[:, [4, 5, 6, 3]]).as_matrix()
    assert np.abs(R_run - R0.T @ R_ref @ R0).max() <= tol
    assert np.abs(R_ref - np.eye(3)).max() > 1e-4  # the base really turned
    # The tip series are the tip node's displacement (E axes), and its deflection along the
    # direction the hinge turns it: at the tip (x along E's x, hinge axis E's y) that is -E's z.
    tip = sc.model.tip_nodes[0]
    np.testing.assert_allclose(ref.tip_displacement[:, 0], u_ref[:, tip], rtol=0, atol=1e-15)
    np.testing.assert_allclose(ref.tip_deflection[:, 0], -u_ref[:, tip, 2], rtol=0, atol=1e-15)


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
    assert model.deforming == (False, True, True) and model.layout(2)["attachment_node"] >= 0
    v0 = np.zeros(model.num_velocities)
    v0[:6] = [0.01, -0.02, 0.005, 0.02, -0.05, 0.03]  # m/s, rad/s: the base moves and tumbles
    error = {}
    for dt in (2e-3, 1e-3):
        r = model.simulate(1.0, dt, scheme=GeneralizedAlpha(1.0), v0=v0)
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
    rigid_model = array_scene("rigid").compile()
    rigid = thetas(rigid_model, rigid_model.simulate(1.5, dt, scheme=GeneralizedAlpha(1.0)))
    assert np.ptp(rigid, axis=0).min() > 0.9  # every hinge swings
    gap = []
    for scale in (1.0, 1e2, 1e4):
        model = array_scene(E=70e9 * scale).compile()
        r = model.simulate(1.5, dt, scheme=GeneralizedAlpha(1.0))
        gap.append(np.abs(thetas(model, r) - rigid).max())
    assert gap[0] > 1e-2  # flexibility matters at the real stiffness
    assert gap[1] < gap[0] / 50 and gap[2] < gap[1] / 50 and gap[2] < 1e-5


# ------------------------------------------------------------------------------------------------
# (d) The attachment: a child hinge on a loaded panel

OMEGA, CHILD_MASS, CHILD_LENGTH = 0.5, 5.0, 0.6  # rad/s, kg, m
CHILD_POINT = np.array([1.04, 0.0, 0.0])         # hinge 1, m, in the panel's frame E_0


def spinning_panel_with_a_child(fidelity="reduced-linear"):
    """A fixed base; hinge 0 (axis y, a 100 kg m^2 flywheel fitting, no spring) carries a reduced
    panel, heavily damped; hinge 1, 2 cm past the panel's free edge, carries a 5 kg rod folded
    normal to the panel (along E_0's z) and held there by a stiff spring. Spun at OMEGA about hinge
    0, the rod's centrifugal load bends the panel through the attachment."""
    shell, root = aluminium_panel()
    m, com, J = rod(CHILD_MASS, CHILD_LENGTH)
    scene = (dfx.Scene().set_base(1.0, 1.0, free=False)
             .add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0), fitting_inertia=100.0)
             .set_appendage(shell, root, fidelity=fidelity, modes=4, damping=(40.0, 0.0))
             .add_hinge(0, point=CHILD_POINT, axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2), k_theta=400.0, c_theta=5.0)
             .add_rigid_part(m, J, com, body=1))
    return scene.compile(), shell, root, (m, com, J)


def assert_child_frame_on_the_node(model, shell, q, node, u, psi):
    """The child hinge's origin and axes in W (the engine's frames()) equal those placed from the
    parent's frame and the attachment node's displacement u and rotation psi:
    o = o_0 + R_W0 (X + u + exp(psi~) (point - X)), R_W1 = R_W0 exp(psi~) Rot(y, theta_1) R_PE0
    (1e-12)."""
    R, o = model.frames(q)
    R_W0, o_0, R_W1, o_1 = R[0, 0], o[0, 0], R[0, 1], o[0, 1]
    R_att = Rotation.from_rotvec(psi).as_matrix()
    X = shell.nodes[node]
    np.testing.assert_allclose(o_1, o_0 + R_W0 @ (X + u + R_att @ (CHILD_POINT - X)), rtol=0, atol=1e-12)
    expected = R_W0 @ R_att @ Rotation.from_rotvec(q[1] * Y).as_matrix() @ Ry(-np.pi / 2)
    np.testing.assert_allclose(R_W1, expected, rtol=0, atol=1e-12)


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
    node = model.layout(1)["attachment_node"]
    assert node >= 0 and np.allclose(shell.nodes[node], [1.02, 0.0, 0.0])  # the nearest node
    assert [model.layout(k)["iq_theta"] for k in (0, 1)] == [0, 1]  # fixed base: q = [theta_0, theta_1, eta]
    v0 = np.zeros(model.num_velocities)
    v0[0] = OMEGA
    r = model.simulate(5.0, 0.01, scheme=GeneralizedAlpha(0.8), v0=v0)
    q = r.q[-1]
    lay = model.layout(0)
    start, n = lay["iq_elastic"], lay["num_elastic"]
    d = (q[start:start + n] @ model.core.displacement_map(0).T).reshape(-1, 6)[node]
    u, psi = d[:3], d[3:]
    np.testing.assert_allclose(u, model.node_displacements(q, 0)[0, node], rtol=1e-14, atol=0)
    assert_child_frame_on_the_node(model, shell, q, node, u, psi)

    rate = np.radians(r.deployment_rate[-1])  # rad/s
    assert abs(rate[0] - OMEGA) < 1e-3 and abs(rate[1]) < 1e-5  # settled spin
    assert abs(u[2]) > 1e-3 and abs(psi[1]) > 5e-3  # the child's load bends the panel (m, rad)
    ref = static_reference(shell, root, child, node, rate[0] * Y, q[1])[node]
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
    array = chain_scenes.locked_array("reduced-linear", nx=4, free=free)
    r = array.simulate(1.9, 0.01)
    locks = r.summary()["first_lock_time_s"]
    assert all(t is not None for t in locks), locks  # every hinge reached its lock
    E = r.kinetic_energy + r.potential_energy
    assert np.max(E - E[0]) <= 1e-6 * r.kinetic_energy.max()
    assert np.abs(r.tip_deflection[:, 1:]).max() > 1e-2  # the panels really bend (m)


# ------------------------------------------------------------------------------------------------
# Jacobians and the results' series

@pytest.mark.parametrize("fidelity", ["reduced-linear", "reduced-nonlinear", "reduced-manifold"])
def test_jacobians_match_finite_differences(fidelity):
    """Reference: central differences. dr/da = M exactly (r is affine in a; 1e-12); dPi/dv = A(q)
    (Pi is linear in v; 1e-12); dr/dv, dr/dq (along retract) and dPi/dq to the differences' 1e-6,
    at a state with the panels deformed and the second hinge riding on the first panel (on the
    manifold: moving with g(q), through the chain rule of z = P g(q) and G^T's own derivative
    contracted with the attachment's force). Damping the matrix carries exactly: mass-proportional,
    and stiffness-proportional for linear strain (with Green strain the matrix drops beta_K
    dK_T/dq d', as the one-hinge model's does)."""
    beta_K = 1e-3 if fidelity == "reduced-linear" else 0.0
    ch = array_scene(fidelity, damping=(0.3, beta_K)).compile().core
    nq, n = ch.num_positions, ch.num_velocities
    q, v, a = random_state(nq, n, 3)
    q[10:] *= 0.02
    v[9:] *= 0.1
    check_jacobians(ch, q, v, a, mass_tol=1e-12)


def test_manifold_parent_conserves_energy():
    """A hinge riding on a reduced-manifold panel, whose attachment moves with the slaved in-plane
    displacement g(q). Reference: the exact flow conserves the energy (undamped, no locks,
    rho_inf = 1; the attachment's force G^T P^T tau_z does the work its kinematics z = P g(q)
    take), so the trapezoidal rule leaves its O(dt^2) truncation error alone: measured 2.0e-5 of
    the peak kinetic energy at 2 ms and 5.1e-6 at 1 ms (3.9x): within 1e-4 at 2 ms, and at most a
    third of it at 1 ms."""
    model = array_scene("reduced-manifold").compile()
    assert model.fidelities == (None, "reduced-manifold", "reduced-manifold")
    v0 = np.zeros(model.num_velocities)
    v0[:6] = [0.01, -0.02, 0.005, 0.02, -0.05, 0.03]
    error = {}
    for dt in (2e-3, 1e-3):
        r = model.simulate(1.0, dt, scheme=GeneralizedAlpha(1.0), v0=v0)
        assert r.strain_energy.max() > 0.01 * r.kinetic_energy.max()  # the panels really did bend
        E = r.kinetic_energy + r.potential_energy
        error[dt] = np.abs(E - E[0]).max() / r.kinetic_energy.max()
    assert error[2e-3] <= 1e-4
    assert error[1e-3] <= error[2e-3] / 3


def test_child_hinge_rides_on_a_manifold_panel():
    """The spinning panel of test_child_hinge_rides_on_the_loaded_parent_panel on the manifold.
    (i) Kinematics, reference: the child hinge's frame placed here from the attachment node's
    displacement and rotation lifted through the map (eta = g(q), Model.core.panel_coordinates,
    then the basis): 1e-12. (ii) Statics, reference: the same chain with a reduced-nonlinear
    panel on the same basis, whose in-plane coordinates are free (the attachment moves linearly
    in them): the settled node's deflection within 1e-5 (measured 5e-7) and its foreshortening,
    the in-plane pull-in that the bending's Green strain makes (absent with linear strain:
    2.8e-8 m against 7.5e-6), within 1 % (measured 0.4 %)."""
    settled = {}
    for fidelity in ("reduced-manifold", "reduced-nonlinear"):
        model, shell, root, child = spinning_panel_with_a_child(fidelity)
        node = model.layout(1)["attachment_node"]
        v0 = np.zeros(model.num_velocities)
        v0[0] = OMEGA
        q = model.simulate(5.0, 0.01, scheme=GeneralizedAlpha(0.8), v0=v0).q[-1]
        settled[fidelity] = model.node_displacements(q, 0)[0, node]
        if fidelity != "reduced-manifold":
            continue
        lay = model.layout(0)
        q_el = q[lay["iq_elastic"]:lay["iq_elastic"] + lay["num_elastic"]]
        eta = model.core.panel_coordinates(0, q_el[None, :])[0]
        d = (eta @ model.core.displacement_map(0).T).reshape(-1, 6)[node]
        u, psi = d[:3], d[3:]
        np.testing.assert_allclose(u, settled[fidelity], rtol=1e-14, atol=0)
        assert_child_frame_on_the_node(model, shell, q, node, u, psi)
    u, ref = settled["reduced-manifold"], settled["reduced-nonlinear"]
    assert abs(ref[2]) > 1e-3 and abs(ref[0]) > 1e-6  # bent, and pulled in
    assert abs(u[2] - ref[2]) <= 1e-5 * abs(ref[2])
    assert abs(u[0] - ref[0]) <= 1e-2 * abs(ref[0])


def test_results_animation_export_and_scene_file(tmp_path):
    """The series of a flexible chain (units, shapes), the deformed panels in W (animation's
    world_points: the mesh plus its node displacements placed with the body frames), the VTK
    export, and a saved scene that runs bit for bit alike."""
    scene = array_scene("reduced-nonlinear", damping=(0.5, 0.0))
    for k, angle in enumerate((np.pi / 2, np.pi, np.pi)):
        scene.set_lock(angle, 0.03, 1e-4, dfx.contact.ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4), hinge=k)
    model = scene.compile()
    assert model.fidelities == (None, "reduced-nonlinear", "reduced-nonlinear")
    with pytest.raises(ValueError, match="hinge = 0 carries no panel"):
        model.basis_info(0)  # the yoke
    assert model.basis_info(1)["static_corrections"] == 12 and model.basis_info(2)["static_corrections"] == 6
    r = model.simulate(0.3, 0.01, nodes="all")
    n, nodes = len(r.t), model.shells[1].nodes.shape[0]
    assert [h["fidelity"] for h in r.metadata["hinges"]] == [None, "reduced-nonlinear", "reduced-nonlinear"]
    assert [h.get("basis_size") for h in r.metadata["hinges"]] == [None, model.basis_info(1)["size"],
                                                                     model.basis_info(2)["size"]]
    assert r.tip_deflection.shape == r.strain_energy.shape == (n, 3) and r.tip_displacement.shape == (n, 3, 3)
    assert r.node_displacements_1.shape == r.node_displacements_2.shape == (n, nodes, 3)
    assert "node_displacements_0" not in r
    assert r.units["tip_deflection"] == "m" and r.units["node_displacements_2"] == "m"
    assert r.units["strain_energy"] == "J"
    assert np.all(r.tip_deflection[:, 0] == 0) and np.abs(r.tip_deflection[:, 1:]).max() > 1e-4
    np.testing.assert_allclose(r.potential_energy, r.strain_energy.sum(axis=1) + sum(
        -t0 * th + 0.5 * k * th**2 for t0, k, th in zip((2.0, 1.5, 1.0), (0.3, 0.2, 0.2), thetas(model, r).T)),
        rtol=1e-12)

    from deployfx import animation, export
    R_WE, o_W = animation.body_frames(model, r)
    for k in (1, 2):
        X = model.shells[k].nodes + r[f"node_displacements_{k}"]
        expected = o_W[:, k, None, :] + np.einsum("kij,knj->kni", R_WE[:, k], X)
        np.testing.assert_allclose(animation.world_points(model, r, hinge=k), expected, rtol=0, atol=1e-14)
        rigid = animation.world_points(model, r, hinge=k, scale=0.0)
        assert np.abs(rigid - expected).max() > 1e-4  # the drawing is the deformed panel
    paths = export.write_vtk_series(model, r, tmp_path / "vtk", every=10)
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
    hinge = dict(k_theta=1.0, body=_core.RigidInertia(inertia=0.01 * np.eye(3)))
    panel = dict(shell=shell._impl, fixed_dofs=list(root), fidelity="reduced-linear", modes=3)
    for change, message in [
        (dict(alpha_M=-1.0), r"hinges\[1\]\.panel\.alpha_M = -1 is out of range: must be finite and >= 0"),
        (dict(beta_K=np.nan), r"hinges\[1\]\.panel\.beta_K = nan is out of range"),
        (dict(modes=0), r"hinges\[1\]\.panel\.modes = 0 is out of range: must be in \[1, 72\]"),
        (dict(modes=3, derivative_modes=4, fidelity="reduced-nonlinear"),
         r"hinges\[1\]\.panel\.derivative_modes = 4 is out of range"),
        (dict(fidelity="wobbly"), r"panel\.fidelity = 'wobbly' is invalid: must be 'rigid', 'linear'"),
    ]:
        with pytest.raises(ValueError, match=message):
            child = _core.HingeSpec(parent=0, point=[1.04, 0, 0], **hinge,
                                    panel=_core.PanelSpec(**dict(panel, **change)))
            _core.Model(base_free=False, base=_core.RigidInertia(mass=1.0, inertia=np.eye(3)),
                        hinges=[_core.HingeSpec(parent=-1, **hinge, panel=_core.PanelSpec(**panel)), child])

    with pytest.raises(ValueError, match=r"appendage.modes = 0 is out of range: must be in \[1, 72\]"):
        dfx.Scene().set_base(1.0, 1.0).add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0)).set_appendage(
            shell, root, fidelity="reduced-linear", modes=0)
    model = array_scene().compile()
    r = model.simulate(0.02, 0.01)
    with pytest.raises(ValueError, match=r"hinge = 0 carries no panel"):
        model.node_displacements(r.q, 0)
    with pytest.raises(ValueError, match=r"hinge = 3 is out of range: must be in \[0, 2\]"):
        model.node_displacements(r.q, 3)
    with pytest.raises(ValueError, match=rf"q has shape \(1, 5\): this model has {model.num_positions} coordinates"):
        model.node_displacements(np.zeros((1, 5)), 1)
    with pytest.raises(ValueError, match=r"hinge = -1 is out of range"):
        model.layout(-1)
    with pytest.raises(ValueError, match=r"hinge = -1 is out of range"):
        model.core.layout(-1)


def test_a_hinge_on_the_clamped_root_of_a_flexible_panel():
    """A child hinge whose nearest node is on the parent's clamped root edge: the attachment does
    not move with the panel (its node's dofs are fixed), the unit-load corrections there vanish and
    are dropped; the chain compiles and runs (reference: the child then rides on E_1 rigidly)."""
    shell, root = aluminium_panel()
    model = (dfx.Scene().set_base(50.0, 5.0)
             .add_hinge("base", point=(0.3, 0, 0), axis=(0, 1, 0), tau0=1.0, fitting_inertia=0.01)
             .set_appendage(shell, root, fidelity="reduced-linear", modes=3)
             .add_hinge(0, point=(0.0, 0.3, 0.0), axis=(1, 0, 0), tau0=0.5, fitting_inertia=0.01)
             .add_rigid_part(1.0, 0.01, (0, 0.2, 0), body=1)).compile()
    node = model.layout(1)["attachment_node"]
    assert node >= 0 and shell.nodes[node][0] == pytest.approx(0.02)  # on the root edge
    info = model.basis_info(0)
    assert info["static_corrections"] == 12  # proposed: E's six, the node's six (zero: dropped)
    assert info["size"] == array_scene().compile().basis_info(2)["size"]  # as the same panel without a child
    r = model.simulate(0.5, 0.01)
    assert np.all(np.isfinite(r.q)) and np.abs(thetas(model, r)).max() > 0.01
    R, o = model.frames(r.q[-1])
    np.testing.assert_allclose(o[0, 1], o[0, 0] + R[0, 0] @ np.array([0.0, 0.3, 0.0]), atol=1e-12)
