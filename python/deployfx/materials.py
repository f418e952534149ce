"""Lamina materials, plies and laminates (classical lamination theory with transverse shear).

SI units throughout: moduli in Pa, density in kg/m^3, thickness in m, angles in degrees.
References: Reddy, *Mechanics of Laminated Composite Plates and Shells*, 2nd ed. (2004),
Sec. 2.3-3.4; Jones, *Mechanics of Composite Materials* (1999), Sec. 2.4.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence, Union

import numpy as np

from . import _core
from ._checks import as_float


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.array(a, dtype=float)
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class Isotropic:
    """An isotropic material.

    Parameters
    ----------
    E : Young's modulus, Pa (> 0).
    nu : Poisson's ratio (-1 < nu < 0.5).
    rho : density, kg/m^3 (> 0).
    """

    E: float
    nu: float
    rho: float
    _impl: _core.Orthotropic = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        args = {k: as_float(f"Isotropic.{k}", getattr(self, k)) for k in ("E", "nu", "rho")}
        object.__setattr__(self, "_impl", _core.Orthotropic.isotropic(**args))

    @property
    def G(self) -> float:
        """Shear modulus E / (2 (1 + nu)), Pa."""
        return self._impl.G12


@dataclass(frozen=True)
class Orthotropic:
    """An orthotropic lamina (axis 1 along the fibres) in plane stress with transverse shear.

    Parameters
    ----------
    E1, E2 : Young's moduli along and across the fibres, Pa (> 0).
    G12, G13, G23 : shear moduli, Pa (> 0).
    nu12 : major Poisson's ratio, |nu12| < sqrt(E1/E2) (positive-definite compliance).
    rho : density, kg/m^3 (> 0).
    """

    E1: float
    E2: float
    G12: float
    G13: float
    G23: float
    nu12: float
    rho: float
    _impl: _core.Orthotropic = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        names = ("E1", "E2", "G12", "G13", "G23", "nu12", "rho")
        args = {k: as_float(f"Orthotropic.{k}", getattr(self, k)) for k in names}
        object.__setattr__(self, "_impl", _core.Orthotropic(**args))

    @property
    def nu21(self) -> float:
        """Minor Poisson's ratio nu12 E2 / E1."""
        return self.nu12 * self.E2 / self.E1


Material = Union[Isotropic, Orthotropic]


@dataclass(frozen=True)
class Ply:
    """One layer of a laminate.

    Parameters
    ----------
    material : an :class:`Isotropic` or :class:`Orthotropic` material.
    thickness : m (> 0).
    angle_deg : fibre direction from the laminate x axis, counter-clockwise, degrees.
    """

    material: Material
    thickness: float
    angle_deg: float = 0.0

    def __post_init__(self) -> None:
        if not isinstance(self.material, (Isotropic, Orthotropic)):
            raise TypeError(
                "Ply.material must be deployfx.Isotropic or deployfx.Orthotropic, "
                f"got {type(self.material).__name__}"
            )
        t, a = as_float("Ply.thickness", self.thickness), as_float("Ply.angle_deg", self.angle_deg)
        if not (math.isfinite(t) and t > 0):
            raise ValueError(f"Ply.thickness = {t!r} is out of range: must be > 0 (m)")
        if not math.isfinite(a):
            raise ValueError(f"Ply.angle_deg = {a!r} is out of range: must be finite (degrees)")

    def _to_core(self) -> _core.Ply:
        return _core.Ply(self.material._impl, float(self.thickness), float(self.angle_deg))

    def Q_bar(self) -> np.ndarray:
        """In-plane reduced stiffness of the rotated ply in laminate axes (3x3), Pa."""
        # One turn first (fmod is exact): deg2rad(1.7e308) overflows to inf (issue 29).
        return _readonly(self.material._impl.Q_bar(np.deg2rad(math.fmod(self.angle_deg, 360.0))))


class Laminate:
    """A stack of plies, bottom (z = -h/2) first, with its section stiffness and inertia.

    ``(N, M) = [[A, B], [B, D]] (eps0, kappa)`` with N in N/m, M in N m/m, and
    ``(Q_xz, Q_yz) = As (gamma_xz, gamma_yz)``, ``As = k sum(Qs_bar t_k)`` with the shear
    correction factor ``k = 5/6`` (:attr:`shear_correction`).
    """

    def __init__(self, plies: Sequence[Ply]):
        if isinstance(plies, (str, bytes)) or not hasattr(plies, "__iter__"):
            raise TypeError(f"Laminate.plies must be a sequence of deployfx.Ply, "
                            f"got {type(plies).__name__} {plies!r}")
        plies = tuple(plies)
        for i, p in enumerate(plies):
            if not isinstance(p, Ply):
                raise TypeError(f"Laminate.plies[{i}] must be a deployfx.Ply, got {type(p).__name__}")
        self._plies = plies
        self._impl = _core.Laminate([p._to_core() for p in plies])

    @classmethod
    def from_angles(cls, material: Material, ply_thickness: float, angles_deg: Sequence[float]) -> "Laminate":
        """Plies of one material and thickness (m) at the given angles (degrees), bottom first."""
        return cls([Ply(material, ply_thickness, a) for a in angles_deg])

    def __repr__(self) -> str:
        angles = "/".join(f"{p.angle_deg:g}" for p in self._plies)
        return f"Laminate([{angles}], thickness={self.thickness:g} m)"

    @property
    def plies(self) -> tuple:
        """The :class:`Ply` objects, bottom (z = -h/2) first."""
        return self._plies

    @property
    def thickness(self) -> float:
        """Total thickness h, m."""
        return self._impl.thickness

    @property
    def A(self) -> np.ndarray:
        """Extensional stiffness (3x3), N/m."""
        return _readonly(self._impl.A)

    @property
    def B(self) -> np.ndarray:
        """Membrane-bending coupling stiffness (3x3), N."""
        return _readonly(self._impl.B)

    @property
    def D(self) -> np.ndarray:
        """Bending stiffness (3x3), N m."""
        return _readonly(self._impl.D)

    @property
    def As(self) -> np.ndarray:
        """Transverse shear stiffness (2x2, xz then yz) with the shear correction, N/m."""
        return _readonly(self._impl.As)

    @property
    def shear_correction(self) -> float:
        """Transverse shear correction factor k (5/6)."""
        return _core.Laminate.shear_correction

    @property
    def mass_per_area(self) -> float:
        """I0 = sum rho_k t_k, kg/m^2."""
        return self._impl.I0

    @property
    def first_moment_per_area(self) -> float:
        """I1 = sum rho_k (z_k+1^2 - z_k^2)/2 about the mid-plane, kg/m (0 when symmetric)."""
        return self._impl.I1

    @property
    def rotary_inertia_per_area(self) -> float:
        """I2 = sum rho_k (z_k+1^3 - z_k^3)/3 about the mid-plane, kg."""
        return self._impl.I2

    @property
    def z(self) -> np.ndarray:
        """Ply interfaces from -h/2 to h/2 (plies + 1), m."""
        return _readonly(self._impl.z)
