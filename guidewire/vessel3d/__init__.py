"""3-D vessels: centreline tubes with radii and branches (:mod:`~guidewire.vessel3d.vessel`), their lumen rows
(:mod:`~guidewire.vessel3d.tube`), shipped shapes (:mod:`~guidewire.vessel3d.shapes`: a helix, a tortuous coronary
vessel, the aortic-arch family) and VMTK centreline files (:mod:`~guidewire.vessel3d.vtp`, optional extra)."""

from .arch import ARCH_TYPES, BRANCH_NAMES, aortic_arch
from .vessel import Branch3D, Vessel3D

__all__ = ["Branch3D", "Vessel3D"]
__all__ += ["ARCH_TYPES", "BRANCH_NAMES", "aortic_arch"]
from .vtp import read_centerlines, write_centerlines  # noqa: E402  (vtk is imported only when they are called)

__all__ += ["read_centerlines", "write_centerlines"]
