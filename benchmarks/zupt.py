"""Throughput of the zero-velocity detectors (samples/s) against plain per-sample loops.

Input: a synthetic foot-mounted walk (1 Hz strides: 40 % still, 60 % swing with
large rotation and acceleration, plus sensor noise) at 100 Hz, 3 million
samples (quick: 200 000). The reference loops (:mod:`tests.reference.zupt`)
run on a 20 000-sample prefix (quick: 5 000) and their time is scaled linearly
to the full length for ``reference_seconds`` (they are O(n)).
"""

from __future__ import annotations

import time

import numpy as np

from gaitml.recording import Recording
from gaitml.zupt import DETECTORS, get_detector
from gaitml.zupt._intervals import half_window_samples
from tests.reference import zupt as ref
from tests.synthetic import synthetic_foot_walk

__all__ = ["run"]


def _reference_fn(name: str, det, rec: Recording):
    fs = rec.sampling_rate_hz
    acc, gyr = rec.acc, rec.gyr
    if name == "pseudo-std":
        s = half_window_samples(det.half_window_s, fs)
        return lambda: ref.reference_pseudo_std(gyr, s) < det._threshold()
    if name == "shoe":
        return lambda: ref.reference_shoe(acc, gyr, det._half(fs), det.sigma_a_ms2, det.sigma_w_rads) < det.gamma
    if name == "gyro-range":
        s = half_window_samples(det.half_window_s, fs)
        return lambda: ref.reference_gyro_range(acc, gyr, s, det.gyr_range_rads, det.acc_max_ms2)
    if name == "magnitude-std":
        s = half_window_samples(det.half_window_s, fs)
        return lambda: ref.reference_magnitude_std(
            acc, gyr, s, det.acc_min_ms2, det.acc_max_ms2, det.acc_std_ms2, det.gyr_max_rads, det.gyr_std_rads
        )
    if name == "magnitude":
        return lambda: ref.reference_magnitude(acc, fs, det.t_min_ms2, det.t_max_ms2, det.min_run_fraction)
    raise KeyError(name)


def _load() -> float:
    try:
        import os

        return os.getloadavg()[0]
    except OSError:  # pragma: no cover - platform without getloadavg
        return float("nan")


def _best_of(fn, repeats: int, clock=time.perf_counter) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = clock()
        fn()
        best = min(best, clock() - t0)
    return best


def run(quick: bool = False) -> list[dict]:
    """One row per detector: our ``detect`` on the full input vs the per-sample loop."""
    n = 200_000 if quick else 3_000_000
    n_ref = 5_000 if quick else 20_000
    rec = synthetic_foot_walk(n)
    small = rec.slice(0, n_ref)
    rows = []
    for name in DETECTORS:
        det = get_detector(name)
        det.detect(small)  # warm-up
        sec = _best_of(lambda d=det: d.detect(rec), 1 if quick else 3)
        cpu = _best_of(lambda d=det: d.detect(rec), 1 if quick else 3, clock=time.process_time)
        ref_small = _best_of(_reference_fn(name, get_detector(name), small), 1)
        agree = bool(np.array_equal(_reference_fn(name, get_detector(name), small)(), get_detector(name).detect(small).per_sample_zupts_))
        ref_sec = ref_small * n / n_ref
        rows.append(
            {
                "area": "zupt",
                "name": name,
                "n_items": n,
                "unit": "samples",
                "seconds": sec,
                "throughput_per_s": n / sec,
                "reference_seconds": ref_sec,
                "ratio": ref_sec / sec,
                "cpu_seconds": cpu,
                "cpu_throughput_per_s": n / cpu if cpu > 0 else None,
                "note": (
                    f"detect() incl. interval table, 100 Hz synthetic; wall time (cpu time in cpu_seconds; load average "
                    f"{_load():.1f}); reference loop timed on {n_ref} samples, scaled; same mask as reference: {agree}"
                ),
            }
        )
    rows += _interval_rule_rows(rec, quick)
    return rows


def _interval_rule_rows(rec: Recording, quick: bool) -> list[dict]:
    """The detectors with interval rules (issue 30): default ``'stride'`` against ``'fixed'`` (the rules before), same input."""
    rows = []
    n = rec.n_samples
    for name in ("pseudo-std", "magnitude"):
        new, old = get_detector(name), get_detector(name, interval_rules="fixed")
        sec = _best_of(lambda d=new: d.detect(rec), 1 if quick else 3)
        ref_sec = _best_of(lambda d=old: d.detect(rec), 1 if quick else 3)
        rows.append(
            {
                "area": "zupt",
                "name": f"{name} stride rules",
                "n_items": n,
                "unit": "samples",
                "seconds": sec,
                "throughput_per_s": n / sec,
                "reference_seconds": ref_sec,
                "ratio": ref_sec / sec,
                "cpu_seconds": None,
                "cpu_throughput_per_s": None,
                "note": f"interval_rules='stride' (default) vs 'fixed' (the fixed-seconds rules before issue 30), same input; load {_load():.1f}",
            }
        )
    return rows


if __name__ == "__main__":  # pragma: no cover
    for r in run(quick=False):
        print(
            f"{r['name']:>11}: {r['throughput_per_s'] / 1e6:6.2f} M samples/s wall, {r['cpu_throughput_per_s'] / 1e6:6.2f} M/s cpu, "
            f"ratio {r['ratio']:6.0f}  ({r['note']})"
        )
