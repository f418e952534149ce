"""Ply stress and strain recovery on laminated MITC4 shell meshes (deployfx.stress).

References: classical lamination theory (Jones, *Mechanics of Composite Materials*, 1999,
Sec. 2.5-2.6 and 4.2; Reddy, *Mechanics of Laminated Composite Plates and Shells*, 2004,
Sec. 3.3), written independently in tests/clt_reference.py; the Green strain of You et al. (2016)
Eq. 14; the equilibrium transverse shear distribution of Rolfes & Rohwer (Int. J. Numer. Meth.
Eng. 40, 1997, 51-60) and, for a homogeneous section, the parabola 3 Q / (2 h) (1 - 4 z^2 / h^2)
(Timoshenko & Goodier, *Theory of Elasticity*, 1970, Sec. 21). The paper's IM6/SC1081 ply
(Table 2) throughout.
"""
import numpy as np
import pytest

import clt_reference as clt
import deployfx as dfx
from deployfx import stress

PLY = dfx.Orthotropic(E1=177e9, E2=10.8e9, G12=7.6e9, G13=7.6e9, G23=8.504e9, nu12=0.27, rho=1600)
Q = clt.lamina_Q(177e9, 10.8e9, 7.6e9, 0.27)
T_PLY = 0.5e-3
LAYUPS = {"[0/0/0/0]": [0, 0, 0, 0], "[0/90/90/0]": [0, 90, 90, 0],
          "[30/-30/30/-30]": [30, -30, 30, -30]}  # the paper's two, an antisymmetric angle-ply


def laminate(angles):
    return dfx.Laminate.from_angles(PLY, T_PLY, angles)


def tilted_mesh(angles, nx=3, ny=2, size=(0.6, 0.4), seed=0):
    """A distorted nx x ny mesh of a flat plate lying in a tilted plane of 3-D space: the local
    frame (x along the laminate's 0-degree axis) is R_WL, returned with the local node coordinates
    (the element frames are all R_WL, so imposed local fields are the elements' own)."""
    rng = np.random.default_rng(seed)
    x, y = np.meshgrid(np.linspace(0, size[0], nx + 1), np.linspace(0, size[1], ny + 1))
    xy = np.column_stack([x.ravel(), y.ravel()])
    interior = (xy[:, 0] > 0) & (xy[:, 0] < size[0]) & (xy[:, 1] > 0) & (xy[:, 1] < size[1])
    xy[interior] += rng.uniform(-0.25, 0.25, (interior.sum(), 2)) * [size[0] / nx, size[1] / ny]
    quads = np.array([[j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1,
                       (j + 1) * (nx + 1) + i] for j in range(ny) for i in range(nx)])
    axis = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R_WL = np.eye(3) + np.sin(0.7) * K + (1 - np.cos(0.7)) * K @ K  # Rodrigues
    local = np.column_stack([xy, np.zeros(len(xy))])
    nodes_W = local @ R_WL.T + [0.3, -0.2, 1.1]
    shell = dfx.ShellModel(nodes_W, quads, laminate(angles), ref_axis=R_WL[:, 0])
    return shell, local, R_WL


def world_dofs(R_WL, disp_L, rot_L):
    """Mesh dofs from local displacements and rotation vectors (n, 3) each."""
    u = np.zeros((len(disp_L), 6))
    u[:, :3] = disp_L @ R_WL.T
    u[:, 3:] = rot_L @ R_WL.T
    return u.ravel()


def expected_in_plane(angles, eps0, kappa, z):
    """(plies, 3 stations, 3) ply-axis in-plane stresses from the independent CLT."""
    return np.array([[clt.ply_stress(Q, a, eps0, kappa, z[k, j]) for j in range(3)]
                     for k, a in enumerate(angles)])


@pytest.mark.parametrize("name", LAYUPS)
@pytest.mark.parametrize("where", ["centroid", "gauss"])
def test_pure_membrane_strain_matches_lamination_theory(name, where):
    # u = eps_x x + gamma/2 y, v = gamma/2 x + eps_y y: a uniform membrane strain, no rotation;
    # every Q4 reproduces it (patch test), so each ply's stress is CLT's at every point, to
    # round-off (1e-9 of the largest stress).
    angles = LAYUPS[name]
    shell, X, R = tilted_mesh(angles)
    eps0 = np.array([1.2e-3, -0.7e-3, 0.9e-3])
    disp = np.column_stack([eps0[0] * X[:, 0] + eps0[2] / 2 * X[:, 1],
                            eps0[2] / 2 * X[:, 0] + eps0[1] * X[:, 1], np.zeros(len(X))])
    s = stress.ply_stresses(shell, world_dofs(R, disp, np.zeros_like(disp)), where=where)
    assert s.stress.shape == (6, 1 if where == "centroid" else 4, 4, 3, 5)
    want = expected_in_plane(angles, eps0, np.zeros(3), s.z)
    scale = np.abs(want).max()
    np.testing.assert_allclose(s.stress[..., :3], np.broadcast_to(want, s.stress[..., :3].shape),
                               atol=1e-9 * scale, rtol=0)
    np.testing.assert_allclose(s.stress[..., 3:], 0.0, atol=1e-9 * scale)
    strain = np.array([clt.strain_to_ply(eps0, a) for a in angles])
    np.testing.assert_allclose(s.strain[..., :3],
                               np.broadcast_to(strain[:, None, :], s.strain[..., :3].shape),
                               atol=1e-12)


@pytest.mark.parametrize("name", LAYUPS)
@pytest.mark.parametrize("where", ["centroid", "gauss"])
def test_pure_curvature_matches_lamination_theory(name, where):
    # w = -(kx x^2 + ky y^2 + kxy x y) / 2 with the Kirchhoff rotations beta = -grad w: a uniform
    # curvature and no transverse shear, reproduced exactly by bilinear rotations and MITC4's
    # tied shear. Ply stresses vary linearly through each ply: CLT at the stations, to round-off.
    angles = LAYUPS[name]
    shell, X, R = tilted_mesh(angles, seed=1)
    kappa = np.array([0.8, -0.5, 0.6])  # 1/m
    x, y = X[:, 0], X[:, 1]
    w = -(kappa[0] * x**2 + kappa[1] * y**2 + kappa[2] * x * y) / 2
    beta_x, beta_y = kappa[0] * x + kappa[2] * y / 2, kappa[1] * y + kappa[2] * x / 2
    disp = np.column_stack([np.zeros_like(w), np.zeros_like(w), w])
    rot = np.column_stack([-beta_y, beta_x, np.zeros_like(w)])  # beta = (theta_y, -theta_x)
    s = stress.ply_stresses(shell, world_dofs(R, disp, rot), where=where)
    want = expected_in_plane(angles, np.zeros(3), kappa, s.z)
    scale = np.abs(want).max()
    np.testing.assert_allclose(s.stress[..., :3], np.broadcast_to(want, s.stress[..., :3].shape),
                               atol=1e-9 * scale, rtol=0)
    np.testing.assert_allclose(s.stress[..., 3:], 0.0, atol=1e-9 * scale)
    # The stations are the plies' bottom, middle and top.
    np.testing.assert_allclose(s.z[:, 0], -1e-3 + T_PLY * np.arange(4), atol=1e-15)
    np.testing.assert_allclose(s.z[:, 2] - s.z[:, 0], T_PLY, rtol=1e-12)


@pytest.mark.parametrize("where", ["centroid", "gauss"])
def test_green_strain_of_a_stretch_and_a_tilt(where):
    # u = a x, w = c x + d y with the fibres turned with the mid-surface (beta = -grad w, no
    # shear): You et al. (2016) Eq. 14 gives eps_x = a + (a^2 + c^2)/2, eps_y = d^2/2,
    # gamma_xy = c d; von Karman's strain drops the in-plane displacement's own a^2/2 (the normal
    # displacement's quadratic terms alone: Reddy 2004, Ch. 3, the von Karman strains); the
    # linear strain is (a, 0, 0). On a plate tilted in 3-D space, in its own axes.
    angles = LAYUPS["[0/90/90/0]"]
    shell, X, R = tilted_mesh(angles, seed=2)
    a, c, d = 1e-3, 0.05, 0.03
    disp = np.column_stack([a * X[:, 0], np.zeros(len(X)), c * X[:, 0] + d * X[:, 1]])
    rot = np.tile([d, -c, 0.0], (len(X), 1))
    u = world_dofs(R, disp, rot)
    green = [a + (a * a + c * c) / 2, d * d / 2, c * d]
    von_karman = [a + c * c / 2, d * d / 2, c * d]
    for measure, eps0 in (("green", green), ("von-karman", von_karman), ("linear", [a, 0, 0])):
        s = stress.ply_stresses(shell, u, strain=measure, where=where)
        want = expected_in_plane(angles, eps0, np.zeros(3), s.z)
        np.testing.assert_allclose(s.stress[..., :3],
                                   np.broadcast_to(want, s.stress[..., :3].shape),
                                   atol=1e-9 * np.abs(want).max(), rtol=0)
        assert s.strain_measure == measure


@pytest.mark.parametrize("angles", [[0], [0, 0, 0, 0]])
def test_homogeneous_section_has_the_parabolic_shear(angles):
    # One material at one angle: tau = 3 Q / (2 h) (1 - 4 z^2 / h^2), uncoupled (1e-12).
    lam = laminate(angles)
    h = lam.thickness
    z = np.linspace(-h / 2, h / 2, 41)
    H = stress.shear_distribution(lam, z)
    parabola = 1.5 / h * (1 - 4 * z**2 / h**2)
    np.testing.assert_allclose(H[:, 0, 0], parabola, atol=1e-12 * 1.5 / h)
    np.testing.assert_allclose(H[:, 1, 1], parabola, atol=1e-12 * 1.5 / h)
    np.testing.assert_allclose(H[:, 0, 1], 0.0, atol=1e-12 * 1.5 / h)
    np.testing.assert_allclose(H[:, 1, 0], 0.0, atol=1e-12 * 1.5 / h)


@pytest.mark.parametrize("angles", list(LAYUPS.values()) + [[0, 90], [45, -45, 0]])
def test_equilibrium_shear_against_numerical_integration(angles):
    # Rolfes & Rohwer's distribution, integrated numerically from an independent A, B, D
    # (clt_reference; trapezoid on 4000 intervals a ply): agreement to 1e-9 of 3/(2h). It vanishes
    # at both faces and integrates to the identity (Simpson per ply, exact for its parabolas),
    # for symmetric, cross-ply, angle-ply and unsymmetric ([0/90], B != 0) lay-ups alike.
    lam = laminate(angles)
    h = lam.thickness
    z = np.linspace(-h / 2, h / 2, 4 * len(angles) + 1)
    H = stress.shear_distribution(lam, z)
    ref = clt.equilibrium_shear_numeric(Q, angles, T_PLY, z)
    np.testing.assert_allclose(H, ref, atol=1e-9 * 1.5 / h)
    np.testing.assert_allclose(H[[0, -1]], 0.0, atol=1e-12 * 1.5 / h)
    zk = lam.z
    total = np.zeros((2, 2))
    for k in range(len(angles)):
        Hk = stress.shear_distribution(lam, [zk[k], (zk[k] + zk[k + 1]) / 2, zk[k + 1]])
        total += (zk[k + 1] - zk[k]) / 6 * (Hk[0] + 4 * Hk[1] + Hk[2])
    np.testing.assert_allclose(total, np.eye(2), atol=1e-12)


@pytest.mark.parametrize("name", LAYUPS)
def test_recovered_transverse_shear_integrates_to_the_resultant(name):
    # w = c x + e y, no rotation: uniform MITC4 shear strains (c, e), resultants Q = As (c, e).
    # The recovered ply shear stresses, turned back to the laminate axes and integrated through
    # the thickness (Simpson per ply over the three stations, exact), give Q back (1e-10).
    angles = LAYUPS[name]
    shell, X, R = tilted_mesh(angles, seed=3)
    c, e = 2e-4, -1e-4
    disp = np.column_stack([np.zeros(len(X)), np.zeros(len(X)), c * X[:, 0] + e * X[:, 1]])
    s = stress.ply_stresses(shell, world_dofs(R, disp, np.zeros_like(disp)), where="gauss")
    Qres = shell.laminate.As @ [c, e]
    th = np.deg2rad(angles)
    tau13, tau23 = s.stress[..., 3], s.stress[..., 4]  # (elements, points, plies, stations)
    cth, sth = np.cos(th)[None, None, :, None], np.sin(th)[None, None, :, None]
    tau_xz, tau_yz = cth * tau13 - sth * tau23, sth * tau13 + cth * tau23
    w = np.array([1, 4, 1]) / 6 * T_PLY
    np.testing.assert_allclose((tau_xz * w).sum(axis=(2, 3)), Qres[0], rtol=1e-10)
    np.testing.assert_allclose((tau_yz * w).sum(axis=(2, 3)), Qres[1], rtol=1e-10)
    # gamma_13 = tau_13 / G13, gamma_23 = tau_23 / G23
    np.testing.assert_allclose(s.strain[..., 3], tau13 / 7.6e9, rtol=1e-14)
    np.testing.assert_allclose(s.strain[..., 4], tau23 / 8.504e9, rtol=1e-14)


def _gauss_weights(local_xy, quads):
    """det J at the 2x2 Gauss points of each bilinear quad (element order (-g,-g), (g,-g), ...)."""
    g = 1 / np.sqrt(3)
    xi, eta = np.array([-1, 1, 1, -1]), np.array([-1, -1, 1, 1])
    out = np.zeros((len(quads), 4))
    for e, q in enumerate(quads):
        P = local_xy[q]
        for p, (a, b) in enumerate(zip(xi * g, eta * g)):
            dxi = 0.25 * xi * (1 + eta * b)
            deta = 0.25 * eta * (1 + xi * a)
            J = np.array([dxi @ P, deta @ P])
            out[e, p] = np.linalg.det(J)
    return out


def test_energy_of_the_recovered_fields_is_the_elements_strain_energy():
    # For u = v = theta_z = 0 the drilling strain vanishes and the element's strain energy
    # (ShellModel.strain_energy, Green membrane strain of Eq. 14, MITC4 shear) is
    # 1/2 int (sigma . eps) dV over its Gauss points. For a homogeneous section the equilibrium
    # shear's energy equals the FSDT one with k = 5/6 (Reissner 1945), so the recovered ply fields
    # at the Gauss points must give the element's energy back: a check of the interpolation, the
    # frames and the Green terms (1e-10). Through each ply: Simpson (in-plane, quadratic in z) and
    # 3-point Gauss on the stations' parabola (shear, quartic in z).
    angles = LAYUPS["[0/0/0/0]"]
    shell, X, R = tilted_mesh(angles, seed=4)
    rng = np.random.default_rng(5)
    n = len(X)
    disp = np.column_stack([np.zeros(n), np.zeros(n), rng.normal(0, 0.02, n)])
    rot = np.column_stack([rng.normal(0, 0.05, (n, 2)), np.zeros(n)])
    u = world_dofs(R, disp, rot)
    s = stress.ply_stresses(shell, u, strain="green", where="gauss")
    sig, eps = s.stress, s.strain
    simpson = np.array([1, 4, 1]) / 6 * T_PLY
    in_plane = 0.5 * ((sig[..., :3] * eps[..., :3]).sum(-1) * simpson).sum(-1)  # (e, p, plies)
    # Shear: Lagrange-interpolate tau over the three stations and integrate tau^2 / G exactly.
    gl = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])  # on [-1, 1]
    glw = np.array([5, 8, 5]) / 9
    L = np.stack([gl * (gl - 1) / 2, 1 - gl**2, gl * (gl + 1) / 2])  # (station, point)
    tau_at = np.einsum("epksc,sq->epkqc", sig[..., 3:], L)
    tau_sq = tau_at[..., 0] ** 2 / 7.6e9 + tau_at[..., 1] ** 2 / 8.504e9
    shear = 0.5 * (tau_sq * glw).sum(-1) * T_PLY / 2
    density = (in_plane + shear).sum(-1)  # (elements, points), J/m^2
    U = (density * _gauss_weights(X[:, :2], np.asarray(shell.quads))).sum()
    assert U == pytest.approx(shell.strain_energy(u), rel=1e-10)


# -- a cantilever strip under a tip load --------------------------------------------------------

def cantilever(angles, nx, ny=2, length=1.0, width=0.02, load=1.0):
    """A strip clamped as a beam at x = 0 (u_x and the slope theta_y held along the root; w, v
    and theta_x at the root's mid node), so the root leaves the anticlastic bending free, and a
    line load of `load` N along +z at the tip."""
    plate = dfx.Plate(length, width, laminate(angles), nx, ny)
    nodes = plate.model.nodes
    root = np.flatnonzero(np.isclose(nodes[:, 0], 0))
    tip = np.flatnonzero(np.isclose(nodes[:, 0], length))
    mid = root[np.argmin(np.abs(nodes[root, 1] - width / 2))]
    fixed = sorted([6 * n + k for n in root for k in (0, 4)] + [6 * mid + k for k in (1, 2, 3)])
    f = np.zeros(plate.model.num_dofs)
    edge = np.isclose(nodes[tip, 1], 0) | np.isclose(nodes[tip, 1], width)
    f[6 * tip + 2] = load / ny * np.where(edge, 0.5, 1.0)
    return plate, plate.model.static(f, fixed)


@pytest.mark.parametrize("name", ["[0/0/0/0]", "[0/90/90/0]"])
@pytest.mark.parametrize("nx", [4, 8, 16, 32])
def test_cantilever_root_ply_stresses_match_beam_and_lamination_theory(name, nx):
    # Beam statics: M_x(x) = -P (L - x) / b (the element's sign, kappa_x = beta_x,x), Q_x = P / b,
    # M_y = M_xy = N = 0; CLT: (eps0, kappa) = [A B; B D]^-1 (N, M); ply stresses at the root
    # element's centroid x_c, where a bilinear element's constant curvature is the average over
    # it. Measured for nx = 4..32 (ny = 2, b/L = 0.02), relative to the ply's peak: the bending
    # stresses along x (sigma_1 of 0-degree plies, sigma_2 of 90-degree ones) within 2e-8 for
    # [0/0/0/0] and 0.07-0.13 % for [0/90/90/0], not decreasing with nx: the root element's moment
    # is exact (the strip is statically determinate), the cross-ply's small difference is the
    # plate's anticlastic root layer, which beam theory leaves out; tau_xz within 4e-8 of
    # 3 Q / (2 h). Tolerances 0.5 % and 1e-6. The stresses along y come from that root layer, not
    # from beam theory, and are not compared.
    angles = LAYUPS[name]
    P, L, b = 1.0, 1.0, 0.02
    plate, u = cantilever(angles, nx, load=P, length=L, width=b)
    s = stress.ply_stresses(plate, u)
    F = np.linalg.inv(clt.abd(Q, angles, T_PLY))
    H = clt.equilibrium_shear_numeric(Q, angles, T_PLY, s.z.ravel()).reshape(4, 3, 2, 2)
    for e in (0, nx):  # the root elements across the width
        xc = s.points[e, 0, 0]
        assert xc == pytest.approx(L / (2 * nx))
        ek = F @ [0, 0, 0, -P * (L - xc) / b, 0, 0]
        for k, a in enumerate(angles):
            along_x = 0 if a == 0 else 1
            want = np.array([clt.ply_stress(Q, a, ek[:3], ek[3:], z) for z in s.z[k]])
            peak = np.abs(want[:, along_x]).max()
            np.testing.assert_allclose(s.stress[e, 0, k, :, along_x], want[:, along_x], rtol=0,
                                       atol=5e-3 * peak)
            tau = np.array([clt.shear_to_ply(H[k, j] @ [P / b, 0.0], a) for j in range(3)])
            # tau_xz is tau_13 in a 0-degree ply, -tau_23 in a 90-degree one.
            col, sign = (3, 1.0) if a == 0 else (4, -1.0)
            np.testing.assert_allclose(sign * s.stress[e, 0, k, :, col], sign * tau[:, col - 3],
                                       rtol=1e-6, atol=1e-6 * 1.5 * P / b / 2e-3)
