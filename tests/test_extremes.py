"""Stability at the extremes (issue 6): contact stiffness 1e3..1e12 N/m^1.5, time steps 1e-5..0.05 s,
plate length/thickness up to 1e4, spin-up far above the first bending frequency, body/appendage
mass ratio 1e-2..1e6, 1000 s undamped, and (issue 29) the undamped reduced-nonlinear paper scene
over 30 s. Each test checks physics against a closed form, an independent reduced model or a
conservation law, with the tolerance and source stated.

The reference for the deployment scenes is the rigid panel's exact reduction. Base (body + yoke,
centre of mass c_B) and appendage (panel + hinge fitting, centre of mass s(theta) from the hinge
point p) turn in the x-z plane with zero total momentum. With r = p - c_B + s and
mu = m_B m_A / (m_B + m_A), the angular momentum about the system's fixed centre of mass is
  H = b phi' + a theta' = 0,  a = J_A + mu r.s,  b = J_B + J_A + mu |r|^2,
and the kinetic energy 1/2 I_eff theta'^2, I_eff = J_A + mu |s|^2 - a^2 / b (Routh reduction of the
cyclic base angle phi). Hence the base turns by phi(theta) = -int a/b dtheta, and with the spring
tau0 - k theta (theta0 = tau0/k) the substitution theta = theta0 (1 - cos u) turns the energy
quadrature into t(u) = int_0^u sqrt(I_eff(theta(u'))/k) du' (smooth at the turning points).
"""
import dataclasses
import functools
import re

import numpy as np
import pytest
import scipy.integrate
import scipy.linalg

import deployfx as dfx
from closed_forms import cross_ply_clpt_omega, cross_ply_fsdt_navier_omega, ss_plate_frequency_kirchhoff
from deployfx import _core, scenes
from deployfx.contact import ContactLaw
from deployfx.integrators import GeneralizedAlpha, SimulationError

# You et al. (2016) Table 1: the appendage, 2.0 x 1.3 m, four 0.5 mm plies, rho = 1600 kg/m^3.
RHO, THICK, LENGTH, WIDTH = 1600.0, 2e-3, 2.0, 1.3
PAPER = scenes.Paper2016Parameters()
THETA_LOCK = np.pi / 2  # hinge travel at the stop (90 -> 180 deg of deployment)


def stop_latch_paper(*args, **overrides):
    """The paper's scene with its stop-and-latch lock: walls in the hinge angle with no ride
    friction before the stop, the geometry the closed forms below describe (the default groove's
    riding pin delays the lock by ~3 ms: tests/test_groove_lock.py covers its extremes)."""
    return scenes.paper2016(*args, **{"lock_geometry": "stop-latch", **overrides})


def rigid_scene(**overrides):
    return stop_latch_paper(2, "rigid", nx=2, ny=1, **overrides)


def simulate(scene, t_end, dt, **options):
    """The paper scene's run, its one hinge's view (Result.hinge(0): per-hinge series (n,))."""
    return scene.simulate(t_end, dt, **options).hinge(0)


class TwoBody:
    """The zero-momentum planar reduction above, for the paper scene's parameters (overridable)."""

    def __init__(self, **overrides):
        p = dataclasses.replace(PAPER, **overrides)
        m_b = p.body_mass + p.yoke_mass
        c_b = p.yoke_mass * p.yoke_com_x / m_b
        self.J_B = (float(np.mean(p.body_inertia)) + p.yoke_inertia[1] + p.body_mass * c_b**2
                    + p.yoke_mass * (p.yoke_com_x - c_b) ** 2)
        self.m_A = RHO * THICK * LENGTH * WIDTH
        self.J_A = self.m_A * (LENGTH**2 + THICK**2) / 12 + p.fitting_inertia  # about y
        self.mu = m_b * self.m_A / (m_b + self.m_A)
        self.p = np.array([p.hinge_x - c_b, 0.0, 0.0])
        self.c_E = np.array([p.root_offset + LENGTH / 2, 0.0, 0.0])  # panel centre in E
        self.tau0, self.k = p.tau0, p.k_theta
        self.theta0 = p.tau0 / p.k_theta
        self.J_hinge = self.J_A + self.m_A * self.c_E @ self.c_E  # fixed base

    def abc(self, theta):
        c, s_ = np.cos(theta - np.pi / 2), np.sin(theta - np.pi / 2)
        s = np.array([c * self.c_E[0], 0.0, -s_ * self.c_E[0]])  # Ry(theta - pi/2) c_E
        r = self.p + s
        return self.J_A + self.mu * r @ s, self.J_B + self.J_A + self.mu * r @ r, self.J_A + self.mu * s @ s

    def I_eff(self, theta):
        a, b, c = self.abc(theta)
        return c - a * a / b

    def dI_eff(self, theta, eps=1e-6):
        return (self.I_eff(theta + eps) - self.I_eff(theta - eps)) / (2 * eps)

    def base_angle(self, theta):
        """phi(theta) = -int_0^theta a/b (rad)."""
        f = lambda x: -self.abc(x)[0] / self.abc(x)[1]
        return scipy.integrate.quad(f, 0.0, theta, epsabs=1e-15, epsrel=1e-13)[0]

    def time_to(self, theta):
        """Time (s) from rest at theta = 0 to theta (< 2 theta0), by the energy quadrature."""
        u1 = np.arccos(1 - theta / self.theta0)
        g = lambda u: np.sqrt(self.I_eff(self.theta0 * (1 - np.cos(u))) / self.k)
        return scipy.integrate.quad(g, 0.0, u1, epsabs=1e-14, epsrel=1e-13)[0]

    def period(self):
        g = lambda u: np.sqrt(self.I_eff(self.theta0 * (1 - np.cos(u))) / self.k)
        return 2 * scipy.integrate.quad(g, 0.0, np.pi, epsabs=1e-14, epsrel=1e-13)[0]

    def impact_energy(self):
        """Relative kinetic energy at the stop (J): the spring's work tau0 theta - k theta^2/2."""
        return self.tau0 * THETA_LOCK - self.k * THETA_LOCK**2 / 2


PAPER_2BODY = TwoBody()


def finite(result):
    return all(np.all(np.isfinite(np.asarray(result[name], dtype=float))) for name in result.series)


def test_two_body_reference_reproduces_the_known_paper_numbers():
    # The reduction's own checks: the spring's neutral angle is the lock (7200 N mm / 80 N mm/deg
    # = 90 deg), the rigid panel reaches the stop at 2.451 s (README, test_hinged_system), and the
    # 3x3 Navier FSDT solver of closed_forms agrees with the stable 2x2 root used below at a/h = 100.
    assert PAPER_2BODY.theta0 == pytest.approx(THETA_LOCK, rel=1e-12)
    assert PAPER_2BODY.time_to(THETA_LOCK) == pytest.approx(2.451, abs=1e-3)
    a, h, E, nu = 1.0, 0.01, 200e9, 0.3
    D = E * h**3 / (12 * (1 - nu**2))
    Dm = np.array([[D, nu * D, 0], [nu * D, D, 0], [0, 0, (1 - nu) * D / 2]])
    kGh = 5 / 6 * E / (2 * (1 + nu)) * h
    for m, n in [(1, 1), (1, 2), (2, 2)]:
        ref = cross_ply_fsdt_navier_omega(kGh, kGh, Dm, 8000 * h, 8000 * h**3 / 12, a, a, m, n)
        assert mindlin_ss_omega(E, nu, 8000.0, h, a, a, m, n) == pytest.approx(ref, rel=1e-8)


# ------------------------------------------------------------------------------------------------
# 1. Contact stiffness from 1e3 to 1e12 N/m^1.5 (the paper's Kelvin-Voigt-Hertz law, D = 1e6 N s/m)

STIFFNESSES = [10.0**e for e in range(3, 13)]


def penetration_bound(K, D, r=PAPER.pin_radius):
    """Largest stop penetration delta (m) the first impact can reach, whatever the time step.
    The spring's neutral angle is the lock (theta0 = theta_lock), so the static penetration is 0 and
    the bound is dynamic, from the relative kinetic energy T0 and angular momentum I_eff theta0' at
    the stop (rigid panel, zero total momentum). While the pin goes in, F = K delta^1.5 + D delta'
    with delta' >= 0, and the spring (tau0 - k theta <= 0 past theta0) and friction only decelerate:
      energy:  (2/5) K delta^2.5 <= T0;   impulse:  D delta <= int F dt <= I_eff theta0' / r.
    (The reduction's (1/2) I_eff' theta'^2 term changes the impulse by < 1e-3 over < 1 deg.)"""
    T0 = PAPER_2BODY.impact_energy()
    L0 = np.sqrt(2 * T0 * PAPER_2BODY.I_eff(THETA_LOCK))
    return min((2.5 * T0 / K) ** 0.4, L0 / (D * r) if D > 0 else np.inf)


@pytest.mark.parametrize("K", STIFFNESSES, ids=lambda K: f"K{K:.0e}")
def test_contact_stiffness_range_at_the_papers_step(K):
    # Rigid panel, the paper's lock (pin at 30 mm, 0.2 mm play, mu = 0.25) and step (0.01 s).
    law = ContactLaw("paper", K=K, n=1.5, D=PAPER.contact.D)
    r = simulate(rigid_scene(contact=law), 4.0, 0.01)  # raises SimulationError if it diverges
    assert finite(r)
    # No missed impact: the onset is located at the quadrature's time to the stop (2.4511 s),
    # whatever K (measured 9e-6 s off at dt = 0.01 s): 1e-4 s.
    t_lock = r.summary()["first_lock_time_s"]
    assert t_lock is not None and t_lock == pytest.approx(PAPER_2BODY.time_to(THETA_LOCK), abs=1e-4)
    # The pin is arrested by the wall: the overshoot past the stop stays within the law's dynamic
    # bound. At this step the contact is under-resolved (the soft laws' dashpot time m_eff/D is
    # 12 ms) and overshoots the bound by up to 17 % (0.43 vs 0.37 mm at K <= 1e6; 2 % at 1e11):
    # allowed 25 %. A missed impact would carry the pin on to the spring's turning point, 47 mm
    # past the stop. (Resolved, the penetration matches the reduced model: next test.)
    r_pin = PAPER.pin_radius
    theta = np.radians(r.deployment_angle - 90.0)
    bound = 1.25 * penetration_bound(K, law.D) / r_pin
    assert theta.max() - THETA_LOCK < bound
    # Once past the latch the pin stays in the groove (between latch and stop, within the bound).
    after = r.t > t_lock + 0.05
    assert theta[after].min() > THETA_LOCK - PAPER.clearance / r_pin - bound
    # The contact law, friction and the scheme (rho_inf = 0.8) may only remove energy: kinetic +
    # spring energy whenever both walls are open never exceeds its value before the impact (the
    # contact's own elastic energy is zero there); 1e-9 of the impact energy.
    E = r.kinetic_energy + r.potential_energy
    k0 = int(np.flatnonzero(r.lock_force > 0)[0])
    open_after = np.flatnonzero(r.lock_force == 0)
    open_after = open_after[open_after > k0]
    T0 = PAPER_2BODY.impact_energy()
    if open_after.size:
        assert E[open_after].max() <= E[k0 - 1] + 1e-9 * T0
    assert E[-1] < E[k0 - 1]
    # Momentum: no external load, conserved to round-off through the impacts (1e-12 of the base's).
    assert r.summary()["momentum_drift"] < 1e-12


def test_an_open_wall_event_is_its_gap_even_where_the_law_would_pull():
    # No missed impact within a step: a stop wall open at the last accepted state, with the pin
    # outside it (a fresh system's history), switches when the gap r (theta - theta_lock) closes,
    # whatever the Kelvin-Voigt law's force K delta^1.5 + D delta' would be there. A pin found
    # 1 um inside and leaving at 0.1 m/s (force 32 N - 1e5 N < 0) crossed the wall within the
    # step: its event is -delta = -1e-6 m (exact), where minus that force (+1e5 N) hid the tap.
    # Approaching from 1 um outside, the event is the gap, +1e-6 m. q = [r_W, quaternion, theta],
    # v = [v_W, w_B, theta'] (Model.layout); lock_events gives (stop, latch) per locked hinge.
    system = rigid_scene().model.core
    assert system.layout(0)["iq_theta"] == 7 and system.layout(0)["iv_theta"] == 6
    q, v = system.initial_positions(), np.zeros(system.num_velocities)
    r = PAPER.pin_radius
    for delta, rate, expected in [(1e-6, -0.1 / r, -1e-6), (-1e-6, 0.1 / r, 1e-6)]:
        q[7], v[6] = THETA_LOCK + delta / r, rate
        stop, latch = system.lock_events(q, v, data=system.make_data())
        assert stop == pytest.approx(expected, rel=1e-9)
        assert latch == np.inf  # not latched yet
    with pytest.raises(ValueError, match="must have sizes"):
        system.lock_events(q[:-1], v)


def first_impact_reference(law, r=PAPER.pin_radius, mu=PAPER.friction.mu, v_reg=PAPER.friction.v_reg):
    """Maximum stop penetration (m) and the time to reach it (s) of the first impact, from the
    reduced 1-DOF equation I_eff theta'' + (1/2) I_eff' theta'^2 = tau0 - k theta - r F - r mu F
    tanh(r theta' / v_reg) (Lagrange on the Routhian above), started at the stop with the energy
    quadrature's rate, integrated by scipy's DOP853 to theta' = 0. F: Kelvin-Voigt-Hertz
    K delta^n + D delta' (You et al. 2016) or Hunt-Crossley K delta^n (1 + 3 (1 - e)/2 delta'/v0)."""
    tb = PAPER_2BODY
    w0 = np.sqrt(2 * tb.impact_energy() / tb.I_eff(THETA_LOCK))
    v0, c = r * w0, 1.5 * (1 - law.e)

    def rhs(t, y):
        th, w = y
        d = max(r * (th - THETA_LOCK), 0.0)
        if law.kind == "kelvin-voigt-hertz":
            F = law.K * d**law.n + law.D * r * w
        else:
            F = law.K * d**law.n * (1 + c * r * w / v0)
        tau = tb.tau0 - tb.k * th - r * F - r * mu * F * np.tanh(r * w / v_reg)
        return [w, (tau - 0.5 * tb.dI_eff(th) * w * w) / tb.I_eff(th)]

    stop = lambda t, y: y[1]
    stop.terminal, stop.direction = True, -1
    sol = scipy.integrate.solve_ivp(rhs, (0.0, 10.0), [THETA_LOCK, w0], method="DOP853", rtol=1e-11,
                                    atol=1e-14, events=stop)
    return r * (sol.y_events[0][0][0] - THETA_LOCK), sol.t_events[0][0]


@functools.lru_cache(maxsize=None)
def state_before_the_stop(law):
    system = rigid_scene(contact=law).model.core
    pre = _core.simulate(system, system.initial_positions(), np.zeros(system.num_velocities), t_end=2.44,
                         dt=0.01, scheme=GeneralizedAlpha(0.8)._params())
    assert pre["failure"] == ""
    return system, pre["q"][-1], pre["v"][-1]


@pytest.mark.parametrize("kind", ["paper", "hunt-crossley"])
@pytest.mark.parametrize("K", STIFFNESSES, ids=lambda K: f"K{K:.0e}")
def test_first_impact_penetration_matches_the_reduced_model(kind, K):
    # The impact resolved: the run restarts 11 ms before the stop (from the dt = 0.01 s state) with a
    # step of 1/1000 of the time to maximum penetration (1e-5 .. 1e-3 s). Maximum penetration within
    # 0.5 % of the reduced model above, from 38 um (stiff) to 0.3 mm (the paper law's dashpot,
    # D = 1e6 N s/m, soft K) and 46 mm (Hunt-Crossley e = 0.5 at K = 1e3: the pin runs 87 deg past
    # the stop and is still caught). Measured: 0.17 % (the paper law's force jumps to D v0 at onset)
    # and < 1e-4 (Hunt-Crossley).
    law = (ContactLaw("paper", K=K, n=1.5, D=PAPER.contact.D) if kind == "paper"
           else ContactLaw("hunt-crossley", K=K, n=1.5, e=0.5))
    ref, t_max = first_impact_reference(law)
    system, q, v = state_before_the_stop(law)
    dt = float(np.clip(t_max / 1000, 1e-5, 1e-3))
    tr = _core.simulate(system, q, v, t_end=0.02 + 1.2 * t_max, dt=dt, scheme=GeneralizedAlpha(0.8)._params())
    assert tr["failure"] == ""
    assert np.all(np.isfinite(tr["theta"]))
    delta = PAPER.pin_radius * (tr["theta"][:, 0].max() - THETA_LOCK)
    assert delta == pytest.approx(ref, rel=5e-3)
    assert tr["lock_force"].max() > 0


@pytest.mark.parametrize("K", [1e3, 1e12], ids=lambda K: f"K{K:.0e}")
def test_contact_stiffness_extremes_with_a_flexible_panel(K):
    # Linear flexible panel (2 x 1 mesh) at the paper's step: no divergence; the impact found (the
    # flexible panel lags the rigid one: first lock within 3 % of 2.451 s, as in
    # test_hinged_system); momentum at round-off; the mechanical energy never exceeds its start by
    # more than the scheme's O(dt^2) error (5e-3 of the impact energy; measured 2.4e-3), and so the
    # penetration stays within the energy bound (2/5) K delta^2.5 <= T0 + that error (0.09 deg at
    # 1e12; at 1e3 the ringing plate's root moment pushes the pin 1.1 deg into the dashpot-like
    # wall, well inside the bound, which only the impulse of a single impact makes tight).
    law = ContactLaw("paper", K=K, n=1.5, D=PAPER.contact.D)
    r = simulate(stop_latch_paper(2, "linear", nx=2, ny=1, contact=law), 3.5, 0.01)
    assert finite(r)
    s = r.summary()
    assert s["first_lock_time_s"] == pytest.approx(PAPER_2BODY.time_to(THETA_LOCK), rel=0.03)
    assert s["momentum_drift"] < 1e-12
    E = r.kinetic_energy + r.potential_energy
    T0 = PAPER_2BODY.impact_energy()
    assert E.max() - E[0] < 5e-3 * T0
    delta = PAPER.pin_radius * np.radians(r.deployment_angle.max() - 180.0)
    assert 0.4 * K * max(delta, 0.0) ** 2.5 <= T0 + (E.max() - E[0])
    assert r.lock_force.max() > 0


# ------------------------------------------------------------------------------------------------
# 2. Time steps from 1e-5 to 0.05 s

DTS = [1e-5, 1e-4, 1e-3, 1e-2, 5e-2]
T_END = {1e-5: 0.02, 1e-4: 0.2, 1e-3: 1.0, 1e-2: 3.0, 5e-2: 3.0}  # <= 2000 steps; the last two lock


@functools.lru_cache(maxsize=None)
def dt_run(model, dt, lock_geometry="stop-latch"):
    try:
        return simulate(scenes.paper2016(2, model, nx=2, ny=1, lock_geometry=lock_geometry), T_END[dt], dt), None
    except SimulationError as e:
        return e.result.hinge(0), e


@pytest.mark.parametrize("lock_geometry", ["stop-latch", "groove"])
@pytest.mark.parametrize("dt", DTS)
@pytest.mark.parametrize("model", ["rigid", "linear", "nonlinear"])
def test_any_step_completes_or_stops_with_a_clear_error(model, dt, lock_geometry):
    # Issue 6: never NaN. A run either completes (all series finite, momentum at round-off: the base
    # rows are solved as Pi(q, v) = Pi_0 at any step, 1e-11 of the base's peak) or raises
    # SimulationError saying what failed and when, with finite partial results up to then. Either
    # lock (the groove's riding pin delays the lock by ~3 ms, inside the 3 % below).
    r, error = dt_run(model, dt, lock_geometry)
    assert finite(r)
    if error is not None:
        assert re.search(r"at t = [0-9.e+-]+ s", str(error)), str(error)
        assert r.failure and r.t[-1] < T_END[dt]
        return
    assert r.t[-1] == pytest.approx(T_END[dt], abs=1e-12)
    assert r.summary()["momentum_drift"] < 1e-11
    # Sanity (no runaway): between stowed and the stop plus the flexible panel's push (< 1.5 deg).
    assert 89.0 < r.deployment_angle.min() and r.deployment_angle.max() < 181.5
    if T_END[dt] > 2.6:  # through the lock: the first lock within 3 % of the rigid quadrature
        assert r.summary()["first_lock_time_s"] == pytest.approx(PAPER_2BODY.time_to(THETA_LOCK), rel=0.03)


def rigid_angle_exact(t):
    """theta(t) (rad) of the rigid panel before the lock: u' = sqrt(k / I_eff(theta0 (1 - cos u)))."""
    tb = PAPER_2BODY
    sol = scipy.integrate.solve_ivp(lambda _, u: [np.sqrt(tb.k / tb.I_eff(tb.theta0 * (1 - np.cos(u[0]))))],
                                    (0.0, float(np.max(t))), [0.0], method="DOP853", rtol=1e-13, atol=1e-15,
                                    dense_output=True)
    return tb.theta0 * (1 - np.cos(sol.sol(t)[0]))


@pytest.mark.parametrize("model", ["rigid", "linear", "nonlinear"])
def test_steps_from_1e_5_to_1e_2_converge_at_second_order(model):
    # The deployment angle and (flexible) node E deflection at t = 0.02 s, a sample of every run
    # with dt <= 0.01 s, against the dt = 1e-5 s run (rigid: against the exact theta(t) above,
    # which the 1e-5 run matches to 1e-10 deg). Generalized-alpha is second order (Chung & Hulbert
    # 1993): the error falls 100x per decade of dt from 1e-3 to 1e-4 s; accepted 50..200x. From
    # 1e-2 s (two steps, under the hinge fitting's root mode) it still falls (measured 33..100x).
    def at(r, name):
        k = np.flatnonzero(np.isclose(r.t, 0.02, rtol=0, atol=1e-12))
        return float(r[name][k[0]])

    runs = {dt: dt_run(model, dt)[0] for dt in (1e-5, 1e-4, 1e-3, 1e-2)}
    for r in runs.values():
        assert r.t[-1] >= 0.02
    names = ["deployment_angle"] + ([] if model == "rigid" else ["node_E_deflection"])
    for name in names:
        if model == "rigid":
            ref = 90.0 + np.degrees(rigid_angle_exact(np.array([0.02]))[0])
            assert at(runs[1e-5], name) == pytest.approx(ref, abs=1e-10)
        else:
            ref = at(runs[1e-5], name)
        err = {dt: abs(at(runs[dt], name) - ref) for dt in (1e-4, 1e-3, 1e-2)}
        assert 50 < err[1e-3] / err[1e-4] < 200, (name, err)
        assert err[1e-2] > 10 * err[1e-3], (name, err)


def test_rigid_trajectory_error_is_second_order_up_to_dt_0_05():
    # The whole approach to the stop (t <= 2.4 s) against the exact theta(t) for dt = 0.05, 0.02 and
    # 0.01 s: max error ~ C dt^2, ratio 6.25 and 4 on these steps (measured 6.248, 4.000; accepted
    # +-10 %), and below 1e-4 rad at the paper's 0.01 s.
    errs = []
    for dt in (0.05, 0.02, 0.01):
        r = simulate(rigid_scene(lock=False), 2.4, dt)
        theta = np.radians(r.deployment_angle - 90.0)
        errs.append(np.abs(theta - rigid_angle_exact(r.t)).max())
    assert 5.6 < errs[0] / errs[1] < 6.9 and 3.6 < errs[1] / errs[2] < 4.4, errs
    assert errs[2] < 1e-4


def test_a_diverging_run_stops_with_a_clear_error():
    # A run that really diverges: Newmark with beta = 0.01, gamma = 1/2 is only conditionally
    # stable, for omega h < 1 / sqrt(gamma/2 - beta) = 2.085 (Hughes, "The Finite Element Method",
    # 1987, Sec. 9.1). The 2 x 1 linear panel's highest mode (omega_max ~ 3.5e6 rad/s) at
    # dt = 0.01 s is far beyond it. Nothing in the scene adds energy (no lock, undriven), so the
    # energy growth is reported as a divergence with its time, and the series computed so far are
    # kept on the exception. The same run with generalized-alpha (unconditionally stable) raises
    # nothing: the check does not fire on a sound run.
    plate = dfx.paper2016.appendage_plate(2, 2, 1)
    free = np.setdiff1d(np.arange(plate.model.num_dofs), plate.fixed_dofs("CFFF"))
    M = plate.model.mass_matrix().toarray()[np.ix_(free, free)]
    K = plate.model.stiffness_matrix().toarray()[np.ix_(free, free)]
    omega_max = np.sqrt(scipy.linalg.eigh(K, M, eigvals_only=True).max())
    beta, gamma, dt = 0.01, 0.5, 0.01
    assert omega_max * dt > 100 / np.sqrt(gamma / 2 - beta)
    sc = stop_latch_paper(2, "linear", nx=2, ny=1, lock=False)
    with pytest.raises(SimulationError, match=r"diverged: the total energy grew .* at t = ") as e:
        sc.simulate(0.5, dt, scheme=dfx.integrators.Newmark(beta=beta, gamma=gamma))
    partial = e.value.result
    assert 1 < len(partial.t) and partial.t[-1] < 0.5
    assert np.all(np.isfinite(partial.deployment_angle))
    sound = sc.simulate(0.5, dt)
    assert np.all(np.isfinite(sound.deployment_angle))


# ------------------------------------------------------------------------------------------------
# 3. Plate length/thickness up to 1e4: no shear locking

E_ST, NU_ST, RHO_ST = 200e9, 0.3, 8000.0


def mindlin_ss_omega(E, nu, rho, h, a, b, m, n, kappa=5 / 6):
    """Flexural omega (rad/s) of mode (m, n) of a simply supported isotropic Mindlin plate (Mindlin
    1951; Reddy 2004 Sec. 7.3): with k^2 = pi^2 ((m/a)^2 + (n/b)^2), I0 = rho h, I2 = rho h^3/12,
    I0 I2 w^4 - (kGh I2 k^2 + I0 D k^2 + I0 kGh) w^2 + kGh D k^4 = 0; the lower root in the
    cancellation-free form w^2 = 2C / (B + sqrt(B^2 - 4AC)) (accurate at a/h = 1e4, where the
    3x3 eigen solve of closed_forms loses the root to round-off)."""
    D = E * h**3 / (12 * (1 - nu**2))
    kGh = kappa * E / (2 * (1 + nu)) * h
    I0, I2 = rho * h, rho * h**3 / 12
    k2 = np.pi**2 * ((m / a) ** 2 + (n / b) ** 2)
    A, B, C = I0 * I2, kGh * I2 * k2 + I0 * D * k2 + I0 * kGh, kGh * D * k2**2
    return np.sqrt(2 * C / (B + np.sqrt(B * B - 4 * A * C)))


def distorted_ss_square(a, h, n, distortion, seed=6):
    """An n x n SS square plate whose interior nodes are moved at random by up to `distortion`
    element sizes in x and y; the boundary nodes (and so the SS-1 dofs) are those of the Plate."""
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E_ST, NU_ST, RHO_ST), h, 0.0)])
    plate = dfx.Plate(a, a, lam, n, n)
    nodes = plate.model.nodes.copy()
    inner = (nodes[:, 0] > 0) & (nodes[:, 0] < a) & (nodes[:, 1] > 0) & (nodes[:, 1] < a)
    rng = np.random.default_rng(seed)
    nodes[inner, :2] += distortion * (a / n) * rng.uniform(-1, 1, (inner.sum(), 2))
    return dfx.ShellModel(nodes, plate.model.quads, lam), plate.fixed_dofs("SSSS")


@pytest.mark.parametrize("distortion", [0.0, 0.25])
def test_no_shear_locking_up_to_a_over_h_1e4_on_regular_and_distorted_meshes(distortion):
    # SS square steel plate, 32 x 32 MITC4 elements, regular and with interior nodes moved by up to
    # 1/4 element (locking shows first on distorted meshes). Modes (1,1), (1,2), (2,1), (2,2) within
    # 1 % of the Mindlin closed form at a/h = 1e2, 1e3, 1e4 (measured <= 0.75 %). A locking element
    # stiffens as (a/h)^2; here the relative error must not depend on a/h: the same at 1e4 as at
    # 1e2 within 0.05 percentage points. At a/h >= 1e3 Mindlin is Kirchhoff (Leissa 1969 Eq. 4.19)
    # to 1.5e-5 (rotary inertia and shear, ~ (pi h/a)^2 (m^2 + n^2)/2 x 0.37).
    a, modes = 1.0, [(1, 1), (1, 2), (2, 1), (2, 2)]
    errors = {}
    for a_over_h in (1e2, 1e3, 1e4):
        h = a / a_over_h
        model, fixed = distorted_ss_square(a, h, 32, distortion)
        f, _ = model.modes(4, fixed)
        ref = np.sort([mindlin_ss_omega(E_ST, NU_ST, RHO_ST, h, a, a, m, n) for m, n in modes])
        errors[a_over_h] = 2 * np.pi * f / ref - 1
        assert np.all(np.abs(errors[a_over_h]) < 0.01), (a_over_h, errors[a_over_h])
        if a_over_h >= 1e3:
            D = E_ST * h**3 / (12 * (1 - NU_ST**2))
            kirchhoff = np.sort([ss_plate_frequency_kirchhoff(D, RHO_ST * h, a, a, m, n) for m, n in modes])
            np.testing.assert_allclose(ref, kirchhoff, rtol=3e-5)
    np.testing.assert_allclose(errors[1e4], errors[1e2], atol=5e-4)


@pytest.mark.parametrize("a_over_h", [1e3, 1e4])
def test_cross_ply_thin_limit_holds_up_to_a_over_h_1e4(a_over_h):
    # [0/90/90/0], E1/E2 = 40, G13 = 0.6 E2 (strongly shear-flexible plies, Reddy 2004 Table 7.3.3),
    # SS-1 on 24 x 24: the fundamental within 1 % of the CLPT closed form (Reddy 2004 Eq. 6.3.31),
    # the thin limit (test_plate_modal covers a/h = 10 and 100).
    E2, a = 1e9, 1.0
    ply = dfx.Orthotropic(E1=40 * E2, E2=E2, G12=0.6 * E2, G13=0.6 * E2, G23=0.5 * E2, nu12=0.25, rho=1.0)
    h = a / a_over_h
    lam = dfx.Laminate.from_angles(ply, h / 4, [0, 90, 90, 0])
    f = dfx.Plate(a, a, lam, 24, 24).natural_frequencies(1, "SSSS")[0]
    assert 2 * np.pi * f == pytest.approx(cross_ply_clpt_omega(lam.D, lam.mass_per_area, a, a), rel=0.01)


def test_cantilever_frequencies_do_not_depend_on_thickness_in_the_thin_limit():
    # CFFF square (the appendage's boundary), 16 x 16: lambda = omega a^2 sqrt(rho h / D) is the same
    # at a/h = 1e4 as at 1e3 to 1e-4 (a locking element would stiffen 100x more at 1e4), and
    # within -2 % .. +0.5 % of Leissa (1969) Table 4.60: 3.492, 8.525, 21.43, 27.33, 31.11
    # (test_plate_modal: a/h = 1000).
    lam_by_ratio = {}
    for a_over_h in (1e3, 1e4):
        h = 1.0 / a_over_h
        lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(E_ST, NU_ST, RHO_ST), h, 0.0)])
        D = E_ST * h**3 / (12 * (1 - NU_ST**2))
        f = dfx.Plate(1.0, 1.0, lam, 16, 16).natural_frequencies(5, "CFFF")
        lam_by_ratio[a_over_h] = 2 * np.pi * f * np.sqrt(RHO_ST * h / D)
    np.testing.assert_allclose(lam_by_ratio[1e4], lam_by_ratio[1e3], rtol=1e-4)
    rel = lam_by_ratio[1e4] / np.array([3.492, 8.525, 21.43, 27.33, 31.11]) - 1
    assert np.all(rel < 0.005) and np.all(rel > -0.02), rel


# ------------------------------------------------------------------------------------------------
# 4. Spin-up far above the first bending frequency (test_spin_up_beam covers 2 and 4 rad/s)

BEAM = scenes.SPIN_UP_BEAM
OMEGA_1 = 1.8751040687**2 * np.sqrt(BEAM["EI"] / (BEAM["rhoA"] * BEAM["L"] ** 4))  # 3.80 rad/s
SOUTHWELL_1 = 1.1933  # uniform cantilever, zero hub radius (Southwell & Gough 1921; Wright et al. 1982)


def hub_rate(t, omega_s, t_s=15.0):
    """Kane, Ryan & Banerjee (1987): Omega(t) and Omega'(t) during spin-up."""
    return ((omega_s / t_s) * (t - t_s / (2 * np.pi) * np.sin(2 * np.pi * t / t_s)),
            (omega_s / t_s) * (1 - np.cos(2 * np.pi * t / t_s)))


@pytest.mark.parametrize("omega_s", [10.0, 20.0])
def test_nonlinear_spin_up_far_above_the_first_frequency_stays_bounded(omega_s):
    # omega_s = 2.6 and 5.3 omega_1. (a) The ramp (15 s) is slow against the first period (1.65 s),
    # so the tip lags quasi-statically: the hub's angular acceleration loads the beam with
    # rho A Omega' x, whose static tip deflection is 11 rho A Omega' L^5 / (120 EI) (Roark, linearly
    # varying load), reduced by the in-plane (lead-lag) stiffening of the first mode,
    # omega^2 = omega_1^2 + (S_1 - 1) Omega^2 (centrifugal S_1 Omega^2 minus the -Omega^2 M
    # softening). Peak within 5 % and 0.3 s of the maximum of this estimate (measured +1.5 %,
    # +2.2 % at 13 % of L). (b) After spin-up the beam rotates steadily: the axial tip stretch of a
    # rotating bar, E A u'' + rho A Omega^2 (x + u) = 0, u(0) = u'(L) = 0: u(L) = tan(kL)/k - L,
    # k = Omega sqrt(rho A / EA), within 0.5 % (measured -0.1 %), and the transverse tip within
    # 2 % of the peak.
    scene = scenes.spin_up_beam(omega_s, model="nonlinear")
    shell = scene.model.shells[0]
    tip_nodes = np.flatnonzero(np.isclose(shell.nodes[:, 0], BEAM["L"]))  # the free end's two nodes
    assert len(tip_nodes) == 2
    r = scene.model.simulate(20.0, 0.01, scheme=GeneralizedAlpha(0.9), nodes={0: tip_nodes})
    assert finite(r)
    nodes = r.node_displacements_0
    tip, axial = -nodes[:, :, 2].mean(axis=1), nodes[:, :, 0].mean(axis=1)
    L, EI, rhoA, EA = BEAM["L"], BEAM["EI"], BEAM["rhoA"], BEAM["EA"]
    t = np.linspace(0.0, 15.0, 15001)
    Om, dOm = hub_rate(t, omega_s)
    quasi_static = 11 * rhoA * dOm * L**5 / (120 * EI) * OMEGA_1**2 / (OMEGA_1**2 + (SOUTHWELL_1 - 1) * Om**2)
    k, j = int(np.argmax(np.abs(tip))), int(np.argmax(quasi_static))
    assert tip[k] < 0  # the tip lags
    assert abs(tip[k]) == pytest.approx(quasi_static[j], rel=0.05)
    assert r.t[k] == pytest.approx(t[j], abs=0.3)
    steady = r.t > 15.0
    kk = omega_s * np.sqrt(rhoA / EA)
    assert axial[steady].mean() == pytest.approx(np.tan(kk * L) / kk - L, rel=5e-3)
    assert np.abs(tip[steady]).max() < 0.02 * abs(tip[k])


@pytest.mark.parametrize("omega_s", [10.0, 20.0])
def test_linear_spin_up_far_above_the_first_frequency_reports_divergence(omega_s):
    # The conventional linear model (K - Omega^2 M) loses its first mode's stiffness at
    # Omega = omega_1: the run must stop with "diverged", finite partial series, near that hub rate.
    # The softened quasi-static tip 11 rho A Omega' L^5/(120 EI) / (1 - Omega^2/omega_1^2) reaches
    # the L/2 limit only at Omega = 0.90 omega_1 (10 rad/s) and 0.85 omega_1 (20 rad/s), and past
    # omega_1 the response grows as exp(sqrt(Omega^2 - omega_1^2) t): accepted Omega in
    # [0.85, 1.15] omega_1 (measured 1.04 and 1.02, 0.1 s after Omega = omega_1).
    with pytest.raises(SimulationError, match="diverged") as info:
        scenes.spin_up_beam(omega_s, model="linear").simulate(20.0, 0.01)
    partial = info.value.result
    hub_rate = np.radians(partial.deployment_rate[:, 0])  # the driven hinge's rate, rad/s
    assert np.all(np.isfinite(partial.tip_deflection)) and np.all(np.isfinite(hub_rate))
    assert 0.85 * OMEGA_1 < hub_rate[-1] < 1.15 * OMEGA_1
    assert partial.t[-1] < 15.0


# ------------------------------------------------------------------------------------------------
# 5. Body/appendage mass ratio from 1e-2 to 1e6

@pytest.mark.parametrize("ratio", [1e-2, 1e-1, 1.0, 1e2, 1e4, 1e6], ids=lambda x: f"ratio{x:.0e}")
def test_mass_ratio_range_against_the_two_body_closed_form(ratio):
    # Base mass m_B = ratio x the panel's 8.32 kg, inertia scaled with the paper body's radius of
    # gyration (500/3000 m^2), no yoke; rigid panel, the paper's lock and scheme, dt = 1/400 of the
    # time to the stop. Against the exact reduction above:
    # - total angular and linear momentum at round-off: 1e-10 of the base's peak (measured 1e-13);
    # - the first lock time within 2e-5 relative of the energy quadrature (measured 3e-6);
    # - the base's counter-rotation phi(theta) = -int a/b within 1e-5 of its peak (measured 8e-7),
    #   from 1.2 rad at ratio 0.1 to 2e-5 rad at 1e6.
    m_B = ratio * RHO * THICK * LENGTH * WIDTH
    kw = dict(body_mass=m_B, body_inertia=m_B * PAPER.body_inertia / PAPER.body_mass, yoke_mass=0.0,
              yoke_inertia=(0.0, 0.0, 0.0))
    tb = TwoBody(**kw)
    t_ref = tb.time_to(THETA_LOCK)
    r = simulate(rigid_scene(**kw), 1.01 * t_ref, t_ref / 400)
    assert finite(r)
    H = np.linalg.norm(r.total_angular_momentum, axis=1).max()
    P = np.linalg.norm(r.total_linear_momentum, axis=1).max()
    assert H < 1e-10 * np.linalg.norm(r.body_angular_momentum, axis=1).max()
    assert P < 1e-10 * np.linalg.norm(r.body_linear_momentum, axis=1).max()
    assert r.summary()["first_lock_time_s"] == pytest.approx(t_ref, rel=2e-5)
    before = r.lock_force == 0
    theta = np.radians(r.deployment_angle[before] - 90.0)
    phi = np.radians(r.body_attitude[before, 1])
    phi_ref = np.array([tb.base_angle(th) for th in theta])
    assert np.abs(phi - phi_ref).max() < 1e-5 * np.abs(phi_ref).max()
    assert phi_ref[-1] < 0 < theta[-1]  # counter-rotation


def test_heavy_base_tends_to_the_fixed_base_closed_form():
    # Fixed base: theta'' = (tau0 - k theta) / J_hinge, so theta = theta0 (1 - cos w t) and the stop
    # (theta0 = theta_lock) is reached at t = (pi/2) sqrt(J_hinge / k). A free base of 1e6 x the
    # panel's mass reaches it within 2e-5 of that (the free-base correction a^2/b ~ 1e-5 J_hinge,
    # measured -6e-6); a fixed-base run within 1e-5. At 1e4 the difference is 7.5e-4, 100x larger.
    tb = TwoBody()
    t_fixed = np.pi / 2 * np.sqrt(tb.J_hinge / tb.k)
    fixed = simulate(rigid_scene(base_free=False), 2.52, t_fixed / 400)
    assert fixed.summary()["first_lock_time_s"] == pytest.approx(t_fixed, rel=1e-5)
    times = {}
    for ratio in (1e4, 1e6):
        m_B = ratio * tb.m_A
        kw = dict(body_mass=m_B, body_inertia=m_B / 6, yoke_mass=0.0, yoke_inertia=(0.0, 0.0, 0.0))
        times[ratio] = simulate(rigid_scene(**kw), 2.52, t_fixed / 400).summary()["first_lock_time_s"]
    assert times[1e6] == pytest.approx(t_fixed, rel=2e-5)
    assert abs(times[1e4] / t_fixed - 1) > 30 * abs(times[1e6] / t_fixed - 1)


# ------------------------------------------------------------------------------------------------
# 6. 1000 s undamped with rho_inf = 1

def test_1000_s_undamped_conserves_energy_and_momentum():
    # Rigid panel on the paper's free base, no lock: the spring swings it between 90 and 270 deg
    # (theta0 = pi/2), 102 periods in 1000 s; generalized-alpha with rho_inf = 1, dt = 0.01 s.
    # - Energy: |E(t) - E(0)| below 1e-6 of the peak kinetic energy (issue 6; measured 9.2e-7:
    #   a 3e-7 O(dt^2) oscillation plus a drift of the Newton residual, about 7e-12 per step, so
    #   smaller steps do not help over 1000 s).
    # - Momentum at round-off: 1e-12 of the base's peak (measured 6e-14 and 4e-14).
    # - Phase: the mean period within 1e-5 of the closed-form quadrature 9.8042 s (the trapezoidal
    #   rule lengthens it by (w h)^2/12 = 3.4e-6, Hughes 1987 Sec. 9.3).
    model = rigid_scene(lock=False).model
    r = model.simulate(1000.0, 0.01, scheme=GeneralizedAlpha(1.0))
    assert finite(r)
    E = r.kinetic_energy + r.potential_energy
    assert np.abs(E - E[0]).max() < 1e-6 * r.kinetic_energy.max()
    Hb = np.linalg.norm(r.body_angular_momentum, axis=1).max()
    Pb = np.linalg.norm(r.body_linear_momentum, axis=1).max()
    assert np.linalg.norm(r.total_angular_momentum, axis=1).max() < 1e-12 * Hb
    assert np.linalg.norm(r.total_linear_momentum, axis=1).max() < 1e-12 * Pb
    theta = r.q[:, model.layout(0)["iq_theta"]]  # rad, the hinge travel
    x = theta - PAPER_2BODY.theta0
    s = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    tc = r.t[s] - x[s] * (r.t[s + 1] - r.t[s]) / (x[s + 1] - x[s])
    assert len(tc) > 100
    assert (tc[-1] - tc[0]) / (len(tc) - 1) == pytest.approx(PAPER_2BODY.period(), rel=1e-5)
    assert theta.max() == pytest.approx(2 * PAPER_2BODY.theta0, abs=1e-5)  # turning point: 270 deg


# ------------------------------------------------------------------------------------------------
# 7. The undamped reduced-nonlinear paper scene, 30 s at the paper's step (issue 29)

@pytest.mark.parametrize("mesh", [(2, 1), (6, 4)], ids=lambda m: f"{m[0]}x{m[1]}")
def test_undamped_reduced_nonlinear_scene_runs_30_s(mesh):
    # The paper's equations without structural damping, the stop-and-latch lock (no ride friction
    # to damp the start), the default scheme (generalized-alpha, rho_inf = 0.8) at dt = 0.01 s.
    # Before the consistent predictor (GeneralizedAlpha::relax_slaved) both meshes diverged
    # before the lock: 2 x 1 at 0.235 s, 6 x 4 at 0.16 s (Newton landed on another root of the
    # step equation, docs/research/undamped-stability.md). Now:
    # - the run completes (no energy growth reported, no Newton failure);
    # - the total energy never rises above its start by more than 2e-4 of the peak kinetic energy
    #   (measured 4.1e-5 on 2 x 1 and 6.8e-6 on 6 x 4, both in the first 0.03 s, never after a
    #   contact; 5.9e-4 in the taps after the lock while the steps after a contact jumped back to
    #   dt, issue 29; the API's divergence limit is 0.1): nothing in the scene adds energy;
    # - momentum at round-off (1e-11 of the base's peak, as for every run above);
    # - the first lock within the undamped ripple's band about the full model's 2.466 s (its
    #   10 mrad hinge-angle ripple at 1.09 rad/s: +-18 ms, measured 2.481 and 2.458 s).
    nx, ny = mesh
    r = stop_latch_paper(2, "reduced-nonlinear", nx=nx, ny=ny, damping=(0.0, 0.0)).simulate(30.0, 0.01)
    assert finite(r) and r.t[-1] == pytest.approx(30.0, abs=1e-12)
    E = r.kinetic_energy + r.potential_energy
    assert (E - E[0]).max() <= 2e-4 * r.kinetic_energy.max()
    summary = r.summary()
    assert summary["momentum_drift"] < 1e-11
    assert summary["first_lock_time_s"][0] == pytest.approx(2.466, abs=0.025)


@pytest.mark.parametrize("preload_change", [1.255e-10, -1.165e-6], ids=["+1.3e-10", "-1.2e-6"])
def test_undamped_rattle_on_the_walls_adds_no_energy(preload_change):
    # The undamped 6 x 4 scene's rattle in the lock's play, on trajectories a relative change of
    # the spring preload tau0 picks (issue 29; docs/research/undamped-stability.md). Before, 12
    # of 120 such changes (1e-12..1e-4) diverged after the lock, these two at 17.5 s and 18.0 s:
    # (1) the walls were stepped over at dt when the law's dashpot stops the pin alone
    #     (m/D = 22 us), while the panel behind it rebounds on the wall's Hertz stiffness at
    #     omega h = 1.5-3, which pumped energy into the panel within 0.3 s of resting contact;
    #     the engine now resolves that rebound on the time scale of the hinge's inertia with the
    #     panel held rigid (then 2 of 120 diverged, this second one at 7.49 s);
    # (2) after a resolved contact the next step jumped back to dt and amplified the contact's
    #     accelerations carried in the scheme's history by h^2 (0.5 - beta); the contact's error
    #     bound now lets the steps grow back (0 of 180 diverge).
    # Test: 30 s at the default step and scheme, no energy above the start beyond 2e-4 of the peak
    # kinetic energy (measured 6.8e-6 for both, in the first 0.03 s).
    tau0 = scenes.Paper2016Parameters().tau0
    scene = stop_latch_paper(2, "reduced-nonlinear", nx=6, ny=4, damping=(0.0, 0.0),
                             tau0=tau0 * (1 + preload_change))
    r = scene.simulate(30.0, 0.01, progress=False)
    assert r.t[-1] == pytest.approx(30.0, abs=1e-12)
    E = r.kinetic_energy + r.potential_energy
    assert (E - E[0]).max() <= 2e-4 * r.kinetic_energy.max()
    assert r.metadata["contact_steps"] > 0


def test_undamped_reduced_nonlinear_default_basis_is_not_chaotic():
    # Why the undamped first lock now converges in dt (issue 29; the sequence is in
    # docs/research/undamped-stability.md, 2026-11-26): a mode bent together with the first
    # stretches the mid-surface by q(phi_1, phi_j), which only their modal derivative relaxes.
    # Session 17's basis (derivatives of the pairs among the first 6 modes, none of mode 1 with
    # modes 7-10 or the static corrections) stiffened those modes 6.8x with mode 1's amplitude and
    # made the undamped model chaotic; the default basis carries mode 1's partners. Test: a
    # relative change of 1e-9 in the spring preload tau0 moves the hinge angle (dt = 1 ms, up to
    # 2.4 s, before the lock) by an amount that grows linearly with time for the default basis
    # (measured 1.0e-10 rad in the first 0.4 s, 1.6e-9 in the last), and by orders of magnitude
    # more for session 17's (measured 2.9e-7 in the last window: exponential growth).
    tau0 = scenes.Paper2016Parameters().tau0

    def windows(**basis):
        angle = []
        for f in (1.0, 1.0 + 1e-9):
            r = stop_latch_paper(2, "reduced-nonlinear", nx=6, ny=4, damping=(0.0, 0.0), tau0=tau0 * f,
                                 **basis).simulate(2.4, 0.001, progress=False)
            angle.append(np.radians(r.deployment_angle[:, 0]))
        d = np.abs(angle[1] - angle[0])
        return [d[(r.t >= lo) & (r.t < lo + 0.4)].max() for lo in np.arange(0.0, 2.4, 0.4)]

    default = windows()
    assert default[-1] <= 5e-9 and default[-1] <= 25 * default[0], default  # linear: 16x over 6 windows
    session_17 = windows(derivative_modes=6, derivative_partners=0)
    assert session_17[-1] >= 30 * default[-1], (session_17, default)
