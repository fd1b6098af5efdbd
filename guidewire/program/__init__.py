"""A scene as a nonlinear program: the layout-independent :mod:`.model`, the :mod:`.formulation` in the reduced
(:mod:`.reduced`, bar angles) or full-space (:mod:`.full_space`, angles and nodes) layout, and the checks that refuse
an infeasible scene before solving (:mod:`.feasibility`)."""

from .formulation import Formulation, formulate

__all__ = ["Formulation", "formulate"]
