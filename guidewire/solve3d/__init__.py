"""3-D scenes, their sparse program and solve: a framed rod (:mod:`guidewire.rod`) clamped with an insertion rotation,
with contacts, walls, a 3-D vessel (:mod:`guidewire.vessel3d`) and a tip load."""

from .program import Program
from .result import ContactForce3D, Solution3D
from .scene import Base3D, Contact3D, Scene3D, Wall3D
from .solve import solve3d

__all__ = ["Base3D", "Contact3D", "ContactForce3D", "Program", "Scene3D", "Solution3D", "Wall3D", "solve3d"]
