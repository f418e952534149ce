"""deployfx: deployment and locking dynamics of flexible laminated-composite appendages.

Laminated materials: :class:`Isotropic`, :class:`Orthotropic`, :class:`Ply`, :class:`Laminate`.
SI units throughout.
"""
from .materials import Isotropic, Laminate, Orthotropic, Ply

__all__ = ["Isotropic", "Orthotropic", "Ply", "Laminate"]
__version__ = "0.1.0"
