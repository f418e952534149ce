"""Fuzz cases of the Scene builder, compile() and simulate() on tiny scenes (run in the child of
fuzz_harness.py). Kept apart from fuzz_cases_api.py: the multibody engine's API is being
rewritten, and these cases follow it."""
from __future__ import annotations

import functools

import numpy as np

import deployfx as dfx
from deployfx import contact
from deployfx.integrators import SimulationError
from fuzz_harness import case

NAMES = ("mass", "inertia", "com", "free", "point", "axis", "tau0", "k_theta", "c_theta",
         "fitting", "shell", "fixed_dofs", "fidelity", "damping", "modes", "derivative_modes",
         "theta_lock", "pin_radius", "clearance", "law", "friction", "contact", "t_end", "dt",
         "base", "hinge", "appendage", "lock", "K", "n", "D", "e", "mu", "v_reg")


@functools.lru_cache(maxsize=None)
def _plate(nx, ny):
    lam = dfx.Laminate([dfx.Ply(dfx.Isotropic(70e9, 0.33, 2700.0), 2e-3)])
    return dfx.Plate(0.6, 0.4, lam, nx, ny)


def build(base, hinge, appendage, lock):
    scene = dfx.Scene().set_base(base["mass"], base["inertia"], free=base["free"])
    scene.set_hinge(point=hinge["point"], axis=hinge["axis"], tau0=hinge["tau0"],
                    k_theta=hinge["k_theta"], c_theta=hinge["c_theta"],
                    fitting_inertia=hinge["fitting_inertia"])
    if appendage is not None:
        plate = _plate(appendage["nx"], 1)
        fixed = plate.fixed_dofs("CFFF") if appendage["fixed"] == "root" else appendage["fixed"]
        scene.set_appendage(plate.model, fixed, fidelity=appendage["fidelity"],
                            damping=appendage["damping"], modes=appendage["modes"])
    if lock is not None:
        scene.set_lock(lock["theta_lock"], lock["pin_radius"], lock["clearance"],
                       contact.ContactLaw("paper", K=lock["K"], n=1.5, D=lock["D"]),
                       friction=contact.Friction(lock["mu"]))
    return scene


@case("scene_build", NAMES)
def scene_build(base, hinge, appendage, lock):
    scene = build(base, hinge, appendage, lock)
    return dfx.scene_file.scene_to_dict(scene) if appendage is not None else None


@case("scene_simulate", NAMES)
def scene_simulate(base, hinge, appendage, lock, t_end, dt):
    model = build(base, hinge, appendage, lock).compile()
    try:
        r = model.simulate(t_end, dt)
    except SimulationError as e:  # a run that stopped early: what it computed must be finite
        r = e.result
    return {name: np.asarray(r[name]) for name in r.series}, r.metadata
