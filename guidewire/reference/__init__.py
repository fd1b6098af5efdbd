"""Exact continuum reference for the bar-chain guidewire: the planar inextensible Kirchhoff elastica.

The paper (Li et al., Appl. Sci. 2019, 9, 280, §3.2) measures its discrete model against ABAQUS beam
elements; this package replaces that with the exact continuum solution.  Units: mm, rad, N, N·mm.

Model
-----
A wire of bending stiffness ``EI`` (N·mm²) is described by its tangent angle ``theta(s)`` over the arc
length ``s``.  On a stretch without external load the internal force ``F`` (N, the force that the distal
part ``(s, L]`` exerts on the proximal part ``[0, s]``) is constant and

.. math::

    x' = \\cos\\theta,\\quad y' = \\sin\\theta,\\quad \\theta' = \\kappa,\\quad
    EI\\,\\kappa' = F \\times t = F_x \\sin\\theta - F_y \\cos\\theta,

with bending energy ``EI/2 ∫ κ² ds`` (N·mm).  The bending moment is ``M = EI κ`` (counter-clockwise
positive) and ``EI κ²/2 + F·t`` is a first integral.  A wire with sections has ``M = EI (κ − κ₀)`` with its
piecewise ``EI`` and rest curvature ``κ₀`` and ``M' = F × t`` (:mod:`~guidewire.reference.sectioned`).

Modules
-------
* :mod:`~guidewire.reference.shapes` -- the result types :class:`ContinuumShape`, :class:`ElasticaPiece` and
  :class:`ContinuumReaction` (a support's force and moment on the wire).
* :mod:`~guidewire.reference.ode` -- the non-dimensional elastica ODE kernels and their integration.
* :mod:`~guidewire.reference.pieces` -- pieces, the straight wire :func:`straight_shape`, assembly with reactions.
* :mod:`~guidewire.reference.clamped_segment` -- :func:`clamped_segment`: both ends fully clamped (position and
  angle, angles not wrapped).  Several equilibria exist, so :func:`scipy.integrate.solve_bvp` is started from
  several guesses (:mod:`~guidewire.reference.segment_guesses`: the cubic Hermite curve through the poses
  resampled by arc length, the low-energy minimisers of an 8-mode Ritz approximation, the circular arc; a wide
  grid of profiles only if all of those fail), every converged branch is polished by Newton (multiple) shooting
  with variational equations (DOP853, ``rtol = 1e-12``), and the lowest energy wins.
  :func:`clamped_segment_equilibria` returns every branch found.
* :mod:`~guidewire.reference.wall` -- :func:`clamp_wall_free_end`: clamp plus free end pushed against one
  straight wall: closed form in incomplete elliptic integrals (pendulum substitution), tangential contact with a
  straight tail along the wall or, for a shallow wall, the free end resting on it; verified by integrating the
  elastica.
* :mod:`~guidewire.reference.whole_wire` -- :func:`reference_shape`: a whole wire: base clamp, fully clamped
  contacts (segments decouple), a straight free tail, or the one-wall free-end case.  :func:`reference_shapes`
  lists every tied minimiser of a symmetric scene (mirror twins), for comparing a discrete solution with the
  nearest one.
* :mod:`~guidewire.reference.sectioned` (with :mod:`~guidewire.reference.sectioned_ode`) -- a wire with sections:
  piecewise-constant ``EI`` and rest curvature ``κ₀`` (:class:`StiffnessProfile`, e.g. a J-tip on a stiff shaft).
  The state ``(x, y, θ, M)`` with ``M = EI (θ' − κ₀)`` and ``M' = F × t`` is continuous across a section boundary
  (``θ'`` jumps); Newton multiple shooting with a break at every boundary.  Covered: fully clamped contacts
  (:func:`sectioned_segment_equilibria`: every uniform branch continued to the sections, the lowest wins), a free
  stretch (its rest shape) and one wall pushing the free end (:func:`sectioned_wall_shape`: continued from the rest
  shape; a wire that would lie along the wall is declined).  With one stiffness and no rest curvature it reproduces
  the uniform reference to about 1e-10 mm.
* :mod:`~guidewire.reference.scene_reference` -- :func:`continuum_reference` of a :class:`~guidewire.Scene`
  (:class:`ContinuumReference`, or the reason there is none), :func:`nearest_shape` and the paper's Eq. 25
  node error :func:`node_errors` of a discrete solution.

Every result is a :class:`ContinuumShape` whose pieces are initial-value solutions with dense output, so
positions, angles and curvatures can be evaluated at any arc length (error well below 1e-7 mm), with the
support reactions (forces and moments) that balance.

Paper scenes (``EI = 64.65`` N·mm²): Table 1 ``θ_B = π/4`` 4.5551 N·mm; Fig. 6b 1.0312 N·mm.
"""

from .clamped_segment import clamped_segment, clamped_segment_equilibria
from .pieces import straight_shape
from .scene_reference import ContinuumReference, continuum_reference, nearest_shape, node_errors
from .sectioned import StiffnessProfile, sectioned_segment_equilibria, sectioned_wall_shape
from .shapes import ContinuumReaction, ContinuumShape, ElasticaPiece
from .wall import clamp_wall_free_end
from .whole_wire import reference_shape, reference_shapes

__all__ = [
    "ContinuumReaction",
    "ContinuumReference",
    "ContinuumShape",
    "ElasticaPiece",
    "StiffnessProfile",
    "clamp_wall_free_end",
    "clamped_segment",
    "clamped_segment_equilibria",
    "continuum_reference",
    "nearest_shape",
    "node_errors",
    "reference_shape",
    "reference_shapes",
    "sectioned_segment_equilibria",
    "sectioned_wall_shape",
    "straight_shape",
]
