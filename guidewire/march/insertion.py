"""Quasi-static insertion through a vessel: the wire advanced step by step, new wire appearing at the entrance.

Each step is one :func:`guidewire.solve` of the scene with the inserted length of that step, warm-started from the
previous step's shape and multipliers: by default (``predictor="track"``) the wire slides along its previous track
and the wall and lumen rows' multipliers stay with their nodes, a touching tip's going to the new tip; with
``"push"`` the previous bar angles are carried along with the material (the wire moved by the inserted length
``ΔL``), the first ``ΔL`` along the vessel's centreline (or the base tangent without a vessel), and the rows'
multipliers move with their nodes. When a warm
step fails (a head-on contact can leave the linearised constraints blind: the wall gradient vanishes along the
push), the step is solved again from the default start (cold), and the step says so.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..chain.kinematics import BarChain, scene_bars
from ..program.model import ModelReuse
from ..scene.file import scene_to_dict
from ..scene.scene import Scene
from ..solve.front import solve
from ..solve.result import UNITS, Solution
from ..status import Status, outcome

FloatArray = NDArray[np.float64]

@dataclass(frozen=True)
class Insertion:
    """The steps of :func:`insert`.

    Attributes
    ----------
    lengths : tuple of float
        Inserted length of every step asked for (mm).
    steps : list of Solution
        One per step solved, in order (a failed solve is a step too: it says why and carries no forces).
    started : list of str
        How each step was started: ``"cold"`` (the default start), ``"warm"`` (the previous shape), or
        ``"warm, then cold"`` (the warm solve failed and the cold one gave the step).
    error : str or None
        Why the insertion stopped early (a step's scene refused before solving), else None.
    """

    lengths: tuple[float, ...]
    steps: list[Solution]
    started: list[str]
    error: str | None = None

    @property
    def complete(self) -> bool:
        return self.error is None and len(self.steps) == len(self.lengths)

    @property
    def status(self) -> Status:
        """Why the insertion ended (:func:`guidewire.status.outcome`): SUCCESS, a failed step's status, or
        SCENE_REFUSED."""
        return outcome(self.steps, self.error)

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: ``units``, ``scene`` (the first step's), and ``steps`` (see :func:`step_record`)."""
        return {
            "units": UNITS, "scene": scene_to_dict(self.steps[0].scene) if self.steps else None,
            "complete": self.complete, "status": self.status.name, "error": self.error,
            "steps": [dict(step_record(sol), started=how) for sol, how in zip(self.steps, self.started, strict=True)],
        }


def step_record(sol: Solution) -> dict[str, Any]:
    """One insertion step as JSON-ready values (the keys of ``python -m guidewire insert``'s JSON lines)."""
    tip_angle = float(sol.tangent_angles[-1])
    return {
        "inserted_length": float(sol.scene.wire.length), "bars": sol.n_bars, "success": sol.success,
        "status": sol.status, "message": sol.message, "energy": sol.energy, "nodes": sol.nodes.tolist(),
        "contacts": sol.contacts(), "tip": {"point": sol.nodes[-1].tolist(), "angle": tip_angle},
        "entrance_force_n": sol.entrance_force(), "axial_force_n": sol.axial_force(),
        "tangential_contact_force_n": sol.tangential_contact_force(),
        "max_bending_stress_mpa": float(np.max(sol.bending_stress_mpa)),
        "iterations": sol.iterations, "solve_time_s": sol.solve_time_s,
    }


def _bar_lengths(scene: Scene, bars: int) -> FloatArray:
    """Bar lengths of ``scene`` (mm): equal bars for a uniform wire, else the layout the solve will use (a node at
    every section boundary and contact)."""
    if not scene.wire.sections:
        return np.full(bars, scene.wire.length / bars)
    lengths, _ = scene_bars(scene)
    return np.asarray(lengths, dtype=float)


def _bar_midpoints(scene: Scene, bars: int) -> FloatArray:
    """Arc lengths of the bar midpoints of ``scene`` (mm), by :func:`_bar_lengths`."""
    if not scene.wire.sections:
        return (np.arange(bars) + 0.5) * (scene.wire.length / bars)
    lengths = _bar_lengths(scene, bars)
    return np.cumsum(lengths) - 0.5 * lengths


def _advanced_angles(prev: Solution, scene: Scene, bars: int) -> FloatArray:
    """Start angles for ``scene`` from the previous step: the material at arc length ``s`` was at ``s − ΔL``; the new
    first ``ΔL`` follows the vessel's centreline (or the base tangent)."""
    length = scene.wire.length
    s_mid = _bar_midpoints(scene, bars)
    shift = length - float(prev.s[-1])
    s_old = 0.5 * (prev.s[1:] + prev.s[:-1])
    carried = np.interp(s_mid - shift, s_old, prev.bar_angles)
    vessel = getattr(scene, "vessel", None)
    if vessel is not None:
        _, fresh = vessel.path(s_mid)
        fresh = np.unwrap(np.asarray(fresh, dtype=float))
        fresh += 2.0 * math.pi * round((prev.bar_angles[0] - fresh[0]) / (2.0 * math.pi))
    else:
        fresh = np.full(bars, prev.bar_angles[0] if scene.base.angle is None else scene.base.angle)
    return np.where(s_mid < shift, fresh, carried)


def _tracked_angles(prev: Solution, scene: Scene, bars: int) -> FloatArray:
    """Start angles for ``scene`` from the previous step, the wire sliding along its own track: the first
    ``L_prev`` of the new wire lies where the previous wire lay, the new ``ΔL`` continues the previous tip's tangent
    (a follow-the-leader predictor: inside a tortuous lumen it stays inside, where a pushed copy does not)."""
    s_mid = _bar_midpoints(scene, bars)
    s_old = 0.5 * (prev.s[1:] + prev.s[:-1])
    angles = np.interp(s_mid, s_old, prev.bar_angles)  # beyond the old tip: its last bar's angle
    if scene.vessel is not None:
        angles = _steered_extension(angles, _bar_lengths(scene, bars), s_mid, s_old[-1], prev, scene)
    return angles


#: Turns (rad) of the new length tried by :func:`_steered_extension`, smallest first: 0 to 90° each way in 3° steps.
EXTENSION_TURNS = np.radians(np.arange(0.0, 90.1, 3.0)[:, None] * np.array([1.0, -1.0])).ravel()[1:]


def _steered_extension(angles: FloatArray, lengths: FloatArray, s_mid: FloatArray, s_tip: float, prev: Solution,
                       scene: Scene) -> FloatArray:
    """``angles`` (bar ``lengths``, midpoints at ``s_mid``) with the new length past the previous tip (bars whose
    midpoint lies beyond ``s_tip``) turned as a whole by the smallest of :data:`EXTENSION_TURNS` that keeps its
    nodes inside the lumen by the wire's radius.

    Continuing the tip's tangent can run the new nodes through the wall where the tip meets it head on (the aortic
    arch at 176 mm: 0.6 mm outside, next to a branch's corner), and a start that far outside sends the solve into
    elastic QPs (10 s there, against 0.2 s cold); a tip deflected along the wall is what the pushed wire does
    anyway. Left unchanged when the straight extension is inside, or when no turn is.

    The straight extension is checked on the start's nodes as the solve's chain computes them (the bars of
    :func:`~guidewire.chain.scene_bars` from the scene's base): the clearance asked for every node is the one the
    lumen's rows ask for at that start, which the vessel then answers from its memo (the nodes carried over from the
    previous answer from that answer's query, the new ones once)."""
    new = np.flatnonzero(s_mid > s_tip)
    if new.size == 0:
        return angles
    need = 0.5 * scene.wire.properties_at(s_mid[new]).diameter
    chain = BarChain(np.asarray(scene.base.point, dtype=float), np.asarray(scene_bars(scene)[0], dtype=float))
    nodes = chain.nodes(angles)
    if np.all(scene.vessel.clearance(nodes[1:]).distance[new] >= need):
        return angles
    base = nodes[new[0]]

    def inside(turns: FloatArray) -> NDArray[np.bool_]:
        steps = lengths[new][None, :, None] * _directions(angles[new][None, :] + turns[:, None])
        points = base + np.cumsum(steps, axis=1)  # (turns, new bars, 2): the new nodes for every turn
        clear = scene.vessel.clearance(points.reshape(-1, 2)).distance.reshape(points.shape[:2])
        return np.all(clear >= need, axis=1)

    ok = inside(EXTENSION_TURNS)
    if not ok.any():
        return angles
    steered = angles.copy()
    steered[new] += EXTENSION_TURNS[int(np.argmax(ok))]
    return steered


def _directions(angles: FloatArray) -> FloatArray:
    """Unit vectors of bar angles (rad), shape ``angles.shape + (2,)``."""
    return np.stack((np.cos(angles), np.sin(angles)), axis=-1)


def _advanced_multipliers(prev: Solution, bars: int) -> Solution:
    """The previous step as a warm start for the multipliers: node rows (walls, lumen) moved with the material, by
    the number of bars inserted (contacts and angle rows stay with their contact)."""
    shift = bars - prev.n_bars
    moved = tuple(b.advanced(shift) for b in prev.blocks)
    return replace(prev, blocks=moved)


def _tracked_multipliers(prev: Solution, bars: int) -> Solution:
    """The previous step as a warm start for the multipliers under the track predictor, which keeps node ``k``
    where it was: rows keep their node (a contact on the wall stays where it is while the wire slides past it),
    except the tip's, which go to the new tip (a tip pressed on the wall stays on it). Left on the old tip's node,
    that row guessed a contact inside the wire's run and missed the new tip's, and the first QP of most steps went
    to a backend (on the shipped vessels' insertions the backends then solved 84 QPs on the arch, now 11, and 16 on
    the bend, now 2)."""
    if bars == prev.n_bars:
        return prev
    return replace(prev, blocks=tuple(b.with_tip(prev.n_bars, bars) for b in prev.blocks))


PREDICTORS = ("track", "push")


#: Largest bending strain (stress over Young's modulus) a step passes without a flag (:func:`step_flags`): the
#: recoverable strain of superelastic nitinol, about 8 %; a steel core yields near 1 %, so for it the flag is late.
STRAIN_LIMIT = 0.08

#: Entrance push (N) above which a step is flagged: an interventionalist's hand pushes a guidewire with a few
#: newtons at most (forces of 0.1-2 N are reported in the catheter-lab literature); more means the wire is jammed.
PUSH_LIMIT_N = 5.0

#: Net force (N) along the wire from contacts at its interior nodes (:meth:`Solution.tangential_contact_force`) above
#: which a step is flagged: a frictionless wire on smooth walls has none, and the node rows at 1 bar per mm leave at
#: most 0.03 N in the shipped vessels without corners; at a branch's corner the node rows hold the wire with
#: 0.1-0.6 N (``s_bend_branch``), which the push reading then carries. Small beside the 0.1-2 N a hand pushes with.
#: The 3-D command line flags its steps by the same limit (:meth:`Solution3D.tangential_contact_force`).
TANGENTIAL_LIMIT_N = 0.05


def step_flags(sol: Solution, how: str) -> list[str]:
    """What a user should notice about one insertion step: a failed solve, a cold re-solve after a failed warm
    one, the tip past the vessel's far end, a push above :data:`PUSH_LIMIT_N`, contacts that hold the wire along
    its length with more than :data:`TANGENTIAL_LIMIT_N` (the push reading is off by that much), a bending strain
    above :data:`STRAIN_LIMIT` (with the stress in MPa)."""
    flags = [] if sol.success else [f"FAILED: {sol.message}"]
    if how == "warm, then cold":
        flags.append("cold re-solve (the warm start failed)")
    vessel = sol.scene.vessel
    if vessel is not None and bool(vessel.past_end(sol.nodes[-1:])[0]):
        flags.append("tip past the vessel's far end")
    push = sol.entrance_force() if sol.success else None
    if push is not None and push > PUSH_LIMIT_N:
        flags.append(f"push {push:.3g} N above {PUSH_LIMIT_N:g} N: the wire is jammed")
    along = sol.tangential_contact_force()
    if along is not None and abs(along) > TANGENTIAL_LIMIT_N:
        flags.append(f"contacts hold the wire along its length with {along:+.3g} N (node rows at an angle to it, as at "
                     f"a vessel's corner; a frictionless wire has none): the push reading carries it, dE/dL ≈ push "
                     f"{'-' if along >= 0 else '+'} {abs(along):.3g} N")
    if sol.success and sol.bending_stress_mpa.size:
        strains = sol.bending_stress_mpa / sol.scene.wire.properties_at(sol.s).youngs_modulus
        k = int(np.argmax(strains))
        strain = float(strains[k])
        if strain > STRAIN_LIMIT:
            flags.append(f"bending stress {sol.bending_stress_mpa[k]:.4g} MPa at s = {sol.s[k]:.4g} mm (strain "
                         f"{100 * strain:.3g} % > {100 * STRAIN_LIMIT:g} %): the wire would kink")
    return flags


def insert(scene: Scene, lengths: Iterable[float], *, predictor: str = "track",
           progress: Callable[[Solution, str, int, int], None] | None = None, **options: Any) -> Insertion:
    """Advance the wire of ``scene`` through the inserted ``lengths`` (mm, increasing), one quasi-static solve each.

    Parameters
    ----------
    scene : Scene
        The scene (a vessel, walls, contacts); its bar density (``wire.bars / wire.length``, per refined mm with
        refined sections: :attr:`guidewire.Wire.bar_density`) is kept at every length.
    lengths : iterable of float
        Inserted lengths (mm), strictly increasing and positive.
    predictor : {"track", "push"}
        How a step starts from the previous one: ``"track"`` (default) — the wire slides along its previous shape
        and the new length continues the tip; ``"push"`` — the previous shape moves with the material, pushed in by
        ``ΔL``, the new length along the centreline at the entrance.
    progress : callable, optional
        ``progress(solution, how, index, total)`` after each step (``how``: ``"cold"``, ``"warm"`` or ``"warm, then
        cold"``), e.g. to print it as it goes (the command line does, with :func:`step_flags`).
    **options
        Passed to :func:`guidewire.solve` (``hessian``, ``qp_solver``, ``tol``, ``max_iter``, ...); not ``bars``,
        ``initial_angles`` or ``multipliers0`` (the insertion sets them); ``reuse=None`` builds every step's program
        anew (default: a :class:`guidewire.program.model.ModelReuse` shared by the steps).

    Returns
    -------
    Insertion
        Every step solved, in order; a step refused before solving (e.g. infeasible) ends it with ``error`` set.

    Raises
    ------
    ValueError
        For lengths that are not positive and strictly increasing, or options the insertion sets itself.
    """
    values = _check_insertion(lengths, predictor, options)
    density = scene.wire.bar_density
    options.setdefault("reuse", ModelReuse())
    steps: list[Solution] = []
    started: list[str] = []
    for length in values:
        grown = scene.wire.with_length(length)  # sections stay anchored at the tip: they move with the material
        bars = max(1 + len(grown.section_boundaries()), scene.wire.bars_at(length, density))
        step_scene = scene.with_wire(length=length, bars=bars)
        try:
            sol, how = _step(step_scene, bars, steps[-1] if steps else None, predictor, options)
        except (ValueError, TypeError) as exc:
            return Insertion(values, steps, started, f"step at {length:g} mm: {exc}")
        steps.append(sol)
        started.append(how)
        if progress is not None:
            progress(sol, how, len(steps) - 1, len(values))
    return Insertion(values, steps, started)


def _check_insertion(lengths: Iterable[float], predictor: str, options: dict[str, Any]) -> tuple[float, ...]:
    """The inserted lengths as floats, after checking them, the predictor and the options :func:`insert` sets."""
    values = tuple(float(v) for v in lengths)
    if not values:
        raise ValueError("lengths is empty; give the inserted lengths (mm), e.g. numpy.arange(10, 101, 1.0).")
    if predictor not in PREDICTORS:
        raise ValueError(f"predictor is {predictor!r}; expected one of {PREDICTORS}.")
    increasing = all(b > a for a, b in zip(values, values[1:], strict=False))
    if not all(math.isfinite(v) and v > 0 for v in values) or not increasing:
        raise ValueError("lengths must be positive and strictly increasing (mm); an insertion step must be positive.")
    for name in ("bars", "initial_angles", "initial_nodes", "multipliers0"):
        if name in options:
            raise ValueError(f"{name} is set by insert() for every step; pass the scene with the bar density you want.")
    return values


def _step(scene: Scene, bars: int, prev: Solution | None, predictor: str,
          options: dict[str, Any]) -> tuple[Solution, str]:
    """One insertion step and how it started: cold for the first, else warm from ``prev`` (by ``predictor``), and
    cold again when the warm start fails and the cold one succeeds."""
    if prev is None:
        return solve(scene, **options), "cold"
    if predictor == "track":
        start, lam = _tracked_angles(prev, scene, bars), _tracked_multipliers(prev, bars)
    else:
        start, lam = _advanced_angles(prev, scene, bars), _advanced_multipliers(prev, bars)
    sol = solve(scene, initial_angles=start, multipliers0=lam, **options)
    if not sol.success:
        cold = solve(scene, **options)
        if cold.success:
            return cold, "warm, then cold"
    return sol, "warm"
