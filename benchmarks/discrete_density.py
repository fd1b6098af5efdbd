"""Discrete density (the paper's Fig. 10): solve time and error against the continuum as the bar count grows.

What is measured
----------------
*n/L sweep* — the paper's Table 1 scene with θ_B = π/4 (``guidewire.paper_scenes()["table1_pi_4"]``: clamp A (0, 0)
along +x, contact B (60, 40) at s = L = 100 mm with angle π/4) at n/L from 0.1 to 10 per mm (n = 10 … 1000).

*L sweep at n/L = 1* — the same scene scaled by c = L/100 as a whole (B at (60c, 40c), s_B = L, the same angles and
EI), n = L bars, L from 25 to 800 mm. The continuum shape scales with c, so at a fixed bar length of 1 mm the relative
resolution grows with L: the node error goes like c·(1/n)^p = L^(1−p) for a scheme of order p, the energy like 1/c.

Both energy schemes ("paper": the paper's Eq. 15; "second_order") are solved by ``ours`` (:func:`guidewire.solve`,
defaults), ``ours[bfgs]`` (the paper's damped BFGS) and the peers of
:mod:`_peers` (scipy SLSQP, scipy trust-constr, IPOPT when installed), all from the formulation's start with the same
analytic derivatives. Per solve: time (median of ``--repeats``, one run once a solve takes > 1 s), iterations,
function evaluations, energy (and its relative difference to the continuum energy), largest constraint violation,
mean and max node error (mm) against the exact continuum elastica at the same arc length (the paper's Eq. 25, via
the continuum reference's ``node_errors``). A solve longer than ``--limit`` s is stopped and that solver is not run
at larger n in that sweep and scheme; a solve predicted to pass the limit is not started, and a solver that has spent
``--budget`` s (default 100) of solve time is not started again (``ours`` has no budget; :class:`_timing.Budget`);
every skip is in the table.

The order p of each scheme is the least-squares slope of log(mean error) against log(n/L) over ours' solves. The
figure has four panels: time vs n/L (Fig. 10), error vs n/L with the fitted orders, error vs run time (one curve per
scheme and solver: the Pareto front a user picks from; solved points only) and the L sweep.

*Graded* (``--graded``, :mod:`_graded_front`): uniform against curvature-graded bars (the paper's "discrete density by
curvature", ``solve(scene, bars=n, density="curvature")``) on every paper scene with a continuum reference, ours
only: error against bars and run time, and the bars and time each needs for a given mean node error.

Usage: ``python benchmarks/discrete_density.py [--graded] [--quick] [--repeats K] [--out DIR] [--limit S]``
Writes ``discrete_density.{md,csv,png}`` (``discrete_density_graded.*`` with ``--graded``; ``…_quick.*`` with
``--quick``) in ``--out``.
"""

from __future__ import annotations

import math
import time
from pathlib import Path
from typing import Any

import _arguments as A
import _environment as E  # first: pins BLAS to one thread before numpy loads
import _guidewire as G
import _tables as T
import _timing
import numpy as np

import guidewire

DENSITIES = (0.1, 0.15, 0.2, 0.3, 0.5, 0.7, 1.0, 1.5, 2.0, 3.0, 5.0, 7.0, 10.0)
QUICK_DENSITIES = (0.1, 0.3, 1.0)
LENGTHS = (25.0, 50.0, 100.0, 200.0, 400.0, 800.0)
QUICK_LENGTHS = (50.0, 100.0)
SCHEMES = ("paper", "second_order")
BASE_LENGTH = 100.0  # mm, Table 1


def table1() -> guidewire.Scene:
    """Table 1 with θ_B = π/4, as the paper reproduction uses it."""
    return guidewire.paper_scenes()["table1_pi_4"]


def scaled_table1(length: float) -> guidewire.Scene:
    """Table 1 (θ_B = π/4) with all lengths scaled by ``length / 100`` and ``length`` bars (n/L = 1)."""
    scene = table1()
    c = length / BASE_LENGTH
    (contact,) = scene.contacts
    scaled = guidewire.Contact(contact.s * c, (contact.point[0] * c, contact.point[1] * c), contact.angle,
                               name=contact.name)
    wire = scene.wire
    return guidewire.Scene(
        guidewire.Wire(length, int(round(length)), wire.youngs_modulus, wire.diameter,
                       moment_of_inertia=wire.moment_of_inertia),
        scene.base, (scaled,), name=f"table1_pi_4 ×{c:g}",
    )


def solve_all(sweep: str, scene: guidewire.Scene, bars: int, solvers: dict[str, Any], budget: _timing.Budget,
              repeats: int) -> list[dict[str, Any]]:
    """Every scheme × solver on one scene at ``bars`` bars (time limit: the budget's); one row each."""
    ref, note = G.reference(scene)
    rows = []
    for scheme in SCHEMES:
        case = G.make_case(scene, bars=bars, scheme=scheme)
        for name, run in solvers.items():
            res = budget.measure(name, f"{sweep} {scheme}", bars, run, case, repeats)
            ev = G.evaluate(case, res.get("x"), ref)
            ref_energy = float(ref.energy) if ref is not None else math.nan
            feasible = ev["max_violation"] <= G.FEASIBILITY_TOL
            rows.append({
                "sweep": sweep, "L_mm": scene.wire.length, "n": bars, "n_per_L": bars / scene.wire.length,
                "scheme": scheme, "solver": name, "outcome": res["outcome"], "success": bool(res["success"]),
                "solved": bool(res["success"]) and feasible, "time_s": res["time"], "repeats": res["repeats"],
                "nit": res["nit"], "nfev": res["nfev"], "energy": ev["energy"], "reference_energy": ref_energy,
                "energy_vs_reference": (ev["energy"] - ref_energy) / ref_energy, "max_violation": ev["max_violation"],
                "mean_error_mm": ev["mean_error_mm"], "max_error_mm": ev["max_error_mm"],
                "message": "" if res["success"] and res["outcome"] == "ran" else res["message"],
                "reference_note": note,
            })
    return rows


def fitted_order(rows: list[dict[str, Any]], x_key: str, y_key: str) -> tuple[float, float]:
    """Least-squares ``(slope, intercept)`` of log y against log x over rows with finite positive values."""
    pts = [(r[x_key], r[y_key]) for r in rows if r["solved"] and np.isfinite(r[y_key]) and r[y_key] > 0]
    if len(pts) < 2:
        return math.nan, math.nan
    x, y = np.log(np.array(pts)).T
    slope, intercept = np.polyfit(x, y, 1)
    return float(slope), float(intercept)


def main() -> None:
    ap = A.parser(__doc__, quick_help="three n/L values, two lengths, one repeat (< 1 minute)", repeats=5,
                  limit=60.0, budget=100.0, budget_help="solve time (s) per solver for the whole run")
    ap.add_argument("--graded", action="store_true", help="uniform against curvature-graded bars (_graded_front)")
    a = A.parse(ap)
    if a.graded:
        import _graded_front

        with E.one_thread():
            rows = _graded_front.run(a.repeats, a.quick)
        _graded_front.write(rows, T.output_stem(a.out, "discrete_density_graded", a.quick), E.environment(),
                            a.repeats, (0.01, 0.003))
        return
    densities = QUICK_DENSITIES if a.quick else DENSITIES
    lengths = QUICK_LENGTHS if a.quick else LENGTHS
    repeats, limit = a.repeats, a.limit
    solvers = {**G.ours_variants(backends=False), **G.peer_variants()}
    env = E.environment()
    settings = (f"n/L ∈ {list(densities)} per mm at L = 100 mm; L ∈ {[int(v) for v in lengths]} mm at n/L = 1; "
                f"schemes {', '.join(SCHEMES)}; solvers {', '.join(solvers)}; {_timing.repeats_note(repeats)}; "
                f"time limit {limit:g} s per solve, {a.budget:g} s of solves per solver")
    print("\n".join(env + [settings]))
    hessian_note = G.peer_hessian_note(G.make_case(table1(), bars=20))
    jobs = [("n/L", table1(), int(round(d * BASE_LENGTH))) for d in densities]
    jobs += [("L at n/L = 1", scaled_table1(length), int(round(length))) for length in lengths]
    jobs.sort(key=lambda job: job[2])  # small n of both sweeps first: a spent budget cuts the largest n
    rows: list[dict[str, Any]] = []
    budget = _timing.Budget(limit, a.budget)
    start = time.perf_counter()
    with E.one_thread():
        G.warm_up(solvers, limit)
        for sweep, scene, bars in E.progress(jobs, desc="sweep points"):
            rows += solve_all(sweep, scene, bars, solvers, budget, repeats)
    print(f"total {time.perf_counter() - start:.0f} s")
    write(rows, list(solvers), a.out, env, settings, hessian_note, quick=a.quick)


# --------------------------------------------------------------------------------------------------------------------
# Output
# --------------------------------------------------------------------------------------------------------------------
def orders(rows: list[dict[str, Any]]) -> dict[str, dict[str, float]]:
    """Fitted orders of ours per scheme: mean and max error vs n/L, and mean error vs L at n/L = 1."""
    out = {}
    for scheme in SCHEMES:
        a = [r for r in rows if r["sweep"] == "n/L" and r["scheme"] == scheme and r["solver"] == "ours"]
        b = [r for r in rows if r["sweep"] != "n/L" and r["scheme"] == scheme and r["solver"] == "ours"]
        out[scheme] = {
            "mean": -fitted_order(a, "n_per_L", "mean_error_mm")[0],
            "max": -fitted_order(a, "n_per_L", "max_error_mm")[0],
            "intercept": fitted_order(a, "n_per_L", "mean_error_mm")[1],
            "L_slope": fitted_order(b, "L_mm", "mean_error_mm")[0],
        }
    return out


def write(rows: list[dict[str, Any]], solvers: list[str], out: Path, env: list[str], settings: str,
          hessian_note: str, *, quick: bool) -> None:
    stem = T.output_stem(out, "discrete_density", quick)
    T.write_csv(rows, stem.with_suffix(".csv"))
    fits = orders(rows)
    lines = [
        "# Discrete density (Fig. 10): time and error against the continuum vs n/L, both schemes, ours and peers",
        "",
        *[f"- {e}" for e in env],
        f"- {settings}",
        "- scene: Table 1, θ_B = π/4 (clamp A (0, 0) along +x, contact B (60, 40) at s = 100 with angle π/4); the "
        "L sweep scales the whole geometry by L/100 (B at (0.6L, 0.4L), s_B = L, same angles and EI) with n = L",
        f"- every solver from the formulation's start with the same analytic derivatives; {hessian_note}",
        "- error: distance of each node from the exact continuum elastica at the same arc length (Eq. 25); energy "
        "relative to the continuum energy; ours' time = `Solution.solve_time_s`, a peer's = its `minimize` call",
        "",
        "## Fitted orders (ours; least squares of log error on log n/L)",
        "",
    ]
    lines += T.markdown_table(
        ["scheme", "order (mean error)", "order (max error)", "mean error at n/L = 1 (mm)",
         "slope of mean error vs L at n/L = 1"],
        [[s, f["mean"], f["max"], _at(rows, s, 1.0), f["L_slope"]] for s, f in fits.items()],
    )
    low, mean, t_lo, t_hi = equal_time_ratio(rows)
    lines += ["", f"At equal run time (ours, n/L sweep, each scheme's Pareto front; time budgets {1e3 * t_lo:.3g}–"
              f"{1e3 * t_hi:.3g} ms, each scheme's smallest error within the budget): the paper scheme's mean error "
              f"is {low:.3g}× (smallest) and {mean:.3g}× (geometric mean) the second-order scheme's."]
    lines += ["", "## Ours against the peers at equal n (n/L sweep): time ratio peer/ours, solved points", ""]
    lines += _ratios(rows, solvers)
    for sweep in dict.fromkeys(r["sweep"] for r in rows):
        lines += ["", f"## Sweep: {sweep}", ""]
        rs = [r for r in rows if r["sweep"] == sweep]
        rs.sort(key=lambda r: (r["scheme"], solvers.index(r["solver"]), r["n"]))
        lines += T.markdown_table(
            ["scheme", "solver", "L (mm)", "n", "n/L", "time (ms)", "it", "f-evals", "energy (N·mm)",
             "vs continuum", "mean error (mm)", "max error (mm)", "max violation", "status"],
            [[r["scheme"], r["solver"], r["L_mm"], r["n"], r["n_per_L"], 1e3 * r["time_s"], r["nit"], r["nfev"],
              r["energy"], r["energy_vs_reference"], r["mean_error_mm"], r["max_error_mm"], r["max_violation"],
              ("ok" if r["solved"] else ("F " if not r["success"] else "infeasible ") + r["message"][:70])]
             for r in rs],
        )
    T.write_markdown(lines, stem.with_suffix(".md"))
    print("\n".join(lines[: lines.index(f"## Sweep: {rows[0]['sweep']}")]))
    plot(rows, solvers, fits, stem.with_suffix(".png"))


def pareto_front(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The non-dominated ``(time, error)`` points, by increasing time (each has a smaller error than all faster)."""
    front: list[tuple[float, float]] = []
    for t, e in sorted(p for p in points if np.isfinite(p[0]) and np.isfinite(p[1])):
        if not front or e < front[-1][1]:
            front.append((t, e))
    return front


def equal_time_ratio(rows: list[dict[str, Any]], solver: str = "ours") -> tuple[float, float, float, float]:
    """Paper-scheme error over second-order error at equal run time, from each scheme's Pareto front (``solver``,
    n/L sweep): ``(smallest ratio, geometric mean ratio, t_lo, t_hi)`` over the time budgets ``t`` from the later of
    the two fastest solves to the slower of the two slowest, each scheme's error being the smallest it reaches
    within ``t`` (past its slowest point, its best; so the comparison stands when one scheme's solves are all
    faster than the other's)."""
    fronts = {}
    for scheme in SCHEMES:
        pts = [(r["time_s"], r["mean_error_mm"]) for r in rows
               if r["sweep"] == "n/L" and r["scheme"] == scheme and r["solver"] == solver and r["solved"]]
        fronts[scheme] = pareto_front(pts)
    if not all(fronts.values()):
        return math.nan, math.nan, math.nan, math.nan
    t_lo = max(f[0][0] for f in fronts.values())
    t_hi = max(f[-1][0] for f in fronts.values())
    if not t_hi > t_lo:
        return math.nan, math.nan, t_lo, t_hi
    grid = np.geomspace(t_lo, t_hi, 50)

    def best(front: list[tuple[float, float]], t: float) -> float:  # smallest error reachable within time t
        return min(e for tt, e in front if tt <= t * (1 + 1e-12))

    ratios = np.array([best(fronts["paper"], t) / best(fronts["second_order"], t) for t in grid])
    return float(ratios.min()), float(np.exp(np.mean(np.log(ratios)))), t_lo, t_hi


def _at(rows: list[dict[str, Any]], scheme: str, density: float) -> float:
    r = next((r for r in rows if r["sweep"] == "n/L" and r["scheme"] == scheme and r["solver"] == "ours"
              and abs(r["n_per_L"] - density) < 1e-9), None)
    return r["mean_error_mm"] if r else math.nan


def _ratios(rows: list[dict[str, Any]], solvers: list[str]) -> list[str]:
    a = [r for r in rows if r["sweep"] == "n/L"]
    ns = sorted({r["n"] for r in a})
    body = []
    for scheme in SCHEMES:
        ours = {r["n"]: r for r in a if r["scheme"] == scheme and r["solver"] == "ours"}
        body.append([scheme, "ours (ms)", *[1e3 * ours[n]["time_s"] if n in ours and ours[n]["solved"] else math.nan
                                            for n in ns]])
        for name in solvers:
            if name == "ours":
                continue
            cells = []
            for n in ns:
                r = next((r for r in a if r["scheme"] == scheme and r["solver"] == name and r["n"] == n), None)
                if r is None or n not in ours:
                    cells.append("")
                elif not r["solved"]:
                    cells.append(r["outcome"] if r["outcome"] != "ran" else "failed")
                else:
                    cells.append(f"×{r['time_s'] / ours[n]['time_s']:.3g}")
            body.append([scheme, name, *cells])
    return T.markdown_table(["scheme", "solver", *[f"n = {n}" for n in ns]], body)


def plot(rows: list[dict[str, Any]], solvers: list[str], fits: dict[str, dict[str, float]], path: Path) -> None:
    plt = T.pyplot()
    if plt is None:
        return
    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    (ax_t, ax_e), (ax_p, ax_l) = axes
    colors = {name: f"C{i}" for i, name in enumerate(solvers)}
    styles = {"second_order": "-", "paper": "--"}
    markers = {"second_order": "o", "paper": "s"}
    sweep_a = [r for r in rows if r["sweep"] == "n/L"]
    for scheme in SCHEMES:
        for name in solvers:
            rs = sorted((r for r in sweep_a if r["scheme"] == scheme and r["solver"] == name and r["solved"]),
                        key=lambda r: r["n"])
            if not rs:
                continue
            label = f"{name}, {scheme}"
            kw = {"color": colors[name], "ls": styles[scheme], "marker": markers[scheme], "ms": 4, "label": label}
            ax_t.loglog([r["n_per_L"] for r in rs], [r["time_s"] for r in rs], **kw)
            ax_p.loglog([r["time_s"] for r in rs], [r["mean_error_mm"] for r in rs], **kw)
        ours = sorted((r for r in sweep_a if r["scheme"] == scheme and r["solver"] == "ours" and r["solved"]),
                      key=lambda r: r["n"])
        if ours:
            x = np.array([r["n_per_L"] for r in ours])
            for key, mk, fill in (("mean_error_mm", markers[scheme], "full"), ("max_error_mm", "^", "none")):
                ax_e.loglog(x, [r[key] for r in ours], ls="", marker=mk, fillstyle=fill, color=colors["ours"]
                            if scheme == "second_order" else "C3", label=f"{scheme}: {key.split('_')[0]} error")
            p, c = fits[scheme]["mean"], fits[scheme]["intercept"]
            if np.isfinite(p):
                ax_e.loglog(x, np.exp(c) * x ** (-p), ls=styles[scheme], color="k", lw=0.8)
                ax_e.annotate(f"{scheme}: order {p:.2f}", (x[len(x) // 2], np.exp(c) * x[len(x) // 2] ** (-p)),
                              textcoords="offset points", xytext=(8, 8), fontsize=9)
        b = sorted((r for r in rows if r["sweep"] != "n/L" and r["scheme"] == scheme and r["solver"] == "ours"
                    and r["solved"]), key=lambda r: r["n"])
        if b:
            ax_l.loglog([r["L_mm"] for r in b], [r["mean_error_mm"] for r in b], ls=styles[scheme],
                        marker=markers[scheme], color="C3" if scheme == "paper" else "C0",
                        label=f"{scheme}: mean error (mm)")
            ax_l.loglog([r["L_mm"] for r in b], [r["time_s"] for r in b], ls=styles[scheme], marker="x", color="0.4",
                        label=f"{scheme}: ours' time (s)")
    front = pareto_front([(r["time_s"], r["mean_error_mm"]) for r in sweep_a if r["solved"]])
    if front:
        ft, fe = zip(*front, strict=True)
        ax_p.step(ft, fe, where="post", color="k", lw=3, alpha=0.25, label="Pareto front (all)")
    ax_t.axvline(1.0, color="r", lw=0.8, alpha=0.6)
    ax_t.set(xlabel="n/L (bars per mm)", ylabel="time per solve (s)", title="Fig. 10: time vs discrete density")
    ax_e.set(xlabel="n/L (bars per mm)", ylabel="node error vs continuum (mm)",
             title="error vs n/L (ours; filled: mean, open: max; lines: fits)")
    ax_p.set(xlabel="time per solve (s)", ylabel="mean node error (mm)",
             title="error vs run time (solved points; lower left is better)")
    ax_l.set(xlabel="L (mm), n = L", ylabel="mean error (mm) / time (s)", title="L sweep at n/L = 1 (ours)")
    for ax in axes.ravel():
        ax.grid(True, which="both", alpha=0.3)
    ax_e.legend(fontsize=8)
    ax_l.legend(fontsize=8)
    lengths = sorted({r["L_mm"] for r in rows if r["sweep"] != "n/L"})
    if lengths:
        ax_l.set_xticks(lengths, [f"{v:g}" for v in lengths])
        ax_l.minorticks_off()
    handles, labels = ax_t.get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=8, title="time and error-vs-time panels: "
               "solver, scheme (solid: second_order, dashed: paper)")
    fig.suptitle("Table 1, θ_B = π/4: discrete density (paper Fig. 10) against the exact continuum elastica")
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
