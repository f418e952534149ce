"""Model.modes: the equations of motion linearised about a state (issue 28, docs/modes.md).

1. A cantilever spinning at a constant rate about the normal of its plane (a driven hinge):
   flapwise frequencies against the rotating Euler-Bernoulli beam (hub radius 0), omega /
   sqrt(EI/(rho A L^4)) against gamma = Omega sqrt(rho A L^4/EI), Wright, Smith, Thresher & Wang
   (1982), J. Appl. Mech. 49, 197-202, as tabulated by Hamza-Cherif (2004) and Yoo & Shin (1998)
   Table 1: flap 1 3.5160, 3.6816, 4.1373, 4.7973, 5.5850, 6.4495 and flap 2 22.0345, 22.1810,
   22.6149, 23.3202, 24.2733, 25.4461 at gamma = 0..5. The table is checked first against an
   independent 40-element Hermite beam with the centrifugal tension T(x) = rho A Omega^2 (L^2 -
   x^2)/2 written here (to 5e-5). The strip is the spin-up beam's (scenes.spin_up_strip), nonlinear
   fidelity: flap 1 on 10 elements within 0.3 % (the plate strip's discretisation: +0.12 % at
   rest); flap 2 on 20 elements, whose +0.6 % discretisation error at rest cancels in the
   stiffening ratio f2(gamma)/f2(0), checked to 0.3 %.
2. The deployed, latched spacecraft on a free base, rigid panel: the two-body closed form
   derived in ``two_body_hinge_mode``, with the hinge stiffness from the lock's contact law at the
   equilibrium penetration (solved here) plus the spring; to 1e-8 in frequency and damping ratio.
3. A locked flexible panel on a fixed base: against the same finite-element matrices of the
   panel (ShellModel) with the hinge rotation added by hand (1e-8), and against the panel's
   clamped modes (Shell.modes) when the lock is stiff (0.2 %).
"""
import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import brentq

import deployfx as dfx
from deployfx import paper2016 as paper, scenes
from deployfx.contact import ContactLaw, Friction

# ----------------------------------------------------------------------------- 1. rotating beam
EI, RHO_A, L_BEAM = 1.4e4, 1.2, 10.0                  # scenes.SPIN_UP_BEAM
SCALE = np.sqrt(EI / (RHO_A * L_BEAM**4))            # 1/s
WRIGHT_FLAP1 = [3.5160, 3.6816, 4.1373, 4.7973, 5.5850, 6.4495]      # gamma = 0..5
WRIGHT_FLAP2 = [22.0345, 22.1810, 22.6149, 23.3202, 24.2733, 25.4461]


def hermite_rotating_beam(gamma: float, elements: int = 40) -> np.ndarray:
    """Non-dimensional flapwise frequencies of a uniform cantilever (EI = rho A = L = 1) spinning
    at gamma about an axis through its root: (K + gamma^2 K_G) phi = omega^2 M phi, cubic Hermite
    elements, K_G from the tension T(x) = gamma^2 (1 - x^2)/2 integrated by 4-point Gauss
    (exact for the element's polynomial). Independent of deployfx."""
    h = 1.0 / elements
    n = 2 * (elements + 1)
    K, M, KG = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    gp, gw = np.polynomial.legendre.leggauss(4)
    for e in range(elements):
        idx = slice(2 * e, 2 * e + 4)
        ke = np.array([[12, 6 * h, -12, 6 * h], [6 * h, 4 * h * h, -6 * h, 2 * h * h],
                       [-12, -6 * h, 12, -6 * h], [6 * h, 2 * h * h, -6 * h, 4 * h * h]]) / h**3
        me = h / 420 * np.array([[156, 22 * h, 54, -13 * h], [22 * h, 4 * h * h, 13 * h, -3 * h * h],
                                 [54, 13 * h, 156, -22 * h], [-13 * h, -3 * h * h, -22 * h, 4 * h * h]])
        kg = np.zeros((4, 4))
        for s, w in zip(gp, gw):
            xi = (s + 1) / 2
            x = (e + xi) * h
            dN = np.array([(-6 * xi + 6 * xi**2) / h, 1 - 4 * xi + 3 * xi**2, (6 * xi - 6 * xi**2) / h,
                           -2 * xi + 3 * xi**2])
            kg += w * h / 2 * 0.5 * (1 - x * x) * np.outer(dN, dN)
        K[idx, idx] += ke
        M[idx, idx] += me
        KG[idx, idx] += kg
    free = slice(2, n)  # clamped root: w = w' = 0
    A = np.linalg.solve(M[free, free], K[free, free] + gamma**2 * KG[free, free])
    return np.sqrt(np.sort(np.linalg.eigvals(A).real))


def spinning_strip(nx: int, Omega: float):
    """The spin-up beam's strip on a driven hinge about the normal of its plane (z): rate ramped
    to Omega over 1 s, then steady."""
    strip = scenes.spin_up_strip(nx)
    return (dfx.Scene().set_base(1.0, 1.0, free=False)
            .set_hinge((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), spin_up=(Omega, 1.0))
            .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="nonlinear")
            .compile())


def flapwise(model, nx: int, gamma: float, count: int) -> np.ndarray:
    """The lowest ``count`` bending frequencies (non-dimensional) of the strip at the relative
    equilibrium of steady spin (t = 5 s): modes whose shape is mostly the strip's symmetric
    transverse (z) translation (not torsion, not in its plane). Flapwise when the spin axis is the
    strip's normal; in the plane of rotation (chordwise) for the spin-up beam's axis (its width)."""
    m = model.modes(12, q=model.initial_positions(), t=5.0, equilibrium=True)
    assert m.num_rigid == 0 and np.abs(m.damping_ratios).max() < 1e-8  # undamped, gyroscopic at most
    S = m.mesh_shapes(0)                                    # (modes, 6 nodes): 2 rows of nx + 1 nodes
    w = S[:, 2::6].reshape(len(m), 2, nx + 1)
    bend = np.linalg.norm(w[:, 0] + w[:, 1], axis=1)
    other = np.linalg.norm(w[:, 0] - w[:, 1], axis=1) + np.linalg.norm(S[:, 0::6], axis=1) + np.linalg.norm(
        S[:, 1::6], axis=1)
    flap = m.frequencies_hz[bend > 3 * other] * 2 * np.pi / SCALE
    return flap[:count]


def test_reference_table_is_the_rotating_euler_bernoulli_beam():
    for gamma in range(6):
        f = hermite_rotating_beam(gamma)
        assert f[0] == pytest.approx(WRIGHT_FLAP1[gamma], rel=5e-5)
        assert f[1] == pytest.approx(WRIGHT_FLAP2[gamma], rel=5e-5)


def test_spinning_cantilever_first_flapwise_frequency():
    for gamma in range(6):
        f = flapwise(spinning_strip(10, gamma * SCALE), 10, gamma, 1)
        assert f[0] == pytest.approx(WRIGHT_FLAP1[gamma], rel=3e-3), gamma


def test_spinning_cantilever_second_flapwise_stiffening():
    rest = flapwise(spinning_strip(20, 0.0), 20, 0.0, 2)
    spin = flapwise(spinning_strip(20, 5 * SCALE), 20, 5.0, 2)
    assert rest[1] == pytest.approx(WRIGHT_FLAP2[0], rel=1e-2)
    assert spin[1] / rest[1] == pytest.approx(WRIGHT_FLAP2[5] / WRIGHT_FLAP2[0], rel=3e-3)
    assert spin[0] == pytest.approx(WRIGHT_FLAP1[5], rel=3e-3)


def test_spin_up_beam_chordwise_frequency():
    # The spin-up beam scene turns about the strip's width: its transverse bending is in the plane
    # of rotation, softened by -Omega^2 M, so omega_chord^2 = omega_flap^2 - Omega^2 (exact for the
    # inextensible beam, docs/research/engine-references.md Sec. 2; the strip's axial-chordwise
    # Coriolis coupling, which Yoo & Shin 1998 show lowers it slightly, is small for this slender
    # beam): 3.5432, 3.8977, 4.0739 at gamma = 1, 4, 5. Tolerance 0.3 % (the mesh: +0.12 % at rest).
    for gamma in (1, 4, 5):
        sc = scenes.spin_up_beam(gamma * SCALE, t_s=1.0, nx=10)
        f = flapwise(sc.model, 10, gamma, 1)
        assert f[0] == pytest.approx(np.sqrt(WRIGHT_FLAP1[gamma] ** 2 - gamma**2), rel=3e-3), gamma


def test_linear_fidelity_does_not_stiffen():
    # Kane, Ryan & Banerjee (1987): without geometric stiffness the flapwise frequencies of the
    # spinning strip stay those at rest (to 1e-5 here, the stretched equilibrium's trace; the
    # nonlinear fidelity's flap 1 rises 36 % at gamma = 3).
    strip = scenes.spin_up_strip(10)
    model = (dfx.Scene().set_base(1.0, 1.0, free=False)
             .set_hinge((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), spin_up=(3 * SCALE, 1.0))
             .set_appendage(strip.model, strip.fixed_dofs("CFFF"), fidelity="linear").compile())
    f = flapwise(model, 10, 3.0, 2)
    rest = flapwise(spinning_strip(10, 0.0), 10, 0.0, 2)
    np.testing.assert_allclose(f, rest, rtol=1e-4)


def test_driven_hinge_is_held():
    model = spinning_strip(4, SCALE)
    assert model.layout(0)["iv_theta"] == -1  # a prescribed angle is no unknown of the model
    m = model.modes(3, q=model.initial_positions(), t=5.0, equilibrium=True)
    assert m.shapes.shape == (model.num_velocities, 3)
    np.testing.assert_array_equal(m.hinge_shapes(), 0.0)


# --------------------------------------------------------------------- 2. free base, rigid panel
P = scenes.Paper2016Parameters()


def walls_paper(*args, **kw):
    """The paper's scene with the stop-and-latch lock, whose walls the closed forms below describe
    (an active set at equilibrium; the default groove is linearised as a run has it: see
    test_lock_history_from_the_state_is_the_runs below and docs/modes.md)."""
    return scenes.paper2016(*args, **{"lock_geometry": "stop-latch", **kw})
KV_LAW = ContactLaw("paper", K=1e6 / (1e-3) ** 1.5, n=1.5, D=2e3)   # the paper's K, a lighter D


def two_body_hinge_mode(k: float, c: float, fitting_inertia: float = P.fitting_inertia):
    """(f_n Hz, zeta) of the hinge mode of the deployed spacecraft with a rigid panel.

    Two rigid bodies joined by a hinge about y through H = (hinge_x, 0, 0), free in space, zero
    momentum: body 1 the base and yoke, body 2 the panel and fitting (deployed along +x, in the
    plane z = 0). By the symmetry y -> -y the hinge motion stays in the x-z plane. With the
    hinge-to-centre-of-mass vectors r_i (along x, so perpendicular to the axis), the centres'
    velocities are v_i = v_H + w_i y x r_i; zero linear momentum m1 v1 + m2 v2 = 0 gives
    v1 = (m2/m)(w1 s1 - w2 s2), v2 = -(m1/m)(w1 s1 - w2 s2), s_i = y x r_i, so
        T = 1/2 [I1 w1^2 + I2 w2^2 + mu |w1 s1 - w2 s2|^2],   mu = m1 m2 / (m1 + m2),
    J = [[I1 + mu s1^2, -mu s1.s2], [-mu s1.s2, I2 + mu s2^2]] (I_i about each centre of mass).
    The spring k and damper c act on the relative angle w2 - w1, K = k u u^T, C = c u u^T with
    u = (-1, 1): besides the rigid rotation, one mode, J_eff lambda^2 + c lambda + k = 0 with
        1 / J_eff = u^T J^-1 u = (J11 + J22 + 2 J12) / det J = I_tot / det J,
    I_tot = I1 + I2 + mu |s1 - s2|^2 the system's inertia about its centre of mass (for
    s1.s2 = 0 this is k (1/J11 + 1/J22)). f_n = sqrt(k / J_eff) / 2 pi, zeta = c / (2 sqrt(k J_eff))."""
    m_base, yoke = P.body_mass + P.yoke_mass, P.yoke_mass
    x1 = yoke * P.yoke_com_x / m_base
    I1 = P.body_inertia + P.yoke_inertia[1] + P.body_mass * x1**2 + yoke * (P.yoke_com_x - x1) ** 2
    h = 4 * paper.PLY_THICKNESS
    m_panel = paper.IM6_SC1081.rho * h * paper.LENGTH * paper.WIDTH
    x2 = P.hinge_x + P.root_offset + paper.LENGTH / 2
    I2 = m_panel * (paper.LENGTH**2 + h**2) / 12 + fitting_inertia   # the fitting on the axis
    mu = m_base * m_panel / (m_base + m_panel)
    s1, s2 = x1 - P.hinge_x, x2 - P.hinge_x                           # along x; |y x r| = |r|
    J11, J22, J12 = I1 + mu * s1**2, I2 + mu * s2**2, -mu * s1 * s2
    J_eff = (J11 * J22 - J12**2) / (J11 + J22 + 2 * J12)
    return np.sqrt(k / J_eff) / (2 * np.pi), c / (2 * np.sqrt(k * J_eff))


def lock_tangent(surplus: float, law: ContactLaw, k_theta: float = P.k_theta):
    """(k, c) of a stop-and-latch lock at rest with a spring torque ``surplus`` (N m) at the
    stop: the penetration delta solving r K delta^n = surplus - k_theta delta / r (the paper's
    spring is relaxed at the stop, tau0 = k_theta pi/2), then k = k_theta + r^2 n K delta^(n-1),
    c = r^2 D (Kelvin-Voigt at rest)."""
    r = P.pin_radius
    delta = brentq(lambda d: r * law.K * d**law.n - (surplus - k_theta * d / r), 0.0, 1e-2, xtol=1e-20)
    return k_theta + r * r * law.n * law.K * delta ** (law.n - 1), r * r * law.D


def deployed_q(model):
    q = model.initial_positions()
    for k in range(model.num_hinges):
        q[model.layout(k)["iq_theta"]] = np.pi / 2
    return q


def test_latched_rigid_panel_on_a_free_base_pin_on_the_stop():
    surplus = 2.0
    sc = walls_paper(2, "rigid", nx=4, ny=2, tau0=P.tau0 + surplus, friction=Friction(0.0), contact=KV_LAW)
    m = sc.model.modes(1, q=deployed_q(sc.model), equilibrium=True)
    f, zeta = two_body_hinge_mode(*lock_tangent(surplus, KV_LAW))
    assert m.num_rigid == 6
    assert m.frequencies_hz[0] == pytest.approx(f, rel=1e-8)
    assert m.damping_ratios[0] == pytest.approx(zeta, rel=1e-8)
    # The shape: the hinge turns and the base counter-rotates about y (zero momentum), nothing else.
    s = m.shapes[:, 0].real
    assert s[6] == 1.0 and s[4] < 0 and np.abs(s[[1, 3, 5]]).max() < 1e-12


def test_latched_rigid_panel_from_a_run_equals_the_closed_form():
    # The panel deploys, latches and rattles in its play; at 3 s its relative equilibrium (the
    # run's latch state) gives the same mode, and the state as it stands (in motion) a stiffer one.
    surplus = 2.0
    sc = walls_paper(2, "rigid", nx=4, ny=2, tau0=P.tau0 + surplus, friction=Friction(0.0), contact=KV_LAW)
    r = sc.simulate(3.0, 0.05, progress=False)
    assert r.latched[-1, 0] == 1
    m = sc.model.modes(1, result=r, time=3.0, equilibrium=True)
    f, zeta = two_body_hinge_mode(*lock_tangent(surplus, KV_LAW))
    assert m.t == 3.0 and m.equilibrium
    assert m.frequencies_hz[0] == pytest.approx(f, rel=1e-8)
    assert m.damping_ratios[0] == pytest.approx(zeta, rel=1e-8)
    moving = sc.model.modes(1, result=r, time=2.96)
    assert moving.num_rigid == 6 and not moving.equilibrium and np.isfinite(moving.frequencies_hz[0])


def symmetric_flap(Omega: float) -> float:
    """omega (rad/s) of the symmetric flap of the two-wing spacecraft (rigid panels, relaxed
    springs) spinning at Omega about z through its centre of mass (the base's origin).

    Both panels turn by beta about their hinge axes (tips toward -z alike): by the symmetry of a
    half turn about z this mode moves only the base along z (zero momentum: M z_b' = 2 S beta',
    S = m d the panel's first moment about its hinge) and leaves the spin alone to first order
    (the flap velocity is along the spin: no Coriolis force; I_zz changes as beta^2). Kinetic
    energy per panel 1/2 (J - 2 S^2/M) beta'^2, J = I_yy + m d^2 + J_fitting about the hinge;
    potential per panel 1/2 k beta^2 - 1/2 Omega^2 I_zz,O(beta), I_zz,O(beta) = I_zz cos^2 beta +
    I_xx sin^2 beta + m (e + d cos beta)^2 about the spin axis (e the hinge's distance from it):
        omega^2 = [k + Omega^2 (I_zz - I_xx + m d (e + d))] / (J - 2 S^2 / M),
    the plate's I_zz - I_xx = m (L^2 - h^2)/12, I_yy = m (L^2 + h^2)/12 (the rotating blade's
    centrifugal flap stiffening, with hinge offset e)."""
    h = 4 * paper.PLY_THICKNESS
    m = paper.IM6_SC1081.rho * h * paper.LENGTH * paper.WIDTH
    L, d, e = paper.LENGTH, P.root_offset + paper.LENGTH / 2, P.hinge_x
    M = P.body_mass + 2 * P.yoke_mass + 2 * m
    J = m * (L**2 + h**2) / 12 + m * d**2 + P.fitting_inertia
    return np.sqrt((P.k_theta + Omega**2 * (m * (L**2 - h**2) / 12 + m * d * (e + d))) / (J - 2 * (m * d) ** 2 / M))


def test_spinning_spacecraft_symmetric_flap():
    # The state in motion: the base spins at 0.3 rad/s (v = w_B), the relative equilibrium keeps
    # the spin (the rigid motion carrying the state's momentum), and the modes come from the
    # whole system with the attitude's kinematics (G = -[w_B]x), its six rigid-body modes the
    # twelve state roots nearest zero. The centrifugal load stiffens the flap by 17 %.
    sc = walls_paper(2, "rigid", nx=4, ny=2, wings=2, friction=Friction(0.0), contact=KV_LAW)
    v = np.zeros(sc.model.num_velocities)
    v[5] = 0.3
    m = sc.model.modes(2, q=deployed_q(sc.model), v=v, equilibrium=True)
    assert m.num_rigid == 6 and m.v[5] == pytest.approx(0.3, rel=1e-12)
    sym = np.flatnonzero(np.abs(m.hinge_shapes()[:, 0] - m.hinge_shapes()[:, 1]) < 1e-6)
    assert sym.size == 1
    omega = 2 * np.pi * m.frequencies_hz[sym[0]]
    assert omega == pytest.approx(symmetric_flap(0.3), rel=1e-8)
    assert omega / symmetric_flap(0.0) == pytest.approx(1.17, abs=0.01)
    assert abs(m.damping_ratios).max() < 1e-10
    rest = sc.model.modes(2, q=deployed_q(sc.model), equilibrium=True)
    sym = np.flatnonzero(np.abs(rest.hinge_shapes()[:, 0] - rest.hinge_shapes()[:, 1]) < 1e-6)
    assert 2 * np.pi * rest.frequencies_hz[sym[0]] == pytest.approx(symmetric_flap(0.0), rel=1e-8)


def test_free_base_in_uniform_translation_has_the_modes_at_rest():
    # Galilean invariance: the latched spacecraft drifting at 1 m/s (diagonal) has the modes it
    # has at rest. At rest the base is condensed at zero momentum; in motion the full system is
    # solved and its twelve state eigenvalues nearest zero (the six rigid-body modes) are left out.
    surplus = 2.0
    sc = walls_paper(2, "reduced-linear", nx=4, ny=2, modes=4, tau0=P.tau0 + surplus,
                          friction=Friction(0.0), contact=KV_LAW)
    rest = sc.model.modes(4, q=deployed_q(sc.model), equilibrium=True)
    v = np.zeros(sc.model.num_velocities)
    v[:3] = 1.0 / np.sqrt(3.0)
    drift = sc.model.modes(4, q=rest.q, v=v)
    assert drift.num_rigid == rest.num_rigid == 6
    np.testing.assert_allclose(drift.frequencies_hz, rest.frequencies_hz, rtol=1e-8)
    np.testing.assert_allclose(drift.damping_ratios, rest.damping_ratios, rtol=1e-6, atol=1e-12)
    np.testing.assert_allclose(np.abs(drift.hinge_shapes()), np.abs(rest.hinge_shapes()), rtol=1e-6, atol=1e-9)


def test_latched_rigid_panel_relaxed_spring_and_floating_pin():
    # The paper's spring is relaxed at the stop (tau0 = k_theta pi/2): the pin touches it with no
    # force, an open wall; the hinge keeps the spring's k_theta only, undamped.
    sc = walls_paper(2, "rigid", nx=4, ny=2, friction=Friction(0.0), contact=KV_LAW)
    m = sc.model.modes(1, q=deployed_q(sc.model), equilibrium=True)
    f, _ = two_body_hinge_mode(P.k_theta, 0.0)
    assert m.frequencies_hz[0] == pytest.approx(f, rel=1e-8)
    assert m.damping_ratios[0] == pytest.approx(0.0, abs=1e-9)
    # The same from a run of the paper's lock (D = 1e6 N s/m, mu = 0.25) whose pin is inside the
    # stop at the sample: the equilibrium's active set opens the wall (the pin touches it with no
    # force), so neither the stop's damper nor its friction enters.
    paper_scene = walls_paper(2, "rigid", nx=4, ny=2)
    r = paper_scene.simulate(3.0, 0.01, progress=False)
    pressed = np.flatnonzero((r.lock_force[:, 0] > 0) & (r.latched[:, 0] == 1) & (r.deployment_angle[:, 0] > 180))
    assert pressed.size
    m = paper_scene.model.modes(1, result=r, time=r.t[pressed[-1]], equilibrium=True)
    assert m.frequencies_hz[0] == pytest.approx(f, rel=1e-8)
    assert m.damping_ratios[0] == pytest.approx(0.0, abs=1e-9)
    # No spring and the pin in the middle of its play: nothing holds the hinge, a zero mode,
    # counted as rigid; the flexible panel's modes remain.
    sc = walls_paper(2, "reduced-linear", nx=4, ny=2, modes=4, tau0=0.0, k_theta=0.0, damping=(0.0, 0.0))
    q = deployed_q(sc.model)
    q[sc.model.layout(0)["iq_theta"]] -= 0.5 * P.clearance / P.pin_radius
    m = sc.model.modes(2, q=q, equilibrium=True)
    assert m.num_rigid == 7
    assert m.frequencies_hz[0] > 0.5


def contact_samples(r, count: int = 3) -> list:
    """Output times in and out of the lock's contacts: nearest the middle of the run's first
    ``count`` impacts, the last before each of their separations (where the pin may already be
    out of the wall while it still pushes: the damper's share), and the first after."""
    ends = [r.t[-1] if i.t_separation_s is None else i.t_separation_s for i in r.impacts[:count]]
    mid = [0.5 * (i.t_onset_s + e) for i, e in zip(r.impacts[:count], ends)]
    out = [float(r.t[np.argmin(np.abs(r.t - x))]) for x in mid]
    out += [float(r.t[r.t < e][-1]) for e in ends] + [float(r.t[r.t > ends[0]][0]) if ends[0] < r.t[-1] else r.t[-1]]
    return out


@pytest.mark.parametrize("geometry, fidelity, law", [
    ("stop-latch", "rigid", ContactLaw("hunt-crossley", K=KV_LAW.K, e=0.8)),   # v0 from the records
    ("stop-latch", "reduced-linear", P.contact),
    ("groove", "rigid", P.contact),
    ("groove", "reduced-linear", P.contact),
])
def test_lock_history_from_the_state_is_the_runs(geometry, fidelity, law):
    # The lock's history derived from a run's sample (latched as recorded, the walls with an impact
    # in progress closed, their approach speeds; a groove's latch pin followed through the samples
    # onto the facet it has dropped to) linearises exactly as the run's own history at that time
    # (data=, the run stopped there), in contact and between contacts.
    sc = scenes.paper2016(2, fidelity, nx=2, ny=1, modes=3, lock_geometry=geometry, contact=law)
    times = sorted(set(contact_samples(sc.simulate(3.0, 0.01, progress=False))))
    assert len(times) >= 2
    closed = []
    for t_end in times:
        data = sc.model.make_data()
        r = sc.model.simulate(t_end, 0.01, progress=False, data=data)
        h = data.lock(0)
        closed.append(any(f.closed for f in h.facets) if geometry == "groove" else h.stop_contact or h.latch_contact)
        n = 1 if fidelity == "rigid" else 3
        own = sc.model.modes(n, result=r, time=t_end, data=data)
        derived = sc.model.modes(n, result=r, time=t_end)
        np.testing.assert_allclose(derived.eigenvalues, own.eigenvalues, rtol=1e-10)
    assert any(closed)  # a wall in contact at one sample at least


# -------------------------------------------------------------- 3. locked flexible panel, fixed base
def hinged_panel_reference(shell, fixed, k_h: float, J_fit: float, count: int) -> np.ndarray:
    """Frequencies (Hz) of the panel on a hinge about y through C's origin with a rotational
    spring k_h, from the shell's own matrices: coordinates (theta, free dofs u), the mesh moving
    by Phi theta + u with Phi the rigid rotation (u_z = -x theta, theta_y = theta);
    M = [[Phi^T M Phi + J_fit, Phi^T M_f], [M_f^T Phi, M_ff]], K = diag(k_h, K_ff)."""
    Ms, Ks = shell.mass_matrix().toarray(), shell.stiffness_matrix().toarray()
    X = np.asarray(shell.nodes)
    Phi = np.zeros(shell.num_dofs)
    Phi[0::6], Phi[2::6], Phi[4::6] = X[:, 2], -X[:, 0], 1.0
    free = np.setdiff1d(np.arange(shell.num_dofs), fixed)
    T = np.zeros((shell.num_dofs, 1 + len(free)))
    T[:, 0] = Phi
    T[free, 1 + np.arange(len(free))] = 1.0
    M = T.T @ Ms @ T
    M[0, 0] += J_fit
    K = np.zeros_like(M)
    K[0, 0] = k_h
    K[1:, 1:] = Ks[np.ix_(free, free)]
    inv = scipy.linalg.eigh(M, K, eigvals_only=True)[::-1]   # 1/omega^2: the lowest modes to round-off
    return 1.0 / np.sqrt(inv[:count]) / (2 * np.pi)


def test_locked_flexible_panel_on_a_fixed_base():
    law = ContactLaw("paper", K=KV_LAW.K, n=1.5, D=0.0)
    surplus = 50.0   # a hard-pressed pin: the lock is far stiffer than the panel's root
    sc = walls_paper(2, "nonlinear", nx=4, ny=2, base_free=False, tau0=P.tau0 + surplus,
                          friction=Friction(0.0), contact=law, damping=(0.0, 0.0))
    m = sc.model.modes(5, q=deployed_q(sc.model), equilibrium=True)
    shell, fixed = sc.model.shells[0], sc.model.links[0].appendage.fixed_dofs
    k_h, _ = lock_tangent(surplus, law)
    ref = hinged_panel_reference(shell, list(fixed), k_h, P.fitting_inertia, 5)
    assert m.num_rigid == 0
    np.testing.assert_allclose(m.frequencies_hz, ref, rtol=1e-8)
    np.testing.assert_allclose(m.damping_ratios, 0.0, atol=1e-9)
    clamped, _ = shell.modes(3, list(fixed))
    np.testing.assert_allclose(m.frequencies_hz[:3], clamped, rtol=2e-3)
    # The shapes in W: the hinge's rotation about its axis (the panel frame C's y, through its
    # origin) carries the mesh as theta (z, 0, -x), plus the elastic displacement, both in C's
    # axes (turned from B's by the pin's penetration into the stop); world_shapes linearises the
    # engine's kinematics instead.
    X = np.asarray(shell.nodes)
    rigid = np.stack([X[:, 2], 0 * X[:, 0], -X[:, 0]], axis=1)
    local = m.hinge_shapes()[:, 0, None, None] * rigid + m.mesh_shapes(0).reshape(len(m), -1, 6)[:, :, :3]
    R_WC = sc.model.frames(m.q)[0][0, 0]
    np.testing.assert_allclose(m.world_shapes(0), local @ R_WC.T, atol=1e-9)


def test_modes_export_to_vtk(tmp_path):
    meshio = pytest.importorskip("meshio")
    from deployfx import export

    sc = walls_paper(2, "reduced-linear", nx=4, ny=2, modes=4, base_free=False, damping=(0.0, 0.0))
    m = sc.model.modes(3, q=deployed_q(sc.model), equilibrium=True)
    path = export.write_modes_vtk(m, tmp_path / "modes.vtu")
    mesh = meshio.read(path)
    np.testing.assert_allclose(mesh.points, sc.model.world_points(m.q, 0)[0], atol=1e-12)
    for j in range(3):
        np.testing.assert_allclose(mesh.point_data[f"mode_{j + 1}"], m.world_shapes(0)[j], atol=1e-12)
    table = np.loadtxt(tmp_path / "modes_modes.csv", delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 1], m.frequencies_hz, rtol=1e-9)
    with pytest.raises(TypeError, match="modes must be a deployfx.Modes"):
        export.write_modes_vtk(m.frequencies_hz, tmp_path / "x.vtu")


def arnoldi_cases():
    strip = spinning_strip(10, 3 * SCALE)
    free = walls_paper(2, "nonlinear", nx=4, ny=2, tau0=P.tau0 + 2.0, friction=Friction(0.0), contact=KV_LAW)
    drift = np.zeros(free.model.num_velocities)
    drift[:3] = 1.0 / np.sqrt(3.0)
    return {"fixed base, spinning strip": (strip, dict(q=strip.initial_positions(), t=5.0, equilibrium=True)),
            "free base at rest": (free.model, dict(q=deployed_q(free.model), equilibrium=True)),
            "free base drifting": (free.model, dict(q=deployed_q(free.model), v=drift))}


@pytest.mark.parametrize("case", ["fixed base, spinning strip", "free base at rest", "free base drifting"])
def test_arnoldi_on_large_models_equals_the_dense_solve(case, monkeypatch):
    # Above _ARNOLDI_ABOVE state sizes (the paper's 15 x 10 full panel: 2 s instead of 46 s) only
    # the eigenvalues nearest the shift are computed (ARPACK on the same factored shifted
    # inverse); forced here on small models, it must give the dense solve's modes.
    from deployfx import modal_analysis

    import scipy.sparse.linalg

    model, state = arnoldi_cases()[case]
    dense = model.modes(8, **state)
    monkeypatch.setattr(modal_analysis, "_ARNOLDI_ABOVE", 0)
    converged = []
    eigs = scipy.sparse.linalg.eigs

    def counted(*args, **kwargs):
        out = eigs(*args, **kwargs)
        converged.append(True)
        return out

    monkeypatch.setattr(scipy.sparse.linalg, "eigs", counted)
    arnoldi = model.modes(8, **state)
    assert converged  # ARPACK ran and converged (no dense fallback)
    assert arnoldi.num_rigid == dense.num_rigid
    np.testing.assert_allclose(arnoldi.eigenvalues, dense.eigenvalues, rtol=1e-7)
    np.testing.assert_allclose(np.abs(arnoldi.shapes), np.abs(dense.shapes), atol=1e-6)


# ------------------------------------------------------------------------------- bad input
def test_bad_input_names_the_parameter():
    sc = walls_paper(2, "rigid", nx=2, ny=1, friction=Friction(0.0))
    model = sc.model
    q = deployed_q(model)
    r = sc.simulate(0.2, 0.05, progress=False)
    with pytest.raises(ValueError, match=r"n = 0 is out of range: must be >= 1"):
        model.modes(0, q=q)
    with pytest.raises(TypeError, match="n must be an integer"):
        model.modes(1.5, q=q)
    with pytest.raises(ValueError, match=r"time = 0.5 is out of range: must be within the result's \[0, 0.2\] s"):
        model.modes(1, result=r, time=0.5)
    with pytest.raises(ValueError, match="time is required"):
        model.modes(1, result=r)
    with pytest.raises(ValueError, match="not both"):
        model.modes(1, result=r, time=0.1, q=q)
    with pytest.raises(ValueError, match="give result= and time=, or the state q="):
        model.modes(1)
    with pytest.raises(ValueError, match=r"q must be 8 finite numbers"):
        model.modes(1, q=q[:-1])
    with pytest.raises(ValueError, match=r"zero_hz = -1.0 is out of range"):
        model.modes(1, q=q, zero_hz=-1.0)
    with pytest.raises(ValueError, match=r"n = 2 is out of range: the linearised model has 1 modes besides its 6"):
        model.modes(2, q=q, equilibrium=True)
    with pytest.raises(ValueError, match="not a run of this model"):
        walls_paper(2, "rigid", nx=2, ny=1, base_free=False).model.modes(1, result=r, time=0.1)
    with pytest.raises(ValueError, match=r"v must be 7 finite numbers"):
        model.modes(1, q=q, v=np.zeros(6))
    with pytest.raises(TypeError, match="result must be a deployfx.Result"):
        model.modes(1, result=r.t, time=0.1)
    with pytest.raises(TypeError, match="equilibrium must be True or False"):
        model.modes(1, q=q, equilibrium="yes")
    with pytest.raises(ValueError, match="time is given without result="):
        model.modes(1, q=q, time=0.1)
    with pytest.raises(ValueError, match="equilibrium=True switches the locks' walls itself"):
        model.modes(1, q=q, equilibrium=True, data=model.make_data())
    # time picks the nearest recorded sample, reported as Modes.t
    assert model.modes(1, result=r, time=0.126).t == pytest.approx(0.15)
