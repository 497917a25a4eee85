"""Benchmark: feature extraction of 1.5 s windows at 50 Hz (targets: >= 20,000 windows/s, >= 50x the reference).

Measures, in the same run and on the same signal:

- ``batch``: :func:`gaitml.features.features_from_arrays` over all windows at once;
- ``streaming``: :class:`gaitml.features.StreamingFeatureExtractor` fed 1 s chunks;
- the plain per-window reference (:mod:`tests.reference.features`) on a subset of the
  windows; its time per window is scaled to the full window count for ``reference_seconds``
  (stated in ``note``).

Wall-clock ``seconds`` are the contract figures; ``cpu_seconds`` / ``cpu_ratio`` (process
CPU time) are added because the machine is shared and wall-clock ratios between a
reference timed once and the extractor timed best-of-3 swing with the load.

Run: ``python -m benchmarks.features [--quick]`` from the repository root.
"""

from __future__ import annotations

import json
import sys
import time

import numpy as np

from gaitml.features import StreamingFeatureExtractor, features_from_arrays
from gaitml.signal import window_params, window_starts
from tests.reference.features import reference_features

__all__ = ["run"]

FS_HZ = 50.0
LENGTH_S = 1.5
OVERLAP = 0.5


def _signal(n_windows: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, int]:
    length, hop = window_params(LENGTH_S, OVERLAP, FS_HZ)
    n = (n_windows - 1) * hop + length
    rng = np.random.default_rng(seed)
    t = np.arange(n) / FS_HZ
    acc = np.column_stack([np.sin(2 * np.pi * 1.8 * t), 0.5 * np.cos(2 * np.pi * 0.9 * t), 9.8 + 2.5 * np.sin(2 * np.pi * 1.8 * t)])
    acc += rng.normal(0, 0.3, acc.shape)
    return acc, window_starts(n, length, hop), length


_CPU: dict[int, float] = {}


def _best_of(fn, repeats: int) -> float:
    """Best wall-clock time of ``repeats`` calls; the CPU time of that call goes to ``_CPU[id(fn)]``."""
    best, best_cpu = np.inf, np.inf
    for _ in range(repeats):
        c0, t0 = time.process_time(), time.perf_counter()
        fn()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if wall < best:
            best, best_cpu = wall, cpu
    _CPU[id(fn)] = best_cpu
    return best


def run(quick: bool = False) -> list[dict]:
    """Return one dict per measurement (keys as in the COMMON bench contract)."""
    n_windows = 5_000 if quick else 100_000
    n_ref = 40 if quick else 500  # the reference takes ~5-20 ms per window
    n_stream = 500 if quick else 10_000  # one push per 1 s of samples
    repeats = 1 if quick else 3
    acc, starts, length = _signal(n_windows)
    assert len(starts) == n_windows

    ref_starts = starts[:n_ref]
    ref_fn = lambda: reference_features(acc, None, ref_starts, length, "all52")  # noqa: E731
    t_ref = _best_of(ref_fn, 1)
    ref_per_window = t_ref / n_ref
    ref_cpu_per_window = _CPU[id(ref_fn)] / n_ref
    ref_total = ref_per_window * n_windows
    t_np = _best_of(lambda: reference_features(acc, None, ref_starts, length, "all52", use_scipy=False), 1)
    np_per_window = t_np / n_ref
    ref_note = (
        f"reference: plain per-window numpy/scipy loop timed on {n_ref} windows ({1e3 * ref_per_window:.2f} ms/window), scaled to {n_windows}; "
        f"a numpy-only per-window loop (moments instead of scipy.stats) takes {1e3 * np_per_window:.2f} ms/window"
    )

    out = []
    for subset in ("all52", "paper34"):
        fn = lambda s=subset: features_from_arrays(acc, None, FS_HZ, starts, length, s)  # noqa: E731
        t = _best_of(fn, repeats)
        out.append(
            {
                "area": "features",
                "name": f"batch-{subset}-1.5s-50Hz",
                "n_items": n_windows,
                "unit": "windows",
                "seconds": t,
                "throughput_per_s": n_windows / t,
                "reference_seconds": ref_total,
                "ratio": ref_total / t,
                "numpy_loop_ratio": np_per_window * n_windows / t,
                "cpu_seconds": _CPU[id(fn)],
                "cpu_ratio": ref_cpu_per_window * n_windows / _CPU[id(fn)],
                "note": f"vectorised extractor, 75-sample windows, hop 38; {ref_note}; target >= 20000 windows/s and >= 50x",
            }
        )

    chunk = int(FS_HZ)  # 1 s of samples per push, as a phone would deliver them

    n_stream_samples = int(starts[n_stream - 1]) + length
    stream_acc = acc[:n_stream_samples]

    def stream() -> None:
        ext = StreamingFeatureExtractor(FS_HZ, LENGTH_S, OVERLAP, "all52")
        for i in range(0, n_stream_samples, chunk):
            ext.push(stream_acc[i : i + chunk])
        assert ext.n_windows_ == n_stream

    t = _best_of(stream, repeats)
    ref_stream = ref_per_window * n_stream
    out.append(
        {
            "area": "features",
            "name": "streaming-all52-1.5s-50Hz-1s-chunks",
            "n_items": n_stream,
            "unit": "windows",
            "seconds": t,
            "throughput_per_s": n_stream / t,
            "reference_seconds": ref_stream,
            "ratio": ref_stream / t,
            "numpy_loop_ratio": np_per_window * n_stream / t,
            "cpu_seconds": _CPU[id(stream)],
            "cpu_ratio": ref_cpu_per_window * n_stream / _CPU[id(stream)],
            "note": f"StreamingFeatureExtractor fed 50-sample (1 s) chunks, 1-2 windows per push, i.e. {1e3 * t / n_stream:.3f} ms per window including buffering; {ref_note.replace(str(n_windows), str(n_stream))}",
        }
    )
    return out


if __name__ == "__main__":  # pragma: no cover
    for row in run(quick="--quick" in sys.argv):
        print(json.dumps(row))
