"""Warm-started continuation over many scenes: insertion through a vessel (:mod:`.insertion`) and sequences of
scenes with a polynomial predictor (:mod:`.sequence`)."""

from .insertion import Insertion, insert
from .sequence import SequenceResult, solve_sequence

__all__ = ["Insertion", "SequenceResult", "insert", "solve_sequence"]
