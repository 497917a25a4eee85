"""Which PDR front end (step detector, step length, heading) serves real walkers: chosen on two tyrex people, scored on the third.

``python -m experiments.scripts.tyrex_frontend [--data ../shared/data] [--csv FILE] [--out FILE] [--cache FILE]``
from the repository root (about 11 minutes under load; ``--cache`` keeps the per-recording step tables
so a rerun only rescores). For every tyrex recording with motion capture
(read as in :mod:`experiments.scripts.tyrex_pdr`) and every combination of

- step detector: ``single-peak`` (paper 003), ``adaptive`` (the CLI default);
- heading: ``hde`` (the CLI default), ``gyro``, each with the gyroscope bias removed (the default) or
  not (``-nobias``, paper 003);
- step length: ``default`` (the uncalibrated :class:`gaitml.pdr.step_length.StepLengthModel`),
  ``linear`` (paper 003 eq. 12, ``A + B f + C var``, fitted by least squares on the training
  people's steps against the true body distance between consecutive steps,
  :func:`gaitml.pdr.calibrate.true_step_lengths`), ``constant``
  (true body distance over steps found, training people);

a forward-only trajectory is built from ``gaitml pdr``'s steps and headings and scored with
:func:`gaitml.evaluation.trajectory.walk_scores`. Leave-one-person-out: for each person, the
combination with the lowest mean (over the seven motions other than AR, which is mostly
standing) of the per-motion median 10 s error on the *other two* people is chosen, and the
left-out person's figures are reported for it, beside the CLI defaults before issue 27
(:data:`OLD_DEFAULTS`).
"""

from __future__ import annotations

import argparse
import itertools
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_pdr import MOTION_ORDER, load_tyrex, md
from gaitml.pdr.calibrate import true_step_lengths  # the library's (moved there); re-exported for the lab

__all__ = ["main", "step_tables", "true_step_lengths"]

DETECTORS = ("single-peak", "adaptive")
#: heading name -> (run_pdr heading, gyro_bias); ``-nobias``: the gyroscope as logged (paper 003)
HEADINGS = {
    "hde": ("hde", "auto"),
    "hde-nobias": ("hde", "off"),
    "gyro": ("gyro", "auto"),
    "gyro-nobias": ("gyro", "off"),
}
#: the CLI defaults before issue 27 (paper 003's front end, uncalibrated step length)
OLD_DEFAULTS = ("single-peak", "hde-nobias", "default")
LENGTHS = ("default", "linear", "constant")
FEATURES = ("freq_hz", "var_ms2sq", "a_max_ms2", "a_min_ms2")
SCORED_MOTIONS = tuple(m for m in MOTION_ORDER if m != "AR")


def step_tables(item) -> list[dict]:
    """Per detector and heading: the step times, headings, step-length features and true lengths of one recording."""
    from gaitml.evaluation.trajectory import body_track
    from gaitml.steps import get_detector

    rec, truth = item["recording"], item["truth"]
    tt = truth.t_s - rec.meta["t0_original_s"]
    body = body_track(tt, truth.pos_m[:, :2])
    out = []
    for det in DETECTORS:
        table = get_detector(det).detect(rec).steps_  # detected once, shared by the heading variants
        for head, (source, bias) in HEADINGS.items():
            out.append(_one(rec, table, det, head, source, bias, tt, body))
    return out


def _one(rec, table, det, head, source, bias, tt, body) -> dict:
    """One detector's steps with one heading source: what :func:`score_all` needs."""
    from gaitml.pdr import run_pdr

    res = run_pdr(rec, steps=table, modes="forward", heading=source, gyro_bias=bias)
    st = res.steps
    event = st.attrs.get("event", "t_peak_s")
    t_step = st[event].to_numpy(float) if len(st) else np.zeros(0)
    return {
        "detector": det,
        "heading": head,
        "t_step": t_step,
        "heading_rad": st["heading_rad"].to_numpy(float) if len(st) else np.zeros(0),
        "features": st[list(FEATURES)].reset_index(drop=True).astype(float)
        if len(st)
        else pd.DataFrame({c: np.zeros(0) for c in FEATURES}),
        "default_length": st["step_length_m"].to_numpy(float) if len(st) else np.zeros(0),
        "true_length": true_step_lengths(t_step, tt, body),
    }


def _trajectory(t_step, lengths, heading_rad, t_end):
    from gaitml.pdr.update import forward_update

    xy = forward_update(np.asarray(lengths, dtype=float), np.asarray(heading_rad, dtype=float))
    t = np.concatenate([[0.0], t_step, [t_end]])
    return t, np.vstack([xy, xy[-1:]])


def _fit_lengths(train: list[dict]) -> dict:
    """The fitted step-length rules of one training set: a linear model and a constant."""
    from gaitml.pdr.step_length import StepLengthModel

    feats = pd.concat([s["features"] for s in train], ignore_index=True).astype(float)
    true = np.concatenate([s["true_length"] for s in train])
    ok = np.isfinite(true) & np.isfinite(feats.to_numpy(float)).all(axis=1)
    model = StepLengthModel().fit(feats[ok].reset_index(drop=True), true[ok], np.full(int(ok.sum()), "walk"))
    n_steps = sum(len(s["t_step"]) for s in train)
    const = float(np.nansum(true) / max(1, np.isfinite(true).sum())) if n_steps else 0.7
    return {"linear": model, "constant": const}


def score_all(items, tables) -> pd.DataFrame:
    """Every combination on every recording, step lengths fitted leave-one-person-out."""
    from gaitml.evaluation.trajectory import walk_scores

    people = sorted({it["subject"] for it in items})
    rows = []
    fold_free: dict = {}
    for person in people:
        for det, head in itertools.product(DETECTORS, HEADINGS):
            train = [
                s
                for it, tabs in zip(items, tables, strict=True)
                if it["subject"] != person
                for s in tabs
                if s["detector"] == det and s["heading"] == head
            ]
            fitted = _fit_lengths(train)
            for it, tabs in zip(items, tables, strict=True):
                s = next(x for x in tabs if x["detector"] == det and x["heading"] == head)
                rec, truth = it["recording"], it["truth"]
                tt = truth.t_s - rec.meta["t0_original_s"]
                for length in LENGTHS:
                    key = (it["file"], det, head)
                    if length == "default" and key in fold_free:  # nothing fitted: the same scores in every fold
                        rows.append({**fold_free[key], "fold": person, "held_out": it["subject"] == person})
                        continue
                    if length == "default":
                        lengths = s["default_length"]
                    elif length == "linear":
                        lengths = fitted["linear"].predict(s["features"], np.full(len(s["t_step"]), "walk")) if len(s["t_step"]) else []
                    else:
                        lengths = np.full(len(s["t_step"]), fitted["constant"])
                    t, exy = _trajectory(s["t_step"], lengths, s["heading_rad"], rec.t_s[-1])
                    sc = walk_scores(t, exy, tt, truth.pos_m[:, :2])
                    rows.append(
                        {
                            "fold": person,
                            "held_out": it["subject"] == person,
                            "subject": it["subject"],
                            "file": it["file"],
                            "motion": it["motion"],
                            "detector": det,
                            "heading": head,
                            "length": length,
                            **sc,
                        }
                    )
                    if length == "default":
                        fold_free[(it["file"], det, head)] = rows[-1]
    return pd.DataFrame(rows)


def choose(table: pd.DataFrame) -> pd.DataFrame:
    """Per fold: the combination with the lowest mean per-motion median 10 s error on the training people."""
    out = []
    for fold, sub in table[~table["held_out"] & table["motion"].isin(SCORED_MOTIONS)].groupby("fold"):
        per = (
            sub.groupby(["detector", "heading", "length", "motion"])["error_10s_pct"]
            .median()
            .groupby(["detector", "heading", "length"])
            .mean()
        )
        best = per.idxmin()
        default = per.loc[OLD_DEFAULTS]
        out.append(
            {"fold": fold, "detector": best[0], "heading": best[1], "length": best[2], "train_score": per.min(), "train_default": default}
        )
    return pd.DataFrame(out)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_frontend", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--csv", metavar="FILE", help="write the long table")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    p.add_argument("--cache", metavar="FILE", help="pickle of the per-recording step tables: read if present, else written")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    items = load_tyrex(Path(args.data))
    if args.cache and Path(args.cache).exists():
        with open(args.cache, "rb") as fh:
            tables = pickle.load(fh)
    else:
        tables = []
        for i, it in enumerate(items):
            tables.append(step_tables(it))
            if (i + 1) % 20 == 0:
                print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        if args.cache:
            with open(args.cache, "wb") as fh:
                pickle.dump(tables, fh)
    table = score_all(items, tables)
    if args.csv:
        table.to_csv(args.csv, index=False)
    chosen = choose(table)
    held = table[table["held_out"]]
    lines = ["### chosen on the other two people (mean over 7 motions of the per-motion median 10 s error, %)", md(chosen, "{:.1f}"), ""]
    rows = []
    for _, c in chosen.iterrows():
        h = held[held["fold"] == c["fold"]]
        for label, (d, hd, ln) in (("chosen", (c["detector"], c["heading"], c["length"])), ("old defaults", OLD_DEFAULTS)):
            sub = h[(h["detector"] == d) & (h["heading"] == hd) & (h["length"] == ln)]
            for metric in ("error_10s_pct", "distance_ratio"):
                rows.append(
                    {
                        "held out": c["fold"],
                        "front end": f"{label}: {d}/{hd}/{ln}",
                        "metric": metric,
                        **sub.groupby("motion")[metric].median().to_dict(),
                    }
                )
    res = pd.DataFrame(rows)
    cols = ["held out", "front end", "metric", *[m for m in MOTION_ORDER if m in res.columns]]
    lines += ["### the left-out person, median per motion", md(res[cols].set_index("held out"), "{:.2f}"), ""]
    pooled = []
    for label in ("chosen", "old defaults"):
        parts = []
        for _, c in chosen.iterrows():
            d, hd, ln = (c["detector"], c["heading"], c["length"]) if label == "chosen" else OLD_DEFAULTS
            parts.append(held[(held["fold"] == c["fold"]) & (held["detector"] == d) & (held["heading"] == hd) & (held["length"] == ln)])
        allp = pd.concat(parts)
        for metric in ("error_10s_pct", "distance_ratio"):
            pooled.append({"front end": label, "metric": metric, **allp.groupby("motion")[metric].median().to_dict()})
    pooled = pd.DataFrame(pooled)
    lines += [
        "### every person held out once (9 or 18 recordings per motion), median per motion",
        md(pooled[["front end", "metric", *[m for m in MOTION_ORDER if m in pooled.columns]]].set_index("front end"), "{:.2f}"),
        "",
    ]
    # every combination, held out, for the record
    every = held.groupby(["detector", "heading", "length", "motion"])["error_10s_pct"].median().unstack("motion")
    every = every.reindex(columns=[m for m in MOTION_ORDER if m in every.columns])
    every["mean (7 motions)"] = every[[m for m in SCORED_MOTIONS if m in every.columns]].mean(axis=1)
    lines += ["### every combination, each person held out (median 10 s error %)", md(every.sort_values("mean (7 motions)"), "{:.1f}"), ""]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
