"""A Green-strain mesh panel's in-plane rows of the residual formed alone (multibody::slaved_rows),
what Newton's membrane sweep reads before it moves the in-plane coordinates
(GeneralizedAlpha::relax_slaved): the same rows as the whole residual's, to round-off, at a
generic state of every kind the rows depend on (free and fixed base, the frame spinning and
accelerating, the plate deformed and vibrating, mass- and stiffness-proportional damping, the lock
closed), on one panel and on two wings. Where the rows are not formed alone (reduced panels, whose
Ritz force is formed whole; a hinge riding on the panel, whose attachment's forces need the
subtree's backward pass) the binding returns None and the integrator takes the whole residual.

Reference: the residual itself (tests/test_iteration_matrix.py checks its derivatives against
central differences). Tolerance: 1e-12 of the largest in-plane entry, the round-off of sums taken
in another order (the rows' products are the whole products' rows, the element forces the same
terms without the bending rows'); measured: equal to the bit at these states. The integrator's
use of them (GeneralizedAlpha::relax_slaved) is checked here on a panel at rest, where the rows
are exactly zero and no sweep is taken; the runs it makes are checked against reference
solutions by the validation suite and the trade table."""
import numpy as np
import pytest

import deployfx as dfx
from deployfx import scenes

import chain_scenes  # tests/: scenes shared by tests
from test_iteration_matrix import closed_lock, generic_state, make_system

RTOL = 1e-12


def assert_rows(sys, q, v, a, t=0.1, data=None):
    """The rows formed alone equal the residual's at the slaved indices."""
    slaved, rows = sys.slaved_rows(q, v, a, t, data=data)
    assert len(slaved) > 0 and rows is not None
    r = sys.residual(q, v, a, t, data=data)
    scale = np.abs(r[slaved]).max()
    assert scale > 0
    np.testing.assert_allclose(rows, r[slaved], rtol=0, atol=RTOL * scale)
    # The other rows are not small: the rows formed alone are a subset worth forming alone.
    others = np.delete(r, slaved)
    assert np.abs(others).max() > 0


@pytest.mark.parametrize("free", [True, False], ids=["free", "fixed"])
@pytest.mark.parametrize("lock", [False, True], ids=["open", "lock"])
def test_in_plane_rows_equal_the_residuals(free, lock):
    sys = make_system("nonlinear", free, lock)
    q, v, a = generic_state(sys, "nonlinear", free)
    assert_rows(sys, q, v, a, data=closed_lock(sys) if lock else None)


def test_stiffness_proportional_damping_rows():
    """beta_K K_T(d) d' (a central difference of the element forces along d') on the rows alone."""
    plate = dfx.paper2016.appendage_plate(2, 4, 2)
    scene = (dfx.Scene().set_base(3000.0, 500.0 * np.eye(3), free=True)
             .set_hinge((0.83, 0.0, 0.0), (0.0, 1.0, 0.0), tau0=7.2, k_theta=4.6)
             .set_appendage(plate.model, plate.fixed_dofs("CFFF"), fidelity="nonlinear", damping=(0.3, 2e-4)))
    sys = scene.compile().core
    q, v, a = generic_state(sys, "nonlinear", True, seed=3)
    assert_rows(sys, q, v, a)


def test_rows_of_a_mesh_facing_minus_z():
    """Elements whose normal is -z (the quads' nodes reversed): the residual's floating-frame
    products then come from the sparse M_ij, not the node graph (FloatingFrameInertia's NodeMass
    needs the fibre rotation of a +z normal); the rows formed alone agree with them."""
    plate = dfx.paper2016.appendage_plate(2, 4, 2)
    model = dfx.ShellModel(plate.model.nodes, plate.model.quads[:, ::-1].copy(), plate.laminate)
    scene = (dfx.Scene().set_base(3000.0, 500.0 * np.eye(3), free=True)
             .set_hinge((0.83, 0.0, 0.0), (0.0, 1.0, 0.0), tau0=7.2, k_theta=4.6)
             .set_appendage(model, plate.fixed_dofs("CFFF"), fidelity="nonlinear", damping=(0.3, 0.0)))
    sys = scene.compile().core
    q, v, a = generic_state(sys, "nonlinear", True, seed=5)
    assert_rows(sys, q, v, a)


def test_two_wings_rows_in_slaved_order():
    """Each wing's in-plane rows, in the order of the slaved indices (panel by panel)."""
    wings = scenes.paper2016(2, "nonlinear", nx=3, ny=2, wings=2).model.core
    rng = np.random.default_rng(4)
    n = wings.num_velocities
    q = wings.retract(wings.initial_positions(), 1e-3 * rng.normal(size=n))
    assert_rows(wings, q, 0.1 * rng.normal(size=n), rng.normal(size=n))


@pytest.mark.parametrize("fidelity", ["reduced-nonlinear", "linear", "rigid"])
def test_rows_not_formed_alone_elsewhere(fidelity):
    """A reduced Green-strain panel has slaved rows but forms its Ritz force whole (None); linear
    strain and a rigid panel have none (no rows)."""
    sys = make_system(fidelity, True, False)
    q, v, a = generic_state(sys, fidelity, True)
    slaved, rows = sys.slaved_rows(q, v, a, 0.1)
    if fidelity == "reduced-nonlinear":
        assert len(slaved) > 0 and rows is None
    else:
        assert len(slaved) == 0 and len(rows) == 0


def test_hinge_on_the_panel_takes_the_whole_residual():
    array = chain_scenes.locked_array("nonlinear", 2).core
    n = array.num_velocities
    slaved, rows = array.slaved_rows(array.initial_positions(), np.zeros(n), np.zeros(n), 0.0)
    assert len(slaved) > 0 and rows is None


def test_panel_at_rest_stays_at_rest():
    """No preload, no motion: the in-plane rows are exactly zero at every predictor, so the
    relaxation hands Newton the whole residual without sweeping (GeneralizedAlpha::relax_slaved's
    rows-alone path) and Newton converges at its first iteration; the state stays the start's to
    the bit (an equilibrium of the equations: Newton's increments are exactly zero)."""
    plate = dfx.paper2016.appendage_plate(2, 4, 2)
    scene = (dfx.Scene().set_base(3000.0, 500.0 * np.eye(3), free=True)
             .set_hinge((0.83, 0.0, 0.0), (0.0, 1.0, 0.0), tau0=0.0, k_theta=4.6)
             .set_appendage(plate.model, plate.fixed_dofs("CFFF"), fidelity="nonlinear", damping=(0.3, 0.0)))
    result = scene.compile().simulate(0.2, 0.01, progress=False)
    q, v = np.asarray(result.q), np.asarray(result.v)
    np.testing.assert_array_equal(q, np.broadcast_to(q[0], q.shape))
    np.testing.assert_array_equal(v, 0.0)
    assert result.metadata["newton_iterations"] == result.metadata["substeps"] == 20
