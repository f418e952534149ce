"""Shared pieces of the quadratic-manifold study (docs/research/quadratic-manifold.md).

Run with PYTHONPATH=<worktree>/python and the compiled _core in python/deployfx/.
Runs are cached as .npz under /tmp/manifold (delete to recompute)."""
import os
import time

import numpy as np
import scipy.sparse.linalg as spla

import deployfx
from deployfx import _core

CACHE = "/tmp/manifold"
os.makedirs(CACHE, exist_ok=True)
BEND_ROWS = (2, 3, 4)      # w, theta_x, theta_y of each node
INPLANE_ROWS = (0, 1, 5)   # u, v, theta_z


def parity_split(Phi):
    """Indices of the bending and of the in-plane basis vectors (exact zeros, fem/parity.hpp)."""
    R = Phi.reshape(-1, 6, Phi.shape[1])
    b = np.abs(R[:, BEND_ROWS, :]).max(axis=(0, 1))
    m = np.abs(R[:, INPLANE_ROWS, :]).max(axis=(0, 1))
    ib, im = np.flatnonzero(m == 0.0), np.flatnonzero(b == 0.0)
    assert len(ib) + len(im) == Phi.shape[1], "basis not split by parity"
    return ib, im


def cached_run(name, make_scene, t_end, dt=0.01, **options):
    """Simulate (or load) a run; keeps t, q, v, node_E (if any), tip deflection, summary items."""
    path = os.path.join(CACHE, name + ".npz")
    if os.path.exists(path):
        return dict(np.load(path, allow_pickle=True))
    scene = make_scene()
    t0 = time.process_time()
    r = scene.simulate(t_end, dt, **options)
    cpu = time.process_time() - t0
    out = dict(t=r.t, q=r.q, v=r.v, cpu=cpu, wall=r.metadata["wall_time_s"],
               tip=np.asarray(r.tip_deflection)[:, 0],
               steps=r.metadata.get("steps", -1), substeps=r.metadata.get("substeps", -1),
               newton=r.metadata.get("newton_iterations", -1), factorizations=r.metadata.get("factorizations", -1))
    if "node_E_deflection" in r.series:
        out["node_E"] = np.asarray(r.node_E_deflection).reshape(len(r.t), -1)[:, 0]
        out["first_lock"] = r.summary()["first_lock_time_s"][0]
    np.savez(path, **out)
    return out


class Panel:
    """A reduced-nonlinear panel: basis, parity split, modal force, full-mesh operators."""

    def __init__(self, model, fixed):
        self.model = model
        self.Phi = model.basis(0)
        self.shell = model.shells[0]
        self.ib, self.im = parity_split(self.Phi)
        self.force = _core.ModalInternalForce(self.shell._impl, self.Phi, True)
        self.K = np.diag(self.force.linear_stiffness).copy()   # diagonal: Ritz vectors
        self.lay = model.core.layout(0)
        self.fixed = np.asarray(fixed)
        self.free = np.setdiff1d(np.arange(self.shell.num_dofs), self.fixed)

    # -- the exact reduced energy and its gradient
    def f(self, eta):
        return self.force.internal_force(np.ascontiguousarray(eta, dtype=float))

    def energy(self, eta):
        return self.force.strain_energy(np.ascontiguousarray(eta, dtype=float))

    def assemble(self, qb, em):
        eta = np.zeros(self.Phi.shape[1])
        eta[self.ib], eta[self.im] = qb, em
        return eta

    def membrane_energy(self, qb, em):
        """U(q_b, eta_m) - q_b^T K_bb q_b / 2: the bending energy is exactly quadratic (symmetric
        lay-up, flat panel), the rest is the membrane strain energy."""
        return self.energy(self.assemble(qb, em)) - 0.5 * np.sum(self.K[self.ib] * qb * qb)

    # -- predictors of eta_m from q_b
    def galerkin_qm(self, qb, load_m=None):
        """(a') eta_m = -K_mm^-1 (f_m(q_b, 0) + load): the quadratic manifold inside the Ritz span."""
        fm = self.f(self.assemble(qb, 0.0))[0][self.im]
        if load_m is not None:
            fm = fm + load_m
        return -fm / self.K[self.im]

    def condense(self, qb, em0, load_m=None, tol=1e-12, itmax=30):
        """(c) argmin_eta_m U(q_b, eta_m) (+ load_m . eta_m): Newton on the in-plane rows."""
        em = np.array(em0, dtype=float)
        for it in range(itmax):
            fv, T = self.f(self.assemble(qb, em))
            r = fv[self.im] + (0.0 if load_m is None else load_m)
            d = np.linalg.solve(T[np.ix_(self.im, self.im)], -r)
            em += d
            if np.linalg.norm(d) <= tol * max(np.linalg.norm(em), 1e-30):
                return em, it + 1
        return em, itmax

    # -- full-mesh static modal derivatives (Idelsohn & Cardona 1985), projected (Jain et al. 2017)
    def modal_derivative_tensor(self, eps=1e-6):
        """C[k, i, j] = Phi_m[:, k]^T M Theta_ij, Theta_ij = -K^-1 (dK_T/dq_j) phi_i on the full
        mesh (central differences of ShellModel's tangent at +-eps phi_j, eps relative to the
        vector's largest entry); also the M-norm share of each Theta_ij outside the Ritz span."""
        K = self.shell.stiffness_matrix().tocsc()
        M = self.shell.mass_matrix().tocsc()
        fr = self.free
        lu = spla.splu(K[fr][:, fr].tocsc())
        Pb = self.Phi[:, self.ib]
        Pm = self.Phi[:, self.im]
        nb = len(self.ib)
        C = np.zeros((len(self.im), nb, nb))
        outside = np.zeros((nb, nb))
        dK = []
        for j in range(nb):
            h = eps / np.abs(Pb[:, j]).max()
            Kp = self.shell.internal_force(h * Pb[:, j])[1]
            Km = self.shell.internal_force(-h * Pb[:, j])[1]
            dK.append((Kp - Km) / (2 * h))
        for j in range(nb):
            for i in range(nb):
                rhs = -(dK[j] @ Pb[:, i])
                th = np.zeros(self.shell.num_dofs)
                th[fr] = lu.solve(rhs[fr])
                C[:, i, j] = Pm.T @ (M @ th)
                proj = self.Phi @ (self.Phi.T @ (M @ th))
                res = th - proj
                outside[i, j] = np.sqrt(res @ (M @ res)) / max(np.sqrt(th @ (M @ th)), 1e-300)
        return 0.5 * (C + C.transpose(0, 2, 1)), outside


def paper_fixed(nx=15, ny=10, layup=2):
    return deployfx.paper2016.appendage_plate(layup, nx, ny).fixed_dofs("CFFF")


# ------------------------------------------------------------------------------------------
# A clamped panel integrated in Python (generalized-alpha, Arnold & Bruls 2007 form), to compare
# the slaved models with the 30-coordinate reduced model under the same integrator.

class Slaved:
    """eta = g(q) on the bending coordinates q: kind "qm" (eta_m = C(q, q)/2, Jain et al. 2017),
    "sc" (eta_m = argmin U, static condensation); kinetic=False drops the in-plane kinetic energy
    (bending mass I only, as a polynomial-in-q model would)."""

    def __init__(self, panel, kind, C=None, kinetic=True, elastic_curvature=True):
        self.p, self.kind, self.C, self.kinetic = panel, kind, C, kinetic
        self.elastic_curvature = elastic_curvature  # "vk": keep d2h/dq2 . eta_m in Newton's matrix
        self._em = np.zeros(len(panel.im))

    def g(self, q):
        p = self.p
        if self.kind == "qm":
            em = 0.5 * np.einsum("kij,i,j->k", self.C, q, q)
            eta = p.assemble(q, em)
            f, T = p.f(eta)
            G = np.einsum("kij,j->ki", self.C, q)
        elif self.kind == "vk":
            # the quartic polynomial: the energy without the in-plane coordinates' own quadratic
            # strains, U = U(q, 0) + eta_m^T f_m(q, 0) + eta_m^T K_mm eta_m / 2, exactly
            # condensed by eta_m = C(q, q)/2 (C the Galerkin tensor): a quartic in q
            em = 0.5 * np.einsum("kij,i,j->k", self.C, q, q)
            eta = p.assemble(q, em)
            f0, T0 = p.f(p.assemble(q, 0.0))
            f = np.zeros_like(f0)
            f[p.ib] = f0[p.ib] + T0[np.ix_(p.ib, p.im)] @ em
            T = T0.copy()
            T[np.ix_(p.im, p.im)] = np.diag(p.K[p.im])
            # the Hessian's term d2h/dq2 . eta_m (h = f_m(q, 0) quadratic: d2h_k = -K_k C_k): it
            # cancels the unrelaxed membrane stress in T0_bb and cannot be dropped
            if self.elastic_curvature:
                T[np.ix_(p.ib, p.ib)] -= np.einsum("k,kij->ij", p.K[p.im] * em, self.C)
            G = np.einsum("kij,j->ki", self.C, q)
        else:
            em, _ = p.condense(q, self._em)
            self._em = em
            eta = p.assemble(q, em)
            f, T = p.f(eta)
            G = -np.linalg.solve(T[np.ix_(p.im, p.im)], T[np.ix_(p.im, p.ib)])
        return eta, f, T, G

    def curvature(self, q, qd):
        """dG/dq . qd . qd (the in-plane acceleration's velocity part)."""
        if self.kind in ("qm", "vk"):
            return np.einsum("kij,i,j->k", self.C, qd, qd)
        h = 1e-6 * max(1.0, np.linalg.norm(q)) / max(np.linalg.norm(qd), 1e-30)
        save = self._em.copy()
        Gp = self.g(q + h * qd)[3]
        Gm = self.g(q - h * qd)[3]
        self._em = save
        return (Gp - Gm) @ qd / (2 * h)

    def residual(self, q, qd, qdd, damping):
        p = self.p
        eta, f, T, G = self.g(q)
        r = qdd + damping * qd + f[p.ib] + G.T @ f[p.im]
        A = np.eye(len(q))
        if self.kinetic:
            am = G @ qdd + self.curvature(q, qd)
            r += G.T @ (am + damping * (G @ qd))
            A = A + G.T @ G
        S = (T[np.ix_(p.ib, p.ib)] + T[np.ix_(p.ib, p.im)] @ G + G.T @ T[np.ix_(p.im, p.ib)]
             + G.T @ T[np.ix_(p.im, p.im)] @ G)
        return r, A, S


class Full30:
    """The 30-coordinate reduced model itself, clamped: eta'' + c eta' + f(eta) = 0."""

    def __init__(self, panel):
        self.p = panel

    def residual(self, eta, ed, edd, damping):
        f, T = self.p.f(eta)
        return edd + damping * ed + f, np.eye(len(eta)), T


def integrate(sys_, x0, v0, h, n, damping, rho=0.8, tol=1e-10, exact_jacobian=False, itmax=50):
    """Generalized-alpha on r(x, v, vdot) = 0; Newton on vdot with the matrix A + g' h c D + b' h^2 S
    (S the tangent without the manifold's curvature terms) or, exact_jacobian, central differences
    of the residual. Returns x history and Newton iterations per step."""
    am, af = (2 * rho - 1) / (rho + 1), rho / (rho + 1)
    gam, bet = 0.5 - am + af, 0.25 * (1 - am + af) ** 2
    k = (1 - af) / (1 - am)
    x, v = np.array(x0, float), np.array(v0, float)
    r, A, S = sys_.residual(x, v, np.zeros_like(x), damping)
    vd = np.linalg.solve(A, -r)
    a = vd.copy()
    X, its = [x.copy()], []
    for step in range(n):
        vd_new = vd.copy()
        for it in range(itmax):
            a_new = (k * vd_new + (af * vd - am * a) / (1 - am))
            xn = x + h * v + h * h * ((0.5 - bet) * a + bet * a_new)
            vn = v + h * ((1 - gam) * a + gam * a_new)
            r, A, S = sys_.residual(xn, vn, vd_new, damping)
            if it > 0 and np.linalg.norm(r) <= tol * max(1.0, np.linalg.norm(A @ vd_new)):
                break
            if exact_jacobian:
                J = np.zeros((len(x), len(x)))
                for j in range(len(x)):
                    e = np.zeros(len(x)); e[j] = 1e-6 * max(1.0, abs(vd_new[j]))
                    def res(dv):
                        an = (k * dv + (af * vd - am * a) / (1 - am))
                        return sys_.residual(x + h * v + h * h * ((0.5 - bet) * a + bet * an),
                                             v + h * ((1 - gam) * a + gam * an), dv, damping)[0]
                    J[:, j] = (res(vd_new + e) - res(vd_new - e)) / (2 * e[j])
            else:
                J = A + gam * h * k * damping * A + bet * h * h * k * S
            vd_new = vd_new - np.linalg.solve(J, r)
        its.append(it)      # residual evaluations after the first: Newton iterations
        a, x, v, vd = a_new, xn, vn, vd_new
        X.append(x.copy())
    return np.array(X), np.array(its)


def galerkin_tensor(panel):
    """C[k, i, j] with eta_m = C(q_b, q_b)/2 = -K_mm^-1 f_m(q_b, 0) (f_m(q_b, 0) is exactly
    quadratic in q_b on a parity-split basis), by polarisation of the modal force."""
    nb = len(panel.ib)
    C = np.zeros((len(panel.im), nb, nb))
    E = np.eye(nb)
    for i in range(nb):
        C[:, i, i] = 2 * panel.galerkin_qm(E[i])
    for i in range(nb):
        for j in range(i + 1, nb):
            C[:, i, j] = C[:, j, i] = panel.galerkin_qm(E[i] + E[j]) - 0.5 * (C[:, i, i] + C[:, j, j])
    return C
