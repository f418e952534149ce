"""The scene file's schema, shared by its writer (deployfx.scene_file) and reader
(deployfx._scene_read): versions, the keys written by name, and which builder keyword
arguments the file gives itself (never options). The schema itself is documented in
:mod:`deployfx.scene_file`."""
from __future__ import annotations

import inspect

#: The schema name every scene file carries.
SCHEMA = "deployfx.scene"
#: The schema version written.
VERSION = 2
#: The schema versions read.
VERSIONS_READ = (1, 2)
_UNITS = ("SI: m, kg, s, rad, N, Pa; each dimensional key ends with its unit (K_N_per_m_n: "
          "N/m^n, n the contact law's exponent); ply angles in degrees; unsuffixed numbers are "
          "dimensionless")

# Keys of Scene's private dicts that the writer puts in the file by name; any other key is an
# "option".
_HINGE_KEYS = {"point", "axis", "R_BE0", "tau0", "k_theta", "c_theta", "fitting", "spin_up"}
_APPENDAGE_KEYS = {"shell", "fixed", "fidelity", "alpha_M", "beta_K"}
_LOCK_KEYS = {"theta_lock", "pin_radius", "clearance", "law", "friction"}

# The keyword arguments the reader passes to each builder method itself: never options.
_GIVEN = {
    "set_hinge": {"point", "axis", "R_BE0", "tau0", "k_theta", "c_theta", "fitting_inertia",
                  "fitting_mass", "fitting_com", "spin_up"},
    "add_hinge": {"parent", "point", "axis", "R_PE0", "tau0", "k_theta", "c_theta",
                  "fitting_inertia", "fitting_mass", "fitting_com"},
    "set_appendage": {"shell", "fixed_dofs", "fidelity", "damping", "hinge"},
    "set_lock": {"theta_lock", "pin_radius", "clearance", "law", "friction", "hinge"},
}

# A hinge's keys in the file (version 2; version 1 has R_BE0 for R_PE0 and no parent or parts).
_HINGE_FILE_KEYS = ("point_m", "axis", "R_PE0", "tau0_N_m", "k_theta_N_m_per_rad",
                    "c_theta_N_m_s_per_rad", "fitting")
_PART_FILE_KEYS = ("mass_kg", "com_m", "inertia_kg_m2")

_ISOTROPIC = ("E", "nu", "rho")
_ORTHOTROPIC = ("E1", "E2", "G12", "G13", "G23", "nu12", "rho")
_MATERIAL_UNITS = {"E": "E_Pa", "E1": "E1_Pa", "E2": "E2_Pa", "G12": "G12_Pa", "G13": "G13_Pa",
                   "G23": "G23_Pa", "nu": "nu", "nu12": "nu12", "rho": "rho_kg_per_m3"}


def _given(method, key: str) -> bool:
    """Whether the reader passes ``key`` to ``method`` itself (then it is never an option)."""
    return key in _GIVEN.get(method.__name__, ())


def _accepts(method, key: str) -> bool:
    """Whether ``method`` takes the keyword argument ``key``."""
    params = inspect.signature(method).parameters
    return (key != "self" and key in params) or any(
        p.kind is inspect.Parameter.VAR_KEYWORD for p in params.values())
