"""The numbers of You et al. (2016), J. Aerosp. Eng. 29(5), DOI 10.1061/(ASCE)AS.1943-5525.0000570,
converted to SI at this boundary. Choices where the paper is silent are marked and documented in
``shared/design/paper2016-scenario.md``.
"""
from __future__ import annotations

from .materials import Laminate, Orthotropic
from .plate import Plate

#: Carbon/epoxy IM6/SC1081, one ply at 0 rad to the local X axis (paper, "Numerical Simulations").
IM6_SC1081 = Orthotropic(E1=177e9, E2=10.8e9, G12=7.6e9, G13=7.6e9, G23=8.504e9, nu12=0.27,
                         rho=1600.0)

#: Ply angles in degrees, bottom first (paper, Table 2).
LAYUPS = {1: (0.0, 0.0, 0.0, 0.0), 2: (0.0, 90.0, 90.0, 0.0)}
#: Ply thickness, m (Table 2).
PLY_THICKNESS = 0.5e-3
#: Appendage length (along the local x axis, away from the hinge) and width, m (Table 1).
LENGTH, WIDTH = 2.0, 1.3
#: The paper's mesh: 15 elements along the length, 10 across, 150 elements, 176 nodes (Fig. 6).
NX, NY = 15, 10


def appendage_laminate(layup: int = 1) -> Laminate:
    """The four-ply IM6/SC1081 laminate of lay-up 1 ([0/0/0/0]) or 2 ([0/90/90/0])."""
    if layup not in LAYUPS:
        raise ValueError(f"layup = {layup!r} is out of range: must be 1 or 2")
    return Laminate.from_angles(IM6_SC1081, PLY_THICKNESS, LAYUPS[layup])


def appendage_plate(layup: int = 1, nx: int = NX, ny: int = NY) -> Plate:
    """The 2.0 m x 1.3 m x 2 mm appendage meshed with nx x ny shell elements. The root edge is
    x = 0 (clamped to the hinge frame: boundary ``"CFFF"``)."""
    return Plate(LENGTH, WIDTH, appendage_laminate(layup), nx, ny)
