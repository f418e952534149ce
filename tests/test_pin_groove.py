"""The pin-groove lock (deployfx.groove; cpp/deployfx/contact/groove_profile.hpp,
joint/pin_groove.hpp, joint/latch_follower.hpp, joint/lock_profiles.hpp) against closed forms,
central differences and today's stop-plus-latch lock (joint/hinge_lock.hpp).

References: the signed distance to a line and a circle and its Hessian kappa t t^T (do Carmo,
"Differential Geometry of Curves and Surfaces", 1976, Sec. 1-5; the distance function's Hessian,
Gilbarg & Trudinger 2001, Sec. 14.6); You et al. (2016), Eq. 45 (normal force along n, friction
mu F_n along t); Coulomb friction's work mu N s; the rebound of an undamped Hertz contact (e = 1)
and of a contact whose friction acts along the normal line (e^2 = (1 - mu)/(1 + mu): the force is
(1 + mu) F on approach and (1 - mu) F on rebound over the same path).
Central differences: step h, error O(h^2) on the smooth pieces, tolerances stated per test.
"""
import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from deployfx import _core
from deployfx import groove as G
from deployfx.contact import ContactLaw, Friction
from deployfx.specs import Lock

PAPER_LAW = ContactLaw("paper", K=1e6 / (1e-3) ** 1.5, D=1e6)  # 1e6 N/mm^1.5, 1e3 N s/mm
LAWS = [PAPER_LAW, ContactLaw("hunt-crossley", K=1e10, e=0.8), ContactLaw("lankarani-nikravesh", K=1e10, e=0.7),
        ContactLaw("flores", K=1e10, e=0.5)]


def rot(a):
    return np.array([np.cos(a), np.sin(a)])


# ---------------------------------------------------------------- profile geometry


def test_pin_against_a_line_is_the_closed_form():
    # Free space on the left of (0,0) -> (1,0): n = +y, gap = y - rho, no curvature; exact.
    p = G.GrooveProfile([G.Line((0, 0), (1, 0))])
    for x, y, rho in [(0.3, 0.02, 0.005), (0.9, -0.001, 0.01), (0.5, 0.0, 0.0), (0.0, 0.3, 0.1)]:
        q = p.query(0, (x, y), rho)
        assert q.in_range
        assert q.gap == pytest.approx(y - rho, abs=1e-16)
        np.testing.assert_allclose(q.n, [0, 1], atol=1e-16)
        np.testing.assert_allclose(q.t, [1, 0], atol=1e-16)
        np.testing.assert_allclose(q.point, [x, 0], atol=1e-16)
        np.testing.assert_array_equal(q.dn_dc, np.zeros((2, 2)))
        assert q.chain_length == pytest.approx(x, abs=1e-16)
    # Beyond the free end the closest point is the end: out of range, no contact.
    assert not p.query(0, (1.2, 0.01), 0.005).in_range
    assert not p.closest((-0.1, 0.01), 0.005).in_range


@pytest.mark.parametrize("radius", [0.05, -0.05])
def test_pin_against_an_arc_is_the_closed_form(radius):
    # A quarter circle about the origin, counter-clockwise for radius > 0 (concave seen from the
    # pin, which is inside: gap = R - |c| - rho, n = -c/|c|, dn/dc = -t t^T/|c|) and clockwise
    # for radius < 0 (convex, the pin outside: gap = |c| - R - rho, n = c/|c|, dn/dc = t t^T/|c|).
    R = abs(radius)
    a, b = (R, 0.0), (0.0, R)
    arc = G.Arc(a, b, radius) if radius > 0 else G.Arc(b, a, radius)
    p = G.GrooveProfile([arc])
    e = p._impl.element(0)
    np.testing.assert_allclose(e.centre, [0, 0], atol=1e-17)
    assert abs(e.sweep) == pytest.approx(np.pi / 2, rel=1e-15)
    s = 1.0 if radius > 0 else -1.0
    for phi, dist, rho in [(0.3, 0.04, 0.005), (1.2, 0.06, 0.002), (0.8, 0.0499, 0.0)]:
        c = dist * rot(phi)
        q = p.query(0, c, rho)
        u = rot(phi)
        t = np.array([-u[1], u[0]])
        assert q.in_range and not q.at_vertex
        assert q.gap == pytest.approx(s * (R - dist) - rho, abs=1e-16)
        np.testing.assert_allclose(q.n, -s * u, atol=1e-15)
        np.testing.assert_allclose(q.dn_dc, -s * np.outer(t, t) / dist, rtol=1e-13, atol=1e-13)
        np.testing.assert_allclose(q.point, R * u, atol=1e-16)


def test_arcs_by_signed_radius_and_by_centre():
    # Signed radius: the minor arc whose centre lies on its turning side (a quarter circle of
    # radius 0.1 m: chord 0.1 sqrt 2).
    e = G.Arc((0.1, 0), (0, 0.1), 0.1)._build()
    np.testing.assert_allclose(e.centre, [0, 0], atol=1e-15)
    assert e.sweep == pytest.approx(np.pi / 2, rel=1e-14)
    e = G.Arc((0.1, 0), (0, 0.1), -0.1)._build()
    np.testing.assert_allclose(e.centre, [0.1, 0.1], atol=1e-15)
    assert e.sweep == pytest.approx(-np.pi / 2, rel=1e-14)
    # By centre: any sweep; 3 pi / 2 counter-clockwise from (1, 0) to (0, -1).
    e = G.ArcAbout((1, 0), (0, -1), (0, 0), True)._build()
    assert e.sweep == pytest.approx(1.5 * np.pi, rel=1e-15)
    assert e.length == pytest.approx(1.5 * np.pi, rel=1e-15)
    np.testing.assert_allclose(e.point(e.length), [0, -1], atol=1e-15)


def mixed_profile():
    """A flat, a convex bump (arc, radius < 0) whose foot is a concave corner, a concave seat
    (radius > 0) met at a convex corner, a convex corner, a sharp V (concave) and a flat:
    6 elements in 3 facets."""
    return G.GrooveProfile([
        G.Line((-0.1, 0.0), (0.0, 0.0)),
        G.Arc((0.0, 0.0), (0.04, 0.0), -0.03),       # the bump: turns right (convex)
        G.Arc((0.04, 0.0), (0.08, 0.0), 0.025),      # the seat: turns left (concave)
        G.Line((0.08, 0.0), (0.1, -0.02)),           # turns right at (0.08, 0): a convex corner
        G.Line((0.1, -0.02), (0.12, 0.02)),          # turns left at (0.1, -0.02): a concave V
        G.Line((0.12, 0.02), (0.2, 0.02)),           # turns right: convex
    ])


def test_facets_split_at_concave_corners():
    # Turns (left > 0 concave): flat -> bump +41.8 deg, bump -> seat -11.3 deg, seat -> line
    # -98.1 deg, the V +108.4 deg, V -> flat -63.4 deg: facets [flat], [bump, seat, line],
    # [V's right flank, flat].
    p = mixed_profile()
    turns = np.degrees([p._impl.turn(k) for k in range(5)])
    np.testing.assert_allclose(turns, [41.81, -11.31, -98.13, 108.43, -63.43], atol=0.01)
    assert p.num_facets == 3
    assert [p.facet_elements(f) for f in range(3)] == [(0, 1), (1, 3), (4, 2)]
    # A pin wedged in the V touches both flanks: two facets in range, both penetrated, pushing
    # from either side (normals (1, 1)/sqrt 2 and (-2, 1)/sqrt 5).
    c = np.array([0.1, -0.02 + 0.005])
    qs = [p.query(f, c, 0.004) for f in range(p.num_facets)]
    wedged = [q for q in qs if q.in_range and q.gap < 0]
    assert [q.facet for q in wedged] == [1, 2]
    assert wedged[0].gap == pytest.approx(0.005 / np.sqrt(2) - 0.004, abs=1e-16)
    assert wedged[1].gap == pytest.approx(0.005 / np.sqrt(5) - 0.004, abs=1e-16)
    np.testing.assert_allclose(wedged[0].n, np.array([1, 1]) / np.sqrt(2), atol=1e-15)
    np.testing.assert_allclose(wedged[1].n, np.array([-2, 1]) / np.sqrt(5), atol=1e-15)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_gap_and_normal_derivatives_match_central_differences(seed):
    # d gap/dc = n and d n/dc = dn_dc (the Hessian) by central differences, h = 1e-7 m on a
    # profile of 0.1 m: truncation ~h^2 kappa^3 ~ 1e-10, round-off ~1e-16/1e-7; tolerance 1e-6
    # relative to the curvature scale 1/|c - centre|. Points where the closest feature changes
    # within +-h (a fan's edge, a medial axis) are skipped.
    p = mixed_profile()
    rng = np.random.default_rng(seed)
    h, rho, checked = 1e-7, 0.003, 0
    for c in np.column_stack([rng.uniform(-0.09, 0.19, 400), rng.uniform(-0.03, 0.04, 400)]):
        for f in range(p.num_facets):
            q = p.query(f, c, rho)
            if not q.in_range:
                continue
            nbrs = [p.query(f, c + d, rho) for d in (np.array([h, 0]), np.array([-h, 0]), np.array([0, h]),
                                                   np.array([0, -h]))]
            if any((not n.in_range) or n.element != q.element or n.at_vertex != q.at_vertex for n in nbrs):
                continue
            grad = np.array([(nbrs[0].gap - nbrs[1].gap) / (2 * h), (nbrs[2].gap - nbrs[3].gap) / (2 * h)])
            np.testing.assert_allclose(grad, q.n, atol=1e-8)
            hess = np.column_stack([(nbrs[0].n - nbrs[1].n) / (2 * h), (nbrs[2].n - nbrs[3].n) / (2 * h)])
            scale = max(1.0, np.abs(q.dn_dc).max())
            np.testing.assert_allclose(hess, q.dn_dc, atol=1e-6 * scale)
            checked += 1
    assert checked > 300


def test_normal_turns_continuously_when_a_pin_rolls_over_a_convex_corner():
    # The convex corner at v = (0.08, 0) of mixed_profile, between the seat (ending along
    # 53.13 deg, normal 143.13 deg) and the line down at -45 deg (normal 45 deg). A pin circling v
    # at distance d from 160 deg to 20 deg: in the fan (45..143.13 deg) its closest point is v,
    # gap = d - rho and n = (c - v)/d exactly; on the line's side n is the line's; on the
    # concave seat's side n points to the seat's centre. Over the whole sweep the normal's angle
    # never moves faster than the pin's angle (no jump at the fan's edges, 1e-12 rad).
    p = mixed_profile()
    f = p._impl.facet_of_element(3)
    v, d, rho = np.array([0.08, 0.0]), 0.004, 0.003
    angles = np.radians(np.linspace(160, 20, 1401))
    normals, gaps, vertex = [], [], []
    for a in angles:
        q = p.query(f, v + d * rot(a), rho)
        assert q.in_range
        normals.append(q.n)
        gaps.append(q.gap)
        vertex.append(q.at_vertex)
    normals, vertex = np.array(normals), np.array(vertex)
    turn = np.unwrap(np.arctan2(normals[:, 1], normals[:, 0]))
    assert np.max(np.abs(np.diff(turn))) <= np.max(np.abs(np.diff(angles))) + 1e-12
    fan = (angles > np.radians(45) + 1e-9) & (angles < np.radians(143.1301) - 1e-6)
    assert np.array_equal(vertex[fan], np.ones(fan.sum(), bool))
    np.testing.assert_allclose(np.array(gaps)[fan], d - rho, atol=1e-16)
    np.testing.assert_allclose(turn[fan], angles[fan], atol=1e-12)
    np.testing.assert_allclose(turn[angles < np.radians(45)], np.radians(45), atol=1e-12)


def test_segment_distance_matches_sampling():
    # The bore's distance to a facet (the latch's drop event): it is attained at the returned
    # parameter (the distance from that point to the facet, sampled every ~2e-6 m: 2e-6) and no
    # sampled pair of points is nearer (sampling can only overestimate the minimum).
    p = mixed_profile()
    rng = np.random.default_rng(5)
    curves = []
    for f in range(p.num_facets):
        first, count = p.facet_elements(f)
        pts = []
        for k in range(first, first + count):
            e = p._impl.element(k)
            pts += [e.point(u) for u in np.linspace(0, e.length, max(2, int(e.length / 2e-6)))]
        curves.append(np.array(pts))
    for _ in range(30):
        p0, p1 = rng.uniform([-0.05, -0.03], [0.15, 0.04]), rng.uniform([-0.05, -0.03], [0.15, 0.04])
        seg = p0 + np.linspace(0, 1, 301)[:, None] * (p1 - p0)
        for f, pts in enumerate(curves):
            d, s = p._impl.segment_distance(f, p0, p1)
            assert 0 <= s <= 1
            at = p0 + s * (p1 - p0)
            assert np.min(np.linalg.norm(pts - at, axis=1)) == pytest.approx(d, abs=2e-6)
            sparse = pts[::50]
            assert d <= np.min(np.linalg.norm(seg[:, None, :] - sparse[None, :, :], axis=2)) + 1e-15


def test_profile_errors_name_the_parameter():
    with pytest.raises(ValueError, match=r"elements\[1\]\.start .* must be within .* elements\[0\]\.end"):
        G.GrooveProfile([G.Line((0, 0), (1, 0)), G.Line((1.001, 0), (2, 0))])
    with pytest.raises(ValueError, match=r"arc\.radius = 0\.1 .* half the chord"):
        G.Arc((0, 0), (1, 0), 0.1)._build()
    with pytest.raises(ValueError, match=r"arc_about.*centre"):
        G.ArcAbout((1, 0), (0, 2), (0, 0), True)._build()
    with pytest.raises(ValueError, match="distinct"):
        G.Line((0, 0), (0, 0))._build()
    with pytest.raises(ValueError, match="empty"):
        G.GrooveProfile([])
    p = G.GrooveProfile([G.Line((0, 0), (1, 0))])
    with pytest.raises(ValueError, match=r"rho = -0\.001 is out of range: must be >= 0"):
        p.query(0, (0.5, 0.1), -0.001)
    with pytest.raises(ValueError, match=r"^c = .* 2 finite coordinates"):
        p.query(0, (np.nan, 0.1), 0.001)
    with pytest.raises(ValueError, match=r"facet = 3 is out of range"):
        p.query(3, (0.5, 0.1), 0.001)


# ---------------------------------------------------------------- today's lock as one profile


def lock(law=PAPER_LAW, mu=0.0, clearance=0.2e-3, r=0.03):
    return Lock(np.pi / 2, r, clearance, law, Friction(mu))


def hinge_history(latched=True, stop=False, latch=False, v0=0.4):
    h = _core.LockHistory()
    h.latched, h.stop_contact, h.latch_contact, h.stop_v0, h.latch_v0 = latched, stop, latch, v0, 0.8 * v0
    return h


@pytest.mark.parametrize("law", LAWS, ids=lambda l: l.kind)
@pytest.mark.parametrize("wall", ["stop", "latch"])
def test_stop_latch_profile_reproduces_todays_lock(law, wall):
    # Geometry of the walls (joint/lock_profiles.hpp): gap = -+ r sin(theta - theta_wall) and
    # lever r cos(theta - theta_wall), where hinge_lock.cpp uses r (theta - theta_wall) and r.
    # Hence, exactly, tau_new(theta, theta') = cos D tau_old(theta_wall + sin D, theta' cos D),
    # D = theta - theta_wall: to round-off (1e-12 relative to the peak torque of the sweep);
    # directly, tau_new = tau_old to within 2 D^2 (|elastic| + |rate-dependent part|) of today's
    # torque (delta and delta' differ by D^2/6 and D^2/2, the lever by D^2/2): ~1e-6 at 0.1 mm.
    L = lock(law)
    g = G.PinGroove.stop_latch(L, rho=0.003)
    h = hinge_history(stop=wall == "stop", latch=wall == "latch")
    gh = _core.stop_latch_history(h)
    th_wall = L.theta_lock if wall == "stop" else L.theta_lock - L.clearance / L.pin_radius
    sign = 1.0 if wall == "stop" else -1.0
    peak = 0.0
    rows = []
    for dpen in np.linspace(-2e-5, 2e-4, 23):              # penetration r D, m
        for rate in (-1.5, -0.2, 0.0, 0.3, 1.2):          # rad/s
            D = sign * dpen / L.pin_radius
            new = g.load(th_wall + D, rate, gh)
            mapped = G.hinge_lock_load(L, h, th_wall + np.sin(D), rate * np.cos(D))
            direct = G.hinge_lock_load(L, h, th_wall + D, rate)
            elastic = G.hinge_lock_load(L, h, th_wall + D, 0.0)["torque"]
            rows.append((D, new, mapped, direct, abs(elastic) + abs(direct["torque"] - elastic)))
            peak = max(peak, abs(direct["torque"]))
    for D, new, mapped, direct, size in rows:
        assert new.torque == pytest.approx(np.cos(D) * mapped["torque"], abs=1e-12 * peak)
        assert new.normal_force == pytest.approx(mapped["normal_force"], abs=1e-12 * peak / 0.03)
        assert abs(new.torque - direct["torque"]) <= 2 * D**2 * size + 1e-12 * peak
        # The derivatives: d_rate = r^2 cos^2 D dF/d delta'; d_theta to within O(D) of today's,
        # and at delta = 0 within r^2 dF/d delta at a round-off delta of 1e-16 m (Hertz's
        # n K delta^(n-1) is not Lipschitz there).
        assert new.d_rate == pytest.approx(np.cos(D) ** 2 * mapped["d_rate"], rel=1e-11, abs=1e-12 * peak)
        at_zero = L.pin_radius**2 * law.n * law.K * 1e-16 ** (law.n - 1)
        assert new.d_theta == pytest.approx(direct["d_theta"], rel=5 * abs(D) + 1e-9, abs=1e-9 * peak + at_zero)


@pytest.mark.parametrize("wall", ["stop", "latch"])
def test_stop_latch_facet_states_and_levers_are_todays_walls(wall):
    # The engine's impact records and step control read each wall's state and the pin's lever
    # (joint::wall_states, contact_resolution). Per facet: the state at (theta, theta') is today's
    # at (theta_wall + sin D, theta' cos D) to round-off (delta = r sin D, delta' = r theta' cos D,
    # F the unclamped law's), the lever d delta/d theta is +-r cos D (1e-15 m), and the angle error
    # a step may make is kContactResolution v0 T / lever (today's: v0 T / r, in m).
    L = lock(ContactLaw("hunt-crossley", K=1e10, e=0.8))
    g = G.PinGroove.stop_latch(L, rho=0.003)
    h = hinge_history(stop=wall == "stop", latch=wall == "latch")
    gh = _core.stop_latch_history(h)
    facet, index = (0, 0) if wall == "stop" else (2, 1)
    facets = gh.facets
    facets[facet].T = 2e-4  # as the engine sets it at onset
    gh.facets = facets
    th_wall = L.theta_lock if wall == "stop" else L.theta_lock - L.clearance / L.pin_radius
    sign = 1.0 if wall == "stop" else -1.0
    for dpen in (-1e-5, 0.0, 3e-5, 1.2e-4):
        for rate in (-0.8, 0.0, 0.6):
            D = sign * dpen / L.pin_radius
            new = g.facet_state(facet, th_wall + D, rate, gh)
            old = _core.hinge_wall_states(G.PinGroove._hinge_lock(L), h, th_wall + np.sin(D), rate * np.cos(D))[index]
            assert new["contact"] and old["contact"]
            assert new["delta"] == pytest.approx(old["delta"], abs=3e-17)  # eps x 0.03 m x a few
            assert new["delta_dot"] == pytest.approx(old["delta_dot"], rel=1e-14, abs=1e-18)
            assert new["F"] == pytest.approx(old["F"], rel=1e-10, abs=1e-9)
            assert g.lever(facet, th_wall + D, gh) == pytest.approx(sign * L.pin_radius * np.cos(D), abs=1e-15)
    v0, T = (h.stop_v0, 2e-4) if wall == "stop" else (h.latch_v0, 2e-4)
    error, min_step = g.contact_resolution(th_wall, gh)
    assert error == pytest.approx(1e-3 * v0 * T / L.pin_radius, rel=1e-12)
    assert min_step == pytest.approx(T / 100, rel=1e-15)
    assert g.contact_resolution(th_wall, _core.stop_latch_history(hinge_history())) == (np.inf, 0.0)


def test_stop_latch_arms_its_latch_where_todays_latch_latches():
    # hinge_lock.cpp: latched once theta >= theta_latch; the latch facet arms when the pin reaches
    # its free side, gap = r sin(theta - theta_latch) >= 0: the same angle, to the 1e-12 rad
    # steps taken around it (the gap's round-off there is ~1e-18 m, 3e-17 rad).
    L = lock()
    g = G.PinGroove.stop_latch(L, rho=0.003)
    th_latch = L.theta_lock - L.clearance / L.pin_radius
    h = g.start_history(0.0)
    armed_at = None
    for th in np.concatenate([np.linspace(0, th_latch - 1e-9, 400), th_latch + np.array([-1e-12, 0, 1e-12])]):
        g.update_history(h, th, 1.0)
        if armed_at is None and h.facets[2].armed:
            armed_at = th
    assert th_latch - 1e-12 < armed_at <= th_latch + 1e-12
    assert h.facets[0].armed and not any(f.closed for f in h.facets)


# ---------------------------------------------------------------- friction along the tangent


def test_friction_leaves_a_normal_impact_unchanged():
    # The stop facet's normal lies along the pin's path where the pin meets it: friction has no
    # first-order effect. Pressed in by D (rad), the pin's centre, on its circle, slides along the
    # straight wall by r (1 - cos D) at v_t = r theta' sin D, with the friction torque's lever
    # r sin D: friction changes the torque by at most mu |tan D| of the normal torque, and its
    # work over an impact is at most 2 mu D_max of the impact energy, so an undamped Hertz impact
    # (K = 1e9 N/m^1.5, I = 1 kg m^2, 0.5 rad/s on r = 0.03 m: D_max = (2.5 E / K)^0.4 / r =
    # 5.3e-3) rebounds within mu D_max = 1.3e-3 of its frictionless e = 1. Today's lock applies
    # mu F_n along the normal line instead: e = sqrt((1 - mu)/(1 + mu)) = 0.7746 (1e-3; the
    # tanh band, v_reg = 1e-4 m/s against 0.015 m/s, shifts it by ~1e-4).
    hertz, mu = ContactLaw("paper", K=1e9, D=0.0), 0.25
    g0, g1 = G.PinGroove.stop_latch(lock(hertz, 0.0), 0.003), G.PinGroove.stop_latch(lock(hertz, mu), 0.003)
    gh = _core.stop_latch_history(hinge_history(stop=True))
    for th in np.pi / 2 + np.linspace(-1e-5, 3e-3, 17):
        D = th - np.pi / 2
        for rate in (-0.7, -1e-3, 0.0, 2e-3, 0.5):
            t0, t1 = g0.load(th, rate, gh).torque, g1.load(th, rate, gh).torque
            assert abs(t1 - t0) <= mu * abs(np.tan(D)) * abs(t0) + 1e-15

    def rebound(load):
        def rhs(t, y):
            return [y[1], load(y[0], y[1])]
        out = lambda t, y: y[0] - np.pi / 2  # back at the wall
        out.terminal, out.direction = True, -1
        s = solve_ivp(rhs, (0, 1.0), [np.pi / 2, 0.5], method="DOP853", rtol=1e-12, atol=1e-15, events=out,
                      first_step=1e-7, max_step=1e-4)
        return -s.y_events[0][0][1] / 0.5

    e0 = rebound(lambda th, w: g0.load(th, w, gh).torque)
    e1 = rebound(lambda th, w: g1.load(th, w, gh).torque)
    D_max = (2.5 * 0.125 / 1e9) ** 0.4 / 0.03
    assert e0 == pytest.approx(1.0, abs=1e-8)
    assert 0 <= e0 - e1 <= mu * D_max
    L_old, h_old = lock(hertz, mu), hinge_history(stop=True)
    e_old = rebound(lambda th, w: G.hinge_lock_load(L_old, h_old, th, w)["torque"])
    assert e_old == pytest.approx(np.sqrt((1 - mu) / (1 + mu)), abs=1e-3)


def arc_track(R, a0=-0.5, a1=2.0):
    """A circular track of radius R about the hinge axis, material inside (clockwise)."""
    return G.GrooveProfile([G.ArcAbout(R * rot(a1), R * rot(a0), (0, 0), False)])


@pytest.mark.parametrize("mu", [0.1, 0.25, 1.0])
def test_pin_pressed_on_a_track_dissipates_mu_N_s(mu):
    # A latch pin pressed with a constant N (no spring rate) slides along a track about the axis
    # (the groove is straight in the pin's path coordinate): its normal stays radial, so
    # N = preload exactly and the friction torque is -mu N s sign(theta') (|v_t| >> v_reg). The
    # work over a travel Delta theta is mu N s Delta theta = mu N (path length), to 1e-12.
    N, rho, R = 3.0, 0.002, 0.032
    latch = G.LatchSpring(stop=0.029, travel=0.008, preload=N, stiffness=0.0)
    g = G.PinGroove(arc_track(R), 0.03, 0.0, rho, PAPER_LAW, Friction(mu), latch)
    h = g.start_history(0.0)
    assert h.support == 0
    s = R + rho
    work = quad(lambda th: g.load(th, 0.8, h).torque, 0.0, 1.2, epsabs=1e-14)[0]
    assert -work == pytest.approx(mu * N * s * 1.2, rel=1e-12)
    assert g.load(0.4, 0.8, h).support_force == pytest.approx(N, rel=1e-14)


def test_a_latch_pin_pushed_to_the_end_of_its_travel_is_a_fixed_pin():
    # The track (radius 32 mm, pin 2 mm: the pin would ride at 34 mm) beyond the bore's reach
    # (29 + 4 = 33 mm): the pin is held at 33 mm, 1 mm into the track, which then pushes with the
    # clamped law K delta^1.5 (no spring load through the support), and friction mu F_n on the
    # pin centre's slip at 33 mm (1e-12).
    K, mu = 1e9, 0.3
    latch = G.LatchSpring(stop=0.029, travel=0.004, preload=2.0, stiffness=0.0)
    g = G.PinGroove(arc_track(0.032), 0.03, 0.0, 0.002, ContactLaw("paper", K=K, D=0.0), Friction(mu), latch)
    h = g.start_history(0.0)
    p = g.position(0.5, h)
    assert h.support == 0 and p["bottomed"] and p["s"] == pytest.approx(0.033, abs=1e-15)
    L = g.load(0.5, 0.6, h)
    Fn = K * 1e-3**1.5
    assert L.normal_force == pytest.approx(Fn, rel=1e-9)
    assert L.support_force == 0
    assert L.torque == pytest.approx(-mu * Fn * 0.033, rel=1e-9)


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_latch_pin_on_a_straight_groove_balances_energy(mu):
    # A latch pin (spring preload 2 N, rate 400 N/m) pushed away from the axis onto a straight
    # groove, the line y = 0.028 m (material above it, free space on the axis side: the left of
    # its direction -x), while the hinge turns at 0.5 rad/s over 63 deg: the work done on the
    # lock, -integral(tau dtheta), equals the spring's energy change plus the friction work
    # integral(mu N ds), with N the support force the module reports (the massless pin's radial
    # balance) and ds = |dc/dtheta| dtheta along the pin's path. Quadrature to 1e-13: 1e-9.
    line = G.GrooveProfile([G.Line((0.06, 0.028), (-0.06, 0.028))])
    latch = G.LatchSpring(stop=0.040, travel=0.030, preload=2.0, stiffness=400.0, toward_axis=False)
    g = G.PinGroove(line, 0.03, np.pi / 2, 0.002, PAPER_LAW, Friction(mu), latch)
    h = g.start_history(0.0)
    assert h.support == 0
    rate, th0, th1 = 0.5, -0.5, 0.6

    def U(th):  # spring energy, J: preload w + k w^2 / 2
        w = g.position(th, h)["w"]
        return 2.0 * w + 200.0 * w * w

    def friction_power(th):  # mu N |dc/dtheta| per unit theta
        p = g.position(th, h)
        return mu * g.load(th, rate, h).support_force * np.hypot(p["ds"], p["s"])

    work = quad(lambda th: g.load(th, rate, h).torque, th0, th1, epsabs=1e-13, limit=200)[0]
    loss = quad(friction_power, th0, th1, epsabs=1e-13, limit=200)[0]
    assert -work == pytest.approx(U(th1) - U(th0) + loss, rel=1e-9, abs=1e-12)
    # and the pin stays on the line: s cos(psi - pi/2) ... its centre at y = 0.028 - rho
    for th in (th0, 0.0, th1):
        s = g.position(th, h)["s"]
        assert s * np.sin(th + np.pi / 2) == pytest.approx(0.026, abs=1e-15)


# ---------------------------------------------------------------- the latch follower


def test_follower_slope_and_curvature_match_central_differences():
    # s(theta) on the paper groove's track, over the notch edge (a roll-over about the corner) and
    # in the notch: ds, d2s against central differences (h = 1e-6 rad; 1e-6 relative).
    g = G.PinGroove.paper(PAPER_LAW, Friction(0.25))
    h = g.start_history(0.0)
    th_latch = np.pi / 2 - 0.2e-3 / 0.03
    for th in (0.3, th_latch - 0.06, th_latch - 0.03, th_latch - 0.01, th_latch - 0.003):
        p, hh = g.position(th, h), 1e-6
        sp, sm = g.position(th + hh, h)["s"], g.position(th - hh, h)["s"]
        assert p["ds"] == pytest.approx((sp - sm) / (2 * hh), rel=1e-6, abs=1e-10)
        dsp, dsm = g.position(th + hh, h)["ds"], g.position(th - hh, h)["ds"]
        assert p["d2s"] == pytest.approx((dsp - dsm) / (2 * hh), rel=1e-5, abs=1e-8)


@pytest.mark.parametrize("mu", [0.0, 0.25])
@pytest.mark.parametrize("where", ["ride", "roll-over", "notch", "stop"])
def test_load_derivatives_match_central_differences(mu, where):
    # d torque/d theta and d torque/d theta' (dual numbers over the analytic geometry) against
    # central differences, h = 1e-7 rad (ride and roll-over) or 1e-10 rad (a stiff contact,
    # 3e10 N/m^1.5): tolerance 1e-5 of the derivative's scale.
    g = G.PinGroove.paper(PAPER_LAW, Friction(mu))
    h = g.start_history(0.0)
    th_latch = np.pi / 2 - 0.2e-3 / 0.03
    if where in ("notch", "stop"):
        g.update_history(h, th_latch + 1e-9, 1.0)  # the drop
        assert h.support == 1
    if where == "stop":
        g.update_history(h, np.pi / 2 + 1e-9, 1.0)
        assert h.facets[0].closed
    th = {"ride": 0.7, "roll-over": th_latch - 0.02, "notch": th_latch + 1e-4, "stop": np.pi / 2 + 2e-6}[where]
    step = 1e-10 if where == "stop" else 1e-7
    for rate in (0.9, 2e-3, -0.4):
        L = g.load(th, rate, h)
        dth = (g.load(th + step, rate, h).torque - g.load(th - step, rate, h).torque) / (2 * step)
        dr = (g.load(th, rate + step, h).torque - g.load(th, rate - step, h).torque) / (2 * step)
        scale = max(abs(L.d_theta), abs(L.torque), 1e-3)
        assert L.d_theta == pytest.approx(dth, abs=1e-5 * scale)
        assert L.d_rate == pytest.approx(dr, abs=1e-5 * max(abs(L.d_rate), 1e-3))


def test_past_the_drop_the_pin_is_held_where_the_drop_left_it():
    # Within a step the pin's support is fixed, as a wall's mode is (an active set): a trial state
    # past the drop (the history not yet updated) holds the pin at the drop's s (continuous with
    # the roll-over's, whose s falls as sqrt(theta_d - theta): 3.6e-7 m at 1e-9 rad, so within
    # 2e-8 m at 1e-12), ds = d2s = 0, and the support keeps pushing the hinge forward, never
    # less than at the drop. Before, the pin fell there and the torque dropped from 0.165 N m to
    # 0: an implicit step ending just past the drop then had no solution (its end-point torque put
    # its end before the drop) and Newton cycled (joint/latch_follower.hpp). The history's update
    # then drops the pin onto the seat, as before.
    d = G.PAPER_DEFAULTS
    g = G.PinGroove.paper(PAPER_LAW, Friction(0.25))
    h = g.start_history(0.0)
    th_latch = d["theta_lock"] - d["clearance"] / d["seat"]
    at_drop = g.position(th_latch - 1e-12, h)
    assert at_drop["found"] and not at_drop["beyond"]
    tau_drop = g.load(th_latch - 1e-12, 1.0, h).torque
    for past in (1e-9, 1e-6, 1e-4):
        p = g.position(th_latch + past, h)
        assert p["beyond"] and not p["found"] and p["drop_margin"] < 0
        assert p["s"] == pytest.approx(at_drop["s"], abs=2e-8)
        assert p["ds"] == 0.0 and p["d2s"] == 0.0
        assert g.load(th_latch + past, 1.0, h).torque >= tau_drop > 0
    g.update_history(h, th_latch + 1e-12, 1.0)
    assert h.support == 1
    landed = g.position(th_latch + 1e-9, h)
    assert landed["found"] and not landed["beyond"]
    assert landed["s"] == pytest.approx(d["seat"], abs=1e-12)


def test_paper_groove_geometry():
    # joint/lock_profiles.hpp with the defaults of docs/research/pin-groove.md: the pin rides at
    # seat + notch depth = 34 mm, its drop event crosses 0 at theta_latch (where hinge_lock.cpp
    # latches), it lands on the notch bottom at the seat, 30 mm, touching the latch flank (gap 0)
    # with the stop flank one clearance away. Lengths to 1e-12 m.
    d = G.PAPER_DEFAULTS
    g = G.PinGroove.paper(PAPER_LAW, Friction(0.25))
    h = g.start_history(0.0)
    assert g.profile.num_facets == 3 and h.support == 2
    assert not h.facets[0].armed and not h.facets[1].armed
    assert g.position(0.0, h)["s"] == pytest.approx(d["seat"] + d["notch_depth"], abs=1e-12)
    th_latch = d["theta_lock"] - d["clearance"] / d["seat"]
    assert g.position(th_latch - 1e-9, h)["drop_margin"] > 0 > g.position(th_latch + 1e-9, h)["drop_margin"]
    g.update_history(h, th_latch + 1e-12, 1.0)
    assert h.support == 1
    assert g.position(th_latch, h)["s"] == pytest.approx(d["seat"], abs=1e-12)
    c = d["seat"] * rot(th_latch)
    assert g.profile.query(2, c, d["pin_radius"]).gap == pytest.approx(0.0, abs=1e-12)
    assert g.profile.query(0, c, d["pin_radius"]).gap == pytest.approx(d["seat"] * np.sin(d["clearance"] / d["seat"]),
                                                                        abs=1e-12)
    assert all(f.armed for f in h.facets)


def deploy(g, I, theta0=0.0, t_end=4.0, chunk=0.02):
    """A rigid 1-DOF hinge, I theta'' = tau0 - k theta + tau_lock (the paper's spring: 7.2 N m,
    80 N mm/deg), from rest at theta0, as an engine would run it: the lock's events located
    (solve_ivp, DOP853, rtol 1e-10) and the history updated there and after every `chunk` s
    (the engine's accepted steps). Returns (the stop's first contact time, history, drop time)."""
    tau0, k = 7.2, 80.0 * 180.0 / np.pi * 1e-3
    h = g.start_history(theta0)
    t, y, t_drop = 0.0, np.array([theta0, 0.0]), None
    while t < t_end:
        n = len(g.events(y[0], y[1], h))
        evs = []
        for i in range(n):
            ev = (lambda i: lambda t, y: g.events(y[0], y[1], h)[i])(i)
            ev.terminal, ev.direction = True, -1
            evs.append(ev)
        sol = solve_ivp(lambda t, y: [y[1], (tau0 - k * y[0] + g.load(y[0], y[1], h).torque) / I],
                        (t, min(t + chunk, t_end)), y, method="DOP853", rtol=1e-10, atol=1e-12, events=evs)
        margins = np.zeros(n)
        if sol.status == 1:
            i = next(i for i, te in enumerate(sol.t_events) if len(te))
            t, y = sol.t_events[i][0], sol.y_events[i][0]
            margins[i] = abs(g.events(y[0], y[1], h)[i]) + 1e-12
        else:
            t, y = sol.t[-1], sol.y[:, -1]
        support = h.support
        g.update_history(h, y[0], y[1], margins)
        if h.support != support:
            t_drop = t
        if h.facets[0].closed:
            return t, h, t_drop
    return None, h, t_drop


def test_paper_groove_locks_at_the_papers_time():
    # You et al. (2016), Fig. 7: 180 deg first reached at 2.46 s (reported on its 0.01 s grid). A
    # rigid hinge with I = 11.16 kg m^2, the inertia that gives deployfx's rigid paper scene its
    # 2.451 s (README), reaches the stop at pi/2 (2/pi)... with the ride friction
    # mu N s = 0.25 x 1.5 N x 0.034 m = 0.0128 N m delaying it by ~2 tau_f / (pi omega k) = 2.8 ms
    # (the linearised quarter period, omega = sqrt(k/I)); within 0.01 s of the paper's 2.46 s.
    I = 4.5837 * (2 * 2.451 / np.pi) ** 2
    t_free, _, _ = deploy(G.PinGroove.paper(PAPER_LAW, Friction(0.0)), I)
    t_lock, h, t_drop = deploy(G.PinGroove.paper(PAPER_LAW, Friction(0.25)), I)
    k = 80.0 * 180.0 / np.pi * 1e-3
    omega = np.sqrt(k / I)
    assert t_free == pytest.approx(2.451, abs=2e-3)
    assert t_lock - t_free == pytest.approx(2 * 0.25 * 1.5 * 0.034 / (np.pi * omega * k), rel=0.15)
    assert abs(t_lock - 2.46) < 0.01
    assert t_drop is not None and t_drop < t_lock and h.support == 1


@pytest.mark.parametrize("preload", [0.2, 1.0, 5.0])
def test_the_dropped_pin_crosses_its_clearance_to_the_stop(preload):
    # After the drop at theta_latch the pin rests on the notch bottom (its spring load on a
    # surface about the axis: no torque but friction) and the hinge crosses the clearance,
    # 0.2 mm on s = 30 mm, at its speed (~1.006 rad/s): 6.6 ms, to 2 %. The latch flank, left at
    # the drop touching the pin (gap 0 to round-off) with the pin moving away, must not close
    # (a closed facet's unclamped force would pull the pin back).
    g = G.PinGroove.paper(PAPER_LAW, Friction(0.25), preload=preload, stiffness=0.0)
    t_lock, h, t_drop = deploy(g, 4.5837 * (2 * 2.451 / np.pi) ** 2)
    assert t_lock - t_drop == pytest.approx(0.2e-3 / 0.03 / 1.006, rel=0.02)
    assert not h.facets[2].closed
    h = g.start_history(0.0)
    g.update_history(h, np.pi / 2 - 0.2e-3 / 0.03, 1.0, [0, 0, 0, 1e-12])  # the drop, located
    assert h.support == 1 and h.facets[2].armed and not h.facets[2].closed


# ---------------------------------------------------------------- extremes and input checks


@pytest.mark.parametrize("rho", [1e-3, 1e-2, 0.1])
@pytest.mark.parametrize("mu", [0.0, 0.5, 1.0])
@pytest.mark.parametrize("K", [1e3, 1e6, 1e12])
def test_extremes_give_finite_loads(rho, mu, K):
    # Pin radius 1 mm to 0.1 m (on a lever of 0.3 m), mu 0 to 1, K_c 1e3 to 1e12 N/m^1.5: finite
    # torques, derivatives and events (or +inf events) over penetrations up to 1 mm and rates
    # up to 50 rad/s, for today's lock as a profile and for the paper groove (its pin 1-2 mm).
    law = ContactLaw("paper", K=K, D=1e3)
    g = G.PinGroove.stop_latch(Lock(np.pi / 2, 0.3, 0.5e-3, law, Friction(mu)), rho=rho)
    gh = _core.stop_latch_history(hinge_history(stop=True, latch=True))
    for th in np.pi / 2 + np.linspace(-5e-3, 5e-3, 21):
        for rate in (-50.0, -1e-6, 0.0, 1e-6, 50.0):
            L = g.load(th, rate, gh)
            assert np.isfinite([L.torque, L.d_theta, L.d_rate, L.normal_force]).all()
            assert not np.isnan(g.events(th, rate, gh)).any()
    p = G.PinGroove.paper(law, Friction(mu), pin_radius=min(rho, 2e-3))
    h = p.start_history(0.0)
    for th in np.linspace(0, np.pi / 2 + 0.01, 301):
        L = p.load(th, 1.0, h)
        assert np.isfinite([L.torque, L.d_theta, L.d_rate, L.normal_force]).all()
        assert not np.isnan(p.events(th, 1.0, h)).any()


def test_inputs_are_range_checked():
    law, fr = PAPER_LAW, Friction(0.2)
    prof = arc_track(0.03)
    with pytest.raises(ValueError, match=r"groove\.pin_distance = 0 is out of range: must be > 0"):
        G.PinGroove(prof, 0.0, 0.0, 0.001, law, fr)
    with pytest.raises(ValueError, match=r"groove\.pin_radius = -0\.001 is out of range: must be >= 0"):
        G.PinGroove(prof, 0.03, 0.0, -0.001, law, fr)
    with pytest.raises(ValueError, match=r"latch\.travel = -0\.001 is out of range: must be > 0"):
        G.PinGroove(prof, 0.03, 0.0, 0.001, law, fr, G.LatchSpring(0.029, -0.001, 1.0, 0.0))
    with pytest.raises(ValueError, match=r"latch\.preload = -1 is out of range: must be >= 0"):
        G.PinGroove(prof, 0.03, 0.0, 0.001, law, fr, G.LatchSpring(0.029, 0.005, -1.0, 0.0))
    with pytest.raises(ValueError, match=r"paper_groove\.notch_depth = 0\.001 is out of range: must be > pin_radius"):
        G.PinGroove.paper(law, fr, notch_depth=1e-3)
    with pytest.raises(ValueError, match=r"paper_groove\.travel = 0\.003 is out of range"):
        G.PinGroove.paper(law, fr, travel=3e-3)
    with pytest.raises(TypeError, match="no parameter 'depth'"):
        G.PinGroove.paper(law, fr, depth=1e-3)
    with pytest.raises(ValueError, match=r"rho = 0\.02 is out of range: must be in \[0, lock\.pin_radius / 2"):
        G.PinGroove.stop_latch(lock(), rho=0.02)
    g = G.PinGroove(prof, 0.03, 0.0, 0.001, law, fr)
    with pytest.raises(ValueError, match=r"theta = nan is out of range: must be finite \(rad\)"):
        g.load(np.nan, 0.0, g.start_history(0.0))
    with pytest.raises(ValueError, match="history.facets has 0 entries"):
        g.load(0.0, 0.0, G.History())
