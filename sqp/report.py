"""The verbose iteration table (``verbose=True``)."""

from __future__ import annotations

from sqp.result import IterationRecord

HEADER = (f"{'iter':>5} {'nfev':>6} {'f':>15} {'maxcv':>9} {'KKT':>9} {'|d|':>9} {'alpha':>8} "
          f"{'penalty':>9} {'QP':>10} {'damped':>6}")


def format_row(rec: IterationRecord) -> str:
    """One table row."""
    flag = "yes" if rec.damped else "no"
    soc = "+soc" if rec.soc else ""
    return (f"{rec.nit:5d} {rec.nfev:6d} {rec.f:15.8e} {rec.maxcv:9.2e} {rec.kkt:9.2e} {rec.step:9.2e} "
            f"{rec.alpha:8.2e} {rec.penalty:9.2e} {rec.qp_status + soc:>10} {flag:>6}")
