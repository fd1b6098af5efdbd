"""Hypothesis profiles for the property tests.

``ci`` (default): few examples, derandomized, so the suite is fast and a CI run is reproducible.
``nightly``: many random examples; select it with ``HYPOTHESIS_PROFILE=nightly python -m pytest`` or
``python -m pytest --hypothesis-profile=nightly``.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "ci", max_examples=20, deadline=None, derandomize=True, print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "nightly", max_examples=500, deadline=None, print_blob=True, suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
