"""Algebraic properties of the shell element: symmetry, definiteness, rigid-body modes,
finite-difference checks of the analytic internal force and tangent (incl. the geometric
stiffness K_s of You et al. 2016 Eq. 22), frame invariance in 3D, and linear buckling."""
import numpy as np
import pytest
import scipy.linalg
import scipy.sparse.linalg

import deployfx as dfx
from closed_forms import flexural_rigidity, uniaxial_buckling_resultant_ss_square


def distorted_model(laminate, seed=0):
    # A 3 x 2 mesh with interior nodes moved off the grid, so no element is a parallelogram.
    rng = np.random.default_rng(seed)
    xs, ys = np.linspace(0, 0.3, 4), np.linspace(0, 0.2, 3)
    nodes = np.array([[x, y, 0.0] for y in ys for x in xs])
    interior = [5, 6]
    nodes[interior, :2] += rng.uniform(-0.02, 0.02, size=(2, 2))
    quads = np.array([[j * 4 + i, j * 4 + i + 1, (j + 1) * 4 + i + 1, (j + 1) * 4 + i]
                      for j in range(2) for i in range(3)])
    return dfx.ShellModel(nodes, quads, laminate)


def unsymmetric_laminate():
    m = dfx.paper2016.IM6_SC1081
    return dfx.Laminate.from_angles(m, 0.5e-3, [0, 45, 90])  # B != 0, A16 != 0, I1 = 0


def test_stiffness_and_mass_symmetric_definite():
    model = distorted_model(unsymmetric_laminate())
    K = model.stiffness_matrix().toarray()
    M = model.mass_matrix().toarray()
    np.testing.assert_allclose(K, K.T, atol=1e-12 * np.abs(K).max())
    np.testing.assert_allclose(M, M.T, atol=1e-12 * np.abs(M).max())
    assert np.linalg.eigvalsh(M).min() > 0  # consistent mass with rotary inertia: definite
    # K is positive semi-definite with exactly six rigid-body modes (generalised problem). A
    # symmetric eigensolver finds each eigenvalue to within about eps lam_max (Golub & Van Loan,
    # Matrix Computations, 4th ed., Sec. 8.1): the rigid-body ones lie at that round-off (here
    # 3e-3 against eps lam_max = 5e-3), the seventh far above it.
    lam = scipy.linalg.eigh(K, M, eigvals_only=True)
    roundoff = 1e2 * np.finfo(float).eps * lam[-1]
    assert np.all(np.abs(lam[:6]) < roundoff), (lam[:8], roundoff)
    assert lam[6] > 1e5 * roundoff


def test_total_mass_and_rigid_translation():
    lam = unsymmetric_laminate()
    model = distorted_model(lam)
    area = 0.3 * 0.2
    assert model.mass == pytest.approx(lam.mass_per_area * area, rel=1e-12)
    # A rigid translation carries no strain energy and no internal force.
    u = np.tile([1e-3, -2e-3, 3e-3, 0, 0, 0], model.nodes.shape[0])
    f, _ = model.internal_force(u)
    assert np.abs(f).max() < 1e-9 * np.abs(model.stiffness_matrix() @ np.ones_like(u)).max()


def test_internal_force_is_gradient_of_energy_and_tangent_is_its_jacobian():
    # Central differences, step 1e-7 of the displacement scale, tolerance 1e-5 relative
    # (truncation O(step^2), round-off O(eps/step)).
    model = distorted_model(unsymmetric_laminate(), seed=1)
    rng = np.random.default_rng(2)
    n = model.num_dofs
    u = rng.normal(size=n) * 2e-3  # displacements ~ thickness: the nonlinear terms matter
    f, K = model.internal_force(u)
    K = K.toarray()
    step = 1e-7 * 2e-3
    f_fd = np.array([(model.strain_energy(u + step * e) - model.strain_energy(u - step * e)) / (2 * step)
                     for e in np.eye(n)])
    np.testing.assert_allclose(f, f_fd, atol=1e-5 * np.abs(f).max())
    K_fd = np.column_stack([(model.internal_force(u + step * e)[0] - model.internal_force(u - step * e)[0])
                            / (2 * step) for e in np.eye(n)])
    np.testing.assert_allclose(K, K_fd, atol=1e-5 * np.abs(K).max())
    np.testing.assert_allclose(K, K.T, atol=1e-10 * np.abs(K).max())
    # The nonlinear tangent differs from K_L by a visible amount at this amplitude.
    assert np.abs(K - model.stiffness_matrix().toarray()).max() > 1e-4 * np.abs(K).max()


@pytest.mark.parametrize("tilted", [False, True], ids=["flat", "tilted"])
def test_force_and_tangent_alone_are_the_elements(tilted):
    # The residual's force alone and the Newton matrix's tangent alone: on a mesh in world axes
    # four elements at a time, lane by lane (fem/shell_batch.hpp; 6 elements: a full batch and one
    # with two unused lanes), else element by element. Against the energy's and the force's
    # central differences (as above, 1e-5) and the element's own force and tangent
    # (internal_force's, formed together) to round-off (1e-13 relative: the same terms summed in
    # another order), and so is the energy alone; the force's in-plane rows (u, v, theta_z) alone the same, every other row zero.
    model = distorted_model(unsymmetric_laminate(), seed=1)
    if tilted:  # turned 30 degrees about x: no element in world axes
        c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
        model = dfx.ShellModel(model.nodes @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T, model.quads,
                               unsymmetric_laminate())
    assert model._impl.batched_force == (not tilted)
    rng = np.random.default_rng(2)
    n = model.num_dofs
    u = rng.normal(size=n) * 2e-3
    f = model._impl.force(u)
    step = 1e-7 * 2e-3
    f_fd = np.array([(model.strain_energy(u + step * e) - model.strain_energy(u - step * e)) / (2 * step)
                     for e in np.eye(n)])
    np.testing.assert_allclose(f, f_fd, atol=1e-5 * np.abs(f).max())
    f_element, K_element = model.internal_force(u)
    np.testing.assert_allclose(f, f_element, rtol=0, atol=1e-13 * np.abs(f).max())
    # The energy alone (an output's) against the 24-column operators' reference.
    assert model._impl.energy(u) == pytest.approx(model.strain_energy(u), rel=1e-13)
    K = model._impl.tangent(u).toarray()
    np.testing.assert_allclose(K, K_element.toarray(), rtol=0, atol=1e-13 * np.abs(K).max())
    K_fd = np.column_stack([(model._impl.force(u + step * e) - model._impl.force(u - step * e)) / (2 * step)
                            for e in np.eye(n)])
    np.testing.assert_allclose(K, K_fd, atol=1e-5 * np.abs(K).max())
    in_plane = np.sort(np.concatenate([np.arange(k, n, 6) for k in (0, 1, 5)]))
    rows = model._impl.force(u, True)
    if not tilted:  # a tilted element's in-plane rows are its whole force (ShellElement::in_plane_force)
        np.testing.assert_array_equal(rows[in_plane], f[in_plane])
        np.testing.assert_array_equal(np.delete(rows, in_plane), 0.0)


def test_geometric_stiffness_of_a_uniform_stretch():
    # K_s (Eq. 22) from given resultants and from the resultants of a displacement agree, and
    # equal the transverse block of the tangent's change under an in-plane stretch.
    lam = unsymmetric_laminate()
    model = distorted_model(lam, seed=3)
    n = model.num_dofs
    nodes = model.nodes
    # A uniform in-plane stretch: eps_x = 1e-4, eps_y = -5e-5, gamma_xy = 2e-5.
    eps = np.array([1e-4, -5e-5, 2e-5])
    u0 = np.zeros(n)
    u0[0::6] = eps[0] * nodes[:, 0] + eps[2] * nodes[:, 1]
    u0[1::6] = eps[1] * nodes[:, 1]
    N = lam.A @ eps  # B kappa = 0 for a pure stretch
    Ks_uniform = model.geometric_stiffness(N).toarray()
    Ks_from_u = model.geometric_stiffness_from(u0).toarray()
    np.testing.assert_allclose(Ks_from_u, Ks_uniform, atol=1e-10 * np.abs(Ks_uniform).max())
    # Tangent at u0 = K_L + K_L*(u0) + K_s(N(u0)). In the transverse (w) block K_L* vanishes for an
    # in-plane deformation, so the block equals K_s of the exact Green-strain resultants
    # (Eq. 14 for the uniform gradient u,x = e0, u,y = e2, v,x = 0, v,y = e1). 1e-9 relative.
    e0, e1, e2 = eps
    green = np.array([e0 + 0.5 * e0**2, e1 + 0.5 * (e1**2 + e2**2), e2 + e0 * e2])
    Ks_green = model.geometric_stiffness(lam.A @ green).toarray()
    _, K_T = model.internal_force(u0)
    w = np.arange(2, n, 6)
    dK = (K_T.toarray() - model.stiffness_matrix().toarray())[np.ix_(w, w)]
    np.testing.assert_allclose(dK, Ks_green[np.ix_(w, w)], atol=1e-9 * np.abs(Ks_green[np.ix_(w, w)]).max())


def test_linear_buckling_of_simply_supported_square_plate():
    # Timoshenko & Gere (1961) Sec. 9.2: N_cr = 4 pi^2 D / b^2 under uniaxial compression.
    # (K + lambda K_s(N0)) phi = 0 with N0 = (-1, 0, 0) N/m. a/h = 100, 16 x 16: within 2 %.
    a, h = 1.0, 0.01
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(200e9, 0.3, 8000.0), h, 0.0)])
    plate = dfx.Plate(a, a, lam, 16, 16)
    free = np.setdiff1d(np.arange(plate.model.num_dofs), plate.fixed_dofs("SSSS"))
    K = plate.model.stiffness_matrix()[free][:, free]
    G = -plate.model.geometric_stiffness([-1.0, 0.0, 0.0])[free][:, free]
    mu = scipy.sparse.linalg.eigsh(G.tocsc(), k=1, M=K.tocsc(), which="LA", return_eigenvectors=False)
    N_cr = 1.0 / mu.max()
    assert N_cr == pytest.approx(uniaxial_buckling_resultant_ss_square(flexural_rigidity(200e9, 0.3, h), a),
                                 rel=0.02)


def test_frequencies_invariant_under_rigid_rotation_in_3d():
    # The element sits in 3D: a free plate rotated arbitrarily (nodes and ref_axis) has the same
    # spectrum to 1e-8 relative.
    lam = unsymmetric_laminate()
    base = distorted_model(lam, seed=4)
    rng = np.random.default_rng(5)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    Q *= np.sign(np.linalg.det(Q))  # a proper rotation
    moved = dfx.ShellModel(base.nodes @ Q.T + [1.0, -2.0, 0.5], base.quads, lam, ref_axis=Q @ [1, 0, 0])
    f0, _ = base.modes(12)
    f1, _ = moved.modes(12)
    np.testing.assert_allclose(f1[6:], f0[6:], rtol=1e-8)
    assert np.all(f1[:6] < 1e-3 * f1[6])  # rigid-body omega^2 at round-off: < 1e-6 of omega_7^2


@pytest.mark.parametrize("nodes, match", [
    (np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0.2], [0, 1, 0]]), "warped"),
    (np.array([[0, 0, 0], [1, 0, 0], [0.2, 0.2, 0], [0, 1, 0]]), "convex"),
    (np.array([[0, 0, 0], [1, 0, 0], [1, 0, 0], [0, 0, 0]]), "degenerate"),
])
def test_bad_elements_are_rejected(nodes, match):
    lam = unsymmetric_laminate()
    with pytest.raises(ValueError, match=match):
        dfx.ShellModel(nodes, np.array([[0, 1, 2, 3]]), lam)


def test_bad_plate_arguments():
    lam = unsymmetric_laminate()
    with pytest.raises(ValueError, match="Plate.nx"):
        dfx.Plate(1.0, 1.0, lam, 0, 4)
    with pytest.raises(ValueError, match="Plate.length"):
        dfx.Plate(-1.0, 1.0, lam, 4, 4)
    p = dfx.Plate(1.0, 1.0, lam, 2, 2)
    with pytest.raises(ValueError, match="boundary"):
        p.natural_frequencies(3, "CFX")
    with pytest.raises(ValueError, match="n = 0"):
        p.natural_frequencies(0, "CFFF")
    with pytest.raises(ValueError, match="pressure"):
        p.static(float("nan"), "CCCC")
    # A plate at most 1000 km long and wide (the largest double overflowed the mesh and the error
    # blamed non-finite nodes: a fuzz finding).
    for length, width, name in ((np.finfo(float).max, 1.0, "length"), (1.0, 2e6, "width")):
        with pytest.raises(ValueError, match=rf"Plate.{name} = .* is out of range: must be in \(0, 1e6\] \(m\)"):
            dfx.Plate(length, width, lam, 4, 1)
