"""The one engine on trees of hinged bodies (issue 23): panels of any fidelity, full finite-element
ones included, carrying further hinges; two wings on one base; runs sharing one model.

Each test names its independent reference:
- the Newton matrix and momentum Jacobian: fourth-order central differences of the residual and of
  the momentum (the engine's matrix is analytic: Dual-number passes of the kinematics and closed
  forms of the bodies' forces);
- two mirror-symmetric wings on a free base: the mirror symmetry of the scene (the base's attitude
  cannot change, the wings move alike), to round-off;
- a free yoke carrying two full nonlinear panels, the second riding on the first: conservation of
  momentum (to round-off: the base rows are solved as Pi_n+1 = Pi_n) and energy (the trapezoidal
  rule's truncation error, the single-hinge tests' tolerance);
- runs of one model in two threads: the serial runs, bit for bit (the model is immutable, each run
  has its own data).
"""
import threading

import numpy as np
import pytest

import deployfx as dfx
from deployfx import _core
from deployfx.integrators import GeneralizedAlpha

Y = np.array([0.0, 1.0, 0.0])


def Ry(a):
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def panel(nx=3, ny=2, length=1.0, width=0.5, offset=0.03):
    """A 2 mm aluminium panel on an nx x ny mesh, root edge `offset` from its hinge axis, centred on
    the hinge point; and its clamped root dofs."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E=70e9, nu=0.33, rho=2700.0), 2e-3)])
    plate = dfx.Plate(length, width, lam, nx=nx, ny=ny)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += offset
    nodes[:, 1] -= width / 2
    return dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("CFFF")


def tree_scene(fidelities, free=True, damping=(0.3, 0.0)):
    """Two wings on a base. Wing +x: a yoke (hinge 0), panel 1 on it, panel 2 riding on panel 1's
    mesh past its free edge (tilted axis: a 3-D motion). Wing -x: a yoke (hinge 3) and panel 4."""
    shell, root = panel()
    lock = dfx.contact.ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e6)
    s = dfx.Scene().set_base(300.0, 50 * np.diag([1.0, 1.2, 0.9]), com=(0.1, -0.05, 0.02), free=free)
    s.add_hinge("base", (0.83, 0.1, 0.0), Y, R_PE0=Ry(-0.3), tau0=2.0, k_theta=1.27, c_theta=0.2, fitting_inertia=0.01)
    s.add_rigid_part(2.0, np.diag([1.0, 1.0, 0.5]), (0.15, 0.0, 0.0), body=0)
    s.set_lock(0.05, 0.03, 0.2e-3, lock, friction=dfx.contact.Friction(0.25, 0.01))
    s.add_hinge(0, (0.3, 0.0, 0.0), Y, R_PE0=Ry(-0.2), tau0=7.2, k_theta=4.58, c_theta=0.3, fitting_inertia=0.02,
                fitting_mass=0.3, fitting_com=(0.01, 0.0, 0.0))
    s.set_appendage(shell, root, fidelity=fidelities[0], damping=damping, modes=4)
    s.set_lock(0.05, 0.03, 0.2e-3, lock)
    s.add_hinge(1, (1.04, 0.2, 0.01), (0.0, 0.6, 0.8), R_PE0=Ry(0.4), tau0=3.0, k_theta=2.0, c_theta=0.1,
                fitting_inertia=0.02)
    s.set_appendage(shell, root, fidelity=fidelities[1], damping=damping, modes=4)
    s.add_hinge("base", (-0.83, 0.0, 0.1), -Y, R_PE0=Ry(np.pi - 0.2), tau0=2.0, k_theta=1.27, fitting_inertia=0.01)
    s.add_rigid_part(2.0, np.diag([1.0, 1.0, 0.5]), (0.15, 0.0, 0.0), body=3)
    s.add_hinge(3, (0.3, 0.0, 0.0), Y, R_PE0=Ry(0.1), tau0=7.2, k_theta=4.58, fitting_inertia=0.02)
    s.set_appendage(shell, root, fidelity=fidelities[2], damping=damping, modes=4)
    return s


def generic_state(model, seed=0):
    """A state away from every symmetry: the base spinning about a tilted axis, each hinge turned
    and moving, each panel deformed (~1 cm) and vibrating."""
    rng = np.random.default_rng(seed)
    q, v = model.initial_positions(), np.zeros(model.num_velocities)
    if model.base_free:
        quat = np.array([0.9, 0.1, -0.3, 0.2])
        q[:7] = [0.3, -0.2, 0.1, *quat / np.linalg.norm(quat)]
        v[:6] = [0.05, -0.02, 0.03, 0.2, -0.3, 0.15]
    for k in range(model.num_hinges):
        lay = model.layout(k)
        if lay["iq_theta"] >= 0:
            q[lay["iq_theta"]], v[lay["iv_theta"]] = 0.3 + 0.1 * k, 0.4 - 0.1 * k
        n = lay["num_elastic"]
        if n:
            scale = 1e-2 / np.abs(model.core.displacement_map(k)).max(axis=0)
            q[lay["iq_elastic"]:lay["iq_elastic"] + n] = scale * rng.normal(size=n)
            v[lay["iv_elastic"]:lay["iv_elastic"] + n] = 3 * scale * rng.normal(size=n)
    return q, v, rng.normal(size=model.num_velocities)


def central(f, n, h=1e-3):
    """Fourth-order central differences of f(j, s) in s at 0, for j < n (columns)."""
    return np.column_stack([(8 * (f(j, h) - f(j, -h)) - (f(j, 2 * h) - f(j, -2 * h))) / (12 * h) for j in range(n)])


CASES = [(("nonlinear", "nonlinear", "linear"), True), (("nonlinear", "reduced-nonlinear", "rigid"), False),
         (("reduced-nonlinear", "linear", "reduced-linear"), True)]


@pytest.mark.parametrize("fidelities,free", CASES, ids=lambda c: "-".join(c) if isinstance(c, tuple) else
                         ("free" if c else "fixed"))
def test_newton_matrix_and_momentum_jacobian_match_central_differences(fidelities, free):
    """Reference: fourth-order central differences (steps 1e-3 of (c_q, c_v, c_a) e_j: r is affine
    in a and at most quadratic in v, and its q-truncation error is below 1e-12 relative). A tree
    whose first panel (full finite elements, or reduced) carries a hinge and a second panel, with
    two locks in contact (friction on one), at a generic state. Every entry within 1e-7 of the
    largest in its row (measured 2e-11), plus 1e-11 of the matrix's largest (round-off where the
    row is 0)."""
    model = tree_scene(fidelities, free).compile()
    assert model.layout(2)["attachment_node"] >= 0
    q, v, a = generic_state(model)
    data = model.make_data()
    history = _core.LockHistory()
    history.latched, history.stop_contact, history.stop_v0 = True, True, 0.1
    for k in (0, 1):
        data.set_lock(k, history)
    n = model.num_velocities
    c_a, c_v, c_q = 1.0, 0.03, 0.002
    S = model.newton_matrix(q, v, a, 0.0, c_a, c_v, c_q, data=data)

    def column(j, s):
        e = np.zeros(n)
        e[j] = s
        return model.residual(model.core.retract(q, c_q * e), v + c_v * e, a + c_a * e, 0.0, data=data)

    fd = central(column, n)
    tol = 1e-7 * np.abs(fd).max(axis=1, keepdims=True) + 1e-11 * np.abs(fd).max()
    assert np.all(np.abs(S - fd) <= tol), np.unravel_index(np.argmax(np.abs(S - fd) / tol), S.shape)

    J = model.momentum_jacobian(q, v, 1.0, 0.02, data=data)

    def momentum(j, s):
        e = np.zeros(n)
        e[j] = s
        return model.momentum(model.core.retract(q, 0.02 * e), v + e, data=data)

    fdJ = central(momentum, n)
    tol = 1e-7 * np.abs(fdJ).max(axis=1, keepdims=True)
    assert np.all(np.abs(J - fdJ) <= tol)


def test_the_integrators_momentum_matrices_equal_the_momentum_jacobian():
    """Reference: Model.momentum_jacobian (itself checked against central differences above). The
    momentum polish's dPi/d(v_W, w_B) comes from the composite inertia of the whole system
    (Featherstone 2008, Sec. 6.2) and the momentum rows' Jacobian from the Newton matrix's own
    derivative passes, (1/c_v)(c_v dPi/dv + c_q dPi/dq): both equal it to round-off (1e-12 of
    each row's largest entry)."""
    model = tree_scene(("nonlinear", "reduced-nonlinear", "linear")).compile()
    q, v, a = generic_state(model, seed=3)
    J0 = model.momentum_jacobian(q, v, 1.0, 0.0)[:, :6]
    Jb = model.core.base_velocity_jacobian(q)
    np.testing.assert_allclose(Jb, J0, rtol=0, atol=1e-12 * np.abs(J0).max())
    c_v, c_q = 0.03, 0.002
    S, J = model.core.newton_matrix_and_momentum_jacobian(q, v, a, 0.0, 1.0, c_v, c_q)
    ref = model.momentum_jacobian(q, v, 1.0, c_q / c_v)
    assert np.all(np.abs(J - ref) <= 1e-12 * np.abs(ref).max(axis=1, keepdims=True))
    np.testing.assert_array_equal(S, model.newton_matrix(q, v, a, 0.0, 1.0, c_v, c_q))


def test_a_prescribed_hinge_on_a_free_base_conserves_momentum():
    """Reference: no external load: a prescribed hinge angle (Kane's spin-up law) acts between the
    base and the body it turns, so the total momentum stays at its initial 0 to 1e-12 of the
    momentum the bodies carry, while the base takes up a momentum of that scale."""
    s = (dfx.Scene().set_base(100.0, 10.0)
         .add_hinge("base", (0.5, 0.0, 0.0), Y, spin_up=(1.0, 2.0), fitting_inertia=0.1, fitting_mass=2.0,
                    fitting_com=(0.3, 0.0, 0.0)))
    r = s.compile().simulate(3.0, 0.01)
    scale = r.metadata["momentum_scale"]
    assert np.abs(r.total_linear_momentum).max() <= 1e-12 * scale["P_N_s"]
    assert np.abs(r.total_angular_momentum).max() <= 1e-12 * scale["H_N_m_s"]
    assert np.abs(r.body_angular_momentum).max() > 0.1 * scale["H_N_m_s"]
    assert r.summary()["momentum_drift"] < 1e-12


def test_two_symmetric_wings_leave_the_base_attitude_alone_and_lock_together():
    """Reference: symmetry. The paper's spacecraft with its mirrored second wing
    (scenes.paper2016(wings=2)) is symmetric under the mirror x -> -x and under y -> -y (each
    panel is centred on its hinge point, the lay-up [0/90/90/0] symmetric): the base's angular
    velocity must vanish, so its attitude stays at its initial value, and the two wings move alike.
    To round-off: attitude below 1e-9 deg (measured 2e-12 deg; one wing alone turns it by 2.7
    deg), the wings' angles within 1e-9 deg of each other (measured 2e-11) and their locks' first
    contact at the same instant (1e-12 s), through two impacts and a rebound."""
    sc = dfx.scenes.paper2016(2, "reduced-nonlinear", nx=4, ny=2, wings=2)
    r = sc.simulate(4.0, 0.01)
    s = r.summary()
    assert np.abs(r.body_attitude).max() < 1e-9
    assert np.abs(r.deployment_angle[:, 0] - r.deployment_angle[:, 1]).max() < 1e-9
    t0, t1 = s["first_lock_time_s"]
    assert t0 == pytest.approx(2.47, abs=0.1) and abs(t0 - t1) < 1e-12
    assert np.abs(r.body_linear_momentum).max() > 1.0  # both panels swing down: the base recoils, it does not turn
    one = dfx.scenes.paper2016(2, "reduced-nonlinear", nx=4, ny=2).simulate(4.0, 0.01)
    assert np.abs(one.body_attitude).max() > 1.0


def test_yoke_and_two_full_nonlinear_panels_conserve_momentum_and_energy():
    """Reference: no external load and no dissipation (undamped panels, no locks, rho_inf = 1).
    The total momentum is constant to 1e-12 of the momentum the bodies carry (the sum of their
    |P|, |H|; the base rows are solved as Pi_n+1 = Pi_n); the energy (kinetic + springs + strain)
    changes by the trapezoidal rule's O(dt^2) truncation error only: within the single-hinge
    nonlinear test's 2e-4 of the peak kinetic energy at dt = 0.625 ms, and a quarter at half the
    step within a factor 1.5 (measured 4.9e-3, 8.6e-4, 1.9e-4 at 2.5, 1.25, 0.625 ms: these light
    aluminium panels ring at their root mode harder than the paper's)."""
    shell, root = panel(nx=3, ny=2)
    s = (dfx.Scene().set_base(200.0, np.diag([30.0, 35.0, 40.0]))
         .add_hinge("base", (0.5, 0.0, 0.0), Y, R_PE0=Ry(-np.pi / 2), tau0=2.0, k_theta=0.3, fitting_inertia=0.01)
         .add_rigid_part(2.0, np.diag([0.01, 0.1, 0.1]), (0.4, 0.0, 0.0), body=0)
         .add_hinge(0, (0.8, 0.0, 0.0), Y, R_PE0=Ry(np.pi), tau0=1.5, k_theta=0.2, fitting_inertia=0.01)
         .set_appendage(shell, root, fidelity="nonlinear")
         .add_hinge(1, (1.04, 0.0, 0.01), (0.0, 0.6, 0.8), R_PE0=Ry(-np.pi), tau0=1.0, k_theta=0.2,
                    fitting_inertia=0.01)
         .set_appendage(shell, root, fidelity="nonlinear"))
    model = s.compile()
    assert model.deforming == (False, True, True) and model.layout(2)["attachment_node"] >= 0
    v0 = np.zeros(model.num_velocities)
    v0[:6] = [0.01, -0.02, 0.005, 0.02, -0.05, 0.03]  # m/s, rad/s: the base moves and tumbles
    error = {}
    for dt in (1.25e-3, 0.625e-3):
        r = model.simulate(0.5, dt, scheme=GeneralizedAlpha(1.0), v0=v0)
        scale = r.metadata["momentum_scale"]
        for name, key in (("total_linear_momentum", "P_N_s"), ("total_angular_momentum", "H_N_m_s")):
            x = r[name]
            assert np.abs(x - x[0]).max() <= 1e-12 * scale[key], name
        assert r.strain_energy.max() > 1e-3 * r.kinetic_energy.max()  # the panels really did bend
        E = r.kinetic_energy + r.potential_energy
        error[dt] = np.abs(E - E[0]).max() / r.kinetic_energy.max()
    assert error[0.625e-3] <= 2e-4
    assert error[0.625e-3] <= 1.5 * error[1.25e-3] / 4


def test_two_threads_on_one_model_give_the_serial_bits():
    """Reference: the serial runs. One compiled model (immutable) simulated by two threads at once,
    each run with its own data (lock histories, memos): every recorded array equals the serial
    run's bit for bit, for a full nonlinear panel with its lock and a reduced one."""
    models = [dfx.scenes.paper2016(2, "nonlinear", nx=3, ny=2).model,
              dfx.scenes.paper2016(2, "reduced-nonlinear", nx=4, ny=2).model]
    for model in models:
        serial = model.simulate(2.6, 0.01)
        out = [None, None]

        def run(i):
            out[i] = model.simulate(2.6, 0.01)

        threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
        for th in threads:
            th.start()
        for th in threads:
            th.join()
        for r in out:
            for name in serial.series:
                assert np.array_equal(r[name], serial[name]), name
        assert serial.summary()["impacts"][0] >= 1  # the lock closed within the run


@pytest.mark.parametrize("fidelity", ["linear", "nonlinear", "reduced-linear", "reduced-nonlinear"])
def test_a_panel_its_supports_leave_free_is_refused_naming_fixed_dofs(fidelity):
    """Reference: a structure free to move as a rigid body against its supports has a singular
    stiffness (six rigid-body modes of a free plate; three held dofs of one node leave the
    rotations about it free): compile refuses it, naming the parameter, instead of failing later
    in Newton or in the basis."""
    shell, root = panel(nx=2, ny=1)
    for fixed in ([], [0, 1, 2]):
        s = (dfx.Scene().set_base(1.0, 1.0, free=False).add_hinge("base", (0.0, 0.0, 0.0), Y, fitting_inertia=0.01)
             .set_appendage(shell, fixed, fidelity=fidelity, modes=2))
        with pytest.raises(ValueError, match=r"hinges\[0\]\.panel\.fixed_dofs leave the panel free to move"):
            s.compile()
    s.set_appendage(shell, root, fidelity=fidelity, modes=2)
    assert s.compile().deforming == (True,)
