"""Test problems with known solutions."""

from sqp.problems.problem import TestProblem, hs_optima

__all__ = ["TestProblem", "hs_optima"]
