"""deployfx: deployment and locking dynamics of flexible laminated-composite appendages.

The structural core: laminated materials (:class:`Isotropic`, :class:`Orthotropic`,
:class:`Ply`, :class:`Laminate`) and the MITC4 laminated shell element on a rectangular
:class:`Plate` or an arbitrary :class:`ShellModel` mesh. SI units throughout.
"""
from .materials import Isotropic, Laminate, Orthotropic, Ply
from .plate import Plate, ShellModel
from . import contact, integrators, metrics, paper2016
from .results import Result, load

__all__ = ["Isotropic", "Orthotropic", "Ply", "Laminate", "Plate", "ShellModel", "Result", "load",
           "contact", "integrators", "metrics", "paper2016"]
__version__ = "0.1.0"
