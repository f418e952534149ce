"""Cost of one Newton iteration's pieces on the paper's scene (You et al. 2016, lay-up 2; issue 6).

For each model and mesh, one run of ``t_end`` s at ``dt`` (generalized-alpha rho_inf = 0.8) and,
at the run's state at ``t_eval`` (mid-deployment: spinning base, hinge moving, plate deformed),
the median wall time of the engine's evaluations through the bindings:

- ``res``: one ``residual(q, v, a, t)``, the baseline of the ratios (measured in the same
  process, so a noisy machine still gives meaningful ratios);
- ``iter``: one ``newton_matrix(q, v, a, t, 1, gamma h c, beta h^2 c)`` (the binding returns
  it dense: for the full meshes the copy is part of the time, ``dense`` estimates it);
- ``mom_J``: one ``momentum_jacobian(q, v, 1, beta h / gamma)`` (free base only);
- the run: ``ms/step``, Newton iterations and factorizations per step, ``ms/it`` (wall time per
  Newton iteration) and ``it/res`` (that over one residual);
- ``floor``: one forward/backward solve with the sparse LU of the full mesh's elastic block
  S_E = M + beta h^2 K (scipy ``splu``), as in bench/paper_bench.py; ``it/floor`` is the
  per-iteration cost over it.

No assertions: speed is measured here, not tested.

    python bench/newton_profile.py [--t-end 3] [--dt 0.01] [--meshes 6x4 15x10]
        [--models rigid reduced-nonlinear linear nonlinear] [--no-run]
"""
from __future__ import annotations

import one_thread  # noqa: F401  (first: one BLAS thread for CPU times)

import argparse
import statistics
import time

import numpy as np
import scipy.sparse.linalg

import deployfx as dfx
from deployfx import _core
from deployfx.integrators import GeneralizedAlpha

MODELS = ("rigid", "reduced-linear", "reduced-nonlinear", "reduced-manifold", "linear", "nonlinear")
RHO = 0.8


def timed(f, budget: float = 0.3, min_calls: int = 3, clock=time.perf_counter) -> float:
    """Median seconds of one call of f(): batches sized so each lasts about 20 ms, on ``clock``
    (wall time; bench/targets.py passes time.process_time, the CPU time)."""
    t0 = clock()
    f()
    once = max(clock() - t0, 1e-7)
    batch = max(1, int(0.02 / once))
    times = []
    start = clock()
    while len(times) < min_calls or clock() - start < budget:
        t0 = clock()
        for _ in range(batch):
            f()
        times.append((clock() - t0) / batch)
    return statistics.median(times)


def solve_floor(nx: int, ny: int, h: float, beta: float) -> float:
    """Median seconds of one ``lu.solve`` with the full mesh's elastic block."""
    plate = dfx.paper2016.appendage_plate(2, nx, ny)
    free = np.setdiff1d(np.arange(plate.model.num_dofs), plate.fixed_dofs("CFFF"))
    S = plate.model.mass_matrix() + beta * h ** 2 * plate.model.stiffness_matrix()
    lu = scipy.sparse.linalg.splu(S.tocsr()[free][:, free].tocsc())
    b = np.random.default_rng(0).standard_normal(len(free))
    return timed(lambda: lu.solve(b))


def profile(model: str, nx: int, ny: int, modes: int, t_end: float, dt: float, t_eval: float,
            run: bool, clock=time.perf_counter) -> dict:
    """The run's and the evaluations' times on ``clock`` (``wall``: the run's, in either clock),
    and the engine's state, scene and data at ``t_eval`` (``state``) for further timings."""
    scene = dfx.scenes.paper2016(layup=2, model=model, nx=nx, ny=ny, modes=modes)
    model = scene.model
    sys = model.core
    p = GeneralizedAlpha(RHO)._params()
    am, af, beta, gamma = p.alpha_m, p.alpha_f, p.beta, p.gamma
    c = (1 - af) / (1 - am)
    out = {"n": sys.num_velocities}
    q0, v0 = sys.initial_positions(), np.zeros(sys.num_velocities)
    # The state to evaluate at: from a run (to t_eval, or the whole run when timed).
    t_state = t_end if run else t_eval
    # The run's own data, so the evaluations below see its lock history (a fresh one would hold
    # the pin on the track it left at the drop).
    data = model.make_data()
    start = clock()
    raw = _core.simulate(sys, q0, v0, t_end=t_state, dt=dt, scheme=p, data=data)
    wall = clock() - start
    if run:
        n = max(int(raw["substeps"]), 1)
        its = int(np.sum(raw["newton_iterations"]))
        out.update(wall=wall, step=wall / n, its=its / n, fact=raw["factorizations"] / n,
                   per_it=wall / max(its, 1), note=raw["failure"][:40])
    k = int(np.searchsorted(raw["t"], min(t_eval, raw["t"][-1])))
    # Two nearby states, alternated, so no evaluation reuses the previous one's work (the reduced
    # Green-strain force keeps its last polynomial, as a Newton iteration's matrix reuses its residual's).
    rng = np.random.default_rng(1)
    states = [(raw["q"][k], raw["v"][k]),
              (sys.retract(raw["q"][k], 1e-9 * rng.normal(size=sys.num_velocities)), raw["v"][k])]
    a = rng.normal(size=sys.num_velocities) * 1e-2
    t = float(raw["t"][k])

    def alternate(f):
        count = [0]

        def g():
            count[0] += 1
            return f(*states[count[0] % 2])
        return g

    out["res"] = timed(alternate(lambda q, v: sys.residual(q, v, a, t, data=data)), clock=clock)
    out["iter"] = timed(alternate(lambda q, v: sys.newton_matrix(q, v, a, t, 1.0, gamma * dt * c,
                                                                 beta * dt * dt * c, data=data)),
                        clock=clock)
    S = sys.newton_matrix(*states[0], a, t, 1.0, gamma * dt * c, beta * dt * dt * c, data=data)
    out["dense"] = timed(lambda: S.copy(), clock=clock)
    lay = [model.layout(k) for k in range(model.num_hinges)]
    border = min([L["iv_elastic"] for L in lay if L["num_elastic"]], default=sys.num_velocities)
    out["state"] = {"S": S, "border": border}  # the elastic coordinates follow the border
    if sys.num_conserved:
        out["mom_J"] = timed(alternate(lambda q, v: sys.momentum_jacobian(q, v, 1.0, dt * beta / gamma,
                                                                          data=data)),
                               clock=clock)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=3.0, help="simulated time of the timed run (s)")
    ap.add_argument("--dt", type=float, default=0.01, help="step (s)")
    ap.add_argument("--t-eval", type=float, default=1.5, help="time of the state the evaluations use (s)")
    ap.add_argument("--meshes", nargs="+", default=["6x4", "15x10"], help="NXxNY")
    ap.add_argument("--models", nargs="+", default=list(MODELS), choices=MODELS)
    ap.add_argument("--modes", type=int, default=10, help="reduced models' clamped modes")
    ap.add_argument("--no-run", action="store_true", help="evaluations only (no timed run)")
    args = ap.parse_args()
    p = GeneralizedAlpha(RHO)._params()
    print(f"paper2016 lay-up 2, generalized-alpha rho_inf = {RHO}, dt = {args.dt:g} s, run to "
          f"{args.t_end:g} s, evaluations at t = {args.t_eval:g} s; times in ms, ratios over one residual")
    head = (f"{'model':18s} {'mesh':>5s} {'nv':>4s} {'res':>8s} {'iter':>8s} {'dense':>7s} {'mom_J':>8s} "
            f"{'iter/res':>8s} {'momJ/res':>8s} | {'wall s':>7s} {'ms/step':>8s} {'it/step':>7s} "
            f"{'fact/st':>7s} {'ms/it':>7s} {'it/res':>7s} {'it/floor':>8s}")
    print(head)
    for mesh in args.meshes:
        nx, ny = (int(x) for x in mesh.lower().split("x"))
        floor = solve_floor(nx, ny, args.dt, p.beta)
        for model in args.models:
            m = profile(model, nx, ny, args.modes, args.t_end, args.dt, args.t_eval, not args.no_run)
            def ms(key, m=m):
                return f"{1e3 * m[key]:8.4f}" if key in m else f"{'-':>8s}"
            line = (f"{model:18s} {mesh:>5s} {m['n']:4d} {ms('res')} {ms('iter')} {1e3 * m['dense']:7.4f} "
                    f"{ms('mom_J')} {m['iter'] / m['res']:8.1f} "
                    f"{(m['mom_J'] / m['res'] if 'mom_J' in m else float('nan')):8.1f} |")
            if "wall" in m:
                line += (f" {m['wall']:7.2f} {1e3 * m['step']:8.3f} {m['its']:7.2f} {m['fact']:7.3f} "
                         f"{1e3 * m['per_it']:7.3f} {m['per_it'] / m['res']:7.1f} {m['per_it'] / floor:8.1f} "
                         f"{m['note']}")
            print(line, flush=True)
        print(f"{'floor':18s} {mesh:>5s} one splu solve of the full mesh's S_E: {1e3 * floor:.4f} ms", flush=True)


if __name__ == "__main__":
    main()
