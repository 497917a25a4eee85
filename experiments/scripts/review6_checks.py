"""Review checks of the stillflag, bouts and truth changes (branch review6; experiments/reports/review6.md).

Every figure of the report's "checked" list, from the library as it is:

- ``steps BASE``: ``adaptive``'s step tables at its defaults, and with the veto's swing stage (0.3), are byte-identical
  between the library in BASE (a folder holding the ``gaitml`` package of the commit before the bouts merge, e.g.
  ``git archive d134309 gaitml | tar -x -C BASE``) and this tree: every 5th tyrex recording's segments, three Oxford
  recordings, two simulated walks with pauses. Each tree runs in its own process.
- ``reader``: ``still_unsure`` computed from the JSON export's words alone (the plain-numpy reader of
  tests/models/test_persist.py) against ``predict_recording`` (``models/demo``) on three simulated ear walks and six tyrex
  Phoning / Texting recordings; beside it, a literal reading of the export's words before review6 (full rate, the
  strongest peak, no step-range check).
- ``rate25``: a small model trained at 25 Hz (chunks then start on multiples of 475 samples, odd ones too): whole
  against chunked (40 and 60 s) ``still_unsure`` on six simulated three-walk files and on the tyrex Phoning / Texting
  recordings.
- ``perf``: ``predict_recording`` on a phone lying still (every window still) for 600 s and 3600 s, the mark on and off
  (ms per 600 s; the first run includes warm-up).

    cd /work/wt-review6; export PYTHONPATH=$PWD GAITML_SHARED_DATA=/work/shared/data
    python -m experiments.scripts.review6_checks reader rate25 perf
    python -m experiments.scripts.review6_checks steps /tmp/base   # after git archive d134309 gaitml | tar -x -C /tmp/base
"""

from __future__ import annotations

import argparse
import hashlib
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
TYREX = "tyrex-attitude/android"


def data_dir() -> Path:
    return Path(os.environ.get("GAITML_SHARED_DATA", "/work/shared/data"))


def step_tables(out_dir: str) -> list[str]:
    """Write adaptive's step tables (defaults; swing stage 0.3 with a gyroscope) of the fixed recordings to ``out_dir``;
    one line per table: name, setting, steps, sha1 of the CSV."""
    from gaitml.io import read_recording, read_segments
    from gaitml.simulate import Subject
    from gaitml.simulate.dataset import simulate_recording
    from gaitml.steps.adaptive import AdaptiveStepDetector

    recs = []
    for f in sorted((data_dir() / TYREX).iterdir())[::5]:
        recs += [(f"{f.name}_{i}", r) for i, r in enumerate(read_segments(f))]
    recs += [(f.name, read_recording(f)) for f in sorted((data_dir() / "oxford-step-counter/optimisation/data").iterdir())[:3]]
    recs += [(f"sim_pauses_{s}", simulate_recording(Subject(), duration_s=300.0, pauses=True, seed=s)) for s in (0, 1)]
    lines = []
    for name, rec in recs:
        for tag, kw in (("default", {}), ("swing0.3", {"gyro_swing_min_periodicity": 0.3})):
            if kw and rec.gyr is None:
                continue
            csv = AdaptiveStepDetector(**kw).detect(rec).steps_.to_csv(index=False, float_format="%.17g")
            Path(out_dir, f"{name}_{tag}.csv").write_text(csv)
            lines.append(f"{name} {tag} {csv.count(chr(10)) - 1} {hashlib.sha1(csv.encode()).hexdigest()[:12]}")
    return lines


def check_steps(base: str) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        got = {}
        for tag, tree in (("base", base), ("this tree", str(ROOT))):
            out = Path(tmp, tag.replace(" ", "_"))
            out.mkdir()
            env = {**os.environ, "PYTHONPATH": tree}
            code = (
                "import gaitml; from experiments.scripts.review6_checks import step_tables; "
                f"print(gaitml.__file__); print(chr(10).join(step_tables({str(out)!r})))"
            )
            # the base tree is first on the path; this tree's experiments package is found from its own folder
            run = subprocess.run([sys.executable, "-c", f"import sys; sys.path.append({str(ROOT)!r}); {code}"], env=env,
                                 capture_output=True, text=True, cwd=tmp, check=True)  # fmt: skip
            where, *got[tag] = run.stdout.rstrip("\n").split("\n")
            print(f"{tag}: gaitml from {where}")
        same = got["base"] == got["this tree"]
        print(f"step tables: {len(got['base'])} (base) / {len(got['this tree'])} (this tree); identical: {same}")
        for a, b in zip(got["base"], got["this tree"], strict=False):
            if a != b:
                print(f"  differs: {a} | {b}")


def literal_old_words(spec: dict, gyr, starts, length: int, labels) -> np.ndarray:
    """The mark as the export's words before review6 read literally: the 5 s at the full rate (no decimation), the
    strongest autocorrelation peak over the stride lags, r at P / 2 rounded down, no check that P / 2 is a step."""
    import scipy.signal

    u = spec["postprocess"]["still"]["unsure"]
    fs, n = float(spec["sampling_rate_hz"]), len(gyr)
    S, pad = int(round(u["window_s"] * fs)), int(round(u["pad_s"] * fs))
    sos = scipy.signal.butter(2, u["band_hz"], btype="bandpass", fs=fs, output="sos")
    lags = np.arange(int(2 * fs / u["step_hz"][1]), int(np.ceil(2 * fs / u["step_hz"][0])) + 1)
    out = np.zeros(len(starts), dtype=bool)
    for w in np.flatnonzero(np.asarray(labels) == "still"):
        a = int(np.clip(round(starts[w] + length / 2 - S / 2), 0, n - S))
        lo, hi = max(a - pad, 0), min(a + S + pad, n)
        x = scipy.signal.sosfiltfilt(sos, gyr[lo:hi] - gyr[lo:hi].mean(0), axis=0)[a - lo : a - lo + S]
        x = x @ np.linalg.eigh(x.T @ x)[1][:, -1]
        if np.sqrt(np.mean(x**2)) < u["min_rms_rads"]:
            continue

        def r(k, x=x):
            return float(np.sum(x[: S - k] * x[k:]) / np.sqrt(np.sum(x[: S - k] ** 2) * np.sum(x[k:] ** 2)))

        rk = np.array([r(int(k)) for k in lags])
        peaks = [i for i in range(1, len(lags) - 1) if rk[i] >= rk[i - 1] and rk[i] > rk[i + 1]]
        if peaks:
            i = max(peaks, key=lambda i: rk[i])
            out[w] = rk[i] >= u["min_periodicity"] and r(int(lags[i]) // 2) <= u["max_half_correlation"]
    return out


def tyrex_recordings(motions=("Phoning", "Texting"), per_motion: int | None = None) -> list:
    from gaitml.io import read_segments

    recs = []
    for motion in motions:
        folders = sorted(f for f in (data_dir() / TYREX).iterdir() if f.name.endswith("_" + motion))
        recs += [max(read_segments(f), key=lambda r: r.n_samples) for f in folders[:per_motion]]
    return recs


def check_reader() -> None:
    import json

    from gaitml.models import load_model, predict_recording, resample_recording
    from gaitml.models._export import input_spec
    from tests.models.test_persist import _still_unsure_from_json
    from tests.models.test_still_veto_swing import ear_walk

    model = load_model(ROOT / "models" / "demo")
    spec = json.loads(json.dumps(input_spec(model)))
    recs = [ear_walk(s, seconds=40.0, stand_s=20.0)[0] for s in range(3)]
    recs += tyrex_recordings(("Phoning",), 4) + tyrex_recordings(("Texting",), 2)
    n_still = marked = exact = literal = 0
    for rec in recs:
        rec = resample_recording(rec, spec["sampling_rate_hz"])
        t = predict_recording(model, rec)
        starts, length, labels = t["start"].to_numpy(), spec["window"]["length_samples"], t["mode"].to_numpy()
        m = t["still_unsure"].to_numpy(bool)
        n_still += int(t["still"].sum())
        marked += int(m.sum())
        exact += int((_still_unsure_from_json(spec, rec.gyr, starts, length, labels) != m).sum())
        literal += int((literal_old_words(spec, rec.gyr, starts, length, labels) != m).sum())
    print(
        f"export reader: {len(recs)} recordings, {n_still} still windows, {marked} marked by predict; the reader of the "
        f"export's words differs in {exact}; a literal reading of the words before review6 in {literal}"
    )


def check_rate25() -> None:
    from gaitml.chunked_run import long_predict
    from gaitml.cli import main
    from gaitml.io import read_recording, write_gaitml_csv
    from gaitml.models import load_model, predict_recording, resample_recording
    from gaitml.recording import Recording
    from tests.models.test_still_veto_swing import ear_walk

    cfg = (
        'name = "review6-25hz"\nseed = 4\n[data]\nsource = "simulated"\nresample_hz = 25.0\n[data.simulated]\n'
        'subjects = 3\nduration_s = 40.0\n[features]\nset = "all52+gyro"\n[train]\ncross_validate = false\n'
    )
    with tempfile.TemporaryDirectory() as tmp:
        Path(tmp, "cfg.toml").write_text(cfg)
        assert main(["train", str(Path(tmp, "cfg.toml")), "--out", str(Path(tmp, "model"))]) == 0
        model = load_model(Path(tmp, "model"))
        paths = []
        for seed in range(6):
            parts = [ear_walk(seed * 3 + k, seconds=60.0, stand_s=20.0)[0] for k in range(3)]
            rec = Recording(acc=np.vstack([r.acc for r in parts]), gyr=np.vstack([r.gyr for r in parts]), sampling_rate_hz=50.0)
            paths.append(Path(tmp, f"ear{seed}.csv"))
            write_gaitml_csv(resample_recording(rec, 25.0), paths[-1])
        tyrex = [f for f in sorted((data_dir() / TYREX).iterdir()) if f.name.endswith(("_Phoning", "_Texting"))]
        for label, files in (("simulated three-walk files", paths), ("tyrex Phoning / Texting", tyrex)):
            for chunk_s in (40.0, 60.0):
                n = mk = differ = 0
                for f in files:
                    whole = predict_recording(model, read_recording(f))
                    chunked = long_predict(model, f, chunk_s=chunk_s, progress=False)
                    n, mk = n + len(whole), mk + int(whole["still_unsure"].sum())
                    differ += int((whole["still_unsure"].to_numpy() != chunked["still_unsure"].to_numpy()).sum())
                print(f"25 Hz model, {label}, {chunk_s:g} s chunks: {n} windows, {mk} marked, {differ} differ")


def check_perf() -> None:
    import gaitml.models._predict as P
    from gaitml.models import load_model, predict_recording
    from gaitml.recording import Recording

    model = load_model(ROOT / "models" / "demo")
    default = P.STILL_UNSURE_DEFAULT
    try:
        for seconds in (600, 3600):
            n, rng = int(seconds * 50), np.random.default_rng(0)
            acc = np.tile([0.0, 0.0, 9.81], (n, 1)) + rng.normal(0, 0.01, (n, 3))
            rec = Recording(acc=acc, gyr=rng.normal(0, 0.005, (n, 3)), sampling_rate_hz=50.0)
            for on in (True, False):
                P.STILL_UNSURE_DEFAULT = on
                t0 = time.perf_counter()
                t = predict_recording(model, rec)
                ms = (time.perf_counter() - t0) * 1000 * 600 / seconds
                print(f"phone lying still {seconds} s, mark {'on' if on else 'off'}: {ms:.0f} ms per 600 s ({int(t['still'].sum())} still)")
    finally:
        P.STILL_UNSURE_DEFAULT = default


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("checks", nargs="+", help="reader, rate25, perf, or steps BASE (the base tree's folder)")
    args = ap.parse_args(argv)
    todo = list(args.checks)
    while todo:
        name = todo.pop(0)
        if name == "steps":
            check_steps(todo.pop(0))
        else:
            {"reader": check_reader, "rate25": check_rate25, "perf": check_perf}[name]()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
