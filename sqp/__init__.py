"""A standalone SQP engine: damped BFGS, QP subproblems through qpsolvers, an L1 merit line search."""
