"""What a run of a :class:`deployfx.Model` records besides the engine's arrays: its series, named
once here from the engine's raw output (:mod:`deployfx.results` documents them), and the
per-hinge description its metadata starts from."""
from __future__ import annotations

import numpy as np

from ._run import base_attitude_deg


def describe_hinges(model) -> tuple:
    """Per hinge, a dict of what the model says of it (parent, fidelity, lock, drive, tip node, mesh,
    a reduced panel's basis and its elastic coordinates), before a run adds its own keys."""
    out = []
    for k, L in enumerate(model.links):
        lay = model.core.layout(k)
        info = {"parent": "base" if lay["parent"] < 0 else int(lay["parent"]),
                "fidelity": None if L.appendage is None else str(L.appendage.fidelity),
                "lock": L.lock is not None, "lock_play_deg": None if L.lock is None else L.lock.play_deg,
                "driven": L.hinge.spin_up is not None, "stowed_angle_deg": L.hinge.stowed_angle_deg,
                "tip_node": int(model.tip_nodes[k])}
        if L.hinge.spin_up is not None:
            info["spin_up"] = {"omega_s_rad_per_s": float(L.hinge.spin_up.omega_s),
                               "t_s_s": float(L.hinge.spin_up.t_s)}
        if L.appendage is not None:
            info["mesh"] = {"nodes": int(L.appendage.shell.nodes.shape[0]),
                            "quads": int(np.asarray(L.appendage.shell.quads).shape[0])}
        b = model.core.basis_info(k)
        if b is not None:
            info.update(modes=b["modes"], static_corrections=b["static_corrections"],
                        modal_derivatives=b["modal_derivatives"], basis_size=b["size"],
                        elastic_coordinates=int(lay["num_elastic"]))  # < basis_size on a manifold
        out.append(info)
    return tuple(out)


def series(model, raw: dict) -> dict:
    """A run's series from the engine's arrays ``raw``: angles in degrees from the stowed angle,
    each deforming panel's tip translations and deflection along its tip direction, the base's
    attitude, momenta and energies, q and v."""
    q = raw["q"]
    n, H = len(q), model.num_hinges
    stowed = model._rest[2]
    tip = np.zeros((n, H, 3))
    deflection = np.zeros((n, H))
    for k, translations in enumerate(model._tips):
        if translations is not None:
            tip[:, k] = translations(q)[:, 0]
            deflection[:, k] = tip[:, k] @ model.tip_directions[k]
    return {
        "t": raw["t"],
        "deployment_angle": stowed + np.degrees(raw["theta"]),
        "deployment_rate": np.degrees(raw["theta_rate"]),
        "spring_torque": raw["spring_torque"], "lock_force": raw["lock_force"],
        "lock_torque": raw["lock_torque"], "latched": raw["latched"],
        "hinge_force": raw["hinge_force"], "hinge_moment": raw["hinge_moment"],
        "strain_energy": raw["strain_energy"], "tip_displacement": tip, "tip_deflection": deflection,
        "body_attitude": base_attitude_deg(q, model.base_free),
        "total_angular_momentum": raw["angular_momentum"], "body_angular_momentum": raw["base_angular_momentum"],
        "total_linear_momentum": raw["linear_momentum"], "body_linear_momentum": raw["base_linear_momentum"],
        "kinetic_energy": raw["kinetic_energy"], "potential_energy": raw["potential_energy"],
        "q": q, "v": raw["v"],
    }
