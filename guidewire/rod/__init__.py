"""A discrete rod in 3D: node positions and per-bar material angles; bending at the joints and twist between bars."""

from guidewire.rod.energy import RodEnergy

__all__ = ["RodEnergy"]
