"""Benchmark: a shipped model against another, in the same run (``predict`` throughput and streaming latency).

    PYTHONPATH=$PWD python -m benchmarks.default_model models/demo OLD_MODEL_DIR [--reps 5] [--duration 600]

(``OLD_MODEL_DIR``: e.g. the previous default, ``git worktree add /tmp/old <commit>`` then
``/tmp/old/models/demo``). Both models read the same simulated hand-held recording with a
gyroscope (seed 7, ``duration`` s at 50 Hz), alternately, best of ``reps`` each:

- ``predict``: :func:`gaitml.models.predict_recording`, the path of ``gaitml predict``
  (features, the SVM, the adjacent-window correction, the still gate and the whole domain
  check, including the orientation-dynamics part when the model records one); windows per s.
- ``stream``: the streaming path of a deployed classifier, one hop of samples pushed at a time
  (:class:`gaitml.features.StreamingFeatureExtractor`), the SVM and the domain check of the one
  new window (features and gravity: one-window callers do not check the dynamics part), the
  foot-placement rule of the window (:func:`gaitml.models.window_placement_reason`) and the
  adjacent-window correction; ms per window.
- ``predict, run-cadence rule off``: the new model's ``predict`` with ``run_min_cadence_hz=0``, so the
  cost of the run-cadence rule (the ``adaptive`` step detector over the recording when some window
  is read ``run``) is the ratio of the two ``predict`` times of the new model.
- ``predict, step veto off``: the new model's ``predict`` with ``still_step_veto=0``, on the same recording,
  on one with pauses (the same walker standing still between bouts, ``pauses=True``), where some windows read
  still and the veto reads the ``adaptive`` detector's steps with its swing stage
  (:func:`gaitml.models._predict.veto_steps`, found once per recording; on a recording with a gyroscope they are not
  the run-cadence rule's, which keeps ``adaptive``'s defaults: the detector then runs once for each), and on a walk
  with pauses with the run-cadence rule off in both runs (the detector runs for the veto alone).

Both run on one BLAS thread where threadpoolctl is available (as the domain rows of
``benchmarks/models.py``: a second BLAS thread on a shared 2-core machine only adds noise).
"""

from __future__ import annotations

import argparse
import contextlib
import math
import time

import numpy as np

__all__ = ["stream_loop", "main"]


def stream_loop(rec, model) -> tuple[float, int]:
    """Wall time (s) and windows of the streaming loop of ``model`` over ``rec``."""
    from gaitml.features import StreamingFeatureExtractor
    from gaitml.models import window_placement_reason
    from gaitml.postprocess import AdjacentWindowCorrector

    ext = StreamingFeatureExtractor(model.sampling_rate_hz, model.length_s, model.overlap, model.feature_set)
    corr = AdjacentWindowCorrector()
    hop, length = ext.hop_samples_, ext.length_samples_
    dom = model.domain
    gyro = "gyro" in model.feature_set
    acc, gyr = np.asarray(rec.acc), np.asarray(rec.gyr)
    chunks = [(acc[i : i + hop], gyr[i : i + hop]) for i in range(0, len(acc), hop)]
    n = 0
    t0 = time.perf_counter()
    for a, g in chunks:
        rows = ext.push(a, g) if gyro else ext.push(a)
        for r, s in zip(rows, ext.last_starts_, strict=True):
            row = r[None, :]
            corr.push(model.estimator.predict(row)[0])
            if dom is not None:
                grav = None
                if dom.gravity_check:
                    total = np.add.reduce(acc[s : s + length])
                    grav = total / math.sqrt(total @ total)
                dom.check(row, grav)
                # the foot-placement rule reads the window's own samples (as predict_recording's windows)
                window_placement_reason(model, acc[s : s + length], gyr[s : s + length] if gyro else None)
            n += 1
    corr.flush()
    return time.perf_counter() - t0, n


def main(argv=None) -> int:
    from gaitml.models import load_model, predict_recording, resample_recording
    from gaitml.simulate import simulate_dataset

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("new")
    ap.add_argument("old")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--duration", type=float, default=600.0)
    a = ap.parse_args(argv)
    models = {"new": load_model(a.new), "old": load_model(a.old)}
    rec = simulate_dataset(n_subjects=1, duration_s=a.duration, pose="mixed", seed=7)[0]
    rec = resample_recording(rec, models["new"].sampling_rate_hz)
    try:
        from threadpoolctl import threadpool_limits

        limit = threadpool_limits(limits=1, user_api="blas")
    except ImportError:  # pragma: no cover - threadpoolctl comes with scikit-learn
        limit = contextlib.nullcontext()
    best = {k: {"predict": np.inf, "stream": np.inf} for k in models}
    best_off = np.inf
    rec_p = resample_recording(
        simulate_dataset(n_subjects=1, duration_s=a.duration, pose="mixed", seed=7, pauses=True)[0], models["new"].sampling_rate_hz
    )
    # walking only, with pauses: no window reads run, so the detector runs for the veto alone
    rec_w = resample_recording(
        simulate_dataset(n_subjects=1, duration_s=a.duration, pose="mixed", seed=7, pauses=True, modes=("walk",))[0],
        models["new"].sampling_rate_hz,
    )
    recs_v = {"plain": rec, "pauses": rec_p, "walk": rec_w}
    veto = {(r, v): np.inf for r in recs_v for v in ("on", "off")}
    n_vetoed: dict[str, tuple[int, int, int]] = {}
    n_win = {}
    with limit:
        for m in models.values():  # warm-up
            predict_recording(m, rec.slice(0, 1000))
        for _ in range(a.reps):
            for k, m in models.items():
                t0 = time.perf_counter()
                table = predict_recording(m, rec)
                best[k]["predict"] = min(best[k]["predict"], time.perf_counter() - t0)
                n_win[k] = len(table)
                ts, ns = stream_loop(rec, m)
                best[k]["stream"] = min(best[k]["stream"], ts / ns)
            t0 = time.perf_counter()
            off = predict_recording(models["new"], rec, run_min_cadence_hz=0.0)
            best_off = min(best_off, time.perf_counter() - t0)
            for r_name, r_rec in recs_v.items():
                for v_name, v in (("on", None), ("off", 0)):
                    t0 = time.perf_counter()
                    # the walk: the run-cadence rule off in both, so that the detector runs for the veto alone
                    cad = {"run_min_cadence_hz": 0.0} if r_name == "walk" else {}
                    vt = predict_recording(models["new"], r_rec, still_step_veto=v, **cad)
                    veto[(r_name, v_name)] = min(veto[(r_name, v_name)], time.perf_counter() - t0)
                    if v is None:
                        n_vetoed[r_name] = (int(vt["still"].sum()), int(vt["still_vetoed"].sum()), len(vt))
    print(f"| model | feature set | dynamics part | predict: windows per s ({a.duration:g} s recording) | stream: ms per window |")
    print("|---|---|---|---|---|")
    for k, m in models.items():
        dyn = "yes" if (m.domain is not None and m.domain.dynamics is not None) else "no"
        path = a.new if k == "new" else a.old
        print(
            f"| {k}: {path} | {m.feature_set} | {dyn} | {n_win[k] / best[k]['predict']:,.0f} ({1000 * best[k]['predict']:.0f} ms) "
            f"| {1000 * best[k]['stream']:.3f} |"
        )
    r_p = best["old"]["predict"] / best["new"]["predict"]
    r_s = best["old"]["stream"] / best["new"]["stream"]
    print(f"\nnew / old speed: predict {r_p:.2f}x, stream {r_s:.2f}x (best of {a.reps}, alternated, one BLAS thread)")
    moved = int(table["run_at_walking_cadence"].sum()) if "run_at_walking_cadence" in table else 0
    print(
        f"new model, run-cadence rule on / off: predict {best_off / best['new']['predict']:.2f}x the speed "
        f"({1000 * best['new']['predict']:.0f} vs {1000 * best_off:.0f} ms; {int((off['mode'] == 'run').sum())} windows "
        f"read run with it off, {moved} moved by it)"
    )
    what = {"plain": "as above", "pauses": "with pauses", "walk": "walking only, with pauses, run-cadence rule off in both"}
    for r_name in recs_v:
        on, off_v = veto[(r_name, "on")], veto[(r_name, "off")]
        k_still, k_vet, k_n = n_vetoed[r_name]
        print(
            f"new model, still gate's step veto on / off, recording {what[r_name]}: "
            f"predict {off_v / on:.2f}x the speed ({1000 * on:.0f} vs {1000 * off_v:.0f} ms; of {k_n} windows {k_still} still, "
            f"{k_vet} kept by the veto)"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
