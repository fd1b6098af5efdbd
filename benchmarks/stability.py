"""Numerical stability: stiff and extreme scenes, one row each, solved by ``guidewire.solve`` with its defaults.

What is measured
----------------
Each case is a scene built with ``guidewire.Scene/Wire/Base/Contact/Wall`` (most start from Table 1 with θ_B = π/4:
clamp A (0, 0) along +x, contact B (60, 40) at s = L = 100 mm; EI = 64.65 N·mm²):

- ``n = 2000``, ``n = 5000``: Table 1 at very fine discretisations;
- ``taut``: a wire whose clamps are 0.999 × its arc length apart, clamp angles ±0.3 rad off the chord (high tension,
  boundary layers at the clamps), and the same with both clamps along the chord (compressed: Euler buckling with
  mirror twins);
- ``θ_B = ±π``, ``±(π − 0.01)``: contact angles at the wrap-around of the angle;
- ``two contacts one bar apart``: Table 1 with two more contacts at s = 50 and 51 mm (n = 100: one bar between
  them), placed on the continuum solution (so the continuum answer is unchanged);
- ``wavy``: 12 contacts on y = A sin(2πx/λ) (A = 5 mm, λ = 40 mm) at x = 10, 20, …, 120 mm, each at its true arc
  length along that curve and with its tangent angle; the base on the curve at x = 0 with its tangent;
- ``wall``: a 300 mm wire clamped along +x pushed by the wall x ≤ 10 mm into a tight bend (n = 300), and the same
  with the wall tilted by 0.05 rad (no up/down symmetry);
- ``EI × 1e−6``, ``EI × 1e6``: Table 1 with the Young's modulus scaled (same shape, energy scaled);
- ``nearly collinear``: point contacts (no angles) at s = 25, 50, 75, 100 mm, 0.01 mm off the x axis alternately and
  at x = 0.9999 s (the constraint gradients nearly lose rank on a nearly straight wire);
- ``n = 2``, ``n = 3``: Table 1 with two and three bars, both schemes (the paper scheme's angle row makes n = 2
  over-determined);
- ``b₂ just feasible``: Table 1 with ``max_relative_angle`` = the smallest b₂ found feasible by bisection (feasible:
  our solve at tol 1e-12, capped at 100 iterations, succeeds at a point violating no row by more than 1e-9), stated
  in the row; the same scene at 0.999 × that b₂ (infeasible by a hair if the bisection is right); and a b₂ that is
  provably infeasible (the node turns cannot add up to θ_B − θ_A): the scene must be rejected before solving (or
  the solve end in an honest failure).

Per case: status code and name, success flag, the KKT residuals of ``solution.result.kkt`` (largest of
stationarity, feasibility, complementarity), largest constraint violation, energy, solve time, and — where the
continuum reference (:mod:`guidewire.reference`) covers the scene — mean and max node error and relative energy
difference, with a verdict: *ok*; *honest failure* (success False with a reason); *FALSE SUCCESS* (success claimed but
infeasible, NaN, or disagreeing with the reference); *BUG* (an exception, NaN, or a hang). Every case runs in a forked
child process with a wall-clock limit and ``max_iter`` = 500, so no case can hang the script or crash it.

Usage: ``python benchmarks/stability.py [--quick] [--repeats K] [--out DIR] [--timeout S] [--cases a,b]``
Writes ``stability.{md,csv,png}`` (``stability_quick.*`` with ``--quick``) in ``--out``.
"""

from __future__ import annotations

import contextlib
import math
import multiprocessing as mp
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import _arguments as A
import _environment as E  # first: pins BLAS to one thread before numpy loads
import _guidewire as G
import _tables as T
import numpy as np
from scipy.integrate import quad

import guidewire
import sqp
from guidewire import Base, Contact, Scene, Wall
from guidewire.scene.paper import paper_wire

MAX_ITER = 500
#: Mean node error (as a fraction of the wire length) up to which an answer agrees with the continuum reference:
#: far above the discretisation error of n ≥ 100 bars (≈ 3e-5 L second order, 2.5e-3 L paper scheme), far below the
#: distance between equilibrium branches (≥ 0.1 L on these scenes).
AGREE_FRACTION = 0.01
#: Bisection steps for b₂ (relative width 2^-steps of the initial bracket) and the iteration cap of each solve.
B2_STEPS, B2_MAX_ITER = 16, 100
#: KKT tolerance of the bisection's solves: at the default 1e-8 a feasible b₂ may be answered with a violation of
#: ~1e-8 rad (within that tolerance) and be mistaken for an infeasible one (measured: 0.95-0.999 × the b₂ found so
#: are feasible, violation 1e-14 at tol 1e-11).
B2_TOL = 1e-12
QUICK_CASES = ("n = 3,", "taut", "θ_B = +π ", "one bar apart", "EI × 1e-06", "tilted")


@dataclass(frozen=True)
class StabilityCase:
    """One row: a scene builder, solve options, whether the continuum reference applies, a time limit."""

    name: str
    build: Callable[[], Scene]
    solve: dict[str, Any] = field(default_factory=dict)
    reference: bool = True
    b2_factor: float | None = None  # max_relative_angle = factor × the smallest feasible b₂ (bisection)
    expect_agreement: bool = True  # False for coarse n, where the reference is information only
    timeout: float = 120.0
    note: str = ""


def table1(theta_b: float = math.pi / 4, **wire: Any) -> Scene:
    """Table 1 geometry with ``theta_b`` and wire fields replaced."""
    scene = guidewire.paper_scenes()["table1_pi_4"]
    (b,) = scene.contacts
    return Scene(scene.wire if not wire else scene.with_wire(**wire).wire, scene.base,
                 (Contact(b.s, b.point, theta_b, name="B"),), name=f"table1 θ_B={theta_b:.4g}")


def taut(offset_angle: float) -> Scene:
    """Clamp at (0, 0) and contact at s = 100 on (99.9, 0): angles +offset / −offset to the chord."""
    return Scene(paper_wire(), Base((0.0, 0.0), offset_angle, name="A"),
                 (Contact(100.0, (99.9, 0.0), -offset_angle, name="B"),), name=f"taut ±{offset_angle:g}")


def one_bar_apart() -> Scene:
    """Table 1 plus contacts at s = 50 and 51 on the continuum solution (points and tangent angles)."""
    base = table1()
    ref, note = G.reference(base)
    if ref is None:
        raise RuntimeError(f"no Table 1 reference to place the contacts on: {note}")
    s = np.array([50.0, 51.0])
    shape = getattr(ref, "shapes", (ref,))[0]
    pts, ang = shape.position(s), shape.tangent_angle(s)
    extra = tuple(Contact(float(si), (float(p[0]), float(p[1])), float(a), name=f"C{i}")
                  for i, (si, p, a) in enumerate(zip(s, pts, ang, strict=True)))
    return Scene(base.wire, base.base, extra + base.contacts, name="two contacts one bar apart")


def wavy(amplitude: float = 5.0, wavelength: float = 40.0, count: int = 12, spacing: float = 10.0) -> Scene:
    """``count`` clamped contacts on y = A sin(2πx/λ) at x = spacing·k, at their arc lengths along the curve."""
    k = 2.0 * math.pi / wavelength

    def slope(x: float) -> float:
        return amplitude * k * math.cos(k * x)

    xs = spacing * np.arange(1, count + 1)
    s = np.array([quad(lambda x: math.hypot(1.0, slope(x)), 0.0, x, epsabs=1e-13, epsrel=1e-13)[0] for x in xs])
    contacts = tuple(Contact(float(si), (float(x), amplitude * math.sin(k * x)), math.atan(slope(x)), name=f"P{i + 1}")
                     for i, (si, x) in enumerate(zip(s, xs, strict=True)))
    length = float(s[-1])
    wire = paper_wire(length, int(round(length)))
    return Scene(wire, Base((0.0, 0.0), math.atan(slope(0.0)), name="O"), contacts, name="wavy")


def wall_bend(length: float = 300.0, offset: float = 10.0, tilt: float = 0.0) -> Scene:
    """A long wire clamped along +x, the wall (cos t, sin t) · p ≤ ``offset`` bending it (n = L bars)."""
    wire = paper_wire(length, int(round(length)))
    wall = Wall((math.cos(tilt), math.sin(tilt)), offset)
    return Scene(wire, Base((0.0, 0.0), 0.0, name="O"), walls=(wall,), name="wall bend")


def collinear() -> Scene:
    """Point contacts at s = 25..100, x = 0.9999 s, y = ±0.01 mm alternately."""
    contacts = tuple(Contact(s, (0.9999 * s, 0.01 * (-1) ** i), None, name=f"P{i + 1}")
                     for i, s in enumerate((25.0, 50.0, 75.0, 100.0)))
    return Scene(paper_wire(), Base((0.0, 0.0), 0.0, name="O"), contacts, name="nearly collinear")


def scaled_ei(factor: float) -> Scene:
    scene = table1()
    return scene.with_wire(youngs_modulus=scene.wire.youngs_modulus * factor)


def cases() -> list[StabilityCase]:
    pi = math.pi
    return [
        StabilityCase("n = 2000", lambda: table1().with_bars(2000), timeout=300.0),
        StabilityCase("n = 5000", lambda: table1().with_bars(5000), timeout=600.0),
        StabilityCase("taut: chord 0.999 L, clamps ±0.3 rad off the chord", lambda: taut(0.3)),
        StabilityCase("taut: chord 0.999 L, clamps along the chord (buckled, twins)", lambda: taut(0.0)),
        StabilityCase("θ_B = +π ", lambda: table1(pi)),
        StabilityCase("θ_B = −π", lambda: table1(-pi)),
        StabilityCase("θ_B = +(π − 0.01)", lambda: table1(pi - 0.01)),
        StabilityCase("θ_B = −(π − 0.01)", lambda: table1(-(pi - 0.01))),
        StabilityCase("two contacts one bar apart (s = 50, 51; n = 100)", one_bar_apart,
                      note="one rigid bar between the two contacts would have to span their chord exactly (the "
                      "continuum chord is 1.3e-4 mm shorter than 1 mm: infeasible by a hair); the chain bridges two "
                      "prescribed positions closer than that with two short bars that can bend (guidewire.chain."
                      "place_bars), so the scene is solved, in agreement with the continuum"),
        StabilityCase("wavy: 12 contacts on y = 5 sin(2πx/40)", wavy),
        StabilityCase("wall x ≤ 10 bends a 300 mm wire (n = 300)", wall_bend),
        StabilityCase("wall as above, tilted by 0.05 rad", lambda: wall_bend(tilt=0.05)),
        StabilityCase("EI × 1e-06", lambda: scaled_ei(1e-6)),
        StabilityCase("EI × 1e+06", lambda: scaled_ei(1e6)),
        StabilityCase("nearly collinear point contacts", collinear),
        StabilityCase("n = 2, second_order", lambda: table1().with_bars(2), expect_agreement=False),
        StabilityCase("n = 3, second_order", lambda: table1().with_bars(3), expect_agreement=False),
        StabilityCase("n = 2, paper scheme", lambda: table1().with_bars(2).with_scheme("paper"),
                      expect_agreement=False,
                      note="infeasible: with φ₂ = π/4 fixed, bar 1 (50 mm) would have to reach a point 25.07 mm "
                           "away; Scene.check_feasible says so before solving"),
        StabilityCase("n = 3, paper scheme", lambda: table1().with_bars(3).with_scheme("paper"),
                      expect_agreement=False),
        StabilityCase("b₂ just feasible (bisection)", table1, reference=False, b2_factor=1.0, timeout=300.0),
        StabilityCase("b₂ = 0.999 × the bisection value", table1, reference=False, b2_factor=0.999, timeout=300.0,
                      note="4.4e-5 rad below the bisection's b₂ (its resolution: 9e-7 rad), so infeasible if the "
                           "bisection is right; either way no false success"),
        StabilityCase("b₂ below total turning / joints (provably infeasible)",
                      lambda: table1(max_relative_angle=0.99 * (math.pi / 4) / 101), reference=False,
                      note="the 101 node turns (base clamp, 99 joints, B) must add up to θ_B − θ_A = π/4, "
                           "each at most b₂ = 0.99 (π/4) / 101: no shape exists"),
    ]


# --------------------------------------------------------------------------------------------------------------------
# One case (runs in the child process)
# --------------------------------------------------------------------------------------------------------------------
_B2: dict[Scene, tuple[float, str]] = {}


def feasible_b2(scene: Scene) -> tuple[float, str]:
    """Smallest ``max_relative_angle`` found feasible by bisection, and how it was found (cached per scene)."""
    if scene not in _B2:
        _B2[scene] = _bisect_b2(scene)
    return _B2[scene]


def _bisect_b2(scene: Scene) -> tuple[float, str]:
    free = guidewire.solve(scene, max_iter=MAX_ITER)
    hi = float(np.max(np.abs(free.relative_angles)))  # the unconstrained answer is feasible at its own max |Δθ|
    lo = 0.0
    solves = 1
    for _ in range(B2_STEPS):
        mid = 0.5 * (lo + hi)
        sol = guidewire.solve(scene.with_wire(max_relative_angle=mid), max_iter=B2_MAX_ITER, tol=B2_TOL)
        solves += 1
        if sol.success and sol.max_violation <= 1e-9:
            hi = mid
        else:
            lo = mid
    return hi, (f"b₂ = {hi:.6g} rad (bisection, {solves} solves: infeasible at {lo:.6g}; unconstrained max |Δθ| = "
                f"{float(np.max(np.abs(free.relative_angles))):.4g})")


def run_case(case: StabilityCase) -> dict[str, Any]:
    """Build, solve and judge one case; every exception becomes part of the row."""
    row: dict[str, Any] = {"case": case.name, "n": None, "scheme": None, "status": None, "success": None,
                           "kkt": math.nan, "stationarity": math.nan, "max_violation": math.nan,
                           "energy": math.nan, "reference_energy": math.nan, "energy_vs_reference": math.nan,
                           "mean_error_mm": math.nan, "max_error_mm": math.nan, "time_s": math.nan,
                           "iterations": None, "message": "", "note": case.note, "reference_note": ""}
    stage = "building the scene"
    try:
        scene = case.build()
        row["n"], row["scheme"] = scene.wire.bars, scene.wire.scheme
        if case.b2_factor is not None:
            stage = "bisecting b₂"
            b2, row["note"] = feasible_b2(scene)
            scene = scene.with_wire(max_relative_angle=b2 * case.b2_factor)
            row["note"] += f"; solved at {case.b2_factor:g} × that = {b2 * case.b2_factor:.6g} rad"
        stage = "solving"
        sol = guidewire.solve(scene, max_iter=MAX_ITER, **case.solve)
    except ValueError as exc:
        row.update(status="rejected", success=False, message=f"ValueError while {stage}: {exc}")
        return row
    except Exception as exc:  # a bug to record, not a crash of the script
        row.update(status="raised", success=False,
                   message=f"{type(exc).__name__} while {stage}: {exc} | {traceback.format_exc(limit=-2)}")
        return row
    kkt = getattr(sol.result, "kkt", None) or {}
    status = sol.status
    name = next((s.name for s in sqp.Status if s.code == status), str(status))
    row.update(status=f"{status} {name}", success=sol.success, time_s=sol.solve_time_s, iterations=sol.iterations,
               kkt=max((float(v) for v in kkt.values()), default=math.nan),
               stationarity=float(kkt.get("stationarity", math.nan)), max_violation=sol.max_violation,
               energy=sol.energy, message=sol.message)
    row["finite"] = bool(np.all(np.isfinite(sol.nodes)) and np.isfinite(sol.energy))
    if case.reference:
        stage = "computing the continuum reference"
        ref, note = G.reference(scene)
        twins = len(getattr(ref, "shapes", ()))
        row["reference_note"] = note + (f"{twins} equal-lowest continuum shapes (mirror twins); errors against the "
                                        "nearest" if twins > 1 else "")
        if ref is not None:
            mean, worst = G.reference_errors(sol.nodes, sol.s, ref)
            energy = float(ref.energy)
            row.update(reference_energy=energy, mean_error_mm=mean, max_error_mm=worst,
                       energy_vs_reference=(sol.energy - energy) / abs(energy))
    else:
        row["reference_note"] = "not covered (b₂ rows are not in the continuum model)"
    row["length"] = scene.wire.length
    return row


def verdict(case: StabilityCase, row: dict[str, Any]) -> tuple[str, str]:
    """``(verdict, agreement)`` of a finished row."""
    if row["status"] in ("raised", "timeout", "crashed"):
        return "BUG", "—"
    if row["status"] == "rejected":
        return "rejected before solving", "—"
    finite = row.get("finite", False)
    agree = "—"
    if np.isfinite(row["mean_error_mm"]):
        ok = row["mean_error_mm"] <= AGREE_FRACTION * row.get("length", 100.0)
        agree = ("yes" if ok else "NO") if case.expect_agreement else ("(coarse) " + ("yes" if ok else "no"))
    if not finite:
        return "BUG: NaN/inf in the answer", agree
    if row["success"]:
        if row["max_violation"] > G.FEASIBILITY_TOL:
            return "FALSE SUCCESS (infeasible)", agree
        if agree == "NO":
            return "FALSE SUCCESS? (other branch than the reference)", agree
        return "ok", agree
    return "honest failure", agree


def _child(case: StabilityCase, conn: Any) -> None:
    with E.one_thread():
        try:
            conn.send(run_case(case))
        except BaseException as exc:  # noqa: BLE001 - the parent must always get a row
            conn.send({"case": case.name, "status": "crashed", "success": False, "message": repr(exc)})
    conn.close()


def run_isolated(case: StabilityCase, timeout: float) -> dict[str, Any]:
    """``run_case`` in a forked child; a hang or a crash of the child becomes a row."""
    ctx = mp.get_context("fork")
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_child, args=(case, child), daemon=True)
    start = time.perf_counter()
    proc.start()
    child.close()
    row: dict[str, Any] | None = None
    if parent.poll(timeout):
        try:
            row = parent.recv()
        except EOFError:
            row = None
    proc.join(5.0)
    if proc.is_alive():
        proc.kill()
        proc.join()
    wall = time.perf_counter() - start
    if row is None:
        status = "timeout" if wall >= timeout else "crashed"
        message = (f"no answer within {timeout:g} s (killed)" if status == "timeout"
                   else f"child process died (exit code {proc.exitcode})")
        row = {"case": case.name, "status": status, "success": False, "message": message}
    row["wall_s"] = wall
    return row


def main() -> None:
    ap = A.parser(__doc__, quick_help="a few cheap cases (< 1 minute)", repeats=1,
                  repeats_help="solves per case (the row shows the last; the time is the median)")
    ap.add_argument("--timeout", type=float, default=0.0, help="override every case's wall-clock limit (s)")
    ap.add_argument("--cases", type=str, default="", help="comma-separated substrings of case names")
    a = A.parse(ap)
    selected = cases()
    if a.quick:
        selected = [c for c in selected if any(q in c.name for q in QUICK_CASES)]
    wanted = A.names(a.cases)
    if wanted:
        selected = [c for c in selected if any(w in c.name for w in wanted)]
    repeats = a.repeats
    env = E.environment()
    settings = (f"{len(selected)} cases; guidewire.solve defaults, max_iter = {MAX_ITER}; {repeats} solve(s) per case; "
                "each case in a forked child with a wall-clock limit")
    print("\n".join(env + [settings]))
    rows = []
    with E.one_thread():
        guidewire.solve(table1().with_bars(10))  # warm-up: first calls load libraries
        G.reference(table1())  # cached for the children (forked after this)
        if any(c.b2_factor is not None for c in selected):
            with contextlib.suppress(Exception):  # a failure here is recorded by the case itself
                feasible_b2(table1())
        for case in E.progress(selected, desc="cases"):
            timeout = a.timeout or (min(case.timeout, 40.0) if a.quick else case.timeout)
            runs = [run_isolated(case, timeout) for _ in range(repeats)]
            row = runs[-1]
            times = [r.get("time_s", math.nan) for r in runs]
            if np.all(np.isfinite(times)):
                row["time_s"] = float(np.median(times))
            row["verdict"], row["agrees_with_reference"] = verdict(case, {**_defaults(), **row})
            rows.append({**_defaults(), **row})
            r = rows[-1]
            print(f"{case.name:62s} {str(r['status']):22s} {r['verdict']:30s} t = {T.cell(r['time_s'], 3)} s  "
                  f"kkt = {T.cell(r['kkt'], 2)}  viol = {T.cell(r['max_violation'], 2)}  "
                  f"err = {T.cell(r['mean_error_mm'], 3)} mm  wall {r['wall_s']:.1f} s", flush=True)
            if r["verdict"].startswith(("BUG", "FALSE")):
                print(f"    !! {r['message'][:400]}", flush=True)
    write(rows, a.out, env, settings, quick=a.quick)


def _defaults() -> dict[str, Any]:
    return {"n": None, "scheme": None, "status": None, "success": None, "kkt": math.nan, "stationarity": math.nan,
            "max_violation": math.nan, "energy": math.nan, "reference_energy": math.nan,
            "energy_vs_reference": math.nan, "mean_error_mm": math.nan, "max_error_mm": math.nan,
            "time_s": math.nan, "iterations": None, "message": "", "note": "", "reference_note": "",
            "wall_s": math.nan}


def write(rows: list[dict[str, Any]], out: Path, env: list[str], settings: str, *, quick: bool) -> None:
    stem = T.output_stem(out, "stability", quick)
    T.write_csv(rows, stem.with_suffix(".csv"))
    counts = {v: sum(r["verdict"].split(" (")[0].split(":")[0] == v for r in rows)
              for v in dict.fromkeys(r["verdict"].split(" (")[0].split(":")[0] for r in rows)}
    lines = [
        "# Stability: stiff and extreme scenes (guidewire.solve defaults)",
        "",
        *[f"- {e}" for e in env],
        f"- {settings}",
        "- KKT = the largest of stationarity, feasibility, complementarity in `solution.result.kkt`; max violation "
        "over every row of the scene's formulation; error = mean/max node distance (mm) from the exact continuum "
        f"elastica at the same arc length; *agrees*: mean error ≤ {AGREE_FRACTION:g} × L (coarse n: information only)",
        "- verdicts: ok · honest failure (success False with a reason) · FALSE SUCCESS (success claimed at an "
        "infeasible point or on another branch than the reference) · BUG (exception, NaN, hang or crash)",
        "",
        "Verdicts: " + ", ".join(f"{k} {v}" for k, v in counts.items()),
        "",
    ]
    lines += T.markdown_table(
        ["case", "n", "scheme", "status", "success", "KKT", "max violation", "energy (N·mm)", "vs continuum",
         "mean error (mm)", "max error (mm)", "agrees", "time (s)", "it", "verdict"],
        [[r["case"], r["n"], r["scheme"], r["status"], r["success"], T.cell(r["kkt"], 2),
          T.cell(r["max_violation"], 2), r["energy"], T.cell(r["energy_vs_reference"], 2), r["mean_error_mm"],
          r["max_error_mm"], r["agrees_with_reference"], T.cell(r["time_s"], 3), r["iterations"], r["verdict"]]
         for r in rows],
    )
    lines += ["", "## Notes and messages", ""]
    for r in rows:
        bits = [b for b in (r["note"], "" if r["verdict"] == "ok" and r["success"] else r["message"],
                            r["reference_note"]) if b]
        if bits:
            lines.append(f"- **{r['case']}**: " + " — ".join(str(b)[:600] for b in bits))
    T.write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines))
    plot(rows, stem.with_suffix(".png"))


def plot(rows: list[dict[str, Any]], path: Path) -> None:
    """KKT residual and max violation per case (log scale), coloured by verdict."""
    plt = T.pyplot()
    if plt is None:
        return
    colors = {"ok": "C2", "honest failure": "C1"}
    fig, axes = plt.subplots(1, 3, figsize=(15, 0.38 * len(rows) + 1.8), sharey=True)
    y = np.arange(len(rows))[::-1]
    for ax, key, title in zip(axes, ("kkt", "max_violation", "time_s"),
                              ("KKT residual", "max violation", "solve time (s)"), strict=True):
        vals = np.array([r[key] if np.isfinite(r[key]) else np.nan for r in rows], dtype=float)
        floor = 1e-17
        col = [colors.get(r["verdict"], "C3") for r in rows]
        ax.barh(y, np.maximum(np.nan_to_num(vals, nan=floor), floor), color=col, log=True)
        ax.set_title(title)
        ax.grid(True, axis="x", alpha=0.3)
    axes[0].set_yticks(y, [r["case"][:48] for r in rows], fontsize=8)
    fig.suptitle("Stability cases (green: ok, orange: honest failure, red: false success / bug)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
