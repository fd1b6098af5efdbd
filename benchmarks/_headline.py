"""The headline tables of ``peers.py``: ours against the fastest peer per n (with the distance to the structure
limit) and the cost growth of ours with n."""

from __future__ import annotations

import math
from typing import Any

import _tables as T
import _timing
import numpy as np
from _peers import STRUCTURE_LIMIT


def headline(rows: list[dict[str, Any]], bars: tuple[int, ...]) -> list[str]:
    """Per n: sgm over problems of ours and of the fastest solved peer (the structure limit is not a peer: it has its
    own columns, over the problems it and ours solved), and the ratios."""
    peers = {r["solver"] for r in rows if not r["solver"].startswith("ours") and r["solver"] != STRUCTURE_LIMIT}
    body = []
    for n in bars:
        ratios, ours_t, peer_t, which, limit = [], [], [], [], []
        for scene in dict.fromkeys(r["scene"] for r in rows):
            rs = [r for r in rows if r["scene"] == scene and r["n"] == n]
            ours = next((r for r in rs if r["solver"] == "ours" and r["solved"]), None)
            if ours is None:
                continue
            bound = next((r for r in rs if r["solver"] == STRUCTURE_LIMIT and r["solved"]), None)
            if bound is not None:
                limit.append(ours["time_s"] / bound["time_s"])
            solved_peers = [r for r in rs if r["solver"] in peers and r["solved"]]
            if not solved_peers:
                continue
            fastest = min(solved_peers, key=lambda r: r["time_s"])
            ratios.append(fastest["time_s"] / ours["time_s"])
            ours_t.append(ours["time_s"])
            peer_t.append(fastest["time_s"])
            which.append(fastest["solver"])
        to_limit = f"{float(np.exp(np.mean(np.log(limit)))):.2g} ({len(limit)})" if limit else "—"
        if not ratios:
            body.append([n, 0, "—", "—", "—", "—", "—", to_limit])
            continue
        names = ", ".join(f"{k} {which.count(k)}" for k in sorted(set(which)))
        body.append([n, len(ratios), f"{1e3 * _timing.sgm(ours_t):.3g}", f"{1e3 * _timing.sgm(peer_t):.3g}",
                     f"{float(np.exp(np.mean(np.log(ratios)))):.2g}", f"{min(ratios):.2g}", names, to_limit])
    return T.markdown_table(["n", "problems (ours and a peer solved)", "ours sgm (ms)", "fastest peer sgm (ms)",
                             "peer/ours (geo. mean)", "peer/ours (worst)", "fastest peer",
                             "ours/structure limit (geo. mean; problems)"], body)


def growth(rows: list[dict[str, Any]], bars: tuple[int, ...]) -> list[str]:
    """Cost growth of ours from n = 100 to the largest n: the exponent ``p`` of ``time ∝ n^p`` per scene (solved at
    both ends), and of the sgm over the scenes solved at both."""
    lo, hi = 100, max(bars)
    if lo not in bars or hi <= lo:
        return []
    pairs = []
    for scene in dict.fromkeys(r["scene"] for r in rows):
        a = next((r for r in rows if r["scene"] == scene and r["n"] == lo and r["solver"] == "ours" and r["solved"]),
                 None)
        b = next((r for r in rows if r["scene"] == scene and r["n"] == hi and r["solver"] == "ours" and r["solved"]),
                 None)
        if a is not None and b is not None:
            pairs.append((scene, a["time_s"], b["time_s"]))
    if not pairs:
        return []
    k = math.log(hi / lo)
    per = [math.log(t1 / t0) / k for _, t0, t1 in pairs]
    whole = math.log(_timing.sgm([p[2] for p in pairs]) / _timing.sgm([p[1] for p in pairs])) / k
    worst = max(zip(per, (p[0] for p in pairs), strict=True))
    return ["", f"Cost growth of ours from n = {lo} to n = {hi} ({len(pairs)} scenes solved at both): sgm time ∝ "
            f"n^{whole:.2f}; per scene n^{min(per):.2f} … n^{worst[0]:.2f} ({worst[1]})."]
