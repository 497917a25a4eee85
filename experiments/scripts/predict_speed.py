"""Where the shipped model's ``predict`` and streaming time goes, and that a faster path changes no output (branch speed).

Five commands (experiments/reports/default-model.md, "Predict cost of the forward-vector model traced"):

- ``stages NEW OLD``: best-of-``--reps`` wall time of each stage of :func:`gaitml.models.predict_recording` (windows,
  the model's features, the SVM and the correction, the domain columns, the rest of the table: foot rule, still gate,
  step veto, run-cadence rule), both models on the recording of ``benchmarks.default_model`` (simulated, seed 7,
  600 s, 50 Hz), alternated, one BLAS thread; also how many windows hold a sample beyond the domain record's
  accelerometer range (the windows whose features the domain check reads differently from the classifier).
- ``dump OUT``: every output the speed work must leave unchanged, written to ``OUT`` (a pickle per model): for
  ``models/demo`` and ``models/demo-acc``, on the 36 tyrex Phoning / Texting walks (``GAITML_SHARED_DATA``) and
  simulated walks (hand-held, with pauses and every mode, at 50 and 100 Hz; and the same walk at 100 Hz without its
  gyroscope): the ``predict`` table whole, the table of 37 s chunks (:func:`gaitml.chunked_run.long_predict`), and
  the streaming path (the model's and the domain record's rows from :class:`gaitml.features.StreamingFeatureExtractor`,
  the SVM's answer and the domain check of each window); plus how often the ``adaptive`` step detector ran.
  Run it once with the code before and once after: for the code before, run this file by its path from a folder
  holding that code's ``gaitml`` (a checkout's folder on ``sys.path`` comes before ``PYTHONPATH`` with ``-m``).
- ``ab BASE NEW OLD``: ``benchmarks.default_model NEW OLD`` run in turn with this checkout's ``gaitml`` and with the
  one in the folder ``BASE`` (e.g. main before the change: ``git archive <commit> gaitml | tar -x -C BASE``), each in
  its own process, ``--rounds`` times alternated; prints every run's rows and the best ``predict`` speed and streaming
  latency of each model under each code (the ratio against ``OLD`` is the same-process figure; the ratio between the
  two codes compares best times of separate processes).
- ``forward BASE``: :func:`gaitml.features._forward.forward_vectors` of this checkout against the module of the same
  name in ``BASE`` (loaded from its file beside it, in the same process): one window of a 300-sample buffer (a
  stream's call) and every window of the 600 s recording, best of 9, one BLAS thread, and whether the rows are
  byte-identical.
- ``compare A B``: whether two dumps are byte-identical (every column's dtype and, for numbers, their bits; NaN
  equal to NaN), table by table, and the largest absolute difference where they are not.

    PYTHONPATH=$PWD python -m experiments.scripts.predict_speed stages models/demo /tmp/demo-old-model
    git archive <commit before> gaitml | tar -x -C /tmp/base
    (cd /tmp/base && PYTHONPATH=/tmp/base GAITML_SHARED_DATA=/work/shared/data python $OLDPWD/experiments/scripts/predict_speed.py dump /tmp/before)
    PYTHONPATH=$PWD GAITML_SHARED_DATA=/work/shared/data python -m experiments.scripts.predict_speed dump /tmp/after
    PYTHONPATH=$PWD python -m experiments.scripts.predict_speed compare /tmp/before /tmp/after
    PYTHONPATH=$PWD python -m experiments.scripts.predict_speed ab /tmp/base models/demo /tmp/demo-old-model
    PYTHONPATH=$PWD python -m experiments.scripts.predict_speed forward /tmp/base
"""

from __future__ import annotations

import argparse
import contextlib
import os
import pickle
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

#: The tyrex motions of the equality check (hand-held: the forward vector's face-up weight is not 0 there).
TYREX_MOTIONS = ("Phoning", "Texting")
#: The models whose outputs the equality check keeps (the shipped forward-vector model and the accelerometer-only one).
MODELS = ("models/demo", "models/demo-acc")
#: Chunk length (s) of the chunked path, as review5_checks.
CHUNK_S = 37.0


def _one_blas_thread():
    try:
        from threadpoolctl import threadpool_limits

        return threadpool_limits(limits=1, user_api="blas")
    except ImportError:  # pragma: no cover
        return contextlib.nullcontext()


def stages(new_path: str, old_path: str, reps: int, duration_s: float) -> pd.DataFrame:
    """The stage times (ms) of predict_recording for both models, best of ``reps``, alternated."""
    from gaitml.models import _predict as P
    from gaitml.models import load_model, resample_recording
    from gaitml.models._predict import domain_view
    from gaitml.simulate import simulate_dataset

    models = {"new": load_model(new_path), "old": load_model(old_path)}
    rec = resample_recording(simulate_dataset(n_subjects=1, duration_s=duration_s, pose="mixed", seed=7)[0], models["new"].sampling_rate_hz)
    best: dict = {}

    def timed(key, f):
        t0 = time.perf_counter()
        r = f()
        best[key] = min(best.get(key, np.inf), time.perf_counter() - t0)
        return r

    names = ("windows", "model features", "SVM + correction", "domain columns", "rest of the table", "predict_recording")
    with _one_blas_thread():
        for _ in range(reps):
            for k, m in models.items():
                w = timed((k, names[0]), lambda m=m: P._windows_for(rec, m.length_s, m.overlap))
                seen, tally = P.model_view(m, rec)
                X = timed((k, names[1]), lambda m=m, seen=seen, w=w: P.model_inputs(m, seen, w))
                out = w[["start", "end", "t_start_s", "t_end_s"]].copy()
                out["mode_raw"], out["mode"] = timed((k, names[2]), lambda m=m, X=X: P.predicted_modes(m, X, True))
                dom = timed((k, names[3]), lambda m=m, seen=seen, w=w, X=X: P.domain_columns(m, seen, w, X))
                timed(
                    (k, names[4]),
                    lambda m=m, out=out, w=w, dom=dom, X=X, tally=tally: P.finish_predictions(
                        out.copy(), w, dom, m, rec, rec, True, X=X, has_domain=True, acc_range=tally
                    ),
                )
                timed((k, names[5]), lambda m=m: P.predict_recording(m, rec))
    # the domain check and the SVM alone, on one window (a stream's) and on every window, in us per window
    extra = ("domain check, one window (us)", "domain check, per window of all (us)", "SVM, one window (us)", "SVM, per window of all (us)")
    inputs = {}
    for k, m in models.items():
        X = P.model_inputs(m, rec, P._windows_for(rec, m.length_s, m.overlap))
        inputs[k] = (X, np.tile([0.0, 0.0, 1.0], (len(X), 1)))
    with _one_blas_thread():
        for _ in range(reps):  # alternated, as the stages
            for k, m in models.items():
                X, g = inputs[k]
                calls = (
                    (extra[0], lambda m=m, X=X, g=g: m.domain.check(X[:1], g[:1]), 1, 300),
                    (extra[1], lambda m=m, X=X, g=g: m.domain.check(X, g), len(X), 3),
                    (extra[2], lambda m=m, X=X: m.estimator.predict(X[:1]), 1, 300),
                    (extra[3], lambda m=m, X=X: m.estimator.predict(X), len(X), 3),
                )
                for name, f, n_win, n_calls in calls:
                    t0 = time.perf_counter()
                    for _ in range(n_calls):
                        f()
                    best[(k, name)] = min(
                        best.get((k, name), np.inf), (time.perf_counter() - t0) / n_calls / n_win * 1e3
                    )  # shown x 1e3: us
    rows = [{"stage": s, "new (ms)": 1e3 * best[("new", s)], "old (ms)": 1e3 * best[("old", s)]} for s in (*names, *extra)]
    df = pd.DataFrame(rows)
    df["new - old (ms)"] = df["new (ms)"] - df["old (ms)"]
    dom = models["new"].domain
    if dom is not None and getattr(dom, "acc_range_ms2", None) is not None:
        _, clipped = domain_view(dom, rec)
        r = float(dom.acc_range_ms2)
        beyond = (np.abs(np.asarray(rec.acc)) > r).any(axis=1)
        w = P._windows_for(rec, models["new"].length_s, models["new"].overlap)
        cum = np.concatenate([[0], np.cumsum(beyond)])
        n_w = int(((cum[w["end"].to_numpy()] - cum[w["start"].to_numpy()]) > 0).sum())
        df.attrs["clipped"] = f"{int(beyond.sum())} of {len(beyond)} samples beyond +-{r:g} m/s^2, in {n_w} of {len(w)} windows"
    return df


def _recordings(data: Path | None) -> list[tuple[str, object]]:
    """(name, Recording as read) of the equality check: tyrex hand-held walks and simulated walks."""
    from gaitml.simulate import simulate_dataset

    out = []
    for fs in (50.0, 100.0):
        rec = simulate_dataset(n_subjects=1, duration_s=240.0, seed=7, pauses=True, pose="mixed", sampling_rate_hz=fs)[0]
        out.append((f"sim_{int(fs)}Hz", rec))
    out.append(("sim_100Hz_no_gyro", out[-1][1].replace(gyr=None)))
    if data is not None:
        from gaitml.io import read_segments
        from gaitml.pipeline.folder_source import tyrex_manifest

        root = data / "tyrex-attitude"
        man = tyrex_manifest(root)
        for row in man[man["motion"].isin(TYREX_MOTIONS)].to_dict("records"):
            segs = read_segments(root / row["file"])
            out.append((f"tyrex/{row['file']}", max(segs, key=lambda r: r.n_samples)))
    return out


def _stream(model, rec) -> dict:
    """The streaming path of ``model`` over ``rec`` (at the model's rate): rows, answers, domain checks."""
    from gaitml.features import StreamingFeatureExtractor
    from gaitml.models import resample_recording
    from gaitml.models.domain import feature_gravity

    rec = resample_recording(rec, model.sampling_rate_hz)
    gyro = "gyro" in model.feature_set
    if gyro and rec.gyr is None:
        return {}
    ext = StreamingFeatureExtractor.for_model(model)
    dom = model.domain
    ext_d = StreamingFeatureExtractor.for_domain(model) if dom is not None else None
    acc, gyr = np.asarray(rec.acc), None if rec.gyr is None else np.asarray(rec.gyr)
    hop = ext.hop_samples_
    rows, rows_d, answers, checks = [], [], [], []
    for i in range(0, len(acc), hop):
        a, g = acc[i : i + hop], (gyr[i : i + hop] if gyr is not None else None)
        r = ext.push(a, g) if gyro else ext.push(a)
        rows.append(r)
        if len(r):
            answers.append(np.asarray(model.estimator.predict(r)).astype(str))
        if ext_d is not None:
            rd = ext_d.push(a, g) if "gyro" in dom.feature_set else ext_d.push(a)
            rows_d.append(rd)
            if len(rd):
                res = dom.check(rd, feature_gravity(rd, dom.feature_names) if dom.gravity_check else None)
                checks.append(np.column_stack([res["distance"], res["in_domain"].astype(float), res["gravity_angle_rad"]]))
    cat = lambda xs: np.concatenate(xs) if xs else np.zeros(0)  # noqa: E731
    return {"rows": cat(rows), "rows_domain": cat(rows_d), "answers": cat(answers), "checks": cat(checks)}


def dump(out_dir: Path, data: Path | None) -> None:
    """Write every output of the equality check to ``out_dir`` (one pickle per model)."""
    import gaitml.steps.adaptive as adaptive
    from gaitml.chunked_run import long_predict
    from gaitml.models import load_model, predict_recording

    out_dir.mkdir(parents=True, exist_ok=True)
    root = Path(__file__).resolve().parents[2]
    recs = _recordings(data)
    runs = {"n": 0}
    real_detect = adaptive.AdaptiveStepDetector.detect

    def counting(self, *a, **k):
        runs["n"] += 1
        return real_detect(self, *a, **k)

    adaptive.AdaptiveStepDetector.detect = counting
    try:
        for mpath in MODELS:
            model = load_model(root / mpath)
            res = {}
            for name, rec in recs:
                if "gyro" in model.feature_set and rec.gyr is None:
                    continue
                runs["n"] = 0
                whole = predict_recording(model, rec)
                n_whole = runs["n"]
                runs["n"] = 0
                with tempfile.TemporaryDirectory() as tmp:
                    chunked = long_predict(model, Path(tmp) / "unused", recording=rec, chunk_s=CHUNK_S, progress=False)
                n_chunked = runs["n"]
                res[name] = {
                    "whole": whole,
                    "whole_attrs": repr(whole.attrs),
                    "chunked": chunked,
                    "chunked_attrs": repr(chunked.attrs),
                    "stream": _stream(model, rec),
                    "adaptive runs (whole, chunked)": (n_whole, n_chunked),
                }
            with open(out_dir / (Path(mpath).name + ".pkl"), "wb") as f:
                pickle.dump(res, f)
            tot = np.sum([v["adaptive runs (whole, chunked)"] for v in res.values()], axis=0)
            print(f"{mpath}: {len(res)} recordings; adaptive ran {tot[0]} times whole, {tot[1]} times chunked")
    finally:
        adaptive.AdaptiveStepDetector.detect = real_detect


def same_bits(a, b) -> tuple[bool, float]:
    """Whether ``a`` and ``b`` (DataFrames, dicts of them or arrays) are byte-identical (columns, index, dtypes and, for
    numbers, their bits; in object columns NaN equals NaN), and the largest absolute difference of their numbers."""
    if isinstance(a, pd.DataFrame):
        if list(a.columns) != list(b.columns) or len(a) != len(b) or not a.index.equals(b.index):
            return False, np.inf
        oks, diffs = (
            zip(*[same_bits(a[c].to_numpy(), b[c].to_numpy()) for c in a.columns], strict=True) if len(a.columns) else ((True,), (0.0,))
        )
        return all(oks), max(diffs)
    if isinstance(a, dict):
        if set(a) != set(b):
            return False, np.inf
        oks, diffs = zip(*[same_bits(a[k], b[k]) for k in a], strict=True) if a else ((True,), (0.0,))
        return all(oks), max(diffs)
    a, b = np.asarray(a), np.asarray(b)
    if a.dtype != b.dtype or a.shape != b.shape:
        return False, np.inf
    if a.dtype.kind == "f":
        same = a.tobytes() == b.tobytes()
        d = np.abs(a - b)
        return same, float(np.nanmax(d)) if d.size and not np.isnan(d).all() else 0.0
    if a.dtype.kind == "O":
        return all(
            (x is y) or (type(x) is type(y) and (x == y or (x != x and y != y))) for x, y in zip(a.ravel(), b.ravel(), strict=True)
        ), 0.0
    return a.tobytes() == b.tobytes(), 0.0


def compare(a_dir: Path, b_dir: Path) -> int:
    """Print, per model and output, how many recordings are byte-identical; return 1 when any is not."""
    bad = 0
    for f in sorted(a_dir.glob("*.pkl")):
        with open(f, "rb") as fa, open(b_dir / f.name, "rb") as fb:
            a, b = pickle.load(fa), pickle.load(fb)
        if set(a) != set(b):
            print(f"{f.stem}: the recordings differ")
            bad += 1
            continue
        for part in ("whole", "whole_attrs", "chunked", "chunked_attrs", "stream"):
            res = [(name, *same_bits(a[name][part], b[name][part])) for name in a]
            n_ok = sum(ok for _, ok, _ in res)
            worst = max(d for _, _, d in res)
            print(f"{f.stem:10s} {part:14s} identical in {n_ok} of {len(res)} recordings (largest abs difference {worst:.3g})")
            for name, ok, d in res:
                if not ok:
                    print(f"    differs: {name} ({d:.3g})")
            bad += n_ok != len(res)
        runs_a = np.sum([v["adaptive runs (whole, chunked)"] for v in a.values()], axis=0)
        runs_b = np.sum([v["adaptive runs (whole, chunked)"] for v in b.values()], axis=0)
        print(f"{f.stem:10s} adaptive runs (whole, chunked): {tuple(int(x) for x in runs_a)} -> {tuple(int(x) for x in runs_b)}")
        for name in a:
            ra, rb = a[name]["adaptive runs (whole, chunked)"], b[name]["adaptive runs (whole, chunked)"]
            if ra != rb:
                print(f"    {name}: {ra} -> {rb}")
    return 1 if bad else 0


def ab(base: Path, new: str, old: str, rounds: int, reps: int) -> pd.DataFrame:
    """Best ``predict`` windows per s and streaming ms per window of both models under this checkout's code and ``base``'s."""
    import re
    import subprocess

    here = Path(__file__).resolve().parents[2]
    codes = {"this checkout": here, "base": base.resolve()}
    best: dict = {}
    ratios: dict = {}
    for _ in range(rounds):
        for name, code in codes.items():
            # run from the code's own folder: a checkout's folder on sys.path comes before PYTHONPATH
            env = {**os.environ, "PYTHONPATH": f"{code}{os.pathsep}{here}"}
            cmd = [
                sys.executable,
                "-m",
                "benchmarks.default_model",
                str(Path(new).resolve()),
                str(Path(old).resolve()),
                "--reps",
                str(reps),
            ]
            out = subprocess.run(cmd, cwd=code, env=env, capture_output=True, text=True, check=True).stdout
            print(f"== {name} ({code})\n" + "\n".join(out.splitlines()[:6]), flush=True)
            for line in out.splitlines():
                r = re.match(r"new / old speed: predict ([\d.]+)x, stream ([\d.]+)x", line)
                if r:
                    ratios.setdefault(name, []).append((float(r.group(1)), float(r.group(2))))
                m = re.match(r"\| (new|old): .*\| ([\d,]+) \(\d+ ms\) \| ([\d.]+) \|$", line)
                if m:
                    key = (name, m.group(1))
                    p, st = float(m.group(2).replace(",", "")), float(m.group(3))
                    b = best.get(key, (0.0, np.inf))
                    best[key] = (max(b[0], p), min(b[1], st))
    rows = [{"code": c, "model": k, "predict (windows per s)": v[0], "stream (ms per window)": v[1]} for (c, k), v in best.items()]
    df = pd.DataFrame(rows)
    df.attrs["ratios"] = {
        c: "new / old of each run (same process): predict "
        + ", ".join(f"{p:.2f}" for p, _ in r)
        + f" (median {np.median([p for p, _ in r]):.2f}); stream "
        + ", ".join(f"{st:.2f}" for _, st in r)
        + f" (median {np.median([st for _, st in r]):.2f})"
        for c, r in ratios.items()
    }
    return df


def forward_ab(base: Path, duration_s: float = 600.0) -> pd.DataFrame:
    """The forward vector's time (us per window) in this checkout and in ``base``'s module, one process."""
    import importlib.util

    from gaitml.features import _forward as here
    from gaitml.models import resample_recording
    from gaitml.simulate import simulate_dataset

    spec = importlib.util.spec_from_file_location("base_forward", base / "gaitml" / "features" / "_forward.py")
    old = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(old)
    acc = np.ascontiguousarray(resample_recording(simulate_dataset(n_subjects=1, duration_s=duration_s, pose="mixed", seed=7)[0], 50.0).acc)
    length = 75
    starts = np.arange(0, len(acc) - length, 37)

    def best(f, n):
        f()
        out = np.inf
        for _ in range(9):
            t0 = time.perf_counter()
            for _ in range(n):
                f()
            out = min(out, (time.perf_counter() - t0) / n)
        return out

    rows = []
    with _one_blas_thread():
        for name, m in (("base", old), ("this checkout", here)):
            one = best(lambda m=m: m.forward_vectors(acc[900:1200], 50.0, np.array([100]), length, face_up=True), 2000)
            every = best(lambda m=m: m.forward_vectors(acc, 50.0, starts, length, face_up=True), 10)
            rows.append({"code": name, "one window (us)": 1e6 * one, f"{len(starts)} windows (us each)": 1e6 * every / len(starts)})
    df = pd.DataFrame(rows)
    a = old.forward_vectors(acc, 50.0, starts, length, face_up=True)
    b = here.forward_vectors(acc, 50.0, starts, length, face_up=True)
    one_a = np.vstack([old.forward_vectors(acc, 50.0, starts[i : i + 1], length, face_up=True) for i in range(len(starts))])
    one_b = np.vstack([here.forward_vectors(acc, 50.0, starts[i : i + 1], length, face_up=True) for i in range(len(starts))])
    df.attrs["identical"] = (
        f"batch rows byte-identical: {a.tobytes() == b.tobytes()}; single-window rows: {one_a.tobytes() == one_b.tobytes()}"
    )
    return df


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    s = sub.add_parser("stages")
    s.add_argument("new")
    s.add_argument("old")
    s.add_argument("--reps", type=int, default=7)
    s.add_argument("--duration", type=float, default=600.0)
    b = sub.add_parser("ab")
    b.add_argument("base", type=Path)
    b.add_argument("new")
    b.add_argument("old")
    b.add_argument("--rounds", type=int, default=3)
    b.add_argument("--reps", type=int, default=3)
    f = sub.add_parser("forward")
    f.add_argument("base", type=Path)
    d = sub.add_parser("dump")
    d.add_argument("out", type=Path)
    c = sub.add_parser("compare")
    c.add_argument("a", type=Path)
    c.add_argument("b", type=Path)
    a = ap.parse_args(argv)
    if a.cmd == "stages":
        df = stages(a.new, a.old, a.reps, a.duration)
        print("| " + " | ".join(df.columns) + " |\n|" + "---|" * len(df.columns))
        for r in df.itertuples(index=False):
            print(f"| {r[0]} | " + " | ".join(f"{v:.2f}" for v in r[1:]) + " |")
        if "clipped" in df.attrs:
            print(f"\n{a.duration:g} s recording: {df.attrs['clipped']} (domain record's range)")
        return 0
    if a.cmd == "ab":
        df = ab(a.base, a.new, a.old, a.rounds, a.reps)
        print("\nbest over the rounds:\n" + df.to_string(index=False))
        for c, line in df.attrs["ratios"].items():
            print(f"{c}: {line}")
        return 0
    if a.cmd == "forward":
        df = forward_ab(a.base)
        print(df.to_string(index=False, float_format=lambda v: f"{v:.1f}"))
        print(df.attrs["identical"])
        return 0
    if a.cmd == "dump":
        env = os.environ.get("GAITML_SHARED_DATA")
        data = Path(env) if env and (Path(env) / "tyrex-attitude").is_dir() else None
        if data is None:
            print("GAITML_SHARED_DATA is not set or holds no tyrex-attitude: simulated walks only", file=sys.stderr)
        dump(a.out, data)
        return 0
    return compare(a.a, a.b)


if __name__ == "__main__":
    raise SystemExit(main())
