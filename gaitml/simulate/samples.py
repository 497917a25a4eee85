"""The small simulated recordings shipped in ``data/samples`` (examples and tests).

``python -m gaitml.simulate.samples data/samples`` rewrites them; the same
code gives byte-identical files (a test checks the committed copies). Three
recordings, 50 Hz, well under 1 MB in all:

- ``S01-walk``: 20 s of flat-held walking (default subject; realism reference);
- ``S02-mixed``: 60 s, all five modes in 10-12 s segments with transitions;
- ``S03-pauses``: 30 s of walking and running with pauses labelled ``stand``.
"""

from __future__ import annotations

import sys
from pathlib import Path

from gaitml.simulate.dataset import simulate_recording, write_simulation
from gaitml.simulate.subject import Subject, sample_subjects

__all__ = ["sample_recordings", "write_samples", "SAMPLES_SEED"]

SAMPLES_SEED = 2024


def sample_recordings() -> list:
    """The sample recordings (see the module docstring)."""
    subs = sample_subjects(3, SAMPLES_SEED, pose="flat")
    walk = simulate_recording(
        Subject(), modes=("walk",), duration_s=20.0, seed=SAMPLES_SEED, meta={"id": "S01-walk", "session": "S01-walk"}
    )
    mixed = simulate_recording(
        subs[1], duration_s=60.0, seed=SAMPLES_SEED + 1, segment_s=(10.0, 12.0), meta={"id": "S02-mixed", "session": "S02-mixed"}
    )
    pauses = simulate_recording(
        subs[2], modes=("walk", "run"), duration_s=30.0, seed=SAMPLES_SEED + 2, pauses=True, segment_s=(8.0, 10.0),
        meta={"id": "S03-pauses", "session": "S03-pauses"},
    )  # fmt: skip
    return [walk, mixed, pauses]


def write_samples(out_dir: str | Path) -> list[Path]:
    """Write the sample recordings, sidecars and manifest to ``out_dir``."""
    return write_simulation(sample_recordings(), out_dir)


if __name__ == "__main__":
    target = sys.argv[1] if len(sys.argv) > 1 else "data/samples"
    for p in write_samples(target):
        print(p)
