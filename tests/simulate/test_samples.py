"""The committed data/samples are what the simulator writes today (byte for byte) and stay small."""

from __future__ import annotations

from pathlib import Path

from gaitml.io import read_dataset
from gaitml.simulate.samples import write_samples

SAMPLES = Path(__file__).resolve().parents[2] / "data" / "samples"


def test_samples_are_small_and_readable():
    files = [p for p in SAMPLES.iterdir() if p.suffix == ".csv"]
    assert sum(p.stat().st_size for p in files) < 1_000_000
    recs = read_dataset(SAMPLES)
    assert [r.name for r in recs] == ["S01-walk", "S02-mixed", "S03-pauses"]
    assert len(set(recs[1].labels)) == 5
    assert "stand" in set(recs[2].labels)
    assert all(len(r.reference["steps"]) > 30 for r in recs)


def test_samples_regenerate_byte_identical(tmp_path):
    write_samples(tmp_path)
    for p in sorted(SAMPLES.glob("*.csv")):
        assert (tmp_path / p.name).read_bytes() == p.read_bytes(), (
            f"{p.name} differs from the simulator's output; run `python -m gaitml.simulate.samples data/samples`"
        )
