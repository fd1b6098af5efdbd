"""A standalone SQP engine: damped BFGS, QP subproblems through qpsolvers, an L1 merit line search.

>>> import sqp
>>> res = sqp.minimize(lambda x: (x[0] - 1) ** 2 + (x[1] - 2) ** 2, [0.0, 0.0],
...                    constraints=[{"type": "ineq", "fun": lambda x: 1 - x[0] - x[1]}])
>>> res.success
True
"""

from sqp.backends import installed_solvers
from sqp.hessian import DENSE_LIMIT, STRUCTURED_MIN
from sqp.legacy import fmin_slsqp
from sqp.options import Options
from sqp.result import IterationRecord, Result, Status
from sqp.solver import minimize

__all__ = [
    "DENSE_LIMIT", "STRUCTURED_MIN", "IterationRecord", "Options", "Result", "Status", "fmin_slsqp",
    "installed_solvers", "minimize",
]
