"""Step lengths calibrated on the motion capture, per mode (walk: paper 003 eq. 12, run: Weinberg eq. 13), each tyrex person held out.

``python -m experiments.scripts.tyrex_steplen [--data ../shared/data] [--model models/demo] [--cache FILE] [--csv FILE] [--out FILE]``
from the repository root. For every tyrex recording with motion capture (read as in
:mod:`experiments.scripts.tyrex_pdr`: the longest stretch between sensor gaps), the default step
detector's steps are found once and, through :func:`gaitml.pdr.calibrate.step_length_samples` (the
library code ``python -m gaitml.pdr.calibrate --truth self`` runs), each step gets its inputs of
eq. 12-13 and its true length (the distance the low-passed body track moves since the step before).
``gaitml pdr``'s run (:func:`gaitml.pdr.run_pdr` with those steps) is kept per variant:

- ``fwd``: forward-only, the CLI defaults (HDE heading, bias removed);
- ``fwd-gyro``: forward-only with ``--heading gyro``;
- ``model``: ``--model models/demo`` (model modes, multi-state update), HDE;
- ``model-gyro``: the same with ``--heading gyro``.

Step lengths (the only stage that changes between rows; the trajectory is rebuilt from the run's
headings and modes exactly as :func:`gaitml.pdr.pipeline.assemble_result` does, and the script
checks on one recording per fold and variant that ``run_pdr(step_length=...)`` gives the same
positions):

- ``default``: the uncalibrated model (what ``gaitml pdr`` does without ``--step-length``);
- ``cal``: :func:`gaitml.pdr.calibrate.fit_step_lengths` on the training people's walking
  recordings as ``walk`` (Texting, Phoning, Swinging, FrontPocket, BackPocket; AR left out: it is
  mostly standing, its few steps shuffle between pauses) and running recordings as ``run``;
  with forward-only every step takes the walk line, run steps included;
- ``pooled`` (forward-only only): one walk line fitted on the walking and running recordings
  together (what a forward-only user would fit);
- ``perpos`` (forward-only only): one line per motion, fitted on the training people's
  recordings of that motion: the position known (an upper reference, not buildable without it).

Folds: each person left out (fitted on the other two, scored on the left-out person's 42
recordings) and ``all`` (fitted and scored on all three: in sample). The models/demo modes are
in sample in every fold (it was trained on all three people); only the length is held out.
``baseline``, ``bound`` and ``still`` as in :mod:`experiments.scripts.tyrex_pdr` (the baseline's
constant step length per gait fitted on the other two people).

Success, fixed before the first run (held out: every person left out once, median over the 9
NoDist recordings of each motion, as issue 27 scores):

1. ``model`` + ``cal`` (``gaitml pdr --model models/demo --step-length``): distance ratio within
   0.9-1.1 in every targeted motion (Texting, Phoning, Swinging, FrontPocket, BackPocket,
   RunningHand, RunningPocket);
2. ``fwd`` + ``cal``: distance ratio within 0.9-1.1 in the five walking motions;
3. in running, ``model`` + ``cal`` no worse than ``fwd`` + ``cal`` in the 10 s error (RunningHand
   and RunningPocket medians).
The 10 s error against 1.25 x the bound and the baseline are reported beside them, not targeted
here (the heading dominates them).
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_pdr import (
    MOTION_ORDER,
    _trajectory_from_steps,
    _truth_on_recording,
    baseline_counts,
    baseline_steps,
    bound_trajectory,
    gyro_heading_about_gravity,
    load_tyrex,
    md,
)

__all__ = ["SUCCESS_MOTIONS", "fit_fold", "load_or_prepare", "main", "prepare", "score"]

#: the runs of ``gaitml pdr`` kept per recording: name -> (modes, heading)
RUNS = {"fwd": ("forward", "hde"), "fwd-gyro": ("forward", "gyro"), "model": ("model", "hde"), "model-gyro": ("model", "gyro")}
#: motions fitted as walk (AR left out: mostly standing) and as run
WALK_MOTIONS = ("Texting", "Phoning", "Swinging", "FrontPocket", "BackPocket")
RUN_MOTIONS = ("RunningHand", "RunningPocket")
SUCCESS_MOTIONS = WALK_MOTIONS + RUN_MOTIONS
#: (run, length) rows scored
ROWS = (
    ("fwd", "default"),
    ("model", "default"),
    ("fwd", "cal"),
    ("fwd-gyro", "cal"),
    ("model", "cal"),
    ("model-gyro", "cal"),
    ("fwd", "pooled"),
    ("fwd-gyro", "pooled"),
    ("fwd", "perpos"),
)


def model_for(model, item):
    """The model of ``item``'s runs: ``model`` itself, or ``model[item['subject']]`` when it is a dict (each person's
    fold model, trained without that person: model modes held out too)."""
    return model[item["subject"]] if isinstance(model, dict) else model


def prepare(item, model, pdr_options: dict | None = None) -> dict:
    """One recording: its calibration samples, each kept run of ``gaitml pdr``, and the reference trajectories' inputs.

    ``model``: a model, or a dict person -> that person's fold model (:func:`model_for`).

    ``pdr_options``: extra :func:`gaitml.pdr.run_pdr` keywords of every run (e.g. ``gyro_bias_start``: what
    ``gaitml pdr --gyro-bias-from`` gives it); kept in the result for :func:`check_same_path`."""
    from gaitml.consts import DEFAULT_STEP_DETECTOR
    from gaitml.pdr import run_pdr
    from gaitml.pdr.calibrate import step_length_samples
    from gaitml.steps import get_detector

    model = model_for(model, item)
    rec = item["recording"]
    tt, xy = _truth_on_recording(item)
    table = get_detector(DEFAULT_STEP_DETECTOR).detect(rec).steps_
    samples = step_length_samples(rec, item["mode"], truth=(tt, item["truth"].pos_m[:, :2]), steps=table)
    runs = {}
    for name, (modes, heading) in RUNS.items():
        if modes == "model" and model is None:
            continue
        res = run_pdr(rec, steps=table, model=model, modes=modes, heading=heading, **(pdr_options or {}))
        st = res.steps
        runs[name] = {
            "t_step": st[st.attrs.get("event", "t_peak_s")].to_numpy(float) if len(st) else np.zeros(0),
            "theta": st["heading_rad"].to_numpy(float) if len(st) else np.zeros(0),
            "modes": st["mode"].to_numpy().astype(str) if len(st) else np.zeros(0, dtype=str),
            "update": res.info["update"],
            "features": st[["freq_hz", "var_ms2sq", "a_max_ms2", "a_min_ms2"]].reset_index(drop=True),
        }
    steps_b = baseline_steps(rec)
    psi = gyro_heading_about_gravity(rec)
    return {
        "file": item["file"],
        "samples": samples,
        "runs": runs,
        "baseline": {"t": steps_b / rec.sampling_rate_hz, "psi": psi[steps_b], "counts": baseline_counts(item)},
        "bound": bound_trajectory(item),
        "t_end": float(rec.t_s[-1]),
        **({"pdr_options": dict(pdr_options)} if pdr_options else {}),
    }


def load_or_prepare(items, model, cache: str | None, t0: float, options_of=None) -> list[dict]:
    """:func:`prepare` for every recording, or the pickle ``cache`` if it exists (written when given and absent).

    ``options_of(item)``, when given, returns the item's ``pdr_options`` for :func:`prepare`."""
    if cache and Path(cache).exists():
        with open(cache, "rb") as fh:
            preps = pickle.load(fh)
        if [p_["file"] for p_ in preps] != [it["file"] for it in items]:
            raise SystemExit(f"error: the cache {cache} holds other recordings; delete it.")
        return preps
    preps = []
    for i, it in enumerate(items):
        preps.append(prepare(it, model, options_of(it) if options_of else None))
        if (i + 1) % 20 == 0:
            print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    if cache:
        Path(cache).parent.mkdir(parents=True, exist_ok=True)
        with open(cache, "wb") as fh:
            pickle.dump(preps, fh)
    return preps


def fit_fold(preps, items, train_people) -> dict:
    """The step-length models of one fold, fitted on ``train_people``'s recordings (library code only)."""
    from gaitml.pdr.calibrate import fit_step_lengths

    def pick(motions, as_mode=None):
        parts = [
            p["samples"].assign(mode=as_mode) if as_mode else p["samples"]
            for p, it in zip(preps, items, strict=True)
            if it["subject"] in train_people and it["motion"] in motions
        ]
        return pd.concat(parts, ignore_index=True)

    cal = fit_step_lengths(pick(SUCCESS_MOTIONS), modes=["walk", "run"])
    pooled = fit_step_lengths(pick(SUCCESS_MOTIONS, "walk"), modes=["walk"])
    perpos = {m: fit_step_lengths(pick((m,), "walk"), modes=["walk"]) for m in SUCCESS_MOTIONS}  # AR: too few steps; takes cal
    return {"cal": cal, "pooled": pooled, "perpos": perpos}


def _lengths(run: dict, length: str, models: dict | None, motion: str) -> np.ndarray:
    from gaitml.pdr.step_length import StepLengthModel

    if not len(run["t_step"]):
        return np.zeros(0)
    m = (
        StepLengthModel()
        if length == "default"
        else (models["perpos"].get(motion, models["cal"]) if length == "perpos" else models[length])
    )
    return np.where(np.isfinite(L := m.predict(run["features"], run["modes"])), L, 0.0)


def _positions(run: dict, lengths) -> np.ndarray:
    """Positions as :func:`gaitml.pdr.pipeline.assemble_result` builds them (start at the origin)."""
    from gaitml.pdr.update import forward_update, multi_state_update

    if run["update"] == "multi":
        return multi_state_update(lengths, run["theta"], run["modes"], unknown="forward")
    return forward_update(lengths, run["theta"])


def _outside_share(run: dict, length: str, models, motion: str) -> float:
    """Share of the steps outside the inputs the length model was fitted on (what ``gaitml pdr`` warns about)."""
    if length == "default" or not len(run["t_step"]):
        return float("nan")
    m = models["perpos"].get(motion, models["cal"]) if length == "perpos" else models[length]
    flags = m.outside_fit(run["features"], run["modes"])
    return float(np.mean(flags)) if flags is not None else float("nan")


def score(prep, item, run_name: str, length: str, models) -> dict:
    """One recording, one run, one step length: the walk scores of issue 27."""
    from gaitml.evaluation.trajectory import walk_scores

    run = prep["runs"][run_name]
    lengths = _lengths(run, length, models, item["motion"])
    xy = _positions(run, lengths)
    t = np.concatenate([[0.0], run["t_step"]])
    if t[-1] < prep["t_end"]:
        t, xy = np.append(t, prep["t_end"]), np.vstack([xy, xy[-1:]])
    tt, txy = _truth_on_recording(item)
    return {
        **walk_scores(t, xy, tt, txy),
        "n_steps": len(run["t_step"]),
        "mean_length_m": float(np.mean(lengths)) if len(lengths) else 0.0,
        "outside_fit_share": _outside_share(run, length, models, item["motion"]),
    }


def check_same_path(item, prep, run_name: str, models, model) -> float:
    """Largest position difference (m) between the rebuilt trajectory and ``run_pdr(step_length=...)`` itself."""
    from gaitml.consts import DEFAULT_STEP_DETECTOR
    from gaitml.pdr import run_pdr
    from gaitml.steps import get_detector

    modes, heading = RUNS[run_name]
    model = model_for(model, item)
    rec = item["recording"]
    table = get_detector(DEFAULT_STEP_DETECTOR).detect(rec).steps_
    res = run_pdr(rec, steps=table, model=model, modes=modes, heading=heading, step_length=models["cal"], **prep.get("pdr_options", {}))
    xy = _positions(prep["runs"][run_name], _lengths(prep["runs"][run_name], "cal", models, item["motion"]))
    return float(np.max(np.abs(res.trajectory[["x_m", "y_m"]].to_numpy() - xy))) if len(xy) else 0.0


def reference_rows(prep, item, baseline_length: float) -> list[dict]:
    from gaitml.evaluation.trajectory import walk_scores

    tt, txy = _truth_on_recording(item)
    out = []
    b = prep["baseline"]
    tb, xyb = _trajectory_from_steps(b["t"], np.full(len(b["t"]), baseline_length), b["psi"])
    t_still = np.array([0.0, prep["t_end"]])
    for name, (t, xy) in (("baseline", (tb, xyb)), ("bound", prep["bound"]), ("still", (t_still, np.zeros((2, 2))))):
        if t[-1] < prep["t_end"]:
            t, xy = np.append(t, prep["t_end"]), np.vstack([xy, xy[-1:]])
        out.append({"variant": name, **walk_scores(t, xy, tt, txy)})
    return out


def _keys(it) -> dict:
    return {k: it[k] for k in ("file", "subject", "phone", "motion", "mode", "disturbance")}


def run_all(items, preps, model) -> tuple[pd.DataFrame, dict, list]:
    people = sorted({it["subject"] for it in items})
    rows, fitted, checks = [], {}, []
    for fold in [*people, "all"]:
        train = [p for p in people if p != fold]
        models = fit_fold(preps, items, train)
        fitted[fold] = models
        for it, pr in zip(items, preps, strict=True):
            if fold != "all" and it["subject"] != fold:
                continue
            for run_name, length in ROWS:
                if run_name not in pr["runs"]:
                    continue
                if length == "default" and fold == "all":
                    continue  # nothing fitted: the held-out folds' rows are the same
                rows.append(
                    {
                        "fold": fold,
                        "held_out": fold != "all",
                        **_keys(it),
                        "variant": f"{run_name}/{length}",
                        **score(pr, it, run_name, length, models),
                    }
                )
        first = next(i for i, it in enumerate(items) if fold == "all" or it["subject"] == fold)
        for run_name in RUNS:
            if run_name in preps[first]["runs"]:
                checks.append((fold, run_name, check_same_path(items[first], preps[first], run_name, models, model)))
    # reference trajectories, once (the baseline's length is fitted on the other two people)
    counts = pd.DataFrame(
        [
            {"subject": it["subject"], "mode": it["mode"], "n": p["baseline"]["counts"][0], "m": p["baseline"]["counts"][1]}
            for it, p in zip(items, preps, strict=True)
        ]
    )
    for it, pr in zip(items, preps, strict=True):
        other = counts[counts["subject"] != it["subject"]].groupby("mode")[["n", "m"]].sum()
        length = float(other.loc[it["mode"], "m"] / other.loc[it["mode"], "n"])
        for r in reference_rows(pr, it, length):
            for fold in (it["subject"], "all"):
                rows.append({"fold": fold, "held_out": fold != "all", **_keys(it), **r})
    return pd.DataFrame(rows), fitted, checks


def _pivot(table: pd.DataFrame, metric: str) -> pd.DataFrame:
    t = table.assign(abs_drift=table["drift_deg_per_min"].abs())
    piv = t.pivot_table(index="variant", columns="motion", values=metric, aggfunc="median")
    order = [f"{r}/{ln}" for r, ln in ROWS] + ["baseline", "bound", "still"]
    return piv.reindex(index=[v for v in order if v in piv.index], columns=[m for m in MOTION_ORDER if m in piv.columns])


def side_by_side(table: pd.DataFrame, metric: str, variants, fmt: str) -> pd.DataFrame:
    """Per motion: held out (pooled over the folds) / in sample, NoDist medians, one cell 'held / in'."""
    nd = table[table["disturbance"] == "NoDist"]
    held = _pivot(nd[nd["held_out"]], metric)
    ins = _pivot(nd[~nd["held_out"]], metric)
    out = pd.DataFrame(index=list(variants), columns=held.columns, dtype=object)
    for v in variants:
        for m in held.columns:
            h = held.loc[v, m] if v in held.index else np.nan
            i = ins.loc[v, m] if v in ins.index else np.nan
            out.loc[v, m] = f"{fmt.format(h)} / {fmt.format(i)}" if np.isfinite(i) and not v.endswith("default") else fmt.format(h)
    return out


def person_range(table: pd.DataFrame, metric: str, variants, fmt: str) -> pd.DataFrame:
    """Per motion: min-max over the left-out people of their median (all their recordings)."""
    held = table[table["held_out"]]
    per = held.assign(abs_drift=held["drift_deg_per_min"].abs()).pivot_table(
        index=["variant", "subject"], columns="motion", values=metric, aggfunc="median"
    )
    out = pd.DataFrame(index=list(variants), columns=[m for m in MOTION_ORDER if m in per.columns], dtype=object)
    for v in variants:
        for m in out.columns:
            vals = per.loc[v, m] if v in per.index.get_level_values(0) else pd.Series(dtype=float)
            out.loc[v, m] = f"{fmt.format(vals.min())}-{fmt.format(vals.max())}"
    return out


def targets(table: pd.DataFrame, variant: str, forward: str) -> pd.DataFrame:
    """Issue 27's targets for one variant, held out, NoDist medians."""
    nd = table[(table["disturbance"] == "NoDist") & table["held_out"]]
    dr, err, drift = (_pivot(nd, c) for c in ("distance_ratio", "error_10s_pct", "abs_drift"))
    rows = {}
    for m in SUCCESS_MOTIONS:
        d, e, b, s = dr.loc[variant, m], err.loc[variant, m], err.loc["bound", m], err.loc["still", m]
        rows[m] = {
            "distance ratio 0.9-1.1": f"{'yes' if 0.9 <= d <= 1.1 else 'no'} ({d:.2f})",
            "10 s error <= 1.25 x bound": f"{'yes' if e <= 1.25 * b else 'no'} ({e:.1f} vs {1.25 * b:.1f})",
            "below still where the bound is": ("yes" if e < s else "no") if b < s else "(bound above still)",
            "drift <= plain gyro": f"{'yes' if drift.loc[variant, m] <= drift.loc['baseline', m] else 'no'} ({drift.loc[variant, m]:.0f} vs {drift.loc['baseline', m]:.0f})",
            "no worse than forward-only": (
                f"{'yes' if e <= err.loc[forward, m] + 1e-9 else 'no'} ({e:.1f} vs {err.loc[forward, m]:.1f})"
                if forward != variant
                else "-"
            ),
            "baseline beaten": f"{'yes' if e < err.loc['baseline', m] else 'no'} ({e:.1f} vs {err.loc['baseline', m]:.1f})",
        }
    return pd.DataFrame(rows)


def success(table: pd.DataFrame) -> list[str]:
    """The criteria fixed before the first run (module docstring)."""
    nd = table[(table["disturbance"] == "NoDist") & table["held_out"]]
    dr, err = _pivot(nd, "distance_ratio"), _pivot(nd, "error_10s_pct")
    out = []
    if "model/cal" in dr.index:
        bad = [f"{m} {dr.loc['model/cal', m]:.2f}" for m in SUCCESS_MOTIONS if not 0.9 <= dr.loc["model/cal", m] <= 1.1]
        out.append(f"1. model + cal distance ratio 0.9-1.1 in all 7 motions: {'MET' if not bad else 'NOT MET (' + ', '.join(bad) + ')'}")
    bad = [f"{m} {dr.loc['fwd/cal', m]:.2f}" for m in WALK_MOTIONS if not 0.9 <= dr.loc["fwd/cal", m] <= 1.1]
    out.append(f"2. fwd + cal distance ratio 0.9-1.1 in the 5 walking motions: {'MET' if not bad else 'NOT MET (' + ', '.join(bad) + ')'}")
    if "model/cal" in err.index:
        cmp = [f"{m} {err.loc['model/cal', m]:.1f} vs {err.loc['fwd/cal', m]:.1f}" for m in RUN_MOTIONS]
        ok = all(err.loc["model/cal", m] <= err.loc["fwd/cal", m] for m in RUN_MOTIONS)
        out.append(f"3. running, model + cal 10 s error <= fwd + cal: {'MET' if ok else 'NOT MET'} ({'; '.join(cmp)})")
    return out


def coefficient_table(fitted: dict) -> pd.DataFrame:
    rows = []
    for fold, models in fitted.items():
        cal, pooled = models["cal"], models["pooled"]
        a, b, c = cal.coefficients_["walk"][1]
        info = cal.calibration_["modes"]
        rows.append(
            {
                "fitted on": "all three (in sample)" if fold == "all" else f"all but {fold}",
                "walk A m": a,
                "walk B m s": b,
                "walk C": c,
                "walk steps": info["walk"]["n_steps"],
                "walk mean true m": info["walk"]["mean_true_length_m"],
                "walk RMS m": info["walk"]["rms_residual_m"],
                "run K": cal.coefficients_["run"][1][0],
                "run steps": info["run"]["n_steps"],
                "run mean true m": info["run"]["mean_true_length_m"],
                "run RMS m": info["run"]["rms_residual_m"],
                "pooled A/B/C": "/".join(f"{v:.3f}" for v in pooled.coefficients_["walk"][1]),
            }
        )
    return pd.DataFrame(rows).set_index("fitted on")


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steplen", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--model", default="models/demo", help="model for the model-mode runs ('' to skip them)")
    p.add_argument("--cache", metavar="FILE", help="pickle of the per-recording runs: read if present, else written")
    p.add_argument("--csv", metavar="FILE", help="write the long table")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    items = load_tyrex(Path(args.data))
    model = None
    if args.model:
        from gaitml.models import load_model

        model = load_model(args.model)
    preps = load_or_prepare(items, model, args.cache, t0)
    table, fitted, checks = run_all(items, preps, model)
    if args.csv:
        table.to_csv(args.csv, index=False)
    worst = max(c[2] for c in checks)
    lines = [
        f"same code path: the rebuilt trajectories differ from run_pdr(step_length=...) by at most {worst:.2e} m "
        f"({len(checks)} checks, one recording per fold and run)",
        "",
        "### fitted step-length models (walk: eq. 12 on the walking motions but AR; run: eq. 13 on the runs)",
        md(coefficient_table(fitted), "{:.3f}"),
        "",
    ]
    shown = [f"{r}/{ln}" for r, ln in ROWS if model is not None or not r.startswith("model")] + ["baseline", "bound", "still"]
    for metric, name, fmt in (
        ("distance_ratio", "distance ratio", "{:.2f}"),
        ("error_10s_pct", "10 s error %", "{:.1f}"),
        ("abs_drift", "|drift| deg/min", "{:.1f}"),
    ):
        lines += [f"### {name}, NoDist median (9 per motion): held out / in sample", md(side_by_side(table, metric, shown, fmt)), ""]
        if metric != "abs_drift":
            lines += [
                f"### {name}: range over the left-out people of their median (all their recordings)",
                md(person_range(table, metric, shown, fmt)),
                "",
            ]
    held = table[table["held_out"] & table["variant"].isin(["fwd/cal", "model/cal", "fwd/pooled"])]
    share = held.pivot_table(index="variant", columns="motion", values="outside_fit_share", aggfunc="mean")
    share = share.reindex(columns=[m for m in MOTION_ORDER if m in share.columns])
    lines += [
        "### steps outside the inputs the length model was fitted on (gaitml pdr's warning), mean share, held out",
        md(share, "{:.3f}"),
        "",
    ]
    for v, fwd in (("fwd/cal", "fwd/cal"), ("model/cal", "fwd/cal"), ("fwd-gyro/cal", "fwd-gyro/cal"), ("model-gyro/cal", "fwd-gyro/cal")):
        if v in set(table["variant"]):
            lines += [f"### issue 27 targets, {v}, held out (NoDist medians)", md(targets(table, v, fwd)), ""]
    lines += ["### success (fixed before the first run)", *success(table), ""]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
