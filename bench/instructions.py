"""Instructions the engine executes for each model of the paper's scene (You et al. 2016, lay-up 2,
generalized-alpha rho_inf = 0.8): a count that does not depend on the machine's load.

Wall and CPU times on a shared virtual machine scatter by 10-25 % from run to run (session 30's
AMD EPYC), more than most single changes gain; the number of instructions a run executes is the
same in every run of one build. For each model one run of ``--t-end`` s at ``--dt`` (the
engine's ``_core.simulate``, as bench/targets.py times it) executes under valgrind's callgrind,
counting only inside ``multibody::simulate`` (the scene's setup, Python and the outputs' arrays
left out), and the table gives the count, per integration step (``substeps``, event-search
trials included) and per Newton iteration, with the run's iterations and factorizations; ``vs
rigid`` is the count over the rigid model's of the same run, when it is among the models.

What the count does not see: cache misses and the instructions' cost (a division against an
addition; glibc's memset by ``rep stosb`` counts once per iteration of the string instruction, so
zeroing large arrays weighs more than it costs). Compare a change by the count of one model
before and after it (two builds), and confirm a large change with CPU time (bench/targets.py,
bench/paper_bench.py). valgrind is an apt package (``apt-get install valgrind``); where it is
missing the script says so and stops. Under callgrind a run takes about 50 times its CPU time,
and the scene's setup runs emulated too: the default 5 s of the six models took 30 minutes on
session 31's machine (linear and nonlinear 15 of them).

No assertions: speed is measured here, not tested.

    python bench/instructions.py [--t-end 5] [--dt 0.01] [--mesh 15x10]
        [--models rigid reduced-linear reduced-nonlinear reduced-manifold linear nonlinear]
"""
from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

from machine import describe
from newton_profile import MODELS, RHO

#: Counted: the engine's run alone (C++ symbol, callgrind's --toggle-collect pattern).
ENGINE_RUN = "*multibody::simulate*"

# One run in a child process (callgrind runs a whole interpreter): the scene as targets.py builds
# it, its counters printed as JSON on the last line.
CHILD = """
import json, sys
import numpy as np
import deployfx as dfx
from deployfx import _core
from deployfx.integrators import GeneralizedAlpha
model, nx, ny, t_end, dt, rho = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6])
scene = dfx.scenes.paper2016(layup=2, model=model, nx=nx, ny=ny, modes=10)
core = scene.model.core
raw = _core.simulate(core, core.initial_positions(), np.zeros(core.num_velocities), t_end=t_end, dt=dt,
                     scheme=GeneralizedAlpha(rho)._params(), data=scene.model.make_data())
print(json.dumps({"substeps": int(raw["substeps"]), "its": int(np.sum(raw["newton_iterations"])),
                  "fact": int(raw["factorizations"]), "failure": str(raw["failure"])}))
"""


def count(model: str, nx: int, ny: int, t_end: float, dt: float) -> dict:
    """The run's counters and the instructions executed inside the engine's run loop."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "callgrind.out")
        cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={out}", f"--toggle-collect={ENGINE_RUN}",
               sys.executable, "-c", CHILD, model, str(nx), str(ny), str(t_end), str(dt), str(RHO)]
        proc = subprocess.run(cmd, check=False, capture_output=True, text=True)
        if proc.returncode != 0:
            raise RuntimeError(f"{model}: the run under callgrind failed:\n{proc.stderr[-2000:]}")
        run = json.loads(proc.stdout.strip().splitlines()[-1])
        with open(out, encoding="utf-8") as f:
            totals = [line for line in f if line.startswith(("totals:", "summary:"))]
    if not totals:
        raise RuntimeError(f"{model}: callgrind wrote no totals")
    run["instructions"] = int(re.split(r"\s+", totals[-1].strip())[1])
    return run


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--t-end", type=float, default=5.0, help="simulated time of each run (s)")
    ap.add_argument("--dt", type=float, default=0.01, help="output step (s)")
    ap.add_argument("--mesh", default="15x10", help="appendage mesh, NXxNY")
    ap.add_argument("--models", nargs="+", default=list(MODELS), choices=MODELS)
    args = ap.parse_args()
    if shutil.which("valgrind") is None:
        print("valgrind is not installed (apt-get install valgrind): no instruction counts")
        return
    nx, ny = (int(k) for k in args.mesh.lower().split("x"))
    print(f"paper2016 lay-up 2, {args.mesh}, t_end = {args.t_end:g} s, dt = {args.dt:g} s, "
          f"generalized-alpha rho_inf = {RHO}; instructions inside {ENGINE_RUN} (callgrind); {describe()}")
    print(f"{'model':18s} {'substeps':>8s} {'its':>7s} {'fact':>6s} {'instr (G)':>10s} "
          f"{'k/substep':>10s} {'k/it':>8s} {'vs rigid':>9s}")
    rows = {}
    for model in args.models:
        r = rows[model] = count(model, nx, ny, args.t_end, args.dt)
        base = rows.get("rigid")
        ratio = f"{r['instructions'] / base['instructions']:9.1f}" if base else f"{'-':>9s}"
        print(f"{model:18s} {r['substeps']:8d} {r['its']:7d} {r['fact']:6d} {r['instructions'] / 1e9:10.3f} "
              f"{r['instructions'] / max(r['substeps'], 1) / 1e3:10.1f} {r['instructions'] / max(r['its'], 1) / 1e3:8.1f} "
              f"{ratio} {r['failure'][:30]}", flush=True)


if __name__ == "__main__":
    main()
