"""Speed-accuracy trade of the paper's scene (You et al. 2016, lay-up 2): error against wall time.

Runs one-factor-at-a-time sweeps around a base case (``--base-mesh``, ``--base-dt``,
generalized-alpha rho_inf = 0.8) with :func:`deployfx.tradeoff`, all in one process:

- fidelity: rigid, reduced-nonlinear with 5/10/20 modes (and 10 on session 17's basis, the
  modal derivatives of every pair among the first 6 modes and no partners, ``derivative_modes=6,
  derivative_partners=0``: 36 vectors against the default's 30), reduced-manifold with 10 (the
  same 30-vector basis, its in-plane coordinates slaved to the bending ones), reduced-linear with
  10, linear, nonlinear;
- mesh (``--meshes``, capped by ``--max-mesh``): nonlinear and reduced-nonlinear (10 modes);
- dt (``--dts``): rigid, reduced-nonlinear (10), nonlinear;
- integrator: generalized-alpha rho_inf = 0.8, HHT alpha = -0.05, Newmark (average
  acceleration), for nonlinear and reduced-nonlinear (10; not in ``--quick``);
- adaptive: nonlinear with error-controlled steps (``tolerance``) on the base output step.

The reference is the finest nonlinear run: the largest mesh of the sweep, fixed steps of
``--ref-dt``. Errors (see :mod:`deployfx.tradeoff`): |first lock time error| (s), relative peak lock
force error, RMS of the node E deflection history error over [0, t_end] relative to the
reference's max |deflection|.

Why t_end = 3 s by default (``--t-end 30`` for the paper's whole record): the three compared
quantities live in the deployment and the first impact (lock at ~2.46 s). Past the impact the
undamped appendage rings for the rest of the 30 s, and its phase error grows with time, so a 30 s
history error measures mostly the phase drift of a 0.8 Hz oscillation.

What converges on the UNDAMPED scene (``damping=(0, 0)``, the default when this was measured, in
session 4; nonlinear; rigid where said). On the damped default scene (session 6) the first lock
and the peak lock force converge: every flexible model within 0.4 ms and 0.07 % of the
reference down to dt = 0.02 s (the README's table).

- Peak lock force: ill-conditioned in dt for the flexible models, and not converged at any step
  this bench can afford. The paper's contact law F = K delta^1.5 + D d(delta)/dt (D = 1e6 N s/m)
  jumps to D r_pin dtheta/dt at contact onset, and for a flexible appendage that jump IS the peak:
  the light hinge fitting (0.02 kg m^2) hits the stop and is stopped within one step (its damping
  time J / (D r_pin^2) = 22 us), then the plate's root pushes on it with a few hundred N. The
  fitting's rate at onset carries the root's high-frequency vibration, so the peak samples a
  phase. Peak (N) [lock time (s)] against dt (s):
  4 x 3: 3.05e4 [2.4767] at 0.01, 5.52e4 [2.4648] at 0.001, 3.07e4 [2.4671] at 5e-4,
  2.90e4 [2.4672] at 2e-4, 2.08e4 [2.4674] at 1e-4, 2.45e4 [2.4674] at 5e-5;
  6 x 4: 3.76e4 [2.4641] at 5e-4, 1.26e4 [2.4654] at 2e-4, 1.44e4 [2.4657] at 1e-4.
  The rigid model (whole panel on the stop, a 16 ms contact) converges: 5.93e4 at 0.01, 4.84e4 at
  0.001, 4.60e4 at 1e-4, 4.59e4 at 1e-5. So read the peak-force column as "how far from the
  reference's sample", with a reference uncertainty of tens of percent.
- The adaptive ``tolerance`` option does not fix the reference: steps shrink in the contact but the
  series are recorded on the output grid (dt), so the sampled peak still misses the maximum
  (rigid, dt = 0.01: 3.6e4 N at tolerance 1e-7 against 4.59e4 N converged). A reference needs a
  small output step; the default is fixed steps of 2e-4 s (quick: 5e-4 s).
- First lock time converges to ~3e-4 s at dt <= 2e-4 (above), with outliers at coarser steps
  where the vibrating fitting touches the stop a few ms early or late; rigid: within 2e-5 s at
  any dt.
- The node E history converges: on a mesh coarser than the reference's its error is the mesh's
  (4 x 3 against 6 x 4: 6-7 % at every dt from 0.02 to 0.002).

Cost of one nonlinear step (ms) at dt = 2e-4 / 0.01 (early deployment, 2.5 / 12.8 Newton
iterations per step): 10 x 7: 7.7 / 55; 15 x 10: 19 / 154; 30 x 20: 162 / 1550. The full sweep's
30 x 20 reference (15000 steps) therefore takes ~40 min and the whole full sweep over an hour.
Measured on a shared 2-core machine: ``--quick`` 176 s; ``--max-mesh 10x7`` 761 s (its 10 x 7
reference at dt = 2e-4: 157 s); in session 6 (damped default, Newton and set-up gains)
``--max-mesh 10x7`` 170 s (reference 51 s); the full sweep with ``--ref-dt 5e-4`` 1393 s (its
30 x 20 reference 747 s).

No assertions: the trade is measured here, not tested. Writes ``tradeoff.csv`` (every column of
:data:`deployfx.tradeoff.COLUMNS`), ``tradeoff.md`` (the short table, for the README),
``tradeoff.png`` (work-precision plot) and ``reference.npz`` (the reference's series, reused with
``--reuse-reference``) to ``--out``.

    python bench/tradeoff.py --quick                     # ~3 min
    python bench/tradeoff.py --max-mesh 10x7             # medium, ~13 min
    python bench/tradeoff.py                             # the issue's sweep, up to 30 x 20
    python bench/tradeoff.py --sweeps fidelity dt --t-end 30
"""
from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import deployfx as dfx
from deployfx.integrators import HHT, GeneralizedAlpha, Newmark
from deployfx.tradeoff import Case, scheme_label
from deployfx.tradeoff_report import SHORT, plot_work_precision, to_markdown, to_text, write_csv
from machine import describe

SWEEPS = ("fidelity", "mesh", "dt", "integrator", "adaptive")
MESHES = ("4x3", "6x4", "10x7", "15x10", "20x13", "30x20")
DTS = (0.02, 0.01, 0.005, 0.002, 0.001)
SCHEMES = (GeneralizedAlpha(0.8), HHT(-0.05), Newmark(0.25, 0.5))
RN = "reduced-nonlinear"


def mesh_size(mesh: str) -> tuple[int, int]:
    nx, ny = (int(v) for v in mesh.lower().split("x"))
    return nx, ny


def elements(mesh: str) -> int:
    return math.prod(mesh_size(mesh))


def build_cases(sweeps, base_mesh: str, base_dt: float, meshes, dts, tolerance: float,
                quick: bool = False) -> list[Case]:
    """The sweep's cases, duplicates removed, in sweep order."""
    nx, ny = mesh_size(base_mesh)
    base = dict(nx=nx, ny=ny, dt=base_dt)
    cases = []
    if "fidelity" in sweeps:
        cases += [Case("rigid", **base)]
        cases += [Case(RN, modes=k, **base) for k in (5, 10, 20)]
        cases += [Case(RN, modes=10, derivative_modes=6, derivative_partners=0, **base)]  # session 17's 36
        cases += [Case("reduced-manifold", modes=10, **base)]
        cases += [Case("reduced-linear", modes=10, **base), Case("linear", **base),
                  Case("nonlinear", **base)]
    if "mesh" in sweeps:
        for mesh in meshes:
            mx, my = mesh_size(mesh)
            cases += [Case("nonlinear", mx, my, base_dt), Case(RN, mx, my, base_dt, modes=10)]
    if "dt" in sweeps:
        for dt in dts:
            cases += [Case("rigid", nx, ny, dt), Case(RN, nx, ny, dt, modes=10),
                      Case("nonlinear", nx, ny, dt)]
    if "integrator" in sweeps:
        for scheme in SCHEMES:
            cases += [Case("nonlinear", nx, ny, base_dt, scheme)]
            cases += [] if quick else [Case(RN, nx, ny, base_dt, scheme, modes=10)]
    if "adaptive" in sweeps:
        cases += [Case("nonlinear", nx, ny, base_dt, tolerance=tolerance)]
    unique = []
    for c in cases:
        if c not in unique:
            unique.append(c)
    return unique


def saved_reference(args, ref: Case):
    """The reference saved in ``--out`` if ``--reuse-reference`` and it matches, else None."""
    path = Path(args.out) / "reference.npz"
    if not (args.reuse_reference and path.exists()):
        return None
    r = dfx.load(path)
    m = r.metadata
    same = (m.get("model") == ref.model and m.get("mesh") == ref.mesh and m.get("dt") == ref.dt
            and m.get("tolerance") == ref.tolerance and m.get("layup") == args.layup
            and m.get("integrator_label") == scheme_label(ref.scheme)
            and m.get("lock_geometry", "stop-latch") == args.lock_geometry
            and m.get("t_end", 0.0) >= args.t_end)
    if not same:
        print(f"{path} does not match the reference {ref.name}, t_end {args.t_end:g}: running it")
        return None
    print(f"reusing the reference {ref.name} from {path} "
          f"(wall time {m.get('wall_time_s', math.nan):.1f} s)")
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="meshes 4x3 and 6x4, base 4x3, dts down "
                    "to 0.002, reference 6x4 at dt 5e-4 (~3 min)")
    ap.add_argument("--t-end", type=float, default=3.0, help="simulated time (s), default 3")
    ap.add_argument("--out", default="bench/out", help="output folder (default bench/out)")
    ap.add_argument("--sweeps", nargs="+", default=list(SWEEPS), choices=SWEEPS)
    ap.add_argument("--meshes", nargs="+", default=None, help=f"NXxNY; default {' '.join(MESHES)}")
    ap.add_argument("--max-mesh", default=None, help="drop meshes with more elements than NXxNY")
    ap.add_argument("--base-mesh", default=None, help="mesh of the fidelity/dt/integrator sweeps "
                    "(default 15x10, quick 4x3; capped by --max-mesh)")
    ap.add_argument("--base-dt", type=float, default=0.01,
                    help="step (s) of the fidelity/mesh/integrator sweeps")
    ap.add_argument("--dts", nargs="+", type=float, default=None,
                    help=f"steps (s) of the dt sweep; default {' '.join(map(str, DTS))}")
    ap.add_argument("--tolerance", type=float, default=1e-5,
                    help="the adaptive sweep's tolerance (m or rad)")
    ap.add_argument("--ref-mesh", default=None, help="reference mesh (default: the largest)")
    ap.add_argument("--ref-dt", type=float, default=None,
                    help="reference step (s), default 2e-4 (quick 5e-4)")
    ap.add_argument("--layup", type=int, default=2, choices=(1, 2))
    ap.add_argument("--repeat", type=int, default=1, help="timed runs per case (median wall time)")
    ap.add_argument("--reuse-reference", action="store_true",
                    help="load --out/reference.npz if it matches the reference case")
    ap.add_argument("--lock-geometry", default="groove", choices=("groove", "stop-latch"),
                    help="the paper scene's lock (default groove, the scene's; the table before "
                         "session 17 was measured with stop-latch)")
    args = ap.parse_args()

    meshes = args.meshes or (["4x3", "6x4"] if args.quick else list(MESHES))
    base_mesh = args.base_mesh or ("4x3" if args.quick else "15x10")
    if args.max_mesh:
        meshes = [m for m in meshes if elements(m) <= elements(args.max_mesh)]
        if elements(base_mesh) > elements(args.max_mesh):
            base_mesh = max(meshes, key=elements)
    dts = args.dts or ([0.02, 0.01, 0.005, 0.002] if args.quick else list(DTS))
    ref_mesh = args.ref_mesh or max(meshes + [base_mesh], key=elements)
    ref_dt = args.ref_dt or (5e-4 if args.quick else 2e-4)
    ref = Case("nonlinear", *mesh_size(ref_mesh), ref_dt)
    cases = build_cases(args.sweeps, base_mesh, args.base_dt, meshes, dts, args.tolerance,
                        args.quick)
    cases = [c for c in cases if c != ref]  # the reference is the table's first row anyway
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    print(f"paper2016 lay-up {args.layup}, {args.lock_geometry} lock, t_end = {args.t_end:g} s; sweeps "
          f"{' '.join(args.sweeps)}; base {base_mesh}, dt {args.base_dt:g} s, GA(0.8); "
          f"reference {ref.name}; {len(cases)} cases; {describe()}")
    start = time.perf_counter()
    reference = saved_reference(args, ref) or ref

    def progress(row, result):
        if row["is_reference"] and result is not None and isinstance(reference, Case):
            keep = ("t", "lock_force", "node_E_deflection", "deployment_angle")
            meta = dict(result.metadata, layup=args.layup, mesh=ref.mesh, lock_geometry=args.lock_geometry,
                        integrator_label=scheme_label(ref.scheme))
            dfx.Result({k: result[k] for k in keep}, {k: result.units[k] for k in keep},
                       meta).save(out / "reference.npz")
        note = f"  FAILED: {row['failure']}" if row["failure"] else ""
        print(f"  [{time.perf_counter() - start:7.1f} s] {row['label']:48s} "
              f"wall {row['wall_time_s']:8.3f} s{note}", flush=True)

    rows = dfx.tradeoff(cases, reference, args.t_end, layup=args.layup, repeat=args.repeat,
                        scene_overrides={"lock_geometry": args.lock_geometry}, callback=progress)
    total = time.perf_counter() - start

    # Speed-up over the reference, run in the same process: ratios survive a noisy machine.
    ref_wall = rows[0]["wall_time_s"]
    for r in rows:
        r["speedup"] = ref_wall / r["wall_time_s"] if r["wall_time_s"] else math.nan
    columns = dict(SHORT, speedup="{:.3g}")
    write_csv(rows, out / "tradeoff.csv")
    (out / "tradeoff.md").write_text(to_markdown(rows, columns) + "\n")
    ref_label = rows[0]["label"].removeprefix("reference: ")
    fig = plot_work_precision(rows, title=f"paper2016 lay-up {args.layup}, t_end = "
                              f"{args.t_end:g} s, reference: {ref_label}")
    fig.savefig(out / "tradeoff.png", dpi=120)
    print()
    print(to_text(rows, columns))
    print(f"\nreference: lock {rows[0]['ref_lock_time_s']:.5f} s, peak lock force "
          f"{rows[0]['ref_peak_lock_force_N']:.4g} N, max |node E deflection| "
          f"{rows[0]['ref_max_node_E_deflection_m']:.4f} m")
    print(f"total {total:.0f} s; wrote tradeoff.csv, tradeoff.md, tradeoff.png, reference.npz "
          f"to {out}\n")
    print(to_markdown(rows, columns))


if __name__ == "__main__":
    main()
