"""Hypothesis profiles and example counts for the property tests.

Two profiles, chosen by the environment variable ``GAITML_HYPOTHESIS_PROFILE``:

- ``ci`` (default): the numbers of examples written in the tests, sized so that
  the whole folder runs in well under a minute;
- ``long``: :data:`LONG_FACTOR` times as many, for a local run before a release
  (``GAITML_HYPOTHESIS_PROFILE=long pytest tests/robustness``).

``GAITML_HYPOTHESIS_EXAMPLES`` (older knob) still sets the algorithm tests' base
count. Every property test calls :func:`count` once per example with the entry
point it exercised and whether the example ran through it or was refused with an
InputError; the counts are printed at the end of the run (and written as JSON to
``GAITML_HYPOTHESIS_COUNTS`` if that is set), so the closing note of a change
can quote how many examples each entry point saw.
"""

from __future__ import annotations

import os
from collections import Counter

from hypothesis import HealthCheck, settings

PROFILE = os.environ.get("GAITML_HYPOTHESIS_PROFILE", "ci")
LONG_FACTOR = 20
if PROFILE not in ("ci", "long"):
    raise RuntimeError(f"GAITML_HYPOTHESIS_PROFILE={PROFILE!r}: use 'ci' or 'long'")

COUNTS: Counter = Counter()


def examples(ci: int) -> int:
    """The number of examples for a test that runs ``ci`` examples in the ci profile."""
    return ci * LONG_FACTOR if PROFILE == "long" else ci


def hyp_settings(ci: int, **kw) -> settings:
    """``hypothesis.settings`` for ``examples(ci)`` examples, no deadline (shared 2-core machines)."""
    kw.setdefault("suppress_health_check", [HealthCheck.too_slow, HealthCheck.data_too_large, HealthCheck.function_scoped_fixture])
    return settings(max_examples=examples(ci), deadline=None, **kw)


def count(entry: str, outcome: str) -> None:
    """Record one example of ``entry`` ('ran' through it, or 'refused' with an InputError)."""
    COUNTS[(entry, outcome)] += 1
