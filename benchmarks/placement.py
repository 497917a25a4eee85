"""Benchmark: the cost of the foot-placement rule in ``predict`` (the same model with and without it, in the same run).

    PYTHONPATH=$PWD python -m benchmarks.placement [MODEL_DIR] [--reps 5] [--duration 600]

:func:`gaitml.models.predict_recording` (the path of ``gaitml predict``: features, the SVM, the
adjacent-window correction, the still gate, the model's domain check and the foot-placement
rule of :mod:`gaitml.models._placement`) of a simulated hand-held recording with a gyroscope
(seed 7, ``duration`` s at the model's rate), alternately with the rule and with the rule
switched off (:func:`gaitml.models._predict.foot_placement` replaced by one returning None),
best of ``reps`` each, one BLAS thread. Also the rule alone on the same windows.
The ratio printed is without / with: the rule's cost is ``1 / ratio - 1``.
"""

from __future__ import annotations

import argparse
import contextlib
import time
from unittest import mock

import numpy as np

__all__ = ["main"]


def main(argv=None) -> int:
    from gaitml.models import load_model, predict_recording, resample_recording
    from gaitml.models._placement import foot_like_windows
    from gaitml.models._predict import _windows_for
    from gaitml.simulate import simulate_dataset

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("model", nargs="?", default="models/demo")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--duration", type=float, default=600.0)
    a = ap.parse_args(argv)
    model = load_model(a.model)
    rec = resample_recording(simulate_dataset(n_subjects=1, duration_s=a.duration, pose="mixed", seed=7)[0], model.sampling_rate_hz)
    w = _windows_for(rec, model.length_s, model.overlap)
    try:
        from threadpoolctl import threadpool_limits

        limit = threadpool_limits(limits=1, user_api="blas")
    except ImportError:  # pragma: no cover - threadpoolctl comes with scikit-learn
        limit = contextlib.nullcontext()
    best = {"with the rule": np.inf, "without the rule": np.inf, "the rule alone": np.inf}
    with limit:
        predict_recording(model, rec.slice(0, 1000))  # warm-up
        n = len(w)
        for i in range(a.reps):
            for rule in (True, False) if i % 2 == 0 else (False, True):  # the order alternates
                with contextlib.nullcontext() if rule else mock.patch("gaitml.models._predict.foot_placement", return_value=None):
                    t0 = time.perf_counter()
                    predict_recording(model, rec)
                    dt = time.perf_counter() - t0
                key = "with the rule" if rule else "without the rule"
                best[key] = min(best[key], dt)
            t0 = time.perf_counter()
            foot_like_windows(rec.acc, rec.gyr, rec.sampling_rate_hz, w)
            best["the rule alone"] = min(best["the rule alone"], time.perf_counter() - t0)
    print(f"| {a.model}, {a.duration:g} s at {model.sampling_rate_hz:g} Hz ({n} windows) | best of {a.reps} (ms) | windows per s |")
    print("|---|---:|---:|")
    for k, v in best.items():
        print(f"| {k} | {1000 * v:.1f} | {n / v:,.0f} |")
    print(
        f"\npredict without / with the rule: {best['without the rule'] / best['with the rule']:.3f}x (alternated, one BLAS thread); "
        f"the rule alone is {100 * best['the rule alone'] / best['without the rule']:.1f} % of predict without it"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
