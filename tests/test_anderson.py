"""Anderson acceleration of a fixed-point iteration (integrate/anderson), which accelerates the
full meshes' modified Newton with a kept matrix (GeneralizedAlpha::step), on linear iterations
x <- G x + c whose fixed point x* = (I - G)^-1 c numpy gives. References: Walker & Ni, SIAM J.
Numer. Anal. 49(4), 2011, 1715-1735: without memory it is the plain iteration, and with a memory
of at least n differences its iterates are x_k+1 = G x_k^GMRES + c (their Theorem 2.2), so it
reaches x* at the latest at iteration n + 1 (GMRES ends in n steps on an n x n system)."""
import numpy as np
import pytest

from deployfx import _core


def linear_map(n, radius, seed, dominant=None):
    """G = V diag(lambda) V^-1 with eigenvalues in [-radius, radius] (one at `dominant`, if
    given), a well-conditioned V, and c; x* by numpy."""
    rng = np.random.default_rng(seed)
    lam = rng.uniform(-radius, radius, n)
    if dominant is not None:
        lam[0] = dominant
    V = np.eye(n) + 0.3 * rng.normal(size=(n, n)) / np.sqrt(n)
    G = V @ np.diag(lam) @ np.linalg.inv(V)
    c = rng.normal(size=n)
    return G, c, np.linalg.solve(np.eye(n) - G, c)


def test_without_memory_it_is_the_plain_iteration():
    G, c, _ = linear_map(10, 0.5, 1)
    x0 = np.ones(10)
    X = _core.anderson_fixed_point(G, c, x0, 0, 8)
    x = x0.copy()
    for k in range(8):
        x = G @ x + c
        np.testing.assert_allclose(X[:, k + 1], x, rtol=1e-13, atol=1e-13)


@pytest.mark.parametrize("n, seed", [(6, 2), (12, 3), (20, 4)])
def test_full_memory_reaches_the_fixed_point_by_iteration_n_plus_1(n, seed):
    # An expanding map too (radius 1.5: the plain iteration diverges), as GMRES does not care.
    G, c, x_star = linear_map(n, 1.5, seed)
    X = _core.anderson_fixed_point(G, c, np.zeros(n), n, n + 1)
    assert np.abs(X[:, n + 1] - x_star).max() <= 1e-8 * np.abs(x_star).max()
    plain = np.zeros(n)
    for _ in range(n + 1):
        plain = G @ plain + c
    assert np.abs(plain - x_star).max() > 1e-2 * np.abs(x_star).max()


def test_short_memory_removes_a_dominant_slow_mode():
    # The kept Newton matrix's case: one slow mode (0.9) above fast ones (|lambda| <= 0.05). The
    # plain iteration gains 0.9 an iteration; with two differences of memory the slow mode is
    # gone within five iterations (the mixing has seen it twice) and the error then falls by
    # about 10 an iteration (measured: 4.6e-3 at 4, 1.4e-11 at 12).
    G, c, x_star = linear_map(30, 0.05, 5, dominant=0.9)
    x0 = np.zeros(30)
    err = lambda X: np.abs(X - x_star[:, None]).max(axis=0) / np.abs(x_star).max()
    plain = err(_core.anderson_fixed_point(G, c, x0, 0, 12))
    mixed = err(_core.anderson_fixed_point(G, c, x0, 2, 12))
    assert plain[12] > 0.25  # 0.9^12 = 0.28 of the slow mode's share left
    assert mixed[5] < 1e-2 * plain[5]
    assert mixed[12] < 1e-9


def test_parallel_increments_reach_the_fixed_point_and_stay_there():
    # G = g I: every increment f = (g - 1)(x - x*) is parallel to the last, so the history's
    # differences span one direction (dF of rank 1 once it holds two columns). One difference
    # makes the step exact: the Krylov space of a multiple of I has dimension 1, so GMRES (Walker
    # & Ni's Theorem 2.2) ends at x_2 = x*; the later iterates, mixed over the rank-deficient
    # history, must stay finite and at x*.
    n = 8
    rng = np.random.default_rng(7)
    G, c = 0.6 * np.eye(n), rng.normal(size=n)
    x_star = np.linalg.solve(np.eye(n) - G, c)
    X = _core.anderson_fixed_point(G, c, np.zeros(n), 2, 6)
    assert np.isfinite(X).all()
    for k in range(2, 7):
        assert np.abs(X[:, k] - x_star).max() <= 1e-12 * np.abs(x_star).max(), k


def test_bad_arguments_are_refused():
    G, c, _ = linear_map(4, 0.5, 6)
    with pytest.raises(ValueError, match="depth"):
        _core.anderson_fixed_point(G, c, np.zeros(4), -1, 3)
    with pytest.raises(ValueError, match="square"):
        _core.anderson_fixed_point(G[:3], c, np.zeros(4), 2, 3)
