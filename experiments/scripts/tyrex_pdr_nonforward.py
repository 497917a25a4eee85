"""Which steps ``gaitml pdr --model`` moves sideways or backward on tyrex, and what they cost (nobody in tyrex steps that way).

``python -m experiments.scripts.tyrex_pdr_nonforward --cache FILE --fold-models DIR [--data ../shared/data] [--csv FILE] [--out FILE]``
from the repository root. ``--cache`` is :mod:`experiments.scripts.tyrex_pdr_targets`' per-recording runs (its
``--cache``, written with ``--fold-models DIR``: each person's runs took the model trained without them), so
the modes are held out; the step length is the fold's calibration (fitted on the two other people,
:func:`experiments.scripts.tyrex_steplen.fit_fold`), as in that script's "calibrated --model, held out" rows.

Every tyrex walker walks forward (or runs), so every step of the ``model`` run whose mode is ``side_left``,
``side_right`` or ``backward`` is an error. For each run of such steps (maximal stretch of one mode) of the walking
motions the script gives: its mode, number of steps, duration (first step to the step after it), the walker's
steps in one model window at the recording's median step interval, where it lies (seconds from the start of
walking; inside the scores' alignment window, :func:`gaitml.evaluation.trajectory.align_once`), the motion
capture's body speed (minimum) and turn rate (maximum) within 1 s of it, the windows around it (the model's raw
and corrected mode: ``mode_raw`` / ``mode`` of :func:`gaitml.models.predict_recording`), the decision value of the
run's mode against ``walk`` (:func:`gaitml.pdr.step_modes.pair_margin`) on the windows nearest its steps, the
steps' out-of-domain flags, and the recording's 10 s error with model modes, forward-only and with only this run
moved forward (the modes change, nothing else: the heading of the ``model`` run is the forward-only one in every
tyrex recording, checked and printed).

Per motion: the median 10 s error (NoDist and all recordings) with model modes, forward-only, every non-forward
step moved forward, and every ``run`` step read ``walk`` (the other way model modes differ from forward-only).
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_pdr import _truth_on_recording, load_tyrex, md
from experiments.scripts.tyrex_pdr_targets import fold_model_paths
from experiments.scripts.tyrex_steplen import WALK_MOTIONS, _lengths, _positions, fit_fold, score

__all__ = ["FORWARD", "forced", "main", "run_rows", "summary"]

#: modes that move along the facing heading (every tyrex step's true direction)
FORWARD = ("walk", "run")
#: seconds either side of a run over which the motion capture's speed and turn rate are read
NEAR_S = 1.0


def forced(prep: dict, modes) -> dict:
    """``prep`` with an extra run ``cf``: the ``model`` run with ``modes`` in place of its own (heading and features kept)."""
    cf = {**prep["runs"]["model"], "modes": np.asarray(modes).astype(str)}
    return {**prep, "runs": {**prep["runs"], "cf": cf}}


def _truth_motion(item) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The motion capture's body track (:func:`gaitml.evaluation.trajectory.body_track`): times, speed (m/s), turn rate (deg/s)."""
    from gaitml.evaluation.trajectory import _uniform_track, body_track

    tt, txy = _truth_on_recording(item)
    t = _uniform_track(tt, txy, "true_xy")[0]
    body = body_track(tt, txy)
    v = np.gradient(body, t, axis=0)
    speed = np.linalg.norm(v, axis=1)
    turn = np.degrees(np.abs(np.gradient(np.unwrap(np.arctan2(v[:, 0], v[:, 1])), t)))
    turn[speed < 0.3] = 0.0  # the direction of a body that stands is noise
    return t, speed, turn


def run_rows(item, prep, model, models) -> list[dict]:
    """One row per run of non-forward steps of the ``model`` run of one recording (see the module docstring)."""
    from gaitml.evaluation.trajectory import align_once
    from gaitml.models._dataset import resample_recording
    from gaitml.models._predict import _windows_for, model_inputs, model_view, predict_recording
    from gaitml.pdr.step_modes import mode_runs, pair_margin, window_values_at_steps

    run = prep["runs"]["model"]
    modes, t = run["modes"], run["t_step"]
    if not np.any(~np.isin(modes, FORWARD)):
        return []
    rec = item["recording"]
    win = predict_recording(model, rec, correction=True, veto_for_step_modes=True)
    r = resample_recording(rec, model.sampling_rate_hz)
    X = model_inputs(model, model_view(model, r)[0], _windows_for(r, model.length_s, model.overlap))
    centre = 0.5 * (win["t_start_s"] + win["t_end_s"]).to_numpy()
    tu, speed, turn = _truth_motion(item)
    tt, txy = _truth_on_recording(item)
    al = align_once(np.r_[0.0, t], _positions(run, _lengths(run, "cal", models, item["motion"])), tt, txy)
    e_model = score(prep, item, "model", "cal", models)["error_10s_pct"]
    e_fwd = score(prep, item, "fwd", "cal", models)["error_10s_pct"]
    per_window = model.length_s / float(np.median(np.diff(t))) if len(t) > 1 else float("nan")
    rows = []
    for a, b, mode in mode_runs(modes):
        if mode in FORWARD:
            continue
        t0, t1 = t[a], (t[b] if b < len(t) else t[-1] + float(np.median(np.diff(t))))
        near = np.flatnonzero((centre > t0 - NEAR_S) & (centre < t1 + NEAR_S))
        nearest = np.unique([int(np.argmin(np.abs(centre - x))) for x in t[a:b]])
        margin = pair_margin(model.estimator, X[nearest], mode, "walk")
        sel = (tu >= t0 - NEAR_S) & (tu <= t1 + NEAR_S)
        modes_cf = modes.copy()
        modes_cf[a:b] = "walk"
        flags = sorted({str(v) for v in window_values_at_steps(win, t[a:b], "in_domain")})
        rows.append(
            {
                "motion": item["motion"],
                "subject": item["subject"],
                "disturbance": item["disturbance"],
                "file": item["file"],
                "mode": mode,
                "n_steps": b - a,
                "steps_per_window": per_window,
                "duration_s": t1 - t0,
                "t_s": t0,
                "from_walk_start_s": t0 - al["anchor_t_s"],
                "in_alignment": bool(al["anchor_t_s"] - NEAR_S <= t0 <= al["align_end_t_s"]),
                "between_forward": bool(a > 0 and b < len(modes) and modes[a - 1] in FORWARD and modes[b] in FORWARD),
                "min_speed_ms": float(speed[sel].min()) if sel.any() else float("nan"),
                "max_turn_deg_s": float(turn[sel].max()) if sel.any() else float("nan"),
                "windows_raw": "/".join(win["mode_raw"].to_numpy()[near]),
                "windows_mode": "/".join(win["mode"].to_numpy()[near]),
                "margin_min": float(margin.min()),
                "margin_max": float(margin.max()),
                "in_domain": "/".join(flags),
                "error_model": e_model,
                "error_forward": e_fwd,
                "error_run_forward": score(forced(prep, modes_cf), item, "cf", "cal", models)["error_10s_pct"],
            }
        )
    return rows


def summary(items, preps, fitted) -> pd.DataFrame:
    """Per walking motion and subset (NoDist, all): median 10 s error of model modes, forward-only, non-forward steps
    moved forward, and run steps read walk (held out: each person with the fold fitted on the other two)."""
    rows = []
    for it, pr in zip(items, preps, strict=True):
        if it["motion"] not in WALK_MOTIONS:
            continue
        models = fitted[it["subject"]]
        modes = pr["runs"]["model"]["modes"]
        rows.append(
            {
                "motion": it["motion"],
                "disturbance": it["disturbance"],
                "model modes": score(pr, it, "model", "cal", models)["error_10s_pct"],
                "forward-only": score(pr, it, "fwd", "cal", models)["error_10s_pct"],
                "non-forward moved forward": score(forced(pr, np.where(np.isin(modes, FORWARD), modes, "walk")), it, "cf", "cal", models)[
                    "error_10s_pct"
                ],
                "run read walk": score(forced(pr, np.where(modes == "run", "walk", modes)), it, "cf", "cal", models)["error_10s_pct"],
                "recordings with non-forward steps": int(np.any(~np.isin(modes, FORWARD))),
                "non-forward steps": int(np.sum(~np.isin(modes, FORWARD))),
                "steps": len(modes),
            }
        )
    t = pd.DataFrame(rows)
    out = []
    for subset, sel in (("NoDist", t[t["disturbance"] == "NoDist"]), ("all", t)):
        cols = ["model modes", "forward-only", "non-forward moved forward", "run read walk"]
        g = sel.groupby("motion", sort=False)
        s = g[cols].median().join(g[["recordings with non-forward steps", "non-forward steps", "steps"]].sum())
        out.append(s.assign(subset=subset).reset_index())
    return pd.concat(out, ignore_index=True).set_index(["subset", "motion"])


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_pdr_nonforward", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--cache", required=True, help="tyrex_pdr_targets' --cache written with --fold-models (read only)")
    p.add_argument("--fold-models", required=True, metavar="DIR", help="the fold models of that cache (tyrex_modes' --model-cache)")
    p.add_argument("--csv", metavar="FILE", help="write the per-run table")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    if not Path(args.cache).is_file():
        raise SystemExit(f"error: no cache {args.cache}; run tyrex_pdr_targets --fold-models DIR --cache {args.cache} first.")
    items = load_tyrex(Path(args.data))
    with open(args.cache, "rb") as fh:
        preps = pickle.load(fh)
    if [p_["file"] for p_ in preps] != [it["file"] for it in items]:
        raise SystemExit(f"error: the cache {args.cache} holds other recordings; pass tyrex_pdr_targets' cache of this data.")
    from gaitml.models import load_model

    people = sorted({it["subject"] for it in items})
    fold_models = {p_: load_model(path) for p_, path in fold_model_paths(Path(args.fold_models), people).items()}
    fitted = {p_: fit_fold(preps, items, [q for q in people if q != p_]) for p_ in people}
    same = [
        bool(np.array_equal(pr["runs"]["model"]["theta"], pr["runs"]["fwd"]["theta"]))
        for it, pr in zip(items, preps, strict=True)
        if it["motion"] in WALK_MOTIONS
    ]
    rows = []
    for it, pr in zip(items, preps, strict=True):
        if it["motion"] in WALK_MOTIONS:
            rows += run_rows(it, pr, fold_models[it["subject"]], fitted[it["subject"]])
    runs = pd.DataFrame(rows)
    if args.csv:
        runs.to_csv(args.csv, index=False)
    shown = runs.drop(columns=["file"]).set_index(["motion", "subject", "disturbance"])
    lines = [
        f"heading of the model run equal to forward-only's in {sum(same)} of {len(same)} walking recordings",
        "",
        "### runs of non-forward steps (held out: fold models, fold step length)",
        md(shown, "{:.2f}"),
        "",
        "### median 10 s error (%) per walking motion, held out",
        md(summary(items, preps, fitted), "{:.2f}"),
        "",
    ]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
