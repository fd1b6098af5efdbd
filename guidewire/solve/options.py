"""What one solve is asked to do: :class:`SolveOptions`, the layout ``"auto"`` picks (:func:`choose_layout`) and the
memory check that refuses a vessel scene too large for a dense program (:func:`check_memory`)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import sqp

from ..scene.scene import Scene

#: sqp's own stopping defaults (:class:`sqp.Options`), which guidewire passes on unchanged.
TOL: float = sqp.Options.tol
MAX_ITER: int = sqp.Options.max_iter

#: ``layout="auto"`` uses the full-space program above this many bars for scenes with walls (see
#: :func:`choose_layout`): :data:`sqp.DENSE_LIMIT`, the most the reduced program's dense wall rows stay with DAQP
#: (measured with DAQP in the Hessian factor's coordinates, :data:`sqp.backends.LDP_MIN_VARIABLES`: Fig. 6a / 6b
#: reduced 6.9 / 6.7 ms against full 13.7 / 16.3 ms at 200 bars, 14.1 / 13.7 against 20.8 / 20.5 ms at 300).
FULL_SPACE_BARS: int = sqp.DENSE_LIMIT

#: Values of ``solve(hessian=...)`` and ``solve(layout=...)``.
HESSIANS = ("exact", "bfgs")
LAYOUT_CHOICES = ("auto", "reduced", "full")


@dataclass(frozen=True)
class SolveOptions:
    """Everything :func:`guidewire.solve` passes down its pipeline besides the scene (the parameters of
    :func:`guidewire.solve`, checked by it; ``tol_mm`` and ``density`` are the front door's, resolved before).

    ``initial_angles``, ``initial_nodes`` and ``multipliers0`` are the start; ``reuse`` a
    :class:`~guidewire.program.model.ModelReuse`; ``qp_solver``, ``qp_options``, ``tol``, ``max_iter`` and
    ``verbose`` go to :func:`sqp.minimize` (:meth:`minimize_options`)."""

    scheme: str | None = None
    bars: int | None = None
    initial_angles: Any = None
    initial_nodes: Any = None
    hessian: str = "exact"
    layout: str = "auto"
    multipliers0: Any = None
    qp_solver: str | None = None
    qp_options: dict[str, Any] | None = None
    tol: float = TOL
    max_iter: int = MAX_ITER
    verbose: bool = False
    reuse: Any = None
    branches: str = "lowest"
    round_iterations: int | None = None
    """Iterations the working-set rounds of one start may take together (None: ``max_iter`` each round); a
    candidate start of ``branches="lowest"`` gets its whole limit this way, so one that never settles is cut short."""
    dense_retry: bool = True
    """Whether a vessel scene that failed in the full space (by the automatic layout) is solved again in the dense
    program of bar angles (:func:`guidewire.solve.pipeline.solve_once`). A candidate start of ``branches="lowest"``
    is not: it explores another branch, and one that fails is dropped, while the dense retry costs O(n³) an
    iteration (0.4-0.6 s at 960 bars); nor is a nested start's coarse solve (a start only)."""
    bfgs_retry: bool = True
    """Whether a stalled exact-Hessian solve is solved again with damped BFGS
    (:func:`guidewire.solve.pipeline.solve_once`); a nested start's coarse solve is not (one that stalled took 4 s at
    100 bars, the arch at 240 mm: a start is not worth it, the fine solve then starts as it would have)."""
    nest_start: bool = False
    """Whether a given start is nested like the default one (:func:`guidewire.solve.pipeline.nested_start`: the
    coarse solve starts from it): a candidate start of ``branches="lowest"`` is; a caller's start is used as given."""

    def minimize_options(self) -> dict[str, Any]:
        """The keyword arguments of :func:`sqp.minimize` these options set (no ``qp_solver`` for sqp's choice)."""
        options = {"qp_solver": None if self.qp_solver == "auto" else self.qp_solver, "qp_options": self.qp_options,
                   "tol": self.tol, "max_iter": self.max_iter, "verbose": self.verbose}
        if options["qp_solver"] is None:
            del options["qp_solver"]
        return options

    @property
    def given_start(self) -> bool:
        """Whether the start is the caller's (then it chooses the branch: no mirror starts)."""
        return self.initial_angles is not None or self.initial_nodes is not None

    def check(self) -> None:
        """Raise ValueError for a Hessian or layout :func:`guidewire.solve` does not know, or that do not mix."""
        if self.hessian not in HESSIANS:
            raise ValueError(f"hessian is {self.hessian!r}; expected 'exact' or 'bfgs'.")
        if self.layout not in LAYOUT_CHOICES:
            raise ValueError(f"layout is {self.layout!r}; expected 'auto', 'reduced' or 'full'.")
        if self.layout == "full" and self.hessian != "exact":
            raise ValueError("layout='full' needs hessian='exact' (the BFGS path is the paper's reduced program).")


def choose_layout(bars: int, hessian: str = "exact", scene: Scene | None = None) -> str:
    """What ``layout="auto"`` means: the reduced program (angles only) for contact scenes at every ``n`` and for
    wall scenes up to :data:`FULL_SPACE_BARS` bars; the full-space one (:mod:`guidewire.program.full_space`: angles
    and nodes, every row sparse) for wall scenes above, with the exact Hessian.

    Contact scenes (no walls, no vessel) have equality-only subproblems with a few dense rows and a banded energy
    Hessian: above :data:`sqp.STRUCTURED_MIN` the engine solves them by a structured KKT solve
    (:mod:`sqp.structured`), Newton's step in 3-4 iterations at every n. Measured, reduced against full in one
    process (medians of 5, BLAS one thread): Table 1 (π/4) 0.50x / 0.29x / 0.17x the time at 200 / 400 / 1600
    bars, Table 2 (π/4) 0.47x / 0.37x / 0.20x, Table 1 (-π/2) and Table 2 (π/2) alike. Wall rows are
    inequalities, dense in the reduced program: measured on Fig. 6a at 400 / 1600 bars reduced 2.1 s / 76 s, full
    28 ms / 0.10 s. Vessel scenes likewise: the bend at 400 / 800 bars reduced 14 s / 53 s, full 44 / 67 ms (the
    lumen's curved rows one node each, :meth:`FullLayout.newton_options`). The BFGS path stays reduced (the paper's
    algorithm)."""
    if scene is not None and not (scene.walls or scene.vessel is not None):
        return "reduced"
    return "full" if hessian == "exact" and bars > FULL_SPACE_BARS else "reduced"


#: Peak memory of a vessel scene's dense program of bar angles, in units of ``n^2`` float64 values (``n`` bars):
#: measured 24-26 from the peak resident size at 200, 400 and 800 bars (the dense Hessian, its factor, the lumen
#: rows' Jacobian and the QP's copies).
DENSE_COPIES = 26


def available_memory() -> int | None:
    """Bytes of memory available to a new allocation (``MemAvailable`` of ``/proc/meminfo``), or None where unknown."""
    try:
        with open("/proc/meminfo") as info:
            for line in info:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        return None
    return None


#: Peak memory of a vessel scene's full-space program per bar (bytes): measured 10 kB at 20 000 bars and 9.4 kB at
#: 80 000 (the bend: peak resident size less that of the imports), with a margin.
FULL_BYTES_PER_BAR = 12_000


def program_bytes(bars: int, layout: str) -> float:
    """Bytes a vessel scene's program with ``bars`` bars needs: ``DENSE_COPIES n²`` doubles for the dense program
    of bar angles (``"reduced"``), :data:`FULL_BYTES_PER_BAR` a bar for the full space."""
    return FULL_BYTES_PER_BAR * float(bars) if layout == "full" else DENSE_COPIES * 8.0 * float(bars) ** 2


#: A program needing at most this many bytes (:func:`program_bytes`) fits without asking the system: 64 MiB, the
#: dense program of about 570 bars or the full space of about 5 600, far below what a machine running Python has free
#: (reading ``/proc/meminfo`` costs ~0.1 ms, a fair share of a warm insertion step).
ALWAYS_FITS = 64 * 2**20


def fits_memory(bars: int, layout: str) -> bool:
    """Whether :func:`program_bytes` fits in the memory available (True where that is unknown, and for a program of
    at most :data:`ALWAYS_FITS` bytes)."""
    if program_bytes(bars, layout) <= ALWAYS_FITS:
        return True
    have = available_memory()
    return have is None or program_bytes(bars, layout) <= have


def check_memory(scene: Scene, bars: int, layout: str = "auto", hessian: str = "exact") -> None:
    """Refuse, before any work, a vessel scene whose program would not fit in memory (:func:`program_bytes`): a
    ValueError that gives the memory needed, the memory available and the largest bar count that fits. ``"auto"``
    is the layout :func:`choose_layout` takes: the dense program of bar angles up to :data:`FULL_SPACE_BARS` bars
    (or with ``hessian="bfgs"``), the full space (O(n) memory) above."""
    if layout == "auto":
        layout = choose_layout(bars, hessian, scene)
    if scene.vessel is None or fits_memory(bars, layout):
        return
    need, have = program_bytes(bars, layout), float(available_memory() or 0)
    if layout == "full":
        what, fits = f"its full-space program ({FULL_BYTES_PER_BAR // 1000} kB a bar)", int(have / FULL_BYTES_PER_BAR)
    else:
        what = f"its dense program of bar angles ({DENSE_COPIES} n² double values)"
        fits = int((have / (DENSE_COPIES * 8.0)) ** 0.5)
    raise ValueError(
        f"a vessel scene with {bars} bars needs about {need / 2**30:.1f} GiB for {what}, more than the "
        f"{have / 2**30:.1f} GiB available; use at most {fits} bars (bars = ..., or fewer bars per mm in the scene "
        "file).")
