"""Shared test fixtures: the real recordings in ../shared/data (skipped when absent)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SHARED_DATA = Path(os.environ.get("GAITML_SHARED_DATA", ROOT.parent / "shared" / "data")).resolve()


def with_domain_range(model, range_ms2: float | None):
    """``model`` with its domain record read through ``range_ms2`` (``DomainModel.acc_range_ms2``; None: as the
    recording comes). The shipped ``models/demo`` reads its check through 2 g; the range tests compare with it unranged."""
    import dataclasses

    if model.domain is None:
        return model
    return dataclasses.replace(model, domain=dataclasses.replace(model.domain, acc_range_ms2=range_ms2))


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
