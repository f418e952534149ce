"""Newton's bordered solve (integrate/bordered_solver): S = [A B; C E] with a dense border and a
sparse elastic block E, solved by the Schur complement on the border (block Gaussian elimination),
against LAPACK's dense solve of the assembled S (numpy). E is factorized by a sparse LDL^T of its
symmetric part (over the nodes' 6 x 6 blocks, math/block_ldlt.hpp, or scalar where the dofs do
not group into nodes) and, where Newton asks for the exact solve, refined against its skew part."""
import numpy as np
import pytest
import scipy.sparse as sp

import deployfx as dfx
from deployfx import _core


def bordered(nb, nodes=40, skew=0.0, seed=0, node_dofs=6):
    """A, B, C and a structurally symmetric E shaped like a chain of nodes of `node_dofs` dofs
    (dense blocks on the block tridiagonal), symmetric positive definite, plus `skew` times a skew
    part on its pattern (the floating frame's gyroscopic terms)."""
    rng = np.random.default_rng(seed)
    n = node_dofs * nodes
    chain = sp.diags([1.0, 1.0, 1.0], [-1, 0, 1], shape=(nodes, nodes))
    pattern = sp.kron(chain, np.ones((node_dofs, node_dofs))).tocoo()
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
        x, method = _core.bordered_solve(A, B, C, E, r, exact)
        assert method == "block-ldlt"
        assert np.abs(x - x_ref).max() <= 1e-12 * np.abs(x_ref).max()


@pytest.mark.parametrize("nb", [0, 7, 9], ids=lambda nb: f"border{nb}")
def test_in_plane_node_blocks_of_three(nb):
    # Nodes of three dofs (a shell's in-plane dofs: the slaved block of a membrane sweep) factorize
    # over 3 x 3 blocks (stored padded to 4 x 3); the solve of one right-hand side and the border's
    # columns at once (E^-1 C: seven, or nine in two passes of up to eight) match LAPACK's to 1e-12
    # relative, refined against a skew part or not.
    for skew in (0.0, 1e-4):
        A, B, C, E, r, x_ref = bordered(nb, nodes=50, skew=skew, node_dofs=3)
        x, method = _core.bordered_solve(A, B, C, E, r, True)
        assert method == "block-ldlt"
        assert np.abs(x - x_ref).max() <= (1e-12 if skew == 0 else 1e-7) * np.abs(x_ref).max()


def test_nodes_of_two_and_three_dofs_indefinite():
    # 3 x 3 blocks with every third node holding two dofs (padded with a unit pivot) and an
    # indefinite symmetric E (shifted past its fourth eigenvalue: each pivot block through its own
    # pivoted LDL^T), with a border of nine columns: backward stable (below 10 eps, Higham 2002,
    # Sec. 7.1) and within 1e-10 of LAPACK's solve.
    _, _, _, E, _, _ = bordered(1, nodes=45, node_dofs=3)
    keep = [d for d in range(E.shape[0]) if not (d // 3 % 3 == 1 and d % 3 == 2)]
    E = E[keep][:, keep]
    lam = np.linalg.eigvalsh(E.toarray())
    E = (E - 1.5 * lam[3] * sp.identity(E.shape[0])).tocsc()
    assert (np.linalg.eigvalsh(E.toarray()) < 0).sum() >= 4
    method, error, backward = _solve_check(E, nb=9)
    assert method == "block-ldlt"
    assert error <= 1e-10 and backward <= 10 * np.finfo(float).eps


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
    # A reduced model's modal block is full: S is factorized whole by one LU with partial pivoting
    # (math/dense_lu.hpp), exact, with no refinement to skip: LAPACK's solve to 1e-12 relative.
    rng = np.random.default_rng(1)
    n, nb = 36, 7
    E = rng.normal(size=(n, n)) + 12.0 * np.eye(n)
    A = rng.normal(size=(nb, nb)) + 10.0 * np.eye(nb)
    B, C = rng.normal(size=(nb, n)), rng.normal(size=(n, nb))
    r = rng.normal(size=nb + n)
    x_ref = np.linalg.solve(np.block([[A, B], [C, E]]), r)
    x, method = _core.bordered_solve(A, B, C, sp.csc_matrix(E), r, False)
    assert method == "dense-lu"
    assert np.abs(x - x_ref).max() <= 1e-12 * np.abs(x_ref).max()


def test_dense_lu_every_size_and_residue():
    # math/dense_lu takes two pivot columns at a time over columns padded to chunks of four rows:
    # every size up to DenseLU::kUnblocked and one past it (odd and even counts of pivots, every
    # residue of the rows modulo the chunk), with zero diagonals (a row exchange at every column),
    # keeps the backward error |S x - r| / (|S| |x|) at round-off (Higham, Accuracy and Stability
    # of Numerical Algorithms, 2002, Sec. 9.3).
    rng = np.random.default_rng(5)
    for m in range(3, 66):  # E, (m - 1) x (m - 1), half full or more: the dense path
        M = rng.normal(size=(m, m))
        np.fill_diagonal(M, 0.0)
        r = rng.normal(size=m)
        x, method = _core.bordered_solve(M[:1, :1], M[:1, 1:], M[1:, :1], sp.csc_matrix(M[1:, 1:]), r)
        assert method == "dense-lu"
        backward = np.abs(M @ x - r).max() / (np.abs(M).sum(axis=1).max() * np.abs(x).max())
        assert backward <= 10 * np.finfo(float).eps, m


def test_dense_lu_pivots_across_the_border():
    # The dense path factorizes S whole, pivoting by rows across border and elastic block: S is
    # solved where E alone is singular (a Schur complement on the border would need E^-1) and
    # where every diagonal entry is zero (no LU without row exchanges). The
    # backward error |S x - r| / (|S| |x|) stays at round-off (Higham, Accuracy and Stability of
    # Numerical Algorithms, 2002, Sec. 9.3: partial pivoting is backward stable in practice);
    # an S with a zero column (a coordinate nothing depends on) raises.
    rng = np.random.default_rng(2)
    n, nb = 12, 3
    E = rng.normal(size=(n, n))
    E[:, 0] = E[:, 1]  # rank-deficient: E^-1 does not exist
    A = rng.normal(size=(nb, nb))
    B, C = rng.normal(size=(nb, n)), rng.normal(size=(n, nb))
    S = np.block([[A, B], [C, E]])
    assert np.linalg.matrix_rank(E) == n - 1 and np.linalg.matrix_rank(S) == n + nb
    Z = S.copy()
    np.fill_diagonal(Z, 0.0)
    for M in (S, Z):
        r = rng.normal(size=n + nb)
        x, method = _core.bordered_solve(M[:nb, :nb], M[:nb, nb:], M[nb:, :nb], sp.csc_matrix(M[nb:, nb:]), r)
        assert method == "dense-lu"
        backward = np.abs(M @ x - r).max() / (np.abs(M).sum(axis=1).max() * np.abs(x).max())
        assert backward <= 10 * np.finfo(float).eps
    # Above DenseLU::kUnblocked rows Eigen's blocked LU takes over: the same backward error.
    m = 100
    M = rng.normal(size=(m, m))
    np.fill_diagonal(M, 0.0)
    r = rng.normal(size=m)
    x, method = _core.bordered_solve(M[:nb, :nb], M[:nb, nb:], M[nb:, :nb], sp.csc_matrix(M[nb:, nb:]), r)
    assert method == "dense-lu"
    assert np.abs(M @ x - r).max() / (np.abs(M).sum(axis=1).max() * np.abs(x).max()) <= 10 * np.finfo(float).eps
    # A non-finite entry (here in the first column, below its pivot: the pivot search passes it
    # over and the elimination spreads it) makes S singular for the solver, on either path.
    for M in (S.copy(), np.pad(S, ((0, m - n - nb), (0, m - n - nb))) + np.eye(m) * (np.arange(m) >= n + nb)):
        M[-1, 0] = np.nan
        with pytest.raises(ValueError, match="singular"):
            _core.bordered_solve(M[:nb, :nb], M[:nb, nb:], M[nb:, :nb], sp.csc_matrix(M[nb:, nb:]), M[:, 0] * 0)
    S_singular = S.copy()
    S_singular[:, -1] = 0.0
    with pytest.raises(ValueError, match="singular"):
        _core.bordered_solve(S_singular[:nb, :nb], S_singular[:nb, nb:], S_singular[nb:, :nb],
                             sp.csc_matrix(S_singular[nb:, nb:]), np.ones(n + nb))


def _solve_check(E, nb=7, seed=3):
    """(method, error relative to LAPACK's solve, normwise backward error |S x - r| / (|S| |x|),
    both in the max norm) of the bordered solve of E bordered by a random A, B, C."""
    rng = np.random.default_rng(seed)
    n = E.shape[0]
    A = rng.normal(size=(nb, nb)) + 10.0 * np.eye(nb)
    B, C = 0.3 * rng.normal(size=(nb, n)), 0.3 * rng.normal(size=(n, nb))
    S = np.block([[A, B], [C, E.toarray()]])
    r = rng.normal(size=nb + n)
    x_ref = np.linalg.solve(S, r)
    E = sp.csc_matrix(E)
    E.sort_indices()  # Eigen's compressed storage requires it; scipy's slicing may not keep it
    x, method = _core.bordered_solve(A, B, C, E, r, True)
    backward = np.abs(S @ x - r).max() / (np.abs(S).max() * np.abs(x).max())
    return method, np.abs(x - x_ref).max() / np.abs(x_ref).max(), backward


def test_node_blocks_of_a_clamped_shell_mesh():
    # The paper's appendage on a 6 x 4 mesh clamped at its root (CFFF: 180 free dofs in 30 nodes):
    # Newton's elastic block c_a M + c_q K (c_q = 0.3 h^2 at h = 0.01 s, generalized-alpha's
    # scale) on the mesh's pattern (full 6 x 6 node blocks, as the engine assembles it) is
    # factorized over the nodes' blocks in the AMD order of the node graph. The solve is backward
    # stable (normwise backward error below 10 eps; Higham, Accuracy and Stability of Numerical
    # Algorithms, 2002, Sec. 7.1) and, S having a condition number of 6e9, agrees with LAPACK's
    # to 1e-9.
    plate = dfx.paper2016.appendage_plate(2, 6, 4)
    free = np.setdiff1d(np.arange(plate.model.num_dofs), plate.fixed_dofs("CFFF"))
    pattern = plate.model.stiffness_matrix().tocsc()[free][:, free].tocoo()  # explicit zeros kept
    M = plate.model.mass_matrix()[free][:, free]
    dense = (M + 0.3 * 0.01**2 * pattern).toarray()
    E = sp.csc_matrix((dense[pattern.row, pattern.col], (pattern.row, pattern.col)),
                      shape=dense.shape)
    method, error, backward = _solve_check(E)
    assert method == "block-ldlt"
    assert backward <= 10 * np.finfo(float).eps
    assert error <= 1e-9


def test_nodes_with_held_dofs_and_an_indefinite_block():
    # Nodes with fewer than six dofs (held dofs removed: groups of 3 to 6 are padded with unit
    # pivots) and a symmetric E that is not positive definite (the symmetric part of Newton's
    # matrix under compression: shifted by 1.5 x its fourth eigenvalue, so four are negative)
    # still factorize by blocks, each pivot block through its own pivoted LDL^T: backward stable
    # (below 10 eps, Higham 2002, Sec. 7.1, as above) and within 1e-10 of LAPACK's solve.
    _, _, _, E, _, _ = bordered(1, nodes=30)
    # Every fourth node keeps three dofs.
    keep = [d for d in range(E.shape[0]) if not (d // 6 % 4 == 1 and d % 6 >= 3)]
    E = E[keep][:, keep]
    lam = np.linalg.eigvalsh(E.toarray())
    E = (E - 1.5 * lam[3] * sp.identity(E.shape[0])).tocsc()
    assert (np.linalg.eigvalsh(E.toarray()) < 0).sum() >= 4
    method, error, backward = _solve_check(E)
    assert method == "block-ldlt"
    assert error <= 1e-10 and backward <= 10 * np.finfo(float).eps


def test_dofs_without_node_blocks_take_the_scalar_ldlt():
    # A pattern whose dofs do not group into nodes (a scalar tridiagonal chain) goes through Eigen's
    # scalar LDL^T of the symmetric part: exact to 1e-12.
    n = 60
    E = sp.diags([-1.0, 4.0, -1.0], [-1, 0, 1], shape=(n, n)).tocsc()
    method, error, backward = _solve_check(E)
    assert method == "simplicial-ldlt"
    assert error <= 1e-12 and backward <= 10 * np.finfo(float).eps


def test_bad_shapes_raise_value_error():
    A, B, C, E, r, _ = bordered(7)
    with pytest.raises(ValueError, match="must be square"):
        _core.bordered_solve(A, B, C, E, r[:-1])


def test_solve_cost_reports_the_solver_and_its_times():
    # bench/targets.py's floor (issue 27): the engine's own bordered solver timed in C++ on one
    # thread's CPU clock. Only what it reports is checked, never how fast (no timing assertions):
    # the method the solver chose, and three positive finite times.
    A, B, C, E, r, _ = bordered(7)
    cost = _core.bordered_solve_cost(A, B, C, E, r, 0.01)
    assert cost["method"] == "block-ldlt"
    for key in ("factorize", "solve", "solve_exact"):
        assert np.isfinite(cost[key]) and cost[key] > 0
    with pytest.raises(ValueError, match="seconds"):
        _core.bordered_solve_cost(A, B, C, E, r, 0.0)
    with pytest.raises(ValueError, match="square"):
        _core.bordered_solve_cost(A, B, C, E, r[:-1], 0.01)
