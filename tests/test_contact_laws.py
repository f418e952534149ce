"""The hinge lock's contact laws (deployfx.contact) against closed forms and an independent
integrator.

References: docs/research/engine-references.md Sec. 4 (the exact Hunt-Crossley restitution,
Carvalho & Martins 2019, and its table of effective restitutions); Hertz impact (Johnson,
"Contact Mechanics", 1985, Sec. 11.4); the linear spring-dashpot, derived below; scipy's DOP853
as a second integrator. The 1-DOF impact runs in C++ (RK4, events located to round-off); its
error at the default step is ~1e-11, so the tolerances below are set by the references.
"""
import numpy as np
import pytest
from scipy.integrate import solve_ivp, trapezoid
from scipy.special import beta, lambertw

from deployfx.contact import ContactLaw, Friction, impact, impact_time_scale

# c in F = K delta^n (1 + c delta_dot / v0), as the original papers define it.
HYSTERESIS = {
    "hunt-crossley": lambda e: 1.5 * (1 - e),          # Hunt & Crossley 1975
    "lankarani-nikravesh": lambda e: 0.75 * (1 - e * e),  # Lankarani & Nikravesh 1990
    "flores": lambda e: 1.6 * (1 - e) / e,             # Flores et al. 2011: 8 (1 - e) / (5 e)
}


def exact_restitution(x):
    """Restitution of m delta'' = -K delta^n (1 + x delta' / v0): the root in (0, 1) of
    x - ln(1 + x) = -e x - ln(1 - e x), i.e. e = [1 + W0(-(1 + x) exp(-(1 + x)))] / x
    (engine-references.md Sec. 4), independent of K, m, n and v0."""
    return float((1 + lambertw(-(1 + x) * np.exp(-(1 + x)), 0).real) / x)


def energy(law, m, delta, delta_dot):
    """Kinetic plus elastic energy (J): m v^2 / 2 + K delta^(n+1) / (n+1)."""
    return 0.5 * m * delta_dot**2 + law.K * np.clip(delta, 0, None) ** (law.n + 1) / (law.n + 1)


# ---------------------------------------------------------------- Hunt-Crossley family


@pytest.mark.parametrize("kind", sorted(HYSTERESIS))
@pytest.mark.parametrize("e", [0.99, 0.9, 0.7, 0.5, 0.3, 0.1])
def test_hunt_crossley_family_restitution_is_the_exact_one(kind, e):
    # The simulated restitution equals the exact relation's root for the law's x = c, to 1e-8
    # (observed ~3e-12). The reference satisfies the relation to 1e-11 in e: residual / slope,
    # with slope d(rhs)/de = x (e x) / (1 - e x).
    law = ContactLaw(kind, K=1e9, e=e)
    x = HYSTERESIS[kind](e)
    assert law.hysteresis_factor == pytest.approx(x, rel=1e-15)
    e_exact = exact_restitution(x)
    residual = (x - np.log1p(x)) - (-e_exact * x - np.log1p(-e_exact * x))
    assert abs(residual) <= 1e-11 * x * (e_exact * x) / (1 - e_exact * x)
    assert impact(law, 2.0, 0.5).restitution == pytest.approx(e_exact, abs=1e-8)


@pytest.mark.parametrize("kind, table", [
    ("lankarani-nikravesh", {0.9: 0.913, 0.7: 0.796, 0.5: 0.725, 0.3: 0.684, 0.1: 0.665}),
    ("flores", {0.9: 0.894, 0.7: 0.683, 0.5: 0.470, 0.3: 0.256, 0.1: 0.069}),
])
def test_effective_restitution_table_of_the_research_notes(kind, table):
    # engine-references.md Sec. 4, "Effective e each law actually produces" (3 decimals, so
    # 5e-4): Lankarani-Nikravesh never gets below ~0.66; Flores stays close to its target.
    for e, e_eff in table.items():
        r = impact(ContactLaw(kind, K=1e9, e=e), 1.0, 1.0)
        assert r.restitution == pytest.approx(e_eff, abs=5e-4)


@pytest.mark.parametrize("kind", sorted(HYSTERESIS))
def test_hunt_crossley_restitution_independent_of_stiffness_mass_speed_exponent(kind):
    # The exact relation has no K, m, v0 or n in it: each varied by orders of magnitude about
    # K = 1e8 N/m^n, m = 1 kg, v0 = 1 m/s, n = 1.5 gives the same restitution to 1e-8.
    e_exact = exact_restitution(HYSTERESIS[kind](0.6))
    base = {"K": 1e8, "m": 1.0, "v0": 1.0, "n": 1.5}
    variations = [{"K": 1e4}, {"K": 1e12}, {"m": 1e-3}, {"m": 1e3}, {"v0": 1e-3}, {"v0": 100.0},
                  {"n": 1.0}, {"n": 2.5}]
    for change in variations:
        p = {**base, **change}
        r = impact(ContactLaw(kind, K=p["K"], n=p["n"], e=0.6), p["m"], p["v0"])
        assert r.restitution == pytest.approx(e_exact, abs=1e-8), change


@pytest.mark.parametrize("kind, e", [("hunt-crossley", 0.8), ("lankarani-nikravesh", 0.4),
                                     ("flores", 0.2)])
def test_hunt_crossley_maximum_penetration(kind, e):
    # Energy balance over compression (engine-references.md Sec. 4):
    # K delta_max^(n+1) / (n+1) = m v0^2 (x - ln(1 + x)) / x^2, to 1e-8 relative.
    K, n, m, v0 = 3e7, 1.5, 0.7, 0.3
    x = HYSTERESIS[kind](e)
    delta_max = ((n + 1) * m * v0**2 * (x - np.log1p(x)) / (K * x**2)) ** (1 / (n + 1))
    r = impact(ContactLaw(kind, K=K, n=n, e=e), m, v0)
    assert r.max_penetration == pytest.approx(delta_max, rel=1e-8)


# ---------------------------------------------------------------- Hertz and Kelvin-Voigt


@pytest.mark.parametrize("law", [ContactLaw("paper", K=2e9),
                                 ContactLaw("hunt-crossley", K=2e9, e=1.0),
                                 ContactLaw("kelvin-voigt-hertz", K=5e5, n=1.0)])
@pytest.mark.parametrize("v0", [0.01, 1.0, 10.0])
def test_undamped_hertz_impact(law, v0):
    # Elastic impact (Johnson 1985, Sec. 11.4): e = 1, delta_max = ((n+1) m v0^2 / (2K))^(1/(n+1)),
    # t_c = 2 delta_max / v0 * B(1/(n+1), 1/2) / (n+1) (2.9432 delta_max / v0 for n = 3/2),
    # F_max = K delta_max^n. To 1e-8.
    m, n = 3.0, law.n
    r = impact(law, m, v0)
    delta_max = ((n + 1) * m * v0**2 / (2 * law.K)) ** (1 / (n + 1))
    assert r.restitution == pytest.approx(1.0, abs=1e-8)
    assert r.max_penetration == pytest.approx(delta_max, rel=1e-8)
    t_c = 2 * delta_max / v0 * beta(1 / (n + 1), 0.5) / (n + 1)
    assert r.contact_duration == pytest.approx(t_c, rel=1e-8)
    assert r.peak_force == pytest.approx(law.K * delta_max**n, rel=1e-8)
    assert r.energy_lost == pytest.approx(0.0, abs=1e-8 * 0.5 * m * v0**2)


def _g(zeta):
    # g(zeta) = arccos(zeta) / sqrt(1 - zeta^2), continued analytically through zeta = 1.
    if zeta < 1:
        return np.arccos(zeta) / np.sqrt(1 - zeta**2)
    return 1.0 if zeta == 1 else np.arccosh(zeta) / np.sqrt(zeta**2 - 1)


@pytest.mark.parametrize("zeta", [0.0, 0.05, 0.3, 0.7, 1.0, 2.0, 5.0])
def test_linear_spring_dashpot_separating_at_zero_force(zeta):
    # F = k x + c x' (n = 1), omega = sqrt(k/m), zeta = c / (2 sqrt(k m)), x(0) = 0, x'(0) = v0.
    # For zeta < 1, x = (v0/omega_d) exp(-zeta omega t) sin(omega_d t), and with zeta = cos(psi),
    # F = -m x'' is proportional to -sin(omega_d t - 2 psi): the force returns to 0 at
    # omega_d t* = 2 psi, before x returns to 0. There x' = -v0 exp(-zeta omega t*), so
    #   e = exp(-2 zeta g(zeta)),  t* = 2 g(zeta) / omega,  g = arccos(zeta) / sqrt(1 - zeta^2)
    # (zeta >= 1 by continuation: g = arccosh(zeta) / sqrt(zeta^2 - 1)); the turning point is
    # at half that time, x_max = (v0/omega) sqrt(e), and F = 0 leaves the mass at
    # x = 2 zeta e v0/omega.
    # (Separating at x = 0 instead gives exp(-zeta pi / sqrt(1 - zeta^2)), engine-references.md.)
    # To 1e-9 relative.
    m, k, v0 = 2.0, 4e6, 0.5
    omega = np.sqrt(k / m)
    law = ContactLaw("kelvin-voigt-hertz", K=k, n=1.0, D=2 * zeta * np.sqrt(k * m))
    r = impact(law, m, v0, record=True)
    e = np.exp(-2 * zeta * _g(zeta))
    assert r.restitution == pytest.approx(e, rel=1e-9)
    assert r.contact_duration == pytest.approx(2 * _g(zeta) / omega, rel=1e-9)
    assert r.max_penetration == pytest.approx(v0 / omega * np.sqrt(e), rel=1e-9)
    assert r.delta[-1] == pytest.approx(2 * zeta * e * v0 / omega, rel=1e-9, abs=1e-12 * v0 / omega)
    if 0 < zeta < 1:
        assert r.restitution > np.exp(-zeta * np.pi / np.sqrt(1 - zeta**2))


def _solve_ivp_impact(K, n, D, m, v0):
    """The same impact with scipy's DOP853 (rtol 1e-13) and its own event location."""
    def force(y):
        return K * max(y[0], 0.0) ** n + D * y[1]

    def rhs(t, y):
        return [y[1], -max(force(y), 0.0) / m]

    def released(t, y):  # F back to 0
        return force(y)

    def turning(t, y):  # delta' = 0
        return y[1]

    def force_peak(t, y):  # dF/dt = n K delta^(n-1) delta' + D delta''
        return n * K * max(y[0], 0.0) ** (n - 1) * y[1] - D * max(force(y), 0.0) / m

    released.terminal, released.direction = True, -1
    turning.direction = force_peak.direction = -1
    T = impact_time_scale(ContactLaw("paper", K=K, n=n, D=D), m, v0)
    s = solve_ivp(rhs, [0, 1e3 * T], [0.0, v0], method="DOP853", rtol=1e-13,
                  atol=[1e-13 * v0 * T, 1e-13 * v0], events=[released, turning, force_peak])
    peak = max(force(y) for y in s.y_events[2]) if len(s.t_events[2]) else D * v0
    return -s.y_events[0][0][1] / v0, s.t_events[0][0], s.y_events[1][0][0], max(peak, D * v0)


def test_kelvin_voigt_hertz_against_solve_ivp():
    # The paper's law F = K delta^1.5 + D delta_dot has no closed-form restitution; DOP853 at
    # rtol 1e-13 is the reference: restitution, duration, penetration and peak force to 1e-8.
    # The restitution depends on v0 (engine-references.md Sec. 4): a faster impact sees a
    # stiffer contact (dF/ddelta ~ delta^0.5), so relatively less damping and a larger e.
    K, n, D, m = 1e9, 1.5, 2e3, 1.0
    law = ContactLaw("paper", K=K, n=n, D=D)
    restitutions = []
    for v0 in (0.01, 0.1, 1.0):
        e_ref, t_ref, x_ref, F_ref = _solve_ivp_impact(K, n, D, m, v0)
        r = impact(law, m, v0)
        assert r.restitution == pytest.approx(e_ref, rel=1e-8)
        assert r.contact_duration == pytest.approx(t_ref, rel=1e-8)
        assert r.max_penetration == pytest.approx(x_ref, rel=1e-8)
        assert r.peak_force == pytest.approx(F_ref, rel=1e-8)
        restitutions.append(r.restitution)
    assert restitutions[0] < restitutions[1] - 0.05 and restitutions[1] < restitutions[2] - 0.05


@pytest.mark.parametrize("law", [ContactLaw("paper", K=1e9, D=2e3),
                                 ContactLaw("flores", K=1e9, e=0.4),
                                 ContactLaw("hunt-crossley", K=1e7, n=1.0, e=0.7)])
def test_energy_never_increases_and_balances_the_dissipation(law):
    # E = m v^2/2 + K delta^(n+1)/(n+1) only decreases (each step, to 1e-12 E0); what it loses is
    # the work of the damping part of the force, integral of (F - K delta^n) delta' dt
    # (trapezoid rule, 1e-6); the mass loses at least that (Kelvin-Voigt also leaves the elastic
    # energy of delta > 0 at separation behind).
    m, v0 = 1.0, 0.5
    r = impact(law, m, v0, record=True)
    E = energy(law, m, r.delta, r.delta_dot)
    assert E[0] == pytest.approx(0.5 * m * v0**2, rel=1e-15)
    assert np.diff(E).max() <= 1e-12 * E[0]
    damping_power = (r.force - law.K * r.delta**law.n) * r.delta_dot
    assert damping_power.min() >= -1e-9 * law.K * r.max_penetration**law.n * v0
    assert E[0] - E[-1] == pytest.approx(trapezoid(damping_power, r.t), rel=1e-6)
    assert r.energy_lost >= (E[0] - E[-1]) * (1 - 1e-9)
    assert r.energy_lost == pytest.approx(0.5 * m * v0**2 * (1 - r.restitution**2), rel=1e-12)


# ---------------------------------------------------------------- the force function


def _reference_force(kind, K, n, D, e, delta, delta_dot, v0):
    """The four laws as written in the papers, clamped at 0 (numpy, independent of the C++)."""
    p = K * np.clip(delta, 0, None) ** n
    if kind == "kelvin-voigt-hertz":
        F = p + D * delta_dot
    else:
        F = p * (1 + HYSTERESIS[kind](e) * delta_dot / v0)
    return np.where(delta > 0, np.maximum(F, 0.0), 0.0)


LAWS = [("kelvin-voigt-hertz", {"K": 1e9, "n": 1.5, "D": 5e3}),
        ("hunt-crossley", {"K": 1e9, "e": 0.5}),
        ("lankarani-nikravesh", {"K": 2e8, "n": 1.0, "e": 0.3}),
        ("flores", {"K": 1e9, "n": 2.0, "e": 0.2})]


@pytest.mark.parametrize("kind, p", LAWS)
def test_force_never_pulls_and_is_the_published_law(kind, p):
    # On a grid through compression, restitution and the clamp (delta in +-1 mm, delta_dot in
    # +-5 m/s, v0 in 0.1..3 m/s): F >= 0, equal to the published formula clamped at 0 (1e-13
    # relative), derivatives exactly 0 where clamped; arrays broadcast, scalars give floats.
    law = ContactLaw(kind, **p)
    delta, delta_dot, v0 = np.meshgrid(np.linspace(-1e-3, 1e-3, 41), np.linspace(-5, 5, 41),
                                       [0.1, 1.0, 3.0], indexing="ij")
    F, dF_dd, dF_dv = law.force(delta, delta_dot, v0)
    assert F.shape == dF_dd.shape == dF_dv.shape == delta.shape
    ref = _reference_force(kind, law.K, law.n, law.D, law.e, delta, delta_dot, v0)
    np.testing.assert_allclose(F, ref, rtol=1e-13, atol=0)
    assert F.min() >= 0 and (F == 0).any() and (F > 0).any()
    assert not dF_dd[F == 0].any() and not dF_dv[F == 0].any()
    single = law.force(5e-4, -0.3, 1.0)
    assert all(isinstance(x, float) for x in single)
    ref_single = _reference_force(kind, law.K, law.n, law.D, law.e, 5e-4, -0.3, 1.0)
    assert single[0] == pytest.approx(float(ref_single), rel=1e-13)


@pytest.mark.parametrize("kind, p", LAWS)
def test_force_derivatives_match_central_differences(kind, p):
    # Central differences with relative step 1e-7 at 200 random points in contact, away from the
    # clamp: error O(h^2) + round-off/h, tolerance 1e-6 relative.
    law = ContactLaw(kind, **p)
    rng = np.random.default_rng(1)
    delta = rng.uniform(1e-5, 1e-3, 200)
    delta_dot = rng.uniform(-2, 2, 200)
    v0 = rng.uniform(0.5, 3, 200)
    F, dF_dd, dF_dv = law.force(delta, delta_dot, v0)
    keep = F > 0.05 * law.K * delta**law.n  # well inside the contact
    assert keep.sum() > 100
    h_d, h_v = 1e-7 * delta, 1e-7 * np.maximum(np.abs(delta_dot), 1.0)

    def force(d, dd):
        return law.force(d, dd, v0)[0]

    fd_d = (force(delta + h_d, delta_dot) - force(delta - h_d, delta_dot)) / (2 * h_d)
    fd_v = (force(delta, delta_dot + h_v) - force(delta, delta_dot - h_v)) / (2 * h_v)
    np.testing.assert_allclose(dF_dd[keep], fd_d[keep], rtol=1e-6)
    np.testing.assert_allclose(dF_dv[keep], fd_v[keep], rtol=1e-6, atol=1e-9 * np.abs(dF_dv).max())


@pytest.mark.parametrize("kind, p", LAWS)
def test_no_nan_for_any_finite_input(kind, p):
    # Extreme but finite inputs (1e-300 .. 1e300, v0 down to 1e-300) give finite, non-negative
    # forces: intermediates saturate instead of producing inf - inf or 0 * inf.
    law = ContactLaw(kind, **p)
    vals = np.array([-1e300, -1.0, -1e-300, 0.0, 1e-300, 1e-10, 1.0, 1e300])
    delta, delta_dot, v0 = np.meshgrid(vals, vals, [1e-300, 1e-3, 1.0, 1e300], indexing="ij")
    out = law.force(delta, delta_dot, v0)
    assert all(np.isfinite(o).all() for o in out)
    assert out[0].min() >= 0


# ---------------------------------------------------------------- friction


def test_friction_dissipates_is_bounded_and_odd():
    # F_t v_t <= 0 (never feeds energy), |F_t| <= mu F_n, odd in v_t, |F_t| within 4.2e-9 of
    # mu F_n at |v_t| = 10 v_reg (1 - tanh 10 = 2 e^-20), no friction without normal force,
    # and finite for any finite input.
    fr = Friction(mu=0.3, v_reg=1e-3)
    v = np.concatenate([-np.logspace(-300, 300, 61), [0.0], np.logspace(-300, 300, 61)])
    v_t, F_n = np.meshgrid(v, [-5.0, 0.0, 1e-300, 1.0, 7e4, 1e300], indexing="ij")
    F_t, dF_dv, dF_dN = fr.force(v_t, F_n)
    assert all(np.isfinite(o).all() for o in (F_t, dF_dv, dF_dN))
    assert (np.sign(F_t) * np.sign(v_t) <= 0).all()
    assert (np.abs(F_t) <= 0.3 * np.clip(F_n, 0, None)).all()
    np.testing.assert_array_equal(fr.force(-v_t, F_n)[0], -F_t)
    assert not F_t[F_n <= 0].any() and not dF_dv[F_n <= 0].any()
    assert (dF_dv <= 0).all()
    F_sat = fr.force(np.array([-1e-2, 1e-2]), 100.0)[0]
    np.testing.assert_allclose(np.abs(F_sat), 30.0, rtol=4.2e-9)
    assert fr.force(0.0, 100.0)[1] == pytest.approx(-0.3 * 100.0 / 1e-3, rel=1e-15)


def test_friction_derivatives_match_central_differences():
    # dF_t/dv_t and dF_t/dF_n against central differences (steps 1e-5 v_reg and 1e-7 F_n): 1e-6
    # relative, plus 1e-8 of the largest slope where tanh saturates and round-off dominates.
    fr = Friction(mu=0.25, v_reg=1e-4)
    rng = np.random.default_rng(2)
    v_t = rng.uniform(-5e-4, 5e-4, 200)
    F_n = rng.uniform(1.0, 1e3, 200)
    _, dF_dv, dF_dN = fr.force(v_t, F_n)
    hv, hn = 1e-5 * fr.v_reg, 1e-7 * F_n

    def F_t(v, n):
        return fr.force(v, n)[0]

    np.testing.assert_allclose(dF_dv, (F_t(v_t + hv, F_n) - F_t(v_t - hv, F_n)) / (2 * hv),
                               rtol=1e-6, atol=1e-8 * np.abs(dF_dv).max())
    np.testing.assert_allclose(dF_dN, (F_t(v_t, F_n + hn) - F_t(v_t, F_n - hn)) / (2 * hn),
                               rtol=1e-6, atol=1e-12)


@pytest.mark.parametrize("v_reg", [1e-4, 5e-2])
@pytest.mark.parametrize("v0", [2.0, -2.0])
def test_sliding_block_stops_at_the_coulomb_distance(v_reg, v0):
    # m x'' = F_t(x', m g): with Coulomb's law the block stops after v0^2 / (2 mu g) at
    # t_s = |v0| / (mu g). The regularised law adds integral_0^inf v (coth(v/v_reg) - 1) dv / (mu g)
    # = pi^2 v_reg^2 / (12 mu g) (3e-9 m at v_reg = 1e-4 m/s; 7e-4 m at 5e-2). DOP853 (rtol 1e-12)
    # to t_s + 40 v_reg / (mu g): the speed only decreases and ends below 1e-12 |v0|; the
    # distance matches to 1e-7 relative; Coulomb's alone to 1e-7 (v_reg = 1e-4) and 2e-3 (5e-2).
    m, mu, g = 4.0, 0.3, 9.81
    fr = Friction(mu=mu, v_reg=v_reg)
    t_end = abs(v0) / (mu * g) + 40 * v_reg / (mu * g)
    s = solve_ivp(lambda t, y: [y[1], fr.force(y[1], m * g)[0] / m], [0, t_end], [0.0, v0],
                  method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
    speed = np.abs(s.sol(np.linspace(0, t_end, 2001))[1])
    assert (np.diff(speed) <= 1e-12).all()
    assert speed[-1] < 1e-12 * abs(v0)
    coulomb = v0**2 / (2 * mu * g)
    distance = abs(s.y[0, -1])
    assert distance == pytest.approx(coulomb + np.pi**2 * v_reg**2 / (12 * mu * g), rel=1e-7)
    assert distance == pytest.approx(coulomb, rel=1e-7 if v_reg < 1e-3 else 2e-3)


# ---------------------------------------------------------------- bad input


@pytest.mark.parametrize("make, name", [
    (lambda: ContactLaw("hunt-crossley", K=-1.0, e=0.5), "contact.K"),
    (lambda: ContactLaw("paper", K=1e9, n=0.5), "contact.n"),
    (lambda: ContactLaw("paper", K=1e9, D=-1.0), "contact.D"),
    (lambda: ContactLaw("paper", K=1e9, D=1.0, e=0.5), "contact.e"),
    (lambda: ContactLaw("flores", K=1e9, e=0.0), "contact.e"),
    (lambda: ContactLaw("lankarani-nikravesh", K=1e9, e=1.2), "contact.e"),
    (lambda: ContactLaw("hunt-crossley", K=1e9, e=0.5, D=10.0), "contact.D"),
    (lambda: ContactLaw("hertz", K=1e9), "contact.kind"),
    (lambda: ContactLaw("flores", K=1e9, e=0.5).force(1e-4, 0.1, 0.0), "contact.v0"),
    (lambda: ContactLaw("flores", K=1e9, e=0.5).force(1e-4, 0.1), "v0"),
    (lambda: Friction(mu=-0.1), "friction.mu"),
    (lambda: Friction(mu=0.1, v_reg=0.0), "friction.v_reg"),
    (lambda: impact(ContactLaw("paper", K=1e9), 0.0, 1.0), "mass"),
    (lambda: impact(ContactLaw("paper", K=1e9), 1.0, -1.0), "v0"),
    (lambda: impact(ContactLaw("paper", K=1e9), 1.0, 1.0, dt_s=-1e-6), "dt"),
    (lambda: impact(ContactLaw("paper", K=1e9), 1.0, 1.0, dt_s=1e-3), "dt"),
])
def test_bad_input_raises_value_error_naming_the_parameter(make, name):
    with pytest.raises(ValueError, match=name):
        make()


def test_non_numbers_raise_type_error():
    with pytest.raises(TypeError, match="contact.K"):
        ContactLaw("paper", K="stiff")
    with pytest.raises(TypeError, match="law"):
        impact("paper", 1.0, 1.0)
