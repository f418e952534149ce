"""A chain of hinges: a base carrying rigid bodies in series on spring hinges (issue 5).

Each test names its independent reference:
- one hinge: the same scene built another way: the paper's panel as a rigid panel of the scene
  builder (the engine integrates the mesh's mass) against a rigid body computed here from the
  mesh's floating-frame shape integrals and given to the engine's low-level model directly;
- two links with parallel axes: the closed-form small-oscillation frequencies of the compound
  double pendulum with torsion springs;
- three panels on a free base: conservation of momentum and energy;
- locks: the lock geometry (stop at theta_lock, latch one clearance before it);
- the Newton and momentum Jacobians: central finite differences.
"""
import numpy as np
import pytest
import scipy.linalg

import deployfx as dfx
from deployfx import _core
from deployfx.contact import ContactLaw, Friction
from deployfx.integrators import GeneralizedAlpha
from deployfx.specs import rigid_appendage
from deployfx.specs import RigidPart

from test_hinged_system import B_H, J_BASE, K_THETA, M_BASE, P_HINGE, TAU0, W, Ry, make_system

Y = np.array([0.0, 1.0, 0.0])


def rod(mass, length):
    """A slender bar along its frame's x from the origin: (mass kg, com m, inertia about the com
    kg m^2) with m L^2 / 12 about y and z (and a small x term so the inertia is definite)."""
    I = mass * length**2 / 12
    return mass, np.array([length / 2, 0.0, 0.0]), np.diag([1e-3 * I, I, I])


def spec(parent, point, axis, body, R=np.eye(3), tau0=0.0, k=0.0, c=0.0, lock=None):
    """The engine's hinge spec: hinge on ``parent`` (-1: the base) carrying the rigid ``body``
    (mass, com, inertia)."""
    m, com, J = body
    return _core.HingeSpec(parent=parent, point=np.asarray(point, float), axis=np.asarray(axis, float), R_PC0=R,
                           tau0=tau0, k_theta=k, c_theta=c, lock=lock,
                           body=_core.RigidInertia(mass=m, com=com, inertia=J))


def chain(free, base_mass, base_inertia, hinges, base_com=np.zeros(3)):
    """The engine's model of a serial chain (hinge k on hinge k - 1's body; specs from spec())."""
    return _core.Model(base_free=free, base=_core.RigidInertia(mass=base_mass, com=base_com, inertia=base_inertia),
                       hinges=hinges)


def simulate(model, q0, v0, t_end, dt, rho_inf):
    """The engine's raw run; per-hinge series (n, H)."""
    return _core.simulate(model, q0, v0, t_end=t_end, dt=dt, scheme=GeneralizedAlpha(rho_inf)._params())


def paper_chain_of_one():
    """The paper's appendage (4 x 2 mesh) as a rigid body computed from its mesh
    (rigid_appendage: the floating-frame shape integrals) plus the fitting (0.02 kg m^2), on the
    engine's low-level model: no panel."""
    plate = dfx.paper2016.appendage_plate(2, 4, 2)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += B_H
    nodes[:, 1] -= W / 2
    body = rigid_appendage(dfx.ShellModel(nodes, plate.model.quads, plate.laminate))
    body = body + RigidPart(0.0, np.zeros(3), 0.02 * np.eye(3))
    h = spec(-1, P_HINGE, Y, (body.mass, body.com, body.inertia), Ry(-np.pi / 2), TAU0, K_THETA)
    return chain(True, M_BASE, J_BASE * np.eye(3), [h])


def random_state(n_q, n_v, seed, free=True):
    rng = np.random.default_rng(seed)
    q = np.zeros(n_q)
    if free:
        q[:3] = [0.1, -0.2, 0.3]
        q[3:7] = np.array([0.9, 0.1, -0.3, 0.2]) / np.linalg.norm([0.9, 0.1, -0.3, 0.2])
        q[7:] = rng.uniform(-1, 1, n_q - 7)
    else:
        q[:] = rng.uniform(-1, 1, n_q)
    return q, rng.normal(size=n_v), rng.normal(size=n_v)


# ------------------------------------------------------------------------------------------------
# (a) One hinge: the same scene built another way

def test_one_hinge_rigid_panel_residual_matches_the_rigid_body_built_by_hand():
    """Reference: the rigid panel of the scene builder (test_hinged_system.make_system, the
    engine's rigid panel) against the mesh's mass merged with the fitting by hand into one rigid
    body; the same coordinates, so the residuals agree to round-off (1e-10 relative)."""
    hs, ch = make_system("rigid", free=True, fitting=0.02), paper_chain_of_one()
    assert (ch.num_positions, ch.num_velocities) == (hs.num_positions, hs.num_velocities) == (8, 7)
    for seed in range(3):
        q, v, a = random_state(8, 7, seed)
        r = hs.residual(q, v, a, 0.0)
        assert np.abs(ch.residual(q, v, a, 0.0) - r).max() <= 1e-10 * np.abs(r).max()
        P = hs.momentum(q, v)
        assert np.abs(ch.momentum(q, v) - P).max() <= 1e-10 * np.abs(P).max()
        S = hs.newton_matrix(q, v, a, 0.0, 1.0, 0.05, 0.01)
        assert np.abs(ch.newton_matrix(q, v, a, 0.0, 1.0, 0.05, 0.01) - S).max() <= 1e-7 * np.abs(S).max()


def test_one_hinge_rigid_panel_trajectory_matches_the_rigid_body_built_by_hand():
    """Reference: the run of the rigid body built by hand (above) of the paper's rigid deployment
    (3 s, dt = 0.01 s, past 180 deg): every coordinate within 1e-10 (m, rad)."""
    hs, ch = make_system("rigid", free=True, fitting=0.02), paper_chain_of_one()
    q0, v0 = hs.initial_positions(), np.zeros(7)
    ref = simulate(hs, q0, v0, 3.0, 0.01, 0.8)
    run = simulate(ch, q0, v0, 3.0, 0.01, 0.8)
    assert ref["failure"] == run["failure"] == ""
    assert run["theta"].shape == (len(run["t"]), 1)
    assert run["theta"][-1, 0] > np.pi / 2
    np.testing.assert_allclose(run["t"], ref["t"], rtol=0, atol=1e-14)
    assert np.abs(run["q"] - ref["q"]).max() < 1e-10
    assert np.abs(run["kinetic_energy"] - ref["kinetic_energy"]).max() < 1e-10 * ref["kinetic_energy"].max()


# ------------------------------------------------------------------------------------------------
# (b) Two links, parallel axes: the compound double pendulum with torsion springs

M1, L1, M2, L2, K1, K2 = 2.0, 1.0, 1.5, 0.8, 5.0, 3.0  # kg, m, kg, m, N m/rad, N m/rad


def double_pendulum():
    """Fixed base; link 1 on a hinge at the origin, link 2 on a hinge at its end (x = L1), both
    axes along y; straight (both along x) at theta = 0, where the springs are relaxed."""
    return chain(False, 1.0, np.eye(3), [spec(-1, [0, 0, 0], Y, rod(M1, L1), k=K1),
                                         spec(0, [L1, 0, 0], Y, rod(M2, L2), k=K2)])


def double_pendulum_reference():
    """Mass and stiffness matrices of the linearised planar compound double pendulum about the
    straight configuration, in the relative angles (theta_1, theta_2) (Lagrange's equations,
    e.g. Meirovitch, Fundamentals of Vibrations, 2001, Sec. 6.2; Greenwood, Principles of
    Dynamics, 1988, Ch. 4). With absolute angles phi_1 = theta_1, phi_2 = theta_1 + theta_2, link
    i's centre at c_i = L_i / 2 and I_i = m_i L_i^2 / 12 about it:
      T = 1/2 (I_1 + m_1 c_1^2) phi_1'^2 + 1/2 m_2 (L_1^2 phi_1'^2 + 2 L_1 c_2 phi_1' phi_2' cos(phi_2 - phi_1)
          + c_2^2 phi_2'^2) + 1/2 I_2 phi_2'^2,   V = 1/2 k_1 theta_1^2 + 1/2 k_2 theta_2^2,
    and at phi_2 = phi_1 the cosine is 1."""
    c1, c2, I1, I2 = L1 / 2, L2 / 2, M1 * L1**2 / 12, M2 * L2**2 / 12
    m22 = I2 + M2 * c2**2
    m12 = m22 + M2 * L1 * c2
    m11 = I1 + M1 * c1**2 + M2 * L1**2 + 2 * M2 * L1 * c2 + m22
    return np.array([[m11, m12], [m12, m22]]), np.diag([K1, K2])


def test_double_pendulum_matrices_match_the_closed_form():
    """M(0) = dr/da = the closed form to round-off; the stiffness dr/dq at rest = diag(k) (1e-6)."""
    ch = double_pendulum()
    M, K = double_pendulum_reference()
    z = np.zeros(2)
    np.testing.assert_allclose(ch.newton_matrix(z, z, z, 0.0, 1.0, 0.0, 0.0), M, rtol=1e-13, atol=1e-13)
    np.testing.assert_allclose(ch.newton_matrix(z, z, z, 0.0, 0.0, 0.0, 1.0), K, rtol=0, atol=1e-6)


@pytest.mark.parametrize("mode", [0, 1])
def test_double_pendulum_frequencies(mode):
    """Reference: det(K - w^2 M) = 0 with M, K of double_pendulum_reference(). A run started in
    mode `mode` (1e-4 rad, so the nonlinear terms shift the frequency by ~1e-8) oscillates in it;
    its period from the zero crossings of the modal coordinate matches 2 pi / w within 0.5 %
    (trapezoidal rule, rho_inf = 1, 200 steps a period: period error (w h)^2 / 12 = 8e-5)."""
    M, K = double_pendulum_reference()
    w2, shapes = scipy.linalg.eigh(K, M)
    w, phi = np.sqrt(w2[mode]), shapes[:, mode]
    period = 2 * np.pi / w
    ch = double_pendulum()
    q0 = 1e-4 * phi / np.abs(phi).max()
    run = simulate(ch, q0, np.zeros(2), 6 * period, period / 200, 1.0)
    assert run["failure"] == ""
    eta = run["theta"] @ (M @ phi)  # modal coordinate
    other = run["theta"] @ (M @ shapes[:, 1 - mode])
    assert np.abs(other).max() < 1e-6 * np.abs(eta).max()  # the mode stays uncoupled
    t = run["t"]
    k = np.flatnonzero(np.sign(eta[:-1]) != np.sign(eta[1:]))
    crossings = t[k] - eta[k] * (t[k + 1] - t[k]) / (eta[k + 1] - eta[k])
    measured = 2 * np.mean(np.diff(crossings))
    assert len(crossings) >= 10
    assert abs(measured / period - 1) < 5e-3


# ------------------------------------------------------------------------------------------------
# (c) Three panels on a free base: conservation

def three_panels(c=0.0, locks=(None, None, None), free=True):
    """A free base (500 kg) and three 4 kg panels of 1 m, the axes not all parallel (a 3-D
    motion), preloaded springs."""
    R = Ry(-np.pi / 2)
    return chain(free, 500.0, np.diag([80.0, 100.0, 120.0]), base_com=np.array([0.02, 0.0, -0.01]),
                 hinges=[spec(-1, [0.6, 0, 0.1], Y, rod(4.0, 1.0), R, 1.5, 0.4, c, locks[0]),
                         spec(0, [1.0, 0, 0.02], np.array([0.0, 0.6, 0.8]), rod(4.0, 1.0), np.eye(3),
                              1.0, 0.3, c, locks[1]),
                         spec(1, [1.0, 0, -0.02], np.array([0.0, 0.0, 1.0]), rod(4.0, 1.0), np.eye(3),
                              -0.8, 0.2, c, locks[2])])


def test_three_panels_conserve_momentum_and_energy():
    """Reference: with no external load and no dissipation, the total momentum (linear, and
    angular about W's origin) is constant, to round-off (1e-12 of its size, the base rows being
    solved as Pi_n+1 = Pi_n); the energy drifts only by the trapezoidal rule's O(h^2) error, here
    within 1e-6 of the peak kinetic energy (rho_inf = 1, dt = 1 ms, 3 s)."""
    ch = three_panels()
    q0 = ch.initial_positions()
    v0 = np.array([0.01, -0.02, 0.005, 0.02, -0.05, 0.03, 0.1, -0.2, 0.3])  # m/s, rad/s
    run = simulate(ch, q0, v0, 3.0, 1e-3, 1.0)
    assert run["failure"] == ""
    Pi = np.hstack([run["linear_momentum"], run["angular_momentum"]])
    scale = np.abs(Pi[0]).max()
    assert np.abs(Pi - Pi[0]).max() <= 1e-12 * scale
    exchanged = np.abs(run["base_angular_momentum"] - run["base_angular_momentum"][0]).max()
    assert exchanged > 1e-2 * scale  # the panels really did trade momentum with the base
    assert np.ptp(run["theta"], axis=0).min() > 0.3  # and swung
    E = run["kinetic_energy"] + run["potential_energy"]
    assert np.abs(E - E[0]).max() <= 1e-6 * run["kinetic_energy"].max()


def check_jacobians(ch, q, v, a, mass_tol=1e-10, h=1e-6):
    """Asserts an engine model's Newton and momentum Jacobians against central differences:
    M = dr/da symmetric positive definite and exact to ``mass_tol`` (r is affine in a), dPi/dv
    = A(q) to 1e-12 (Pi is linear in v), dr/dv, dr/dq (along retract) and dPi/dq to the
    differences' 1e-6 (step ``h``)."""
    n = ch.num_velocities
    E = np.eye(n)
    M = ch.newton_matrix(q, v, a, 0.0, 1.0, 0.0, 0.0)
    np.testing.assert_allclose(M, M.T, rtol=0, atol=1e-12 * np.abs(M).max())
    assert np.linalg.eigvalsh(M).min() > 0
    dr_da = np.column_stack([(ch.residual(q, v, a + E[j], 0.0) - ch.residual(q, v, a - E[j], 0.0)) / 2
                             for j in range(n)])
    np.testing.assert_allclose(M, dr_da, rtol=0, atol=mass_tol * np.abs(M).max())
    dr_dv = np.column_stack([(ch.residual(q, v + h * E[j], a, 0.0) - ch.residual(q, v - h * E[j], a, 0.0)) / (2 * h)
                             for j in range(n)])
    dr_dq = np.column_stack([(ch.residual(ch.retract(q, h * E[j]), v, a, 0.0) -
                              ch.residual(ch.retract(q, -h * E[j]), v, a, 0.0)) / (2 * h) for j in range(n)])
    np.testing.assert_allclose(ch.newton_matrix(q, v, a, 0.0, 0.0, 1.0, 0.0), dr_dv, rtol=0,
                               atol=1e-6 * np.abs(dr_dv).max())
    np.testing.assert_allclose(ch.newton_matrix(q, v, a, 0.0, 0.0, 0.0, 1.0), dr_dq, rtol=0,
                               atol=1e-6 * np.abs(dr_dq).max())
    A = np.column_stack([(ch.momentum(q, v + E[j]) - ch.momentum(q, v - E[j])) / 2 for j in range(n)])
    np.testing.assert_allclose(ch.momentum_jacobian(q, v, 1.0, 0.0), A, rtol=0, atol=1e-12 * np.abs(A).max())
    dP_dq = np.column_stack([(ch.momentum(ch.retract(q, h * E[j]), v) - ch.momentum(ch.retract(q, -h * E[j]), v))
                             / (2 * h) for j in range(n)])
    np.testing.assert_allclose(ch.momentum_jacobian(q, v, 0.0, 1.0), dP_dq, rtol=0, atol=1e-6 * np.abs(dP_dq).max())


def test_jacobians_match_finite_differences():
    """Reference: central differences (check_jacobians), at a random state of three panels."""
    ch = three_panels(c=0.3)
    q, v, a = random_state(10, 9, 4)
    assert ch.num_velocities == 9
    check_jacobians(ch, q, v, a)


# ------------------------------------------------------------------------------------------------
# (d) Locks on two hinges

def test_both_locks_latch_and_hold_the_deployed_array():
    """Reference: the lock's geometry and statics (joint/hinge_lock.hpp). Two panels on a fixed rig
    deploy through 90 deg into Kelvin-Voigt-Hertz locks (pin 30 mm, clearance 0.1 mm); with a
    little hinge damping both latch and the array comes to rest against the stops, each hinge
    past theta_lock by the static penetration of its spring's torque (tau0 - k theta_lock) / r_pin
    = K delta^1.5, delta = r_pin (theta - theta_lock) (the springs between the panels are internal
    to the chain and load hinge 0's lock with nothing), within 1 %."""
    theta_lock, r_pin, clearance = np.pi / 2, 0.03, 1e-4
    law = ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4)
    lock = _core.HingeLockSpec(theta_lock=theta_lock, pin_radius=r_pin, clearance=clearance, law=law._impl, mu=0.2,
                               v_reg=Friction(0.2).v_reg)
    ch = chain(False, 1.0, np.eye(3), [spec(-1, [0, 0, 0], Y, rod(5.0, 1.0), tau0=4.0, k=0.5, c=0.5, lock=lock),
                                       spec(0, [1.02, 0, 0], Y, rod(5.0, 1.0), tau0=2.0, k=0.3, c=0.5, lock=lock)])
    run = simulate(ch, ch.initial_positions(), np.zeros(2), 15.0, 0.01, 0.8)
    assert run["failure"] == ""
    assert np.all(run["latched"][-1] == 1)
    first = [run["t"][np.flatnonzero(run["lock_force"][:, k] > 0)[0]] for k in range(2)]
    assert all(0.5 < t < 10.0 for t in first)
    assert np.abs(run["theta_rate"][-1]).max() < 1e-9  # at rest
    torque = np.array([4.0 - 0.5 * theta_lock, 2.0 - 0.3 * theta_lock])  # N m, at the lock
    static = (torque / r_pin / 1e9) ** (1 / 1.5) / r_pin  # rad past theta_lock
    np.testing.assert_allclose(run["theta"][-1] - theta_lock, static, rtol=1e-2)


# ------------------------------------------------------------------------------------------------
# (e) Bad specifications

@pytest.mark.parametrize("change, name", [
    (lambda h: h.update(axis=np.array([0.0, 1.0, 1.0])), "hinges[1].axis"),
    (lambda h: h.update(k=-1.0), "hinges[1].k_theta"),
    (lambda h: h.update(c=-0.1), "hinges[1].c_theta"),
    (lambda h: h.update(R=2 * np.eye(3)), "hinges[1].R_PC0"),
    (lambda h: h.update(tau0=np.inf), "hinges[1].tau0"),
    (lambda h: h.update(body=(-1.0, np.zeros(3), np.eye(3))), "hinges[1].body.mass"),
    (lambda h: h.update(body=(1.0, np.zeros(3), -np.eye(3))), "hinges[1].body.inertia"),
    (lambda h: h.update(parent=1), "hinges[1].parent"),
    # a point 5e108 m away left the mass matrix singular (a fuzz case): refused, with the range
    (lambda h: h.update(point=[-5e108, 0.0, 0.0]), "hinges[1].point must be 3 finite numbers within 1e4 m"),
    # a fitting inertia of 1.8e308 overflowed the mass matrix (a fuzz case): refused, with the range
    (lambda h: h.update(body=(1e51, np.zeros(3), np.eye(3))), "hinges[1].body.mass = 1e.51 is out of range.*<= 1e50"),
    (lambda h: h.update(body=(1.0, np.zeros(3), 1e60 * np.eye(3))), "hinges[1].body.inertia must have entries within 1e50"),
    # a preload of -1.8e308 N m overflowed the first residual (a fuzz case): refused, with the range
    (lambda h: h.update(tau0=-1.7976931348623157e308), r"hinges[1].tau0 = -1.797693135e\+308 is out of range: must be finite and within"),
    (lambda h: h.update(k=1e60), r"hinges[1].k_theta = 1e\+60 is out of range: must be finite and >= 0, at most 1e50"),
])
def test_bad_hinge_specs_raise_value_error_naming_them(change, name):
    # (A massless leaf body is refused by Scene.compile, "carries no body": test_scene_chain_errors.)
    h = dict(parent=0, point=[1.0, 0, 0], axis=Y, body=rod(1.0, 1.0), R=np.eye(3), tau0=0.0, k=1.0, c=0.0)
    change(h)
    with pytest.raises(ValueError, match=name.replace("[", r"\[").replace("]", r"\]")):
        chain(False, 1.0, np.eye(3), [spec(-1, [0, 0, 0], Y, rod(1.0, 1.0)), spec(**h)])


def test_bad_chain_specs_raise_value_error():
    with pytest.raises(ValueError, match="hinges must hold at least one hinge"):
        chain(False, 1.0, np.eye(3), [])
    with pytest.raises(ValueError, match="base.mass"):
        chain(True, 0.0, np.eye(3), [spec(-1, [0, 0, 0], Y, rod(1.0, 1.0))])
    with pytest.raises(ValueError, match="base.inertia"):
        chain(True, 1.0, np.zeros((3, 3)), [spec(-1, [0, 0, 0], Y, rod(1.0, 1.0))])
    with pytest.raises(ValueError, match="base.mass .*<= 1e50"):
        chain(True, 1e60, np.eye(3), [spec(-1, [0, 0, 0], Y, rod(1.0, 1.0))])
    ch = double_pendulum()
    with pytest.raises(ValueError, match="q, v, a must have sizes 2, 2, 2"):
        ch.residual(np.zeros(3), np.zeros(2), np.zeros(2), 0.0)
    with pytest.raises(ValueError, match="sizes"):
        simulate(ch, np.zeros(2), np.zeros(5), 1.0, 0.1, 0.8)


# ------------------------------------------------------------------------------------------------
# The scene builder

def panel(length=1.0, width=0.5, nx=4, ny=2, offset=0.02):
    """An aluminium panel (2 mm) on an nx x ny mesh, root edge `offset` m from its hinge axis."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    plate = dfx.Plate(length, width, lam, nx=nx, ny=ny)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += offset
    nodes[:, 1] -= width / 2
    return dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")


LAW = ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e4)


def array_scene(fidelity="rigid", locks=True):
    """A free base, a yoke (a rigid part on hinge 0's body) and two rigid panels."""
    shell, root = panel()
    scene = (dfx.Scene().set_base(200.0, 30.0)
             .add_hinge("base", point=(0.5, 0, 0), axis=(0, 1, 0), R_PE0=Ry(-np.pi / 2), tau0=2.0, k_theta=0.3,
                        fitting_inertia=0.01)
             .add_rigid_part(2.0, np.diag([0.01, 0.1, 0.1]), (0.4, 0, 0), body=0)
             .add_hinge(0, point=(0.8, 0, 0), axis=(0, 1, 0), R_PE0=Ry(np.pi), tau0=1.5, k_theta=0.2,
                        fitting_inertia=0.01)
             .set_appendage(shell, root, fidelity="rigid")
             .add_hinge(1, point=(1.04, 0, 0), axis=(0, 1, 0), R_PE0=Ry(-np.pi), tau0=1.0, k_theta=0.2,
                        fitting_inertia=0.01)
             .set_appendage(shell, root, fidelity=fidelity))
    if locks:
        for k, angle in enumerate((np.pi / 2, np.pi, np.pi)):
            scene.set_lock(angle, 0.03, 1e-4, LAW, hinge=k)
    return scene


def test_scene_builds_and_runs_a_chain():
    model = array_scene().compile(description={"scene": "test array"})
    assert isinstance(model, dfx.Model)
    assert model.num_hinges == 3 and model.base_free and model.locks == (True, True, True)
    shell, _ = panel()
    # The bodies' masses (the yoke: the part alone; a panel: the mesh's mass plus the fitting's,
    # 0 here) from the total linear momentum of a base moving at 1 m/s, all else at rest:
    # P = (200 kg base + 2 kg yoke + 2 panels) x 1 m/s.
    q0, v = model.initial_positions(), np.zeros(model.num_velocities)
    v[0] = 1.0
    assert model.momentum(q0, v)[0] == pytest.approx(200.0 + 2.0 + 2 * shell.mass, rel=1e-12)
    r = model.simulate(1.0, 0.01)
    n = len(r.t)
    for name in ("deployment_angle", "spring_torque", "lock_force", "latched", "strain_energy"):
        assert r[name].shape == (n, 3), name
    assert r.hinge_force.shape == r.hinge_moment.shape == (n, 3, 3)
    assert r.body_attitude.shape == r.total_angular_momentum.shape == (n, 3)
    theta = r.q[:, [model.layout(k)["iq_theta"] for k in range(3)]]  # rad, after the base's 7
    np.testing.assert_array_equal([model.layout(k)["iq_theta"] for k in range(3)], [7, 8, 9])
    np.testing.assert_allclose(r.deployment_angle, np.degrees(theta))
    assert np.all(r.deployment_angle[-1] > 1.0)  # every hinge opened
    assert r.units["deployment_angle"] == "deg" and len(r.metadata["hinges"]) == 3
    assert [h["parent"] for h in r.metadata["hinges"]] == ["base", 0, 1]
    assert np.abs(r.total_angular_momentum).max() < 1e-12 * np.abs(r.body_angular_momentum).max()
    s = r.summary()
    assert isinstance(s["first_lock_time_s"], list) and len(s["first_lock_time_s"]) == 3
    assert r.hinge(2).summary()["peak_hinge_force_N"] == s["peak_hinge_force_N"][2]


def test_scene_chain_with_one_hinge_is_the_one_hinge_scene():
    """add_hinge("base", ...) alone is the one-hinge scene of set_hinge: same Model, same run."""
    shell, root = panel()
    kw = dict(point=(0.5, 0, 0), axis=(0, 1, 0), tau0=2.0, k_theta=0.3, fitting_inertia=0.01)
    a = dfx.Scene().set_base(200.0, 30.0).add_hinge("base", R_PE0=Ry(-np.pi / 2), **kw)
    b = dfx.Scene().set_base(200.0, 30.0).set_hinge(R_BE0=Ry(-np.pi / 2), **kw)
    for scene in (a, b):
        scene.set_appendage(shell, root, fidelity="rigid")
    ma, mb = a.compile(), b.compile()
    assert isinstance(ma, dfx.Model) and isinstance(mb, dfx.Model)
    np.testing.assert_array_equal(ma.simulate(0.5, 0.01).deployment_angle, mb.simulate(0.5, 0.01).deployment_angle)


def test_scene_chain_with_a_full_finite_element_panel_runs_and_conserves_momentum():
    # Any fidelity on any body: the last panel of the chain as full Green-strain finite elements
    # (once refused in a chain). Reference: no external load, so the total momentum stays at its
    # initial zero to round-off (1e-12 of the base's peak), through the locks' impacts; and the
    # panel really deforms (strain energy, a tip deflection) while the rigid ones do not.
    model = array_scene("nonlinear").compile()
    assert model.fidelities[2] == "nonlinear" and model.deforming == (False, False, True)
    r = model.simulate(1.5, 0.01)
    assert np.abs(r.total_angular_momentum).max() < 1e-12 * np.abs(r.body_angular_momentum).max()
    assert np.abs(r.total_linear_momentum).max() < 1e-12 * np.abs(r.body_linear_momentum).max()
    assert np.all(r.strain_energy[:, :2] == 0) and r.strain_energy[:, 2].max() > 0
    assert np.abs(r.tip_deflection[:, 2]).max() > 1e-6 and np.all(r.tip_deflection[:, :2] == 0)
    assert np.all(r.deployment_angle[-1] > 1.0)


def test_a_motion_without_inertia_is_refused_at_the_start():
    """A fuzz case: a free base of 1e-100 kg m^2 under a hinge whose fitting alone has inertia
    (1 kg m^2, no mass). About the hinge axis the base's turn and the hinge angle have the mass
    matrix [[J_b + J_f, J_f], [J_f, J_f]], of determinant J_b J_f: singular to working precision
    when J_b / J_f is below the doubles' 2.2e-16. A ValueError that says what to look for, not a
    failed run (with J_b = 1e-10 the matrix factorizes and the run is the scene's to judge)."""
    scene = (dfx.Scene().set_base(215.5, 1e-100)
             .set_hinge(point=(0.0, 0.06, 0.6), axis=(0, 1, 0), k_theta=9.6, c_theta=0.8, fitting_inertia=1.0))
    with pytest.raises(ValueError, match=r"the mass matrix is singular at t = 0.* to working precision: a motion the "
                                         r"hinges allow carries no inertia"):
        scene.compile().simulate(0.02, 0.01)


def test_scene_chain_errors_name_the_parameter():
    shell, root = panel()
    scene = dfx.Scene().set_base(10.0, 1.0)
    with pytest.raises(ValueError, match=r"hinges\[0\].parent = 0 is out of range: must be 'base' \(no hinge yet\)"):
        scene.add_hinge(0, point=(0, 0, 0), axis=(0, 1, 0))
    scene.add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0), tau0=1.0).set_appendage(shell, root, fidelity="rigid")
    with pytest.raises(ValueError, match=r"hinges\[1\].parent = 3 is out of range: must be 'base' or in \[0, 0\]"):
        scene.add_hinge(3, point=(0, 0, 0), axis=(0, 1, 0))
    with pytest.raises(ValueError, match=r"hinges\[1\].parent = 'yoke' is invalid"):
        scene.add_hinge("yoke", point=(0, 0, 0), axis=(0, 1, 0))
    with pytest.raises(ValueError, match=r"hinges\[1\].axis"):
        scene.add_hinge(0, point=(1, 0, 0), axis=(0, 1, 1))
    with pytest.raises(ValueError, match=r"hinges\[1\].R_PE0 must be a rotation"):
        scene.add_hinge(0, point=(1, 0, 0), axis=(0, 1, 0), R_PE0=2.0)
    with pytest.raises(ValueError, match=r"hinges\[1\].k_theta = -1.0 is out of range: must be finite and >= 0"):
        scene.add_hinge(0, point=(1.04, 0, 0), axis=(0, 1, 0), k_theta=-1.0)
    # The fuzz suite's fitting of 1.8e308 kg m^2 overflowed the mass matrix: refused, with the range.
    with pytest.raises(ValueError, match=r"hinges\[1\].fitting.inertia must have entries within 1e50"):
        scene.add_hinge(0, point=(1.04, 0, 0), axis=(0, 1, 0), fitting_inertia=1.7976931348623157e308)
    with pytest.raises(ValueError, match=r"hinges\[1\].fitting.mass = 1e\+60 is out of range: must be finite, >= 0 and <= 1e50"):
        scene.add_hinge(0, point=(1.04, 0, 0), axis=(0, 1, 0), fitting_mass=1e60)
    # And a preload of -1.8e308 N m, which overflowed the first residual.
    with pytest.raises(ValueError, match=r"hinges\[1\].tau0 = -1.7976931348623157e\+308 is out of range: "
                                         r"must be finite and within \[-1e50, 1e50\] \(N m\)"):
        scene.add_hinge(0, point=(1.04, 0, 0), axis=(0, 1, 0), tau0=-1.7976931348623157e308)
    with pytest.raises(ValueError, match=r"appendage.hinge = 4 is out of range: must be in \[0, 0\]"):
        scene.set_appendage(shell, root, fidelity="rigid", hinge=4)
    with pytest.raises(ValueError, match=r"part.body = 'yoke' is invalid"):
        scene.add_rigid_part(1.0, 1.0, (0, 0, 0), body="yoke")
    with pytest.raises(ValueError, match=r"lock.pin_radius = -0.03 is out of range"):
        scene.set_lock(np.pi, -0.03, 1e-4, LAW, hinge=0)
    scene.add_hinge(0, point=(1.04, 0, 0), axis=(0, 1, 0), k_theta=1.0)
    with pytest.raises(ValueError, match=r"hinges\[1\] carries no body"):
        scene.compile()
    scene.set_appendage(shell, root, fidelity="rigid")
    assert scene.compile().num_hinges == 2


def test_scene_file_holds_a_chain(tmp_path):
    """A chain saved and loaded (deployfx.scene_file) runs bit for bit alike."""
    scene = array_scene()
    loaded = dfx.load_scene(dfx.save_scene(scene, tmp_path / "array.toml"))
    a, b = scene.compile().simulate(0.2, 0.01), loaded.compile().simulate(0.2, 0.01)
    np.testing.assert_array_equal(a.deployment_angle, b.deployment_angle)
    np.testing.assert_array_equal(a.lock_force, b.lock_force)


def test_scene_yoke_alone_is_a_chain_of_one():
    """One hinge carrying a rigid part only (a yoke); reference: the rigid pendulum on a fixed
    rig, theta'' = tau0 / J_O from rest (J_O about the axis)."""
    J = np.diag([0.01, 0.2, 0.2])
    model = (dfx.Scene().set_base(1.0, 1.0, free=False)
             .add_hinge("base", point=(0, 0, 0), axis=(0, 1, 0), tau0=0.5)
             .add_rigid_part(2.0, J, (0.3, 0, 0), body=0).compile())
    assert isinstance(model, dfx.Model) and model.num_hinges == 1 and model.shells == (None,)
    r = model.simulate(0.2, 0.01, scheme=GeneralizedAlpha(1.0))
    J_O = 0.2 + 2.0 * 0.3**2
    theta = r.q[:, 0]  # a fixed base has no coordinates: q is the hinge angle
    np.testing.assert_allclose(theta, 0.5 / J_O * r.t**2 / 2, rtol=0, atol=1e-12)
