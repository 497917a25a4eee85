"""Second review of the still gate's step veto: the checks behind experiments/reports/still-gate.md, "Second review".

``python -m experiments.scripts.still_veto_review [--data ../shared/data] [--only chunks,stepwin,pdr,speed]`` from the
repository root. Nothing is fitted; every check compares two runs of the library:

- ``chunks``: the tyrex Phoning and AR walks (motion capture present; the longest segment of each), written as
  gaitml-csv at their own rate and taken down to 20 Hz, predicted whole (:func:`gaitml.models.predict_recording`) and
  in chunks of 13 s and 47 s (:func:`gaitml.chunked_run.long_predict`, chunk sizes the stillsteps round did not try):
  windows whose ``still``, ``still_vetoed``, ``still_unsure``, ``mode``, ``mode_raw`` differ.
- ``stepwin``: a step-window model (the recipe of tests/stepwin/conftest.py: IFSM steps, simulated hand-held phones)
  on the calm walker of tests/models/test_still_step_veto.py (seeds 0-2): of the step windows the statistic reads
  still, how many the default veto (>= 2 steps) keeps.
- ``pdr``: :func:`gaitml.pdr.run_pdr` with ``models/demo`` on the tyrex Phoning walks with the veto on and off
  (``STILL_STEP_VETO_DEFAULT``): steps whose mode differs, the largest position difference, the time (best of 3) and
  how often predict runs the detector.
- ``speed``: :func:`~gaitml.chunked_run.long_predict` of a 1 h simulated walk with no pause (no window reads still),
  as a 50 Hz and as a 20 Hz gaitml-csv, the veto on and off (run-cadence rule off in both), best of 3.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

__all__ = ["differing", "main"]

COLUMNS = ("still", "still_vetoed", "still_unsure", "mode", "mode_raw")


def differing(a, b, columns=COLUMNS) -> dict[str, int]:
    """Per column, the number of rows whose values differ between the tables ``a`` and ``b`` (same length, same windows)."""
    if len(a) != len(b):
        raise ValueError(f"the tables differ in length ({len(a)} vs {len(b)}): the windows are not the same")
    return {c: int((a[c].to_numpy() != b[c].to_numpy()).sum()) for c in columns}


def _tyrex(data: Path, motions) -> list:
    from gaitml.io import read_segments
    from gaitml.pipeline.folder_source import tyrex_manifest

    root = data / "tyrex-attitude"
    man = tyrex_manifest(root)
    rows = man[(man["truth"] != "") & (man["motion"].isin(list(motions)))].to_dict("records")
    return [(row["motion"], max(read_segments(root / row["file"]), key=lambda r: r.duration_s)) for row in rows]


def check_chunks(data: Path, model) -> None:
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv
    from gaitml.models import predict_recording, resample_recording

    tot: dict = {}
    for motion, rec in _tyrex(data, ("Phoning", "AR")):
        for rate in (None, 20.0):
            r = rec if rate is None else resample_recording(rec, rate)
            with tempfile.TemporaryDirectory() as d:
                p = Path(d) / "r.csv"
                write_gaitml_csv(r, p)
                whole = predict_recording(model, read_recording(p))
                for chunk_s in (13.0, 47.0):
                    diff = differing(whole, long_predict(model, p, chunk_s=chunk_s, progress=False))
                    a = tot.setdefault(
                        (motion, "own rate" if rate is None else "20 Hz", chunk_s),
                        dict.fromkeys(("windows", "vetoed", "marked", *COLUMNS), 0),
                    )
                    a["windows"] += len(whole)
                    a["vetoed"] += int(whole["still_vetoed"].sum())
                    a["marked"] += int(whole["still_unsure"].sum())
                    for c, n in diff.items():
                        a[c] += n
    print(
        "\n| motion | recorded at | chunk (s) | windows | vetoed (whole) | still_unsure (whole) | still differs | still_vetoed differs "
        "| still_unsure differs | mode differs | mode_raw differs |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for (motion, rate, chunk_s), a in tot.items():
        print(
            f"| {motion} | {rate} | {chunk_s:g} | {a['windows']} | {a['vetoed']} | {a['marked']} | {a['still']} | {a['still_vetoed']} "
            f"| {a['still_unsure']} | {a['mode']} | {a['mode_raw']} |"
        )


def check_stepwin() -> None:
    from gaitml.cli import main as cli
    from gaitml.models import load_model, predict_step_windows
    from tests.models.test_still_step_veto import calm_walker
    from tests.stepwin.conftest import STEP_MODEL_CONFIG

    with tempfile.TemporaryDirectory() as d:
        (Path(d) / "cfg.toml").write_text(STEP_MODEL_CONFIG)
        assert cli(["train", str(Path(d) / "cfg.toml"), "--out", str(Path(d) / "model")]) == 0
        model = load_model(Path(d) / "model")
        print(
            "\n| calm walker seed | step windows | read still by the statistic | kept by the default veto | steps per still-read window (0/1/2/3+) |"
        )
        print("|---|---|---|---|---|")
        for seed in (0, 1, 2):
            rec = calm_walker(40.0, seed=seed)
            gate = predict_step_windows(model, rec, still_step_veto=0)
            t = predict_step_windows(model, rec)
            k = np.clip(t["window_steps"].dropna().to_numpy(float), 0, 3).astype(int)  # counted where the statistic reads still
            print(
                f"| {seed} | {len(t)} | {int(gate['still'].sum())} | {int(t['still_vetoed'].sum())} | {'/'.join(str(int(x)) for x in np.bincount(k, minlength=4))} |"
            )


def check_pdr(data: Path, model) -> None:
    import gaitml.models._predict as P
    from gaitml.pdr import run_pdr

    recs = [r for _, r in _tyrex(data, ("Phoning",))]
    real, calls = P.recording_steps, [0]

    def counting(rec, swing_periodicity=0.0):  # the veto's steps (swing stage) and the run-cadence rule's, each counted
        calls[0] += 1
        return real(rec, swing_periodicity)

    default = P.STILL_STEP_VETO_DEFAULT
    best, runs, res = {}, {}, {}
    P.recording_steps = counting
    try:
        for _ in range(3):
            for name, v in (("on", P.STILL_STEP_VETO_MIN_STEPS), ("off", None)):
                P.STILL_STEP_VETO_DEFAULT = v
                calls[0] = 0
                t0 = time.perf_counter()
                res[name] = [run_pdr(r, model=model, modes="model") for r in recs]
                best[name] = min(best.get(name, np.inf), time.perf_counter() - t0)
                runs[name] = calls[0]
    finally:
        P.recording_steps, P.STILL_STEP_VETO_DEFAULT = real, default
    n_steps = sum(len(a.steps) for a in res["on"])
    n_diff = sum(int((a.steps["mode"].to_numpy() != b.steps["mode"].to_numpy()).sum()) for a, b in zip(res["on"], res["off"], strict=True))
    dxy = max(
        float(np.max(np.abs(a.trajectory[["x_m", "y_m"]].to_numpy() - b.trajectory[["x_m", "y_m"]].to_numpy())))
        for a, b in zip(res["on"], res["off"], strict=True)
    )
    print(
        f"\npdr --model, {len(recs)} tyrex Phoning walks ({sum(r.duration_s for r in recs):.0f} s): {n_steps} steps, {n_diff} with another "
        f"mode, largest position difference {dxy:.3g} m; time veto on / off {best['on']:.2f} / {best['off']:.2f} s "
        f"({best['on'] / best['off']:.2f}x); predict ran the detector in {runs['on']} / {runs['off']} recordings"
    )


def check_speed(model) -> None:
    from gaitml.chunked_run import long_predict
    from gaitml.io import write_gaitml_csv
    from gaitml.models import resample_recording
    from gaitml.recording import Recording
    from gaitml.simulate import simulate_dataset

    base = simulate_dataset(1, 600.0, sampling_rate_hz=50.0, seed=7, pose="mixed", modes=("walk",))[0]
    rec = Recording(acc=np.vstack([base.acc] * 6), gyr=np.vstack([base.gyr] * 6), sampling_rate_hz=50.0)
    print("\n| 1 h walk, no pause, recorded at | veto off (s) | veto on (s) | on / off | windows still / vetoed |")
    print("|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as d:
        for rate in (50.0, 20.0):
            p = Path(d) / f"walk{rate:g}.csv"
            write_gaitml_csv(rec if rate == 50.0 else resample_recording(rec, rate), p)
            best = {}
            for _ in range(3):
                for name, kw in (("off", {"still_step_veto": 0}), ("on", {})):
                    t0 = time.perf_counter()
                    t = long_predict(model, p, progress=False, run_min_cadence_hz=0, **kw)
                    best[name] = min(best.get(name, np.inf), time.perf_counter() - t0)
            print(
                f"| {rate:g} Hz | {best['off']:.2f} | {best['on']:.2f} | {best['on'] / best['off']:.2f} | "
                f"{int(t['still'].sum())} / {int(t['still_vetoed'].sum())} |"
            )


def main(argv=None) -> int:
    from gaitml.models import load_model

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--model", default="models/demo")
    ap.add_argument("--only", default="chunks,stepwin,pdr,speed")
    a = ap.parse_args(argv)
    only = set(a.only.split(","))
    try:
        from threadpoolctl import threadpool_limits

        threadpool_limits(1)  # timings on one BLAS thread, as benchmarks/default_model.py
    except ImportError:
        pass
    model = load_model(a.model)
    t0 = time.perf_counter()
    if "chunks" in only:
        check_chunks(a.data, model)
    if "stepwin" in only:
        check_stepwin()
    if "pdr" in only:
        check_pdr(a.data, model)
    if "speed" in only:
        check_speed(model)
    print(f"[still_veto_review] done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
