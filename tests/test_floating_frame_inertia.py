"""Floating-frame inertia shape integrals (You et al. 2016 Eq. 9, 28; Shabana 2013 Sec. 5.4)
against closed-form rigid-plate properties and a brute-force kinetic energy integral."""
import numpy as np
import pytest

import deployfx as dfx

A, B, NX, NY = 0.6, 0.4, 3, 2


def two_density_laminate():
    # Plies of different density put the mass centroid off the mid-plane (I1 != 0).
    light = dfx.Isotropic(70e9, 0.3, 1000.0)
    heavy = dfx.Isotropic(70e9, 0.3, 3000.0)
    return dfx.Laminate([dfx.Ply(light, 1e-3, 0), dfx.Ply(heavy, 2e-3, 0)])


@pytest.fixture(scope="module")
def setup():
    lam = two_density_laminate()
    plate = dfx.Plate(A, B, lam, NX, NY)
    return lam, plate, plate.model.floating_frame_inertia()


def test_rigid_plate_mass_properties(setup):
    # Rectangle [0, a] x [0, b], mass moments I0, I1, I2 through the thickness: closed forms of
    # int rho P dV and int rho P P^T dV (1e-12 relative).
    lam, _, ffi = setup
    I0, I1, I2 = lam.mass_per_area, lam.first_moment_per_area, lam.rotary_inertia_per_area
    area = A * B
    assert I1 != 0
    assert ffi.mass == pytest.approx(I0 * area, rel=1e-12)
    np.testing.assert_allclose(ffi.S0, [I0 * area * A / 2, I0 * area * B / 2, I1 * area], rtol=1e-12)
    E0 = np.array([
        [I0 * B * A**3 / 3, I0 * A**2 * B**2 / 4, I1 * B * A**2 / 2],
        [I0 * A**2 * B**2 / 4, I0 * A * B**3 / 3, I1 * A * B**2 / 2],
        [I1 * B * A**2 / 2, I1 * A * B**2 / 2, I2 * area],
    ])
    np.testing.assert_allclose(ffi.E0, E0, rtol=1e-12)
    np.testing.assert_allclose(ffi.J0, np.trace(E0) * np.eye(3) - E0, rtol=1e-12)


def test_component_masses_add_up_to_the_element_mass(setup):
    # sum_i M_ii = M except the drilling inertia, which lives on theta_z only (a flat mesh in x-y).
    _, plate, ffi = setup
    M = plate.model.mass_matrix().toarray()
    D = M - sum(ffi.Mij(i, i).toarray() for i in range(3))
    drill = np.arange(5, M.shape[0], 6)
    rest = np.setdiff1d(np.arange(M.shape[0]), drill)
    assert np.abs(D[np.ix_(rest, rest)]).max() < 1e-14 * np.abs(M).max()
    assert np.abs(D[np.ix_(rest, drill)]).max() < 1e-14 * np.abs(M).max()
    assert np.all(np.linalg.eigvalsh(D[np.ix_(drill, drill)]) > 0)
    for i in range(3):
        for j in range(3):
            np.testing.assert_allclose(ffi.Mij(i, j).toarray(), ffi.Mij(j, i).toarray().T, atol=1e-16)


def tilted_plate_inertia(lam):
    """The fixture's plate turned 30 degrees about x (off the x-y plane): its products take the
    nine sparse M_ij (the node-graph split needs a mid-surface in the x-y plane)."""
    plate = dfx.Plate(A, B, lam, NX, NY)
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    R = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    model = dfx.ShellModel(plate.model.nodes @ R.T, plate.model.quads, lam)
    return model, model.floating_frame_inertia()


@pytest.mark.parametrize("mesh", ["flat", "tilted"])
def test_products_equal_each_mass_blocks_product(setup, mesh):
    # products() forms the nine M_ij z without the nine sparse products: on a mesh in the x-y plane
    # from three scalar matrices on the node graph (body/floating_frame_products.cpp), otherwise with
    # M_ji z as (M_ij^T) z in the pass over M_ij (M_ji = M_ij^T, checked above). Each must equal
    # the sparse product with its own block to round-off (1e-14 of |M_ij| |z|, the summation order
    # differing), the blocks' zeros included.
    lam, plate, ffi = setup
    model = plate.model
    if mesh == "tilted":
        model, ffi = tilted_plate_inertia(lam)
    rng = np.random.default_rng(3)
    z, z2 = rng.normal(size=model.num_dofs), rng.normal(size=model.num_dofs)
    P = ffi.products(z)
    P1, P2 = ffi.products_pair(z, z2)  # two vectors in one pass (a residual's d and dd')
    assert len(P) == len(P1) == len(P2) == 9
    for i in range(3):
        for j in range(3):
            Mij = ffi.Mij(i, j)
            for p, v in ((P, z), (P1, z), (P2, z2)):
                scale = abs(Mij).max() * np.abs(v).sum()
                assert np.abs(p[3 * i + j] - Mij @ v).max() <= 1e-14 * scale, (i, j)
    # The pair's first set is the single vector's to the bit: a run's memo hands out either, and a
    # resumed run (its memo empty) must go on bit for bit (tests/test_checkpoint.py).
    for k in range(9):
        np.testing.assert_array_equal(P1[k], P[k])
    with pytest.raises(ValueError, match="z has wrong size"):
        ffi.products(z[:-1])


def test_products_memo_returns_each_vectors_own_products(setup):
    # products() keeps its last four results: asked again for a vector it holds, it must give
    # that vector's products (bit for bit), for one it has dropped (five others since) a fresh
    # computation, and for a vector with other values (however close) its own products.
    _, plate, ffi = setup
    rng = np.random.default_rng(4)
    zs = [rng.normal(size=plate.model.num_dofs) for _ in range(6)]
    first = [ffi.products(z) for z in zs]
    for z, P in zip(zs[::-1], first[::-1]):  # the last four from the memo, the first two anew
        again = ffi.products(z.copy())
        for k in range(9):
            np.testing.assert_array_equal(again[k], P[k])
    z = zs[0] * (1 + 1e-9)
    P = ffi.products(z)
    for k in range(9):
        Mk = ffi.Mij(k // 3, k % 3)
        assert np.abs(P[k] - Mk @ z).max() <= 1e-14 * abs(Mk).max() * np.abs(z).sum(), k
    assert np.abs(P[1] - first[0][1]).max() > 0


def material_points(lam):
    """Quadrature over the volume, independent of the package: 4x4 Gauss points per element and
    3 per ply. Yields the reference position P, the displacement operator Nop (3 x ndof) of the
    shell kinematics u = sum_i N_i (u_i + z theta_i x e_z), and the mass rho dV."""
    g, gw = np.polynomial.legendre.leggauss(4)
    t3, t3w = np.polynomial.legendre.leggauss(3)
    dx, dy = A / NX, B / NY
    z = lam.z
    rho = [p.material.rho for p in lam.plies]
    ndof = 6 * (NX + 1) * (NY + 1)
    corners = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]])
    for ej in range(NY):
        for ei in range(NX):
            nodes = [ej * (NX + 1) + ei, ej * (NX + 1) + ei + 1, (ej + 1) * (NX + 1) + ei + 1,
                     (ej + 1) * (NX + 1) + ei]
            for a, wa in zip(g, gw):
                for b, wb in zip(g, gw):
                    N = 0.25 * (1 + corners[:, 0] * a) * (1 + corners[:, 1] * b)
                    x, y = (ei + (a + 1) / 2) * dx, (ej + (b + 1) / 2) * dy
                    for k in range(len(rho)):
                        for c, wc in zip(t3, t3w):
                            zz = 0.5 * (z[k] + z[k + 1]) + 0.5 * (z[k + 1] - z[k]) * c
                            Nop = np.zeros((3, ndof))
                            for Ni, n in zip(N, nodes):
                                Nop[:, 6 * n: 6 * n + 3] += Ni * np.eye(3)
                                # z (theta x e_z) = z (theta_y, -theta_x, 0)
                                Nop[0, 6 * n + 4] += Ni * zz
                                Nop[1, 6 * n + 3] -= Ni * zz
                            dm = rho[k] * wa * wb * dx * dy / 4 * wc * (z[k + 1] - z[k]) / 2
                            yield np.array([x, y, zz]), Nop, dm


def brute_force_kinetic_energy(lam, V, w, d, dd):
    """1/2 int rho |V + w x (P + u) + du|^2 dV."""
    T = 0.0
    for P, Nop, dm in material_points(lam):
        vel = V + np.cross(w, P + Nop @ d) + Nop @ dd
        T += 0.5 * dm * vel @ vel
    return T


def test_kinetic_energy_matches_brute_force_integral(setup):
    # The invariants integrate the same field exactly (2x2 Gauss suffices for these polynomials);
    # a finer independent quadrature must agree to 1e-11 relative. Drilling rates are zero:
    # theta_z moves no material.
    lam, plate, ffi = setup
    rng = np.random.default_rng(7)
    n = plate.model.num_dofs
    for _ in range(2):
        V, w = rng.normal(size=3), rng.normal(size=3)
        d, dd = 0.05 * rng.normal(size=n), rng.normal(size=n)
        dd[5::6] = 0.0
        T = ffi.kinetic_energy(V, w, d, dd)
        assert T == pytest.approx(brute_force_kinetic_energy(lam, V, w, d, dd), rel=1e-11)


def frame_and_elastic_motion(n, seed):
    """A generic state: the frame's a, al, w and the dofs' d (5 cm scale), dd', dd''."""
    rng = np.random.default_rng(seed)
    a, al, w = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
    return a, al, w, 0.05 * rng.normal(size=n), rng.normal(size=n), rng.normal(size=n)


def test_inertial_forces_match_brute_force_integrals(setup):
    # int rho A, int rho r x A and int rho N^T A for A = a + al x r + w x (w x r) + 2 w x u' + u''
    # (rigid-body kinematics of the floating frame plus elastic motion; Shabana 2013 Eq. 5.40),
    # by the independent quadrature: 1e-10 relative. Drilling rates/accelerations are zero.
    lam, plate, ffi = setup
    n = plate.model.num_dofs
    a, al, w, d, dd, ddd = frame_and_elastic_motion(n, 11)
    dd[5::6] = 0.0
    ddd[5::6] = 0.0
    F, M, Q = np.zeros(3), np.zeros(3), np.zeros(n)
    for P, Nop, dm in material_points(lam):
        r = P + Nop @ d
        Acc = a + np.cross(al, r) + np.cross(w, np.cross(w, r)) + 2 * np.cross(w, Nop @ dd) + Nop @ ddd
        F += dm * Acc
        M += dm * np.cross(r, Acc)
        Q += dm * Nop.T @ Acc
    f = ffi.inertial_forces(a, al, w, d, dd, ddd)
    np.testing.assert_allclose(f.F, F, rtol=1e-10)
    np.testing.assert_allclose(f.M, M, rtol=1e-10)
    Q[5::6] = f.Q[5::6]  # the drilling inertia of the element is not material
    np.testing.assert_allclose(f.Q, Q, atol=1e-10 * np.abs(Q).max())


def test_mass_proportional_damping_joins_the_inertial_force(setup):
    # With damping alpha_M, Q gains alpha_M L_c dd' (the Rayleigh mass term, formed in one product
    # with L_c dd''; F and M unchanged): against the element mass matrix's product, 1e-13.
    _, plate, ffi = setup
    a, al, w, d, dd, ddd = frame_and_elastic_motion(plate.model.num_dofs, 12)
    f0 = ffi.inertial_forces(a, al, w, d, dd, ddd)
    f1 = ffi.inertial_forces(a, al, w, d, dd, ddd, damping=0.7)
    np.testing.assert_array_equal(f1.F, f0.F)
    np.testing.assert_array_equal(f1.M, f0.M)
    expected = 0.7 * (plate.model.mass_matrix() @ dd)
    np.testing.assert_allclose(f1.Q - f0.Q, expected, rtol=0, atol=1e-13 * np.abs(f1.Q).max())


@pytest.mark.parametrize("mesh", ["flat", "tilted"])
@pytest.mark.parametrize("rows", ["in-plane", "bending"])
def test_inertial_force_rows_equal_the_whole_forces_rows(setup, mesh, rows):
    # Q at a few dofs alone (what the membrane sweeps read): on the flat mesh's in-plane dofs
    # (u, v, theta_z) from the node graph's sums, otherwise from the restricted sparse rows; either
    # must equal inertial_forces' Q there to round-off (1e-13 of the rows' largest entry), damping
    # included. Here Q is the whole of those rows (no elastic force to hide an inertial term in).
    lam, plate, ffi = setup
    model = plate.model
    if mesh == "tilted":
        model, ffi = tilted_plate_inertia(lam)
    n = model.num_dofs
    a, al, w, d, dd, ddd = frame_and_elastic_motion(n, 13)
    types = (0, 1, 5) if rows == "in-plane" else (2, 3, 4)
    dofs = [k for k in range(6, n) if k % 6 in types]  # node 0 left out
    Q = ffi.inertial_forces(a, al, w, d, dd, ddd, damping=0.4).Q[dofs]
    alone = ffi.inertial_force_rows(dofs, a, al, w, d, dd, ddd, damping=0.4)
    np.testing.assert_allclose(alone, Q, rtol=0, atol=1e-13 * np.abs(Q).max())


def test_gyroscopic_matrix_is_skew_and_softening_is_negative(setup):
    # Coriolis forces do no work (G_y skew); the centrifugal "stiffness" G_w is negative
    # semi-definite (it softens: -Omega^2 M for a spin normal to the motion).
    _, _, ffi = setup
    w = np.array([0.3, -1.2, 0.7])
    G = ffi.gyroscopic(w).toarray()
    np.testing.assert_allclose(G, -G.T, atol=1e-14 * np.abs(G).max())
    Gw = ffi.centrifugal_stiffness(w).toarray()
    assert np.linalg.eigvalsh(0.5 * (Gw + Gw.T)).max() < 1e-12 * np.abs(Gw).max()
