"""Shared fixtures of the lab's tests: the real recordings in ../shared/data (skipped when absent).

The lab (experiments/) may import the library; the library's tests (tests/) never import the lab,
so this folder keeps its own copy of the shared-data skip helper.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SHARED_DATA = Path(os.environ.get("GAITML_SHARED_DATA", ROOT.parent / "shared" / "data")).resolve()


def shared(*parts: str) -> Path:
    """Path below the shared real data; skips the test when it is not there."""
    p = SHARED_DATA.joinpath(*parts)
    if not p.exists():
        pytest.skip(f"shared real data not found at {p} (set GAITML_SHARED_DATA to the data folder)")
    return p


@pytest.fixture
def shared_data() -> Path:
    """The ../shared/data folder; skips when it is missing."""
    return shared()
