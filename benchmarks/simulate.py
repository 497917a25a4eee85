"""Throughput of the gait simulator (samples/s of synthesized IMU data).

Measurements: one 120 s recording at 50 Hz (target: well under a second), the classification data set of 8 subjects x 120 s at 50 Hz (what the
classification and demo code simulate repeatedly), one 120 s recording at
200 Hz and the 262 m rectangle route. Each is the best of a few repeats. There
is no plain reference implementation of the simulator, so there is no ratio.
"""

from __future__ import annotations

import time

from gaitml.simulate import sample_subjects, simulate_dataset, simulate_recording, simulate_route

__all__ = ["run"]


def _best(fn, repeats: int) -> tuple[float, object]:
    best, out = float("inf"), None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def _row(name, n, seconds, note):
    return {
        "area": "simulate",
        "name": name,
        "n_items": int(n),
        "unit": "samples",
        "seconds": seconds,
        "throughput_per_s": n / seconds,
        "note": note,
    }


def run(quick: bool = False) -> list[dict]:
    """Time the simulator; ``quick`` uses fewer repeats and a 4-subject data set."""
    reps = 1 if quick else 3
    subj = sample_subjects(1, 0)[0]
    rows = []
    s, rec = _best(lambda: simulate_recording(subj, duration_s=120.0, seed=0), reps)
    rows.append(_row("recording-120s-50hz", rec.n_samples, s, "one subject, 5 modes, straight route"))
    n_sub = 4 if quick else 8
    s, recs = _best(lambda: simulate_dataset(n_sub, 120.0, seed=0), reps)
    rows.append(_row(f"dataset-{n_sub}x120s-50hz", sum(r.n_samples for r in recs), s, "simulate_dataset defaults"))
    s, rec = _best(lambda: simulate_recording(subj, duration_s=120.0, sampling_rate_hz=200.0, seed=0), reps)
    rows.append(_row("recording-120s-200hz", rec.n_samples, s, "one subject, 5 modes"))
    s, rec = _best(lambda: simulate_route("rectangle", seed=0), reps)
    rows.append(_row("route-rectangle-262m", rec.n_samples, s, f"{rec.duration_s:.0f} s, mixed modes"))
    return rows
