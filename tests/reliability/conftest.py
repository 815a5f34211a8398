"""Hypothesis settings for the reliability tests: few examples, no deadline (the machine is shared), derandomised
so a failure shows again on the next run. ``WECOOK_HYPOTHESIS=thorough`` runs many more, randomised."""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

_QUIET = [HealthCheck.too_slow, HealthCheck.function_scoped_fixture, HealthCheck.filter_too_much]
settings.register_profile("wecook", max_examples=40, deadline=None, derandomize=True, suppress_health_check=_QUIET)
settings.register_profile("thorough", max_examples=1500, deadline=None, suppress_health_check=_QUIET)
settings.load_profile(os.environ.get("WECOOK_HYPOTHESIS", "wecook"))
