"""Newton's bordered solve (integrate/bordered_solver): S = [A B; C E] with a dense border and a
sparse elastic block E, solved by the Schur complement on the border (block Gaussian elimination),
against LAPACK's dense solve of the assembled S (numpy). E is factorized by a sparse LDL^T of its
symmetric part and, where Newton asks for the exact solve, refined against its skew part."""
import numpy as np
import pytest
import scipy.sparse as sp

from deployfx import _core


def bordered(nb, nodes=40, skew=0.0, seed=0):
    """A, B, C and a structurally symmetric E shaped like a chain of 6-dof nodes (6 x 6 blocks on
    the block tridiagonal), symmetric positive definite, plus `skew` times a skew part on its
    pattern (the floating frame's gyroscopic terms)."""
    rng = np.random.default_rng(seed)
    n = 6 * nodes
    chain = sp.diags([1.0, 1.0, 1.0], [-1, 0, 1], shape=(nodes, nodes))
    pattern = sp.kron(chain, np.ones((6, 6))).tocoo()
    values = rng.normal(size=pattern.nnz)
    R = sp.coo_matrix((values, (pattern.row, pattern.col)), shape=(n, n)).tocsc()
    Es = 0.1 * (R + R.T) + 4.0 * sp.identity(n)  # Gershgorin: definite
    E = (Es + skew * (R - R.T)).tocsc()
    A = rng.normal(size=(nb, nb)) + 10.0 * np.eye(nb)
    B, C = 0.3 * rng.normal(size=(nb, n)), 0.3 * rng.normal(size=(n, nb))
    r = rng.normal(size=nb + n)
    S = np.block([[A, B], [C, E.toarray()]])
    return A, B, C, E, r, np.linalg.solve(S, r)


@pytest.mark.parametrize("nb", [1, 7, 9], ids=lambda nb: f"border{nb}")
def test_symmetric_elastic_block_solves_to_round_off(nb):
    # Without a skew part the LDL^T of E is exact: the solve matches LAPACK's to 1e-12 relative,
    # with or without refinement, for a border of 1 (fixed base), 7 (free base and hinge: the
    # block solve E^-1 C of the Schur complement, all columns at once) and 9 columns (Eigen's
    # column-by-column solve).
    A, B, C, E, r, x_ref = bordered(nb)
    for exact in (True, False):
        x, dense = _core.bordered_solve(A, B, C, E, r, exact)
        assert not dense
        assert np.abs(x - x_ref).max() <= 1e-12 * np.abs(x_ref).max()


def test_skew_part_is_refined_only_for_the_exact_solve():
    # E's skew part (here 1e-4 of its random entries; a radius of Es^-1 Ek of a few 1e-4, below
    # the 1e-3 above which E is factorized exactly by the sparse LU) is dropped from the LDL^T: the
    # unrefined solve is off by about that radius (between 1e-10 and the 1e-3 bound); the exact
    # solve refines to 1e-8 of x (its stop test), checked at 1e-7.
    A, B, C, E, r, x_ref = bordered(7, skew=1e-4)
    x_exact, _ = _core.bordered_solve(A, B, C, E, r, True)
    x_fast, _ = _core.bordered_solve(A, B, C, E, r, False)
    scale = np.abs(x_ref).max()
    assert np.abs(x_exact - x_ref).max() <= 1e-7 * scale
    assert 1e-10 * scale < np.abs(x_fast - x_ref).max() <= 1e-3 * scale


def test_dense_elastic_block_takes_the_dense_lu():
    # A reduced model's modal block is full: the dense LU is exact, with no refinement to skip.
    rng = np.random.default_rng(1)
    n, nb = 36, 7
    E = rng.normal(size=(n, n)) + 12.0 * np.eye(n)
    A = rng.normal(size=(nb, nb)) + 10.0 * np.eye(nb)
    B, C = rng.normal(size=(nb, n)), rng.normal(size=(n, nb))
    r = rng.normal(size=nb + n)
    x_ref = np.linalg.solve(np.block([[A, B], [C, E]]), r)
    x, dense = _core.bordered_solve(A, B, C, sp.csc_matrix(E), r, False)
    assert dense
    assert np.abs(x - x_ref).max() <= 1e-12 * np.abs(x_ref).max()


def test_bad_shapes_raise_value_error():
    A, B, C, E, r, _ = bordered(7)
    with pytest.raises(ValueError, match="must be square"):
        _core.bordered_solve(A, B, C, E, r[:-1])
