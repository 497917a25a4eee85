"""Benchmarks behind ``gaitml bench``: one module per area, each ``run(quick) -> list[dict]``.

Every row measures our implementation and, where there is one, a plain reference
implementation of the same computation in the same process (``ratio`` =
reference time / our time), so the figures are comparable across machines.
"""

from __future__ import annotations

AREAS = ("features", "steps", "zupt", "models", "pdr", "simulate")
