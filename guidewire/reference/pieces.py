"""Building :class:`~guidewire.reference.shapes.ContinuumShape` objects: curved and straight pieces, the
straight wire, assembly of pieces with the support reactions, and ordering of equilibria by energy."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from .. import fields
from .shapes import Array, ContinuumReaction, ContinuumShape, ElasticaPiece

__all__ = [
    "TIE_RTOL",
    "assemble",
    "curved_piece",
    "lowest_first",
    "shifted_piece",
    "straight_piece",
    "straight_shape",
    "ties",
]

#: Relative energy difference under which two equilibria count as equally low (mirror twins).
TIE_RTOL = 1e-9


def curved_piece(
    s0: float,
    length: float,
    point: Array,
    theta0: float,
    kappa_hat0: float,
    g: Array,
    EI: float,
    dense: Any,
    energy_hat: float,
) -> ElasticaPiece:
    """A curved piece from its non-dimensional solution (``energy_hat = ∫ κ̂² du``)."""
    return ElasticaPiece(
        s0=s0,
        length=length,
        point=np.array(point, dtype=float),
        theta0=float(theta0),
        kappa0=float(kappa_hat0) / length,
        force=np.asarray(g, dtype=float) * EI / length**2,
        energy=EI / (2.0 * length) * float(energy_hat),
        dense=dense,
    )


def straight_piece(s0: float, length: float, point: Array, theta: float) -> ElasticaPiece:
    """An unloaded straight piece from ``point`` in the direction ``theta`` (evaluated in closed form)."""
    return ElasticaPiece(
        s0=s0,
        length=length,
        point=np.array(point, dtype=float),
        theta0=float(theta),
        kappa0=0.0,
        force=np.zeros(2),
        energy=0.0,
        dense=None,
    )


def shifted_piece(piece: ElasticaPiece, ds: float) -> ElasticaPiece:
    """The same piece starting ``ds`` further along the wire."""
    return replace(piece, s0=piece.s0 + ds)


def straight_shape(p0: ArrayLike, theta0: float, length: float, EI: float) -> ContinuumShape:
    """A straight, unloaded wire from ``p0`` in the direction ``theta0`` (energy 0).

    Parameters
    ----------
    p0 : array_like, shape (2,)
        Start point (mm).
    theta0 : float
        Direction (rad).
    length : float
        Length (mm), positive.
    EI : float
        Bending stiffness (N·mm²), positive.

    Returns
    -------
    ContinuumShape
        The straight wire, with a zero clamp reaction at ``p0``.

    Raises
    ------
    TypeError, ValueError
        For a malformed value (:mod:`guidewire.fields` names the field).
    """
    p0 = np.asarray(fields.point(p0, "p0"))
    theta0 = fields.real(theta0, "theta0")
    length = fields.real(length, "length", positive=True)
    EI = fields.real(EI, "EI", positive=True)
    piece = straight_piece(0.0, length, p0, theta0)
    base = ContinuumReaction(0.0, p0, np.zeros(2), 0.0, "clamp")
    return ContinuumShape(length=length, energy=0.0, EI=EI, pieces=(piece,), reactions=(base,))


def assemble(
    pieces: Sequence[ElasticaPiece],
    length: float,
    EI: float,
    base_point: Array,
    supports: Sequence[tuple[float, str]],
) -> ContinuumShape:
    """Concatenate pieces and derive the reactions of the base clamp and the supports at piece ends.

    ``supports`` lists ``(s, kind)`` of the supports; each must coincide with the end of a piece.  A support
    at the end of piece ``j`` exerts ``F_j - F_{j+1}`` and ``M_j(end) - M_{j+1}(start)`` on the wire, with
    ``M = EI (κ - κ₀)`` in each piece's own ``EI`` and ``κ₀`` on a wire with sections.
    """
    first = pieces[0]
    reactions = [ContinuumReaction(0.0, np.array(base_point, dtype=float), -first.force,
                                   -float(first.moment(first.kappa0, EI)), "clamp")]
    ends = np.array([p.s1 for p in pieces])
    for s, kind in supports:
        j = int(np.argmin(np.abs(ends - s)))
        point, _, kappa = pieces[j].end_state()
        force = pieces[j].force.copy()
        moment = float(pieces[j].moment(kappa, EI))
        if j + 1 < len(pieces):
            force -= pieces[j + 1].force
            moment -= float(pieces[j + 1].moment(pieces[j + 1].kappa0, EI))
        reactions.append(ContinuumReaction(float(s), point, force, float(moment), kind))
    return ContinuumShape(
        length=length,
        energy=float(sum(p.energy for p in pieces)),
        EI=EI,
        pieces=tuple(pieces),
        reactions=tuple(reactions),
    )


def lowest_first(shapes: list[ContinuumShape]) -> list[ContinuumShape]:
    """Sort by energy; energies equal to the lowest within ``TIE_RTOL`` keep their order."""
    lowest = min(sh.energy for sh in shapes)
    return sorted(shapes, key=lambda sh: max(sh.energy, lowest * (1.0 + TIE_RTOL)))


def ties(shapes: list[ContinuumShape]) -> list[ContinuumShape]:
    """The leading shapes whose energy equals the lowest within ``TIE_RTOL``."""
    return [sh for sh in shapes if sh.energy <= shapes[0].energy * (1.0 + TIE_RTOL) + 1e-15]
