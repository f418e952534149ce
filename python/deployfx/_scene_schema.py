"""The scene file's schema, shared by its writer (deployfx.scene_file) and reader
(deployfx._scene_read): versions and the keys of each table. The schema itself is documented in
:mod:`deployfx.scene_file`."""
from __future__ import annotations

#: The schema name every scene file carries.
SCHEMA = "deployfx.scene"
#: The schema version written.
VERSION = 4
#: The schema versions read.
VERSIONS_READ = (1, 2, 3, 4)
_UNITS = ("SI: m, kg, s, rad, N, Pa; each dimensional key ends with its unit (K_N_per_m_n: "
          "N/m^n, n the contact law's exponent); ply angles in degrees; unsuffixed numbers are "
          "dimensionless")

# A hinge's keys in the file: required, and optional (version 3).
_HINGE_FILE_KEYS = ("parent", "point_m", "axis", "R_PC0", "tau0_N_m", "k_theta_N_m_per_rad",
                    "c_theta_N_m_s_per_rad", "fitting")
_HINGE_OPTIONAL = ("stowed_angle_deg", "spin_up", "parts", "appendage", "lock", "groove")
_PART_FILE_KEYS = ("mass_kg", "com_m", "inertia_kg_m2")
_APPENDAGE_FILE_KEYS = ("fidelity", "fixed_dofs", "alpha_M_per_s", "beta_K_s", "modes", "shell")
_APPENDAGE_OPTIONAL = ("derivative_modes", "strengths", "derivative_partners")
# A ply's strength allowables (deployfx.Strengths): required, and optional keys.
_STRENGTH_KEYS = ("Xt_Pa", "Xc_Pa", "Yt_Pa", "Yc_Pa", "S12_Pa", "F12_star")
_STRENGTH_OPTIONAL = ("S13_Pa", "S23_Pa")
_LOCK_FILE_KEYS = ("theta_lock_rad", "pin_radius_m", "clearance_m", "law", "friction")
# A pin-groove lock (version 4): its keys, optional keys, its profile elements' keys by kind, and
# its latch spring's keys.
_GROOVE_FILE_KEYS = ("profile", "pin_distance_m", "pin_angle_rad", "pin_radius_m", "law", "friction")
_GROOVE_OPTIONAL = ("latch", "play_deg")
_GROOVE_ELEMENT_KEYS = {"line": ("start_m", "end_m"), "arc": ("start_m", "end_m", "radius_m"),
                        "arc_about": ("start_m", "end_m", "centre_m", "ccw")}
_LATCH_FILE_KEYS = ("stop_m", "travel_m", "preload_N", "stiffness_N_per_m", "toward_axis")
# The builder options versions 1 and 2 wrote under "options" that version 3 names (appendage).
_OLD_APPENDAGE_OPTIONS = ("modes", "derivative_modes")

_ISOTROPIC = ("E", "nu", "rho")
_ORTHOTROPIC = ("E1", "E2", "G12", "G13", "G23", "nu12", "rho")
_MATERIAL_UNITS = {"E": "E_Pa", "E1": "E1_Pa", "E2": "E2_Pa", "G12": "G12_Pa", "G13": "G13_Pa",
                   "G23": "G23_Pa", "nu": "nu", "nu12": "nu12", "rho": "rho_kg_per_m3"}
