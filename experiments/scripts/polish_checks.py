"""Figures of experiments/reports/polish.md: four small fixes checked on synthetic inputs and the shared data.

1. ``steps --json`` read in chunks: its per-window ``cadence`` against the whole-file run's (chunks of 20 s,
   margins of 10 s) at 100, 50 and 110 Hz.
2. (schema only; no figure)
3. The acc unit check on simulated feet (run, walk; seeds 0-9, 100-119) at 100 Hz and resampled to 50 Hz: in
   m/s^2, in g and in milli-g; and every shared recording read (still accepted).
4. Rate changes placed by :func:`gaitml.recording.timestamps.judge_rate` on synthetic timestamps.
5. Gait-check account (adaptive), whole file vs chunks of 20 s with margins of 2, 5, 10 s.

Nothing is fitted: the unit thresholds are physical bounds (docstrings of gaitml.recording.units).

    python -m experiments.scripts.polish_checks [--cache /tmp/polish]
"""

from __future__ import annotations

import argparse
import glob
import os
import warnings
from pathlib import Path

import numpy as np
import pandas as pd


def cadence_rows(cache: Path) -> list[list]:
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording, write_gaitml_csv
    from gaitml.simulate import simulate_dataset
    from gaitml.steps import get_detector

    rows = []
    for seed, dur, fs in [(5, 60.0, 100.0), (3, 90.0, 50.0), (7, 90.0, 110.0)]:
        p = cache / f"cad{seed}_{fs:g}.csv"
        if not p.exists():
            write_gaitml_csv(simulate_dataset(1, dur, sampling_rate_hz=fs, seed=seed, pose="mixed")[0], p)
        whole = get_detector("adaptive").detect(read_recording(p)).cadence_
        c = pd.DataFrame(long_steps(p, "adaptive", chunk_s=20.0, margin_s=10.0, progress=False, keep_cadence=True).attrs["cadence"])
        same = len(c) == len(whole) and np.allclose(c["t_s"], whole["t_s"], atol=1e-9)
        d_cad = float(np.max(np.abs(c["cadence_hz"] - whole["cadence_hz"]))) if same else float("nan")
        d_per = float(np.max(np.abs(c["periodicity"] - whole["periodicity"]))) if same else float("nan")
        rows.append([fs, len(whole), len(c), same, d_cad, d_per])
    return rows


def foot_units() -> dict:
    from gaitml.errors import InputError
    from gaitml.models import resample_recording
    from gaitml.recording import Recording
    from gaitml.simulate.foot import simulate_foot

    n = refused = g_ok = mg_ok = 0
    meds, lows = [], []
    for mode in ("run", "walk"):
        for s in list(range(10)) + list(range(100, 120)):
            r = simulate_foot(modes=(mode,), duration_s=60.0, sampling_rate_hz=100.0, seed=s)
            try:
                q = resample_recording(r, 50.0)
            except InputError:
                refused += 1
                continue
            for x in (r, q):
                n += 1
                m = np.linalg.norm(x.acc, axis=1)
                meds.append(float(np.median(m)))
                lows.append(float(np.percentile(m, 5)))
                for scale, what in ((1.0, "ms2"), (1 / 9.80665, "g"), (1000 / 9.80665, "mg")):
                    try:
                        Recording(acc=x.acc * scale, sampling_rate_hz=x.sampling_rate_hz)
                    except InputError:
                        refused += what == "ms2"
                        continue
                    g_ok += what == "g"
                    mg_ok += what == "mg"
    return {
        "n": n,
        "ms2_refused": refused,
        "g_accepted": g_ok,
        "mg_accepted": mg_ok,
        "median": (min(meds), max(meds)),
        "p5": (min(lows), max(lows)),
    }


def shared_reads() -> tuple[int, int]:
    from gaitml.io import read_recording

    d = os.environ.get("GAITML_SHARED_DATA", "/work/shared/data")
    paths = (
        sorted(glob.glob(f"{d}/gaitmap-example/imu_sample*.csv.gz"))
        + sorted(glob.glob(f"{d}/ifsm-flat-phone/*.xlsx"))
        + sorted(glob.glob(f"{d}/tyrex-attitude/android/*"))
        + sorted(glob.glob(f"{d}/tyrex-attitude/ios/*"))
        + sorted(glob.glob(f"{d}/oxford-step-counter/optimisation/data/*"))
    )
    unit_refusals = 0
    for p in paths:
        try:
            read_recording(p)
        except Exception as exc:  # noqa: BLE001 - counted by kind below
            unit_refusals += "m/s^2" in str(exc) or "in g" in str(exc)
    return len(paths), unit_refusals


def rate_rows() -> list[list]:
    from gaitml.recording.timestamps import judge_rate

    def steps(*parts):
        return np.concatenate([a + np.arange(round((b - a) * fs)) / fs for a, b, fs in parts])

    cases = [
        ("100 Hz, 50 Hz from 30 s", steps((0, 30, 100), (30, 60, 50))),
        ("50 Hz to 30 s, then 100 Hz", steps((0, 30, 50), (30, 90, 100))),
        ("100 Hz, 50 Hz from 20 to 40 s", steps((0, 20, 100), (20, 40, 50), (40, 80, 100))),
        ("ms clock: 400 Hz, 200 Hz from 30 s", np.floor(steps((0, 30, 400), (30, 60, 200)) * 1000) / 1000),
        ("ms clock: 400 Hz throughout", np.floor(np.arange(40_000) / 400 * 1000) / 1000),
    ]
    return [[name, round(judge_rate(t)["rate_hz"], 3), judge_rate(t)["rate_changes"]] for name, t in cases]


def bout_rows(cache: Path) -> list[list]:
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording, write_gaitml_csv
    from gaitml.simulate import simulate_dataset
    from gaitml.simulate.nongait import simulate_nongait
    from gaitml.steps import get_detector

    rows = []
    for kind, seed in [("gestures", s) for s in (100, 101, 102, 103)] + [("walk", s) for s in (3, 4)]:
        p = cache / f"{kind}{seed}.csv"
        if not p.exists():
            rec = (
                simulate_nongait("gestures", seed=seed)
                if kind == "gestures"
                else simulate_dataset(1, 120.0, sampling_rate_hz=50.0, seed=seed)[0]
            )
            write_gaitml_csv(rec, p)
        w = get_detector("adaptive").detect(read_recording(p)).steps_.attrs["gait_check"]
        for margin in (2.0, 5.0, 10.0):
            c = long_steps(p, "adaptive", chunk_s=20.0, margin_s=margin, progress=False).attrs["gait_check"]
            key = ("n_bouts", "n_bouts_rejected", "n_steps_rejected")
            rows.append([kind, seed, margin, [w[k] for k in key], [c[k] for k in key]])
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cache", default="/tmp/polish")
    a = ap.parse_args()
    cache = Path(a.cache)
    cache.mkdir(parents=True, exist_ok=True)
    warnings.filterwarnings("ignore")
    print("## 1. cadence: rate, whole windows, chunked windows, same times, max |d cadence_hz|, max |d periodicity|")
    for r in cadence_rows(cache):
        print(r, flush=True)
    print("## 3. simulated feet:", foot_units(), flush=True)
    print("## 3. shared recordings read, refused for a unit:", shared_reads(), flush=True)
    print("## 4. rate changes: case, rate_hz, rate_changes")
    for r in rate_rows():
        print(r, flush=True)
    print("## 5. gait-check account: file, seed, margin_s, whole [bouts, rejected bouts, rejected steps], chunked")
    for r in bout_rows(cache):
        print(r, flush=True)


if __name__ == "__main__":
    main()
