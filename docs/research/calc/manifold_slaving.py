"""Quadratic manifold / in-plane slaving study for issue 27 (docs/research/quadratic-manifold.md).

    PYTHONPATH=python nice /work/venv/bin/python docs/research/calc/manifold_slaving.py [sections]

sections: slaving dynamic amplitude spinup cost (default: all). Engine runs are cached under
/tmp/manifold (full nonlinear 15 x 10: ~20 s CPU). Every number of the note is printed here.

Notation: the reduced-nonlinear panel's Ritz coordinates eta (M-orthonormal, K diagonal) split by
parity into bending q_b (12 on 15 x 10) and in-plane eta_m (18). Predictors of eta_m from q_b:
  QM-J   eta_m = C(q_b, q_b)/2, C from full-mesh static modal derivatives
         Theta_ij = -K^-1 (dK_T/dq_j) phi_i (central differences of the shell tangent), projected
         on the in-plane Ritz vectors with Phi_m^T M (Jain et al. 2017 on this basis);
  QM-G   eta_m = -K_mm^-1 f_m(q_b, 0): the same quadratic manifold by Galerkin inside the span
         (f_m(q_b, 0) is exactly quadratic in q_b on a parity-split basis);
  +inert the same plus -K_mm^-1 g_m(t), g_m the in-plane rows' inertial load of the recorded
         motion (engine residual with eta_m, eta_m', eta_m'' = 0, minus f_m(q_b, 0));
  SC     exact static condensation, argmin_eta_m U(q_b, eta_m) (Newton, |d| < 1e-12 |eta_m|);
  SC+i   exact condensation with the inertial load: f_m(q_b, eta_m) + g_m(t) = 0.
"""
import sys
import time
from math import comb

import numpy as np

import deployfx
from deployfx import _core
from deployfx.scenes import SpinUpBeamScene

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from manifold_common import (Full30, Panel, Slaved, cached_run, galerkin_tensor, integrate,  # noqa: E402
                             paper_fixed)

SECTIONS = sys.argv[1:] or ["slaving", "dynamic", "amplitude", "spinup", "cost"]
DAMP = 0.7   # the paper scene's alpha_M (C = 0.7 M); beta_K = 0


def table(header, rows, fmt="{:.3g}"):
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for r in rows:
        print("| " + " | ".join(x if isinstance(x, str) else fmt.format(x) for x in r) + " |")
    print()


def uniform(t, y, grid):
    """Series on the uniform output grid (the runs add rows at events)."""
    keep = np.concatenate([[True], np.diff(t) > 0])
    return np.interp(grid, t[keep], y[keep])


def scene():
    return deployfx.scenes.paper2016(layup=2, model="reduced-nonlinear")


S = scene()
P = Panel(S.model, paper_fixed())
RUN = cached_run("reduced_nonlinear_15x10", scene, 30.0)
NE = 6 * S.node_E + 2                       # node E's w row
PHI_E = P.Phi[NE]                           # zero on the in-plane vectors


def inertial_loads(model, panel, t, q, v):
    """g_m(t): the in-plane rows of the engine residual with the in-plane coordinates, rates and
    accelerations zeroed, minus f_m(q_b, 0); accelerations of the other coordinates by central
    differences of the recorded v."""
    iq, iv = panel.lay["iq_elastic"], panel.lay["iv_elastic"]
    a = np.gradient(v, t, axis=0)
    g = np.zeros((len(t), len(panel.im)))
    for k in range(len(t)):
        qk, vk, ak = q[k].copy(), v[k].copy(), a[k].copy()
        qk[iq + panel.im] = 0.0
        vk[iv + panel.im] = 0.0
        ak[iv + panel.im] = 0.0
        r = model.residual(qk, vk, ak, t[k])
        g[k] = r[iv + panel.im] - panel.f(qk[iq:iq + panel.Phi.shape[1]])[0][panel.im]
    return g


def predictors(panel, C_J, qb_all, g_all):
    C_G = galerkin_tensor(panel)
    out = {k: np.zeros((len(qb_all), len(panel.im))) for k in ("QM-J", "QM-G", "QM-J+inert", "QM-G+inert", "SC", "SC+i")}
    em = np.zeros(len(panel.im))
    emi = np.zeros(len(panel.im))
    its = []
    for k, (qb, g) in enumerate(zip(qb_all, g_all)):
        qj = 0.5 * np.einsum("kij,i,j->k", C_J, qb, qb)
        qg = 0.5 * np.einsum("kij,i,j->k", C_G, qb, qb)
        dl = -g / panel.K[panel.im]
        out["QM-J"][k], out["QM-G"][k] = qj, qg
        out["QM-J+inert"][k], out["QM-G+inert"][k] = qj + dl, qg + dl
        em, it = panel.condense(qb, qg)
        emi, it2 = panel.condense(qb, qg + dl, load_m=g)
        its += [it, it2]
        out["SC"][k], out["SC+i"][k] = em, emi
    return out, np.mean(its), C_G


def slaving_errors(panel, t, eta, pred, windows, phi_tip):
    """Rows per predictor and window: max_t|e|/max_t|eta_m|, rms|e|/rms|eta_m|, max|dU_mem|/max U_mem,
    bending-force error over the largest nonlinear bending force f_b - K_bb q_b and over the
    largest bending force f_b."""
    qb, emr = eta[:, panel.ib], eta[:, panel.im]
    Kb = panel.K[panel.ib]
    Umem = np.array([panel.membrane_energy(a, b) for a, b in zip(qb, emr)])
    fb = np.array([panel.f(e)[0][panel.ib] for e in eta])
    fnl = fb - Kb * qb
    rows = []
    for name, em in pred.items():
        e = np.linalg.norm(em - emr, axis=1)
        U = np.array([panel.membrane_energy(a, b) for a, b in zip(qb, em)])
        fbp = np.array([panel.f(panel.assemble(a, b))[0][panel.ib] for a, b in zip(qb, em)])
        df = fbp - fb
        for wname, (t0, t1) in windows.items():
            w = (t >= t0) & (t <= t1)
            n = np.linalg.norm(emr[w], axis=1)
            rows.append([name, wname, e[w].max() / n.max(), np.sqrt(np.mean(e[w] ** 2) / np.mean(n ** 2)),
                         np.abs(U[w] - Umem[w]).max() / np.abs(Umem[w]).max(), np.abs(Umem[w]).max(),
                         np.linalg.norm(df[w], axis=1).max() / np.linalg.norm(fnl[w], axis=1).max(),
                         np.linalg.norm(df[w], axis=1).max() / np.linalg.norm(fb[w], axis=1).max()])
    return rows


# ------------------------------------------------------------------------------------------
if "slaving" in SECTIONS:
    print("## 1. Slaving along the engine's reduced-nonlinear run (paper scene, 15 x 10, 30 s, dt = 0.01)\n")
    t, q, v = RUN["t"], RUN["q"], RUN["v"]
    iq = P.lay["iq_elastic"]
    eta = q[:, iq:iq + 30]
    print(f"basis {P.Phi.shape}: bending {len(P.ib)} (indices {P.ib[0]}-{P.ib[-1]}), in-plane {len(P.im)}; "
          f"engine CPU of the run {RUN['cpu']:.3f} s, first lock {RUN['first_lock']:.5f} s")
    print(f"check: node E from Phi_E,b q_b vs the run's series, max diff {np.abs(eta @ PHI_E - RUN['node_E']).max():.2e} m\n")
    t0 = time.process_time()
    C_J, outside = P.modal_derivative_tensor()
    print(f"full-mesh modal derivatives of the {len(P.ib)} bending vectors ({len(P.ib) * (len(P.ib) + 1) // 2} pairs): "
          f"{time.process_time() - t0:.2f} s CPU. Share (M-norm) of Theta_ij outside the Ritz span: "
          f"median {np.median(outside):.3f}, max {outside.max():.3f}; pairs within the first 3 vectors: max "
          f"{outside[:3, :3].max():.1e}\n")
    g = inertial_loads(S.model, P, t, q, v)
    fm_rec = np.array([P.f(e)[0][P.im] for e in eta])
    fm_0 = np.array([P.f(P.assemble(e[P.ib], 0.0))[0][P.im] for e in eta])
    for wname, w in (("deployment (t < 2.46 s)", t < 2.46), ("all 30 s", t <= 30.0)):
        print(f"{wname}: max|K_mm eta_m| = {np.abs(eta[w][:, P.im] * P.K[P.im]).max():.3g}, max|f_m(q_b, 0)| = "
              f"{np.abs(fm_0[w]).max():.3g}, max|f_m| (the run's membrane force) = {np.abs(fm_rec[w]).max():.3g}, "
              f"max|g_m| (inertial load) = {np.abs(g[w]).max():.3g} (generalized forces on eta, N kg^-1/2)")
    print()
    pred, its, C_G = predictors(P, C_J, eta[:, P.ib], g)
    print(f"|C_J - C_G| / |C_G| = {np.linalg.norm(C_J - C_G) / np.linalg.norm(C_G):.3f} (Frobenius); "
          f"condensation Newton iterations per solve {its:.2f}\n")
    lock = float(RUN["first_lock"])
    windows = {"deploy 0-%.2f s" % (lock - 0.01): (0.0, lock - 0.01), "post-lock": (lock, 30.0), "all 30 s": (0.0, 30.0)}
    rows = slaving_errors(P, t, eta, pred, windows, PHI_E)
    # the quartic polynomial ("poly": the energy without the in-plane coordinates' own quadratic
    # strains, exactly condensed by QM-G): its membrane energy and bending force against the run's
    qb_all, em_all = eta[:, P.ib], eta[:, P.im]
    Kb = P.K[P.ib]
    sl = Slaved(P, "vk", C_G)
    Uv, Ur, fv, fr = [], [], [], []
    for a, b in zip(qb_all, em_all):
        e, f, T, G = sl.g(a)
        Uv.append(0.5 * np.sum(P.K[P.im] * e[P.im] ** 2) + e[P.im] @ P.f(P.assemble(a, 0.0))[0][P.im]
                  + P.energy(P.assemble(a, 0.0)) - 0.5 * np.sum(Kb * a * a))
        Ur.append(P.membrane_energy(a, b))
        fv.append(f[P.ib])
        fr.append(P.f(P.assemble(a, b))[0][P.ib])
    Uv, Ur, fv, fr = map(np.array, (Uv, Ur, fv, fr))
    for wname, (t0, t1) in windows.items():
        w = (t >= t0) & (t <= t1)
        df = np.linalg.norm(fv[w] - fr[w], axis=1).max()
        rows.append(["poly (QM-G, quartic energy)", wname, "-", "-", np.abs(Uv[w] - Ur[w]).max() / np.abs(Ur[w]).max(),
                     np.abs(Ur[w]).max(), df / np.linalg.norm(fr[w] - Kb * qb_all[w], axis=1).max(),
                     df / np.linalg.norm(fr[w], axis=1).max()])
    table(["predictor", "window", "max e/max|eta_m|", "rms e/rms|eta_m|", "max|dU_mem|/max U_mem",
           "max U_mem (J)", "max|df_b|/max|f_b,nl|", "max|df_b|/max|f_b|"], rows)
    np.savez("/tmp/manifold/slaving.npz", C_J=C_J, C_G=C_G)

# ------------------------------------------------------------------------------------------
C_G = galerkin_tensor(P)


def release(scale, h=0.002, n=1500, models=None, exact=()):
    """Clamped panel released from rest at the run's state of largest node E deflection (t = 2.79 s)
    with q_b scaled: node E's history of each slaved model against the 30-coordinate reduced model
    (same integrator, generalized-alpha rho_inf = 0.8, h, n steps, C = 0.7 M)."""
    t, q = RUN["t"], RUN["q"]
    k = int(np.argmax(np.abs(RUN["node_E"]) * (t < 3.5)))
    qb = scale * q[k, P.lay["iq_elastic"]:][P.ib]
    em0, _ = P.condense(qb, np.zeros(len(P.im)))
    X, it = integrate(Full30(P), P.assemble(qb, em0), np.zeros(30), h, n, DAMP)
    wR = X @ PHI_E
    rows = [["reduced 30", f"{abs(wR).max():.4f}", 0.0, 0.0, it.mean()]]
    res = {}
    for name in models:
        kind, kin, jac = name
        sy = {"QM-J": lambda: Slaved(P, "qm", CJ, kinetic=kin), "QM-G": lambda: Slaved(P, "qm", C_G, kinetic=kin),
              "SC": lambda: Slaved(P, "sc", kinetic=kin), "poly": lambda: Slaved(P, "vk", C_G, kinetic=kin),
              "poly, elastic curvature dropped": lambda: Slaved(P, "vk", C_G, kinetic=kin, elastic_curvature=False)}[kind]()
        with np.errstate(all="ignore"):
            Y, it = integrate(sy, qb, np.zeros(len(qb)), h, n, DAMP, exact_jacobian=jac)
        w = Y @ PHI_E[P.ib]
        label = kind + ("" if kin else " no in-plane T") + (" exact J" if jac else "")
        if not np.all(np.isfinite(w)):
            first = int(np.argmax(~np.isfinite(w)))
            rows.append([label, f"non-finite from step {first}", np.nan, np.nan, it[:max(first, 1)].mean()])
            continue
        rows.append([label, "", np.sqrt(np.mean((w - wR) ** 2)) / abs(wR).max(), abs(w - wR).max() / abs(wR).max(),
                     it.mean()])
        res[label] = w
    return abs(q[k, P.lay["iq_elastic"]:] @ PHI_E), t[k], rows


if "dynamic" in SECTIONS or "amplitude" in SECTIONS:
    CJ = np.load("/tmp/manifold/slaving.npz")["C_J"] if __import__("os").path.exists("/tmp/manifold/slaving.npz") \
        else P.modal_derivative_tensor()[0]

if "dynamic" in SECTIONS:
    print("## 2. Node E\n")
    full = cached_run("full_nonlinear_15x10", lambda: deployfx.scenes.paper2016(layup=2, model="nonlinear"), 30.0)
    grid = np.arange(0.0, 30.0 + 1e-9, 0.01)
    Ef, Er = uniform(full["t"], full["node_E"], grid), uniform(RUN["t"], RUN["node_E"], grid)
    d = Er - Ef
    for name, w in [("0-2.46 s", grid < 2.465), ("all 30 s", grid <= 30.0)]:
        print(f"reduced-nonlinear vs full nonlinear, node E {name}: RMS error / max|E_full| = "
              f"{np.sqrt(np.mean(d[w] ** 2)) / np.abs(Ef).max():.4f}, max error / max = {np.abs(d[w]).max() / np.abs(Ef).max():.4f}")
    print(f"first lock: full {float(full['first_lock']):.6f} s, reduced {float(RUN['first_lock']):.6f} s, "
          f"diff {1e3 * (float(RUN['first_lock']) - float(full['first_lock'])):+.3f} ms; CPU full {float(full['cpu']):.1f} s, "
          f"reduced {float(RUN['cpu']):.3f} s\n")
    wE, tk, rows = release(1.0, models=[("QM-J", True, False), ("QM-G", True, False), ("QM-G", False, False),
                                        ("SC", True, False), ("SC", False, False), ("SC", True, True),
                                        ("poly", True, False), ("poly", False, False), ("QM-G", True, True),
                                        ("poly, elastic curvature dropped", True, False)])
    print(f"clamped release from rest at q_b(t = {tk:.2f} s) (node E {float(wE):.3f} m), 3 s, h = 2 ms:\n")
    table(["model", "max|E| (m)", "RMS err/max", "max err/max", "Newton it/step"], rows)

if "amplitude" in SECTIONS:
    print("## 4a. Amplitude: the same release with q_b scaled\n")
    rows = []
    for s in (0.05, 0.1, 0.25, 0.5, 1.0, 1.5):
        wE, tk, r = release(s, models=[("QM-G", True, False), ("SC", True, False), ("SC", False, False),
                                          ("poly", True, False)])
        for x in r[1:]:
            rows.append([f"{s}", f"{float(wE) * s:.3f}"] + x[:1] + x[2:])
    table(["scale", "node E0 (m)", "model", "RMS err/max", "max err/max", "Newton it/step"], rows)

if "spinup" in SECTIONS:
    print("## 4b. Spin-up beam (Kane et al. 1987; 20 x 1 strip, reduced-nonlinear, T_s = 15 s, 30 s, dt = 0.01)\n")
    rows = []
    for om in (2.0, 4.0, 6.0):
        sc = SpinUpBeamScene(om, 15.0, "reduced-nonlinear", 20)
        run = cached_run(f"spinup_{om:g}", lambda: sc, 30.0)
        strip = deployfx.scenes.spin_up_strip(20)
        p = Panel(sc.model, strip.fixed_dofs("CFFF"))
        t, q, v = run["t"], run["q"], run["v"]
        eta = q[:, p.lay["iq_elastic"]:]
        g = inertial_loads(sc.model, p, t, q, v)
        fm0 = np.array([p.f(p.assemble(e[p.ib], 0.0))[0][p.im] for e in eta])
        print(f"omega_s = {om:g}: basis {p.Phi.shape[1]} = {len(p.ib)} bending + {len(p.im)} in-plane; "
              f"max|g_m| = {np.abs(g).max():.3g}, max|f_m(q_b, 0)| = {np.abs(fm0).max():.3g}")
        CJs = p.modal_derivative_tensor()[0]
        pred, _, _ = predictors(p, CJs, eta[:, p.ib], g)
        tipn = 6 * (len(p.Phi) // 6 - 1) + 2   # last node's w (the strip's far corner)
        rs = slaving_errors(p, t, eta, pred, {"30 s": (0.0, 30.0)}, p.Phi[tipn])
        for r in rs:
            rows.append([f"{om:g}", f"{np.abs(run['tip']).max():.3f}"] + r[:1] + r[2:])
        # first bending coordinate's tangent stiffness at the end (steady spin) with each eta_m
        e_end = eta[-1]
        k11 = {nm: p.f(p.assemble(e_end[p.ib], pred[nm][-1]))[1][p.ib[0], p.ib[0]] for nm in ("QM-G", "SC", "SC+i")}
        k11["recorded"] = p.f(e_end)[1][p.ib[0], p.ib[0]]
        print(f"omega_s = {om:g}: T_11 at 30 s (first bending coordinate's tangent; softening Omega^2 = {om ** 2:g}): "
              + ", ".join(f"{k} {x:.3g}" for k, x in k11.items()) + f"; K_11 = {p.K[p.ib[0]]:.3g}")
    print()
    table(["omega_s", "max|tip| (m)", "predictor", "max e/max|eta_m|", "rms e/rms", "max|dU_mem|/max U_mem",
           "max U_mem (J)", "max|df_b|/max|f_b,nl|", "max|df_b|/max|f_b|"], rows)

if "cost" in SECTIONS:
    print("## 3. Cost\n")
    rows = []
    for name in ("rigid", "reduced-linear", "reduced-nonlinear"):
        cpus, r = [], None
        for rep in range(3):
            sc = deployfx.scenes.paper2016(layup=2, model=name)
            t0 = time.process_time()
            r = sc.simulate(30.0, 0.01)
            cpus.append(time.process_time() - t0)
        md = r.metadata
        rows.append([name, f"{min(cpus) * 1e3:.0f}-{max(cpus) * 1e3:.0f}", f"{md['steps']}", f"{md['substeps']}",
                     f"{md['newton_iterations']}", f"{md['factorizations']}", f"{md['contact_steps']}",
                     1e6 * min(cpus) / md["newton_iterations"], 1e6 * min(cpus) / md["substeps"]])
    table(["model (30 s, dt 0.01)", "CPU (ms, 3 runs)", "steps", "substeps", "Newton it", "factorizations",
           "contact steps", "us / Newton it", "us / substep"], rows)
    # one residual and one Newton matrix through the bindings at the run's state at t = 1.0 s
    # (mid-deployment), median of repeated calls (bench/newton_profile.py's measure); the
    # last coordinate (an elastic one, the hinge angle for rigid) is nudged at each call so no memo
    # of the previous evaluation is reused
    rows = []
    for name in ("rigid", "reduced-linear", "reduced-nonlinear"):
        sc = deployfx.scenes.paper2016(layup=2, model=name)
        run = cached_run("paper_" + name.replace("-", "_"), lambda: sc, 2.0)
        k = int(np.argmin(np.abs(run["t"] - 1.0)))
        qk, vk = run["q"][k], run["v"][k]
        ak = np.gradient(run["v"], run["t"], axis=0)[k]
        data = sc.model.make_data()
        h = 0.01

        def med(f, n=400):
            ts = []
            for _ in range(n):
                t0 = time.perf_counter()
                f()
                ts.append(time.perf_counter() - t0)
            return 1e6 * float(np.median(ts))
        dq = qk.copy()
        r_us = med(lambda: (dq.__setitem__(-1, dq[-1] * (1 + 1e-13)), sc.model.core.residual(dq, vk, ak, 1.0, data=data)))
        J_us = med(lambda: (dq.__setitem__(-1, dq[-1] * (1 + 1e-13)), sc.model.core.newton_matrix(dq, vk, ak, 1.0, 1.0, 0.5 * h, 0.25 * h * h, data=data)))
        info = sc.model.basis_info(0)
        rows.append([name, f"{len(vk)}", f"{info['size'] if info else 0}", r_us, J_us])
    table(["model", "velocities", "basis", "residual (us)", "Newton matrix, dense copy (us)"], rows)
    # modal force evaluation cost: the 30-vector force and a 12-vector bending-only force (the same
    # structure as a quartic energy in 12 coordinates: the condensed polynomial's cost class)
    rng = np.random.default_rng(1)
    Pb = P.Phi[:, P.ib]
    fb = _core.ModalInternalForce(P.shell._impl, np.ascontiguousarray(Pb), True)
    E30 = rng.normal(size=(4000, 30)) * 1e-3
    E12 = E30[:, :12].copy()
    rows = []
    for label, f, E in (("30-vector (reduced-nonlinear)", P.force, E30), ("12 bending vectors", fb, E12)):
        for k in range(50):
            f.internal_force(E[k])
        t0 = time.perf_counter()
        for e in E:
            f.internal_force(e)
        rows.append([label, f"{f.quartic_blocks}", 1e6 * (time.perf_counter() - t0) / len(E)])
    t0 = time.perf_counter()
    for e in E12:
        0.5 * np.einsum("kij,i,j->k", C_G, e, e)
    rows.append(["numpy einsum C(q,q) 18x12x12 (Python overhead only)", "", 1e6 * (time.perf_counter() - t0) / len(E12)])
    table(["evaluation (force + tangent, through the binding)", "quartic blocks", "us"], rows)
    nb, nm = len(P.ib), len(P.im)
    print("coefficient counts (symmetric): quartic energy in q_b: C(nb+3,4) = "
          f"{comb(nb + 3, 4)}; energy of eta = g(q) with quadratic g, degree 8: C(nb+7,8) = {comb(nb + 7, 8)}; "
          f"C tensor {nm} x {nb * (nb + 1) // 2} = {nm * nb * (nb + 1) // 2}; 30-vector cubic quartic blocks "
          f"{P.force.quartic_blocks} -> {sum(b * b for b in P.force.quartic_blocks)} entries\n")
    n_rigid, n_man, n_red = 7 + 1, 7 + nb, 7 + 30
    print(f"dense LU flops (2n^3/3): rigid n={n_rigid} {2 * n_rigid ** 3 / 3:.0f}, manifold n={n_man} "
          f"{2 * n_man ** 3 / 3:.0f}, reduced n={n_red} {2 * n_red ** 3 / 3:.0f}")
