"""Speed-accuracy trade of the paper's scene (You et al. 2016, lay-up 2): error against wall time.

Runs one-factor-at-a-time sweeps around a base case (``--base-mesh``, ``--base-dt``,
generalized-alpha rho_inf = 0.8) with :func:`deployfx.tradeoff`, all in one process:

- fidelity: rigid, reduced-nonlinear with 5/10/20 modes, reduced-linear with 10, linear, nonlinear;
- mesh (``--meshes``, capped by ``--max-mesh``): nonlinear and reduced-nonlinear (10 modes);
- dt (``--dts``): rigid, reduced-nonlinear (10), nonlinear;
- integrator: generalized-alpha rho_inf = 0.8, HHT alpha = -0.05, Newmark (average
  acceleration), for nonlinear and reduced-nonlinear (10);
- adaptive: nonlinear with error-controlled steps (``tolerance``) on the base output step.

The reference is the finest nonlinear run: the largest mesh of the sweep, fixed steps of
``--ref-dt``. Errors (see :mod:`deployfx.tradeoff`): |first lock time error| (s), relative peak lock
force error, RMS of the node E deflection history error over [0, t_end] relative to the
reference's max |deflection|.

Why t_end = 3 s by default (``--t-end 30`` for the paper's whole record): the three compared
quantities live in the deployment and the first impact (lock at ~2.46 s). Past the impact the
undamped appendage rings for the rest of the 30 s, and its phase error grows with time, so a 30 s
history error measures mostly the phase drift of a 0.8 Hz oscillation.

What converges, measured (nonlinear, 4 x 3 mesh; rigid 4 x 3 for its own column):

- Peak lock force is ill-conditioned in dt. The paper's contact law has a damping term D dδ/dt
  (D = 1e6 N s/m) that jumps at contact onset, so the force at first contact is about D times the
  pin's approach velocity; for the flexible models the first contact lasts ~1 ms (the root
  vibrates against the pin) and the peak is read from output samples. Nonlinear 4 x 3, peak (N) vs
  dt (s): 3.05e4 (0.01), 5.52e4 (0.001: an earlier contact, 2.4648 s against 2.4671 s), 3.07e4
  (5e-4), 2.90e4 (2e-4), 2.83e4 (1e-4). The rigid model: 5.93e4 (0.01), 4.84e4 (0.001), 4.60e4
  (1e-4), 4.59e4 (1e-5; a 16 ms contact). So the reference step must be 2e-4 or smaller for a
  few-percent peak; coarse-step peaks can be off by +-80 % either way.
- The adaptive ``tolerance`` option does not help the reference: steps shrink inside the contact
  but the series are recorded on the output grid (dt), so the sampled peak still misses the
  maximum (rigid 4 x 3, dt = 0.01: 3.6e4 N at tolerance 1e-7 against 4.59e4 N converged). A
  reference needs a small output step.
- First lock time converges fast (rigid: within 2e-5 s for all dt; nonlinear 4 x 3: 2.4767 s at
  dt = 0.01, 2.4671 s at 5e-4 and 2.4672 s at 1e-4), except for the dt = 0.001 outlier above.
- The node E history converges at second order in dt before the impact; after it, it inherits
  the impact's error.

No assertions: the trade is measured here, not tested. Writes ``tradeoff.csv`` (every column of
:data:`deployfx.tradeoff.COLUMNS`), ``tradeoff.md`` (the short table, for the README),
``tradeoff.png`` (work-precision plot) and ``reference.npz`` (the reference's series, reused with
``--reuse-reference``) to ``--out``.

    python bench/tradeoff.py --quick                     # ~2-3 min on 2 cores
    python bench/tradeoff.py --max-mesh 10x7             # medium
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
from deployfx.tradeoff import (SHORT, Case, plot_work_precision, scheme_label, to_markdown, to_text,
                               write_csv)

SWEEPS = ("fidelity", "mesh", "dt", "integrator", "adaptive")
MESHES = ("4x3", "6x4", "10x7", "15x10", "20x13", "30x20")
DTS = (0.02, 0.01, 0.005, 0.002, 0.001)
SCHEMES = (GeneralizedAlpha(0.8), HHT(-0.05), Newmark(0.25, 0.5))
RN = "reduced-nonlinear"


def mesh_size(mesh: str) -> tuple[int, int]:
    nx, ny = (int(v) for v in mesh.lower().split("x"))
    return nx, ny


def build_cases(sweeps, base_mesh: str, base_dt: float, meshes, dts, tolerance: float) -> list[Case]:
    """The sweep's cases, duplicates removed, in sweep order."""
    nx, ny = mesh_size(base_mesh)
    base = dict(nx=nx, ny=ny, dt=base_dt)
    cases = []
    if "fidelity" in sweeps:
        cases += [Case("rigid", **base)]
        cases += [Case(RN, modes=k, **base) for k in (5, 10, 20)]
        cases += [Case("reduced-linear", modes=10, **base), Case("linear", **base), Case("nonlinear", **base)]
    if "mesh" in sweeps:
        for mesh in meshes:
            mx, my = mesh_size(mesh)
            cases += [Case("nonlinear", mx, my, base_dt), Case(RN, mx, my, base_dt, modes=10)]
    if "dt" in sweeps:
        for dt in dts:
            cases += [Case("rigid", nx, ny, dt), Case(RN, nx, ny, dt, modes=10), Case("nonlinear", nx, ny, dt)]
    if "integrator" in sweeps:
        for scheme in SCHEMES:
            cases += [Case("nonlinear", nx, ny, base_dt, scheme), Case(RN, nx, ny, base_dt, scheme, modes=10)]
    if "adaptive" in sweeps:
        cases += [Case("nonlinear", nx, ny, base_dt, tolerance=tolerance)]
    unique = []
    for c in cases:
        if c not in unique:
            unique.append(c)
    return unique


def reference_result(args, ref: Case):
    """A saved reference from ``--out`` if ``--reuse-reference`` and it matches, else None."""
    path = Path(args.out) / "reference.npz"
    if not (args.reuse_reference and path.exists()):
        return None
    r = dfx.load(path)
    m = r.metadata
    same = (m.get("model") == ref.model and m.get("mesh") == ref.mesh and m.get("dt") == ref.dt
            and m.get("tolerance") == ref.tolerance and m.get("layup") == args.layup
            and m.get("integrator_label") == scheme_label(ref.scheme)
            and m.get("t_end", 0.0) >= args.t_end)
    if not same:
        print(f"{path} does not match the reference {ref.name}, t_end {args.t_end:g}: running it")
        return None
    print(f"reusing the reference {ref.name} from {path} (wall time {m.get('wall_time_s', math.nan):.1f} s)")
    return r


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true",
                    help="meshes 4x3 and 6x4, base 4x3, dts down to 0.002, reference 6x4 at dt 5e-4 (~2-3 min)")
    ap.add_argument("--t-end", type=float, default=3.0, help="simulated time (s), default 3 (see above)")
    ap.add_argument("--out", default="bench/out", help="output folder (default bench/out)")
    ap.add_argument("--sweeps", nargs="+", default=list(SWEEPS), choices=SWEEPS)
    ap.add_argument("--meshes", nargs="+", default=None, help=f"NXxNY; default {' '.join(MESHES)}")
    ap.add_argument("--max-mesh", default=None, help="drop meshes with more elements than NXxNY")
    ap.add_argument("--base-mesh", default=None, help="mesh of the fidelity/dt/integrator sweeps "
                    "(default 15x10, quick 4x3; capped by --max-mesh)")
    ap.add_argument("--base-dt", type=float, default=0.01, help="step of the fidelity/mesh/integrator sweeps (s)")
    ap.add_argument("--dts", nargs="+", type=float, default=None, help=f"default {' '.join(map(str, DTS))}")
    ap.add_argument("--tolerance", type=float, default=1e-5, help="adaptive sweep's tolerance (m or rad)")
    ap.add_argument("--ref-mesh", default=None, help="reference mesh (default: the largest of the sweep)")
    ap.add_argument("--ref-dt", type=float, default=None, help="reference step (s), default 2e-4 (quick 5e-4)")
    ap.add_argument("--layup", type=int, default=2, choices=(1, 2))
    ap.add_argument("--repeat", type=int, default=1, help="timed runs per case (median wall time)")
    ap.add_argument("--reuse-reference", action="store_true", help="load --out/reference.npz if it matches")
    args = ap.parse_args()

    meshes = args.meshes or (["4x3", "6x4"] if args.quick else list(MESHES))
    if args.max_mesh:
        cap = math.prod(mesh_size(args.max_mesh))
        meshes = [m for m in meshes if math.prod(mesh_size(m)) <= cap]
    base_mesh = args.base_mesh or ("4x3" if args.quick else "15x10")
    if args.max_mesh and math.prod(mesh_size(base_mesh)) > cap:
        base_mesh = max(meshes, key=lambda m: math.prod(mesh_size(m)))
    dts = args.dts or ([0.02, 0.01, 0.005, 0.002] if args.quick else list(DTS))
    ref_mesh = args.ref_mesh or max(meshes + [base_mesh], key=lambda m: math.prod(mesh_size(m)))
    ref_dt = args.ref_dt or (5e-4 if args.quick else 2e-4)
    ref = Case("nonlinear", *mesh_size(ref_mesh), ref_dt)
    cases = build_cases(args.sweeps, base_mesh, args.base_dt, meshes, dts, args.tolerance)
    cases = [c for c in cases if c != ref]  # the reference is the table's first row
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)

    print(f"paper2016 lay-up {args.layup}, t_end = {args.t_end:g} s; sweeps {' '.join(args.sweeps)}; "
          f"base {base_mesh}, dt {args.base_dt:g} s, GA(0.8); reference {ref.name}; {len(cases)} cases")
    start = time.perf_counter()
    reference = reference_result(args, ref) or ref

    def progress(row, result):
        if row["is_reference"] and result is not None and isinstance(reference, Case):
            keep = ("t", "lock_force", "node_E_deflection", "deployment_angle")
            meta = dict(result.metadata, layup=args.layup, mesh=ref.mesh,
                        integrator_label=scheme_label(ref.scheme))
            dfx.Result({k: result[k] for k in keep}, {k: result.units[k] for k in keep}, meta).save(
                out / "reference.npz")
        note = f"  FAILED: {row['failure']}" if row["failure"] else ""
        print(f"  [{time.perf_counter() - start:7.1f} s] {row['label']:48s} wall {row['wall_time_s']:8.3f} s{note}",
              flush=True)

    rows = dfx.tradeoff(cases, reference, args.t_end, layup=args.layup, repeat=args.repeat, callback=progress)
    total = time.perf_counter() - start

    ref_wall = rows[0]["wall_time_s"]
    for r in rows:  # speed-up over the reference, run in the same process (a noisy machine still
        r["speedup"] = ref_wall / r["wall_time_s"] if r["wall_time_s"] else math.nan  # gives ratios)
    columns = dict(SHORT)
    columns["speedup"] = "{:.3g}"
    write_csv(rows, out / "tradeoff.csv")
    (out / "tradeoff.md").write_text(to_markdown(rows, columns) + "\n")
    fig = plot_work_precision(rows, title=f"paper2016 lay-up {args.layup}, t_end = {args.t_end:g} s, "
                              f"reference: {rows[0]['label'].removeprefix('reference: ')}")
    fig.savefig(out / "tradeoff.png", dpi=120)
    print()
    print(to_text(rows, columns))
    print(f"\nreference: lock {rows[0]['ref_lock_time_s']:.5f} s, peak lock force "
          f"{rows[0]['ref_peak_lock_force_N']:.4g} N, max |node E deflection| "
          f"{rows[0]['ref_max_node_E_deflection_m']:.4f} m")
    print(f"total {total:.0f} s; wrote {out / 'tradeoff.csv'}, {out / 'tradeoff.md'}, {out / 'tradeoff.png'}\n")
    print(to_markdown(rows, columns))


if __name__ == "__main__":
    main()
