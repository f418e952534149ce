"""The analytic Newton matrix and momentum Jacobian of the engine (issue 6) on one hinge
against central differences of the residual and of the momentum, through the bindings.

newton_matrix(q, v, a, t, c_a, c_v, c_q) = c_a dr/da + c_v dr/dv + c_q dr/dq (dr/dq along
retract()); momentum_jacobian(q, v, c_v, c_q) = c_v dPi/dv + c_q dPi/dq. Every fidelity, free and
fixed base, with and without the lock in contact, at a generic state: the base spinning about a
tilted axis with its centre of mass off B's origin, the hinge at 0.3 rad moving, the plate
deformed and vibrating.

The differences are fourth-order central differences. r is affine in a and, but for the lock's
friction (the hinge row), quadratic in v, and Pi is linear in v: unit steps are exact there and
keep the round-off of the stiff elastic rows small; the hinge row's v-columns take steps of
1e-4. In q (steps 1e-3) the truncation error is below 1e-12 relative. Measured agreement (in
the units below): 4e-8 at worst (the hinge row's v-columns, differenced with steps of
1e-4). Tolerance: each entry within 1e-7 of the largest magnitude in its row group
(the base's force rows, its moment rows, the hinge row, the elastic rows: one unit each) and
column, plus 1e-11 of the matrix's largest entry (round-off of the quotients where an entry is 0).
The lock's own theta- and rate-derivatives are analytic (joint/hinge_lock.hpp).
"""
import numpy as np
import pytest

import deployfx as dfx
from deployfx import _core, scenes

import chain_scenes  # tests/: scenes shared by tests

M_BASE, J_BASE = 3000.0, 500.0
P_HINGE = np.array([0.83, 0.0, 0.0])
B_H, W = 0.03, 1.3
TAU0, K_THETA = 7.2, 80.0e-3 * 180 / np.pi
THETA_LOCK = 0.05
FIDELITIES = ["rigid", "linear", "nonlinear", "reduced-linear", "reduced-nonlinear", "reduced-manifold"]
RTOL, ATOL = 1e-7, 1e-11


def Ry(a):
    return np.array([[np.cos(a), 0, np.sin(a)], [0, 1, 0], [-np.sin(a), 0, np.cos(a)]])


def make_system(fidelity, free, lock, variant=None):
    """The paper's laminate (lay-up 2) on a 4 x 2 mesh, its root edge clamped; damping that the
    matrix carries exactly (hinge c_theta, mass-proportional alpha_M); a soft lock at THETA_LOCK
    the preload keeps closed. ``variant`` "tilted": the mesh turned 30 degrees about E's x axis,
    off its x-y plane, where the floating frame's mass matrices have no node-graph form and the
    inertial block is summed over their nonzeros (body/node_mass_blocks.hpp,
    floating_frame_products.cpp), and the shell's tangent is formed element by element;
    "partial": the root nodes' drilling rotations left free (a node with some of its dofs held: the
    shell tangent's entries there scattered one by one, fem/shell_batch.hpp's runs).
    Returns the engine's compiled model (``_core.Model``)."""
    plate = dfx.paper2016.appendage_plate(2, 4, 2)
    nodes = plate.model.nodes.copy()
    nodes[:, 0] += B_H
    nodes[:, 1] -= W / 2
    if variant == "tilted":
        c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
        nodes = nodes @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T
    model = dfx.ShellModel(nodes, plate.model.quads, plate.laminate)
    fixed = plate.fixed_dofs("CFFF")
    if variant == "partial":
        fixed = fixed[fixed % 6 != 5]
    scene = (dfx.Scene().set_base(M_BASE, J_BASE * np.diag([1.0, 1.2, 0.9]), com=(0.1, -0.05, 0.02), free=free)
             .set_hinge(P_HINGE, (0.0, 1.0, 0.0), R_BE0=Ry(-np.pi / 2), tau0=TAU0, k_theta=K_THETA, c_theta=0.5,
                        fitting_mass=0.5, fitting_com=(0.01, 0.02, -0.01), fitting_inertia=0.02)
             .set_appendage(model, fixed, fidelity=fidelity, damping=(0.3, 0.0), modes=4))
    if lock:
        law = dfx.contact.ContactLaw("kelvin-voigt-hertz", K=1e9, n=1.5, D=1e6)
        scene.set_lock(THETA_LOCK, 0.03, 0.2e-3, law, friction=dfx.contact.Friction(0.25, 0.01))
    return scene.compile().core


def closed_lock(sys):
    """A run's data with the pin latched and resting on the stop: the residual then carries the
    stop's force (and the groove's friction) at any theta."""
    data = sys.make_data()
    history = _core.LockHistory()
    history.latched = True
    history.stop_contact = True
    history.stop_v0 = 0.1  # m/s, the approach speed at onset
    data.set_lock(0, history)
    return data


def num_elastic(sys):
    return sys.layout(0)["num_elastic"]


def generic_state(sys, fidelity, free, seed=0):
    rng = np.random.default_rng(seed)
    n, nq = sys.num_velocities, sys.num_positions
    q = sys.initial_positions()
    v = np.zeros(n)
    i = 0
    if free:
        q[:3] = [0.3, -0.2, 0.1]
        quat = np.array([0.9, 0.1, -0.3, 0.2])
        q[3:7] = quat / np.linalg.norm(quat)
        v[:6] = [0.05, -0.02, 0.03, 0.2, -0.3, 0.15]
        i = 6
    q[nq - n + i] = 0.3           # theta
    v[i] = 0.4                    # theta'
    ne = num_elastic(sys)
    if ne:
        if fidelity.startswith("reduced"):  # Ritz coordinates scaled to ~1 cm of displacement
            shapes = sys.displacement_map(0) @ sys.panel_tangent(0, np.zeros(ne))  # manifold: bending's
            scale = 1e-2 / np.abs(shapes).max(axis=0)
        else:
            scale = np.full(ne, 1e-3)
        q[nq - ne:] = scale * rng.normal(size=ne)
        v[n - ne:] = 3 * scale * rng.normal(size=ne)
    a = rng.normal(size=n)
    return q, v, a


def central(f, x, h):
    """Fourth-order central difference of f along x's unit directions (columns), step h."""
    cols = []
    for j in range(len(h)):
        e = np.zeros(len(h))
        e[j] = h[j]
        cols.append((8 * (f(x(e)) - f(x(-e))) - (f(x(2 * e)) - f(x(-2 * e)))) / (12 * h[j]))
    return np.column_stack(cols)


def row_groups(sys, free, rows):
    """Row index groups of one unit each (momentum: P and H)."""
    if rows == "momentum":
        return [np.arange(3), np.arange(3, 6)]
    n, ne = sys.num_velocities, num_elastic(sys)
    groups = [np.arange(3), np.arange(3, 6)] if free else []
    nb = n - ne
    groups.append(np.arange(6 if free else 0, nb))
    if ne:
        groups.append(np.arange(nb, n))
    return groups


def assert_matches(S, fd, groups, what):
    tol = np.zeros_like(fd)
    col = np.abs(fd)
    for g in groups:
        tol[g] = RTOL * col[g].max(axis=0)
    tol += ATOL * np.abs(fd).max()
    err = np.abs(S - fd)
    worst = np.unravel_index(np.argmax(err / tol), err.shape)
    assert np.all(err <= tol), (what, worst, S[worst], fd[worst], (err / (tol / RTOL))[worst])


CASES = [(f, free, lock, None) for f in FIDELITIES for free in (True, False) for lock in (False, True)]
CASES += [(f, True, False, "tilted") for f in ("linear", "nonlinear")] + [("nonlinear", True, False, "partial")]


@pytest.fixture(scope="module", params=CASES, ids=lambda c: f"{c[0]}-{'free' if c[1] else 'fixed'}"
                f"-{'lock' if c[2] else 'open'}" + (f"-{c[3]}" if c[3] else ""))
def case(request):
    fidelity, free, lock, variant = request.param
    sys = make_system(fidelity, free, lock, variant)
    data = closed_lock(sys) if lock else None
    q, v, a = generic_state(sys, fidelity, free)
    return fidelity, sys, data, free, lock, q, v, a


def test_newton_matrix_equals_central_differences(case):
    fidelity, sys, data, free, lock, q, v, a = case
    n = sys.num_velocities
    t = 0.0
    r = lambda qq, vv, aa: sys.residual(qq, vv, aa, t, data=data)
    hinge = 6 if free else 0
    if lock:  # the stop is closed: its torque enters the hinge row (a fresh run's data: open)
        assert r(q, v, a)[hinge] != sys.residual(q, v, a, t)[hinge]
    groups = row_groups(sys, free, "residual")
    ones = np.ones(n)
    fd_a = central(lambda aa: r(q, v, aa), lambda e: a + e, ones)
    # r is quadratic in v but for the lock's friction (the hinge row): unit steps, and a small
    # one for the hinge row's own entries.
    fd_v = central(lambda vv: r(q, vv, a), lambda e: v + e, ones)
    fd_v[hinge] = central(lambda vv: r(q, vv, a)[hinge], lambda e: v + e, np.full(n, 1e-4)).ravel()
    fd_q = central(lambda qq: r(qq, v, a), lambda e: sys.retract(q, e), np.full(n, 1e-3))
    for (ca, cv, cq), fd, what in [((1, 0, 0), fd_a, "dr/da"), ((0, 1, 0), fd_v, "dr/dv"),
                                   ((0, 0, 1), fd_q, "dr/dq")]:
        assert_matches(sys.newton_matrix(q, v, a, t, ca, cv, cq, data=data), fd, groups, what)
    # A Newton combination is the same combination of the parts.
    c = (1.0, 0.6 * 0.01, 0.3 * 0.01 ** 2)
    assert_matches(sys.newton_matrix(q, v, a, t, *c, data=data), c[0] * fd_a + c[1] * fd_v + c[2] * fd_q, groups,
                   "combination")


def test_momentum_jacobian_equals_central_differences(case):
    _, sys, data, free, _, q, v, _ = case
    n = sys.num_velocities
    Pi = lambda qq, vv: sys.momentum(qq, vv, data=data)
    fd_v = central(lambda vv: Pi(q, vv), lambda e: v + e, np.ones(n))  # Pi is linear in v
    fd_q = central(lambda qq: Pi(qq, v), lambda e: sys.retract(q, e), np.full(n, 1e-3))
    groups = row_groups(sys, free, "momentum")
    assert_matches(sys.momentum_jacobian(q, v, 1.0, 0.0, data=data), fd_v, groups, "dPi/dv")
    assert_matches(sys.momentum_jacobian(q, v, 0.0, 1.0, data=data), fd_q, groups, "dPi/dq")
    assert_matches(sys.momentum_jacobian(q, v, 1.0, 0.01, data=data), fd_v + 0.01 * fd_q, groups, "combination")


def assert_refreshed(sys, old, new, expect):
    """S from refreshed_newton_matrix: the new state's elastic block in the old border, or the old
    matrix whole where the refresh declines (expect False)."""
    c = (1.0, 0.6 * 0.01, 0.3 * 0.01 ** 2)
    S_old = sys.newton_matrix(*old, 0.0, *c)
    S_new = sys.newton_matrix(*new, 0.1, *c)
    S, refreshed = sys.refreshed_newton_matrix(*old, 0.0, *new, 0.1, *c)
    assert refreshed == expect
    if not refreshed:
        np.testing.assert_array_equal(S, S_old)
        return
    nb = sys.num_velocities - sum(sys.layout(k)["num_elastic"] for k in range(sys.num_hinges))
    # The block moved (the linear strains' by their inertial terms alone: 8e-8 of its largest entry).
    assert np.abs(S_new[nb:, nb:] - S_old[nb:, nb:]).max() > 1e-9 * np.abs(S_new[nb:, nb:]).max()
    np.testing.assert_array_equal(S[nb:, nb:], S_new[nb:, nb:])  # the same function at the same state
    np.testing.assert_array_equal(S[:nb], S_old[:nb])
    np.testing.assert_array_equal(S[:, :nb], S_old[:, :nb])


@pytest.mark.parametrize("fidelity", FIDELITIES)
def test_refreshed_matrix_is_the_new_elastic_block_in_the_old_border(fidelity):
    """A kept matrix's elastic block refreshed at a new state (what full Newton on a reduced
    Green-strain panel does between whole matrices; NewtonOptions::elastic_refreshes) is the
    Newton matrix of the new state there, checked against central differences above, and the
    old state's everywhere else; a manifold panel's block, which needs the whole force on its
    coordinates, and a rigid panel's (none) are left as built."""
    sys = make_system(fidelity, free=True, lock=False)
    old, new = generic_state(sys, fidelity, True, seed=0), generic_state(sys, fidelity, True, seed=1)
    assert_refreshed(sys, old, new, fidelity not in ("rigid", "reduced-manifold"))


def two_states(sys, seed):
    """Two states of a tree's model: its start, and one with every coordinate moved a little."""
    rng = np.random.default_rng(seed)
    n = sys.num_velocities
    q0, zero = sys.initial_positions(), np.zeros(n)
    q1 = sys.retract(q0, 1e-3 * rng.normal(size=n))
    return (q0, 0.1 * rng.normal(size=n), rng.normal(size=n)), (q1, 0.1 * rng.normal(size=n), zero)


def test_refreshed_matrix_on_trees():
    """Two wings of reduced Green-strain panels (the elastic blocks placed by the pattern's
    slots, not the identity): each panel's block refreshed, the rest as built. A hinge riding on
    a panel (its attachment's coupling shares the parent's values): declined, S as built."""
    wings = scenes.paper2016(2, "reduced-nonlinear", nx=2, ny=1, modes=4, wings=2).model.core
    assert_refreshed(wings, *two_states(wings, 0), True)
    array = chain_scenes.locked_array("reduced-nonlinear", 2).core
    assert_refreshed(array, *two_states(array, 1), False)
