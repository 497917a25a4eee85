"""Is ``adaptive``'s doubled ``cadence_hz`` on calm walks a reporting defect or doubled steps? (diagnosis, no fitting)

``python -m experiments.scripts.cadence_octave --data ../shared/data [--model-cache DIR] [--model MODEL_DIR] [--rates 50,20] [--csv STEM]``
from the repository root. Every tyrex recording with motion capture, as ``gaitml predict`` sees it
(:func:`experiments.scripts.tyrex_modes.load_tyrex_labelled`: the longest segment, at 50 Hz), its steps by the
default detector (:func:`gaitml.models._predict.recording_steps`, the steps the run-cadence rule reads) within the
motion capture's span, against the capture's steps (:func:`experiments.scripts.tyrex_steps.mocap_steps`).

Per recording (question 1 of the report section):

- ``cadence_hz``: the median of the detector's per-step ``cadence_hz`` (1 / the local period of its 5 s
  autocorrelation windows);
- ``spacing``: 1 / the median interval between consecutive detected steps (intervals of a gap, over
  ``BOUT_GAP_RATIO`` local periods, left out as the detector's own bout rule does);
- ``mocap``: the capture's steps per second (steps per event / the median interval of its events);
- ``count ratio``: detected steps / the capture's steps over the same span.

Per step, a step is *doubled by cadence_hz* where its ``cadence_hz`` is at least :data:`DOUBLED_RATIO` times the
capture's local cadence (the median interval of the capture's events within :data:`LOCAL_REACH_S` of the step);
for those steps the ratio of their own spacing (1 / the mean of the intervals to their neighbours) to the
capture's tells a reporting defect (spacing ~ 1x, the peaks are right) from doubled steps (spacing ~ 2x).

With ``--model-cache`` (the fold models of ``tyrex_modes --config experiments/demo.toml --recipes a``; question 2):
each person's recordings through their own fold model (trained on the two other people), and the walking windows
answered ``run``: their local cadence (:func:`gaitml.models._predict.window_step_cadence`, the highest
``cadence_hz`` near the window) against the capture's, and which ones the rule keeps ``run`` because of a doubled
cadence (the detector reads at or above the walk-to-run threshold, the capture below it). With ``--model`` (a model
trained on all three people, ``models/demo``) the same in sample. ``--rates``: the recordings taken down to each rate
(:func:`experiments.scripts.tyrex_modes.at_rate`) first.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

#: a step's ``cadence_hz`` at least this times the capture's local cadence is counted as doubled (between the
#: octave, 2x, and the walk-to-run margin, 1.2x: the doubled readings of the run20 report are 1.7-2.2x)
DOUBLED_RATIO = 1.6
#: the capture's local cadence at a step: the median interval of its events within this many seconds of it
LOCAL_REACH_S = 2.5
#: an interval between two detected steps over this many local periods is a gap, not a step interval
#: (:data:`gaitml.steps.adaptive.BOUT_GAP_RATIO`)
GAP_RATIO = 2.0


def _mocap_rate(ts: np.ndarray, per: int, a: float, b: float) -> float:
    s = ts[(ts >= a) & (ts <= b)]
    return per / float(np.median(np.diff(s))) if len(s) > 2 else np.nan


def step_rows(rec, steps: pd.DataFrame, cap: dict) -> pd.DataFrame:
    """Per detected step inside the capture's span: ``t_s`` (recording clock), ``cadence_hz``, ``spacing_hz`` (1 / the
    mean of its intervals to its neighbours, gaps left out; NaN for a lone step) and ``mocap_hz`` (local)."""
    t0 = float(rec.meta["t0_original_s"])
    ts = np.sort(np.asarray(cap["t_s"], dtype=float) - t0)
    fs = rec.sampling_rate_hz
    t = steps["peak"].to_numpy(np.int64) / fs
    if len(t) == 0:
        return pd.DataFrame({k: np.zeros(0) for k in ("t_s", "cadence_hz", "spacing_hz", "mocap_hz", "interval_s")})
    per_s = 1.0 / steps["cadence_hz"].to_numpy(float)
    d = np.diff(t)
    gap = d > GAP_RATIO * np.maximum(per_s[:-1], per_s[1:])
    prev = np.concatenate([[np.nan], np.where(gap, np.nan, d)])
    nxt = np.concatenate([np.where(gap, np.nan, d), [np.nan]])
    with np.errstate(invalid="ignore"):
        interval = np.nanmean(np.vstack([prev, nxt]), axis=0)
    inside = (t + t0 >= cap["t_first_s"]) & (t + t0 <= cap["t_last_s"])
    loc = np.array([_mocap_rate(ts, cap["steps_per_event"], x - LOCAL_REACH_S, x + LOCAL_REACH_S) for x in t])
    return pd.DataFrame({"t_s": t, "cadence_hz": 1.0 / per_s, "spacing_hz": 1.0 / interval, "mocap_hz": loc, "interval_s": prev})[inside]


def recording_rows(items) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Question 1: one row per recording (module docstring), and every step (:func:`step_rows` with ``person``,
    ``motion``, ``recording``)."""
    from experiments.scripts.tyrex_steps import mocap_steps
    from gaitml.models._predict import recording_steps

    rows, all_steps = [], []
    for k, it in enumerate(items):
        rec = it["recording"]
        cap = mocap_steps(it["truth"], it["motion"])
        st = step_rows(rec, recording_steps(rec), cap)
        all_steps.append(st.assign(person=it["subject"], motion=it["motion"], recording=k))
        t0 = float(rec.meta["t0_original_s"])
        span = (rec.t_s[0] + t0, rec.t_s[-1] + t0)
        ct = np.sort(np.asarray(cap["t_s"], dtype=float))
        ct = ct[(ct >= span[0]) & (ct <= span[1])]
        n_cap = cap["steps_per_event"] * len(ct)
        iv = st["interval_s"].dropna().to_numpy()
        dbl = (st["cadence_hz"] >= DOUBLED_RATIO * st["mocap_hz"]).to_numpy()
        ok = st["mocap_hz"].notna().to_numpy()
        rows.append(
            {
                "person": it["subject"],
                "phone": it.get("phone", ""),
                "motion": it["motion"],
                "steps": len(st),
                "mocap steps": int(n_cap),
                "count ratio": len(st) / n_cap if n_cap else np.nan,
                "cadence_hz": float(st["cadence_hz"].median()) if len(st) else np.nan,
                "spacing": 1.0 / float(np.median(iv)) if len(iv) else np.nan,
                "mocap": cap["steps_per_event"] / float(np.median(np.diff(ct))) if len(ct) > 2 else np.nan,
                "steps with mocap": int(ok.sum()),
                "doubled cadence_hz": int(dbl.sum()),
                "doubled: cadence/mocap": float(np.median(st["cadence_hz"].to_numpy()[dbl] / st["mocap_hz"].to_numpy()[dbl]))
                if dbl.any()
                else np.nan,
                "doubled: spacing/mocap": float(np.nanmedian(st["spacing_hz"].to_numpy()[dbl] / st["mocap_hz"].to_numpy()[dbl]))
                if dbl.any()
                else np.nan,
                "other: spacing/mocap": float(np.nanmedian(st["spacing_hz"].to_numpy()[ok & ~dbl] / st["mocap_hz"].to_numpy()[ok & ~dbl]))
                if (ok & ~dbl).any()
                else np.nan,
            }
        )
    return pd.DataFrame(rows), pd.concat(all_steps, ignore_index=True)


def step_verdict(steps: pd.DataFrame) -> str:
    """Pooled over ``steps``: of the steps whose ``cadence_hz`` reads doubled (>= :data:`DOUBLED_RATIO` x the capture's
    local cadence), how many are spaced doubled too (their own spacing >= DOUBLED_RATIO x) and how many are spaced like
    the capture (within 0.8-1.25 x: a reporting defect)."""
    ok = steps["mocap_hz"].notna() & steps["spacing_hz"].notna()
    r_cad = steps["cadence_hz"] / steps["mocap_hz"]
    r_sp = steps["spacing_hz"] / steps["mocap_hz"]
    dbl = ok & (r_cad >= DOUBLED_RATIO)
    n = int(dbl.sum())
    if n == 0:
        return "no step reads a doubled cadence_hz"
    sp = r_sp[dbl]
    q = np.percentile(sp, [25, 50, 75])
    return (
        f"{n} of {int(ok.sum())} steps read cadence_hz >= {DOUBLED_RATIO:g} x the capture's local cadence (median "
        f"{float(np.median(r_cad[dbl])):.2f} x); their own spacing is {q[1]:.2f} x the capture's (quartiles {q[0]:.2f}-{q[2]:.2f}): "
        f"{int((sp >= DOUBLED_RATIO).sum())} spaced doubled too (>= {DOUBLED_RATIO:g} x), "
        f"{int(((sp >= 0.8) & (sp <= 1.25)).sum())} spaced like the capture (0.8-1.25 x, a reporting defect), "
        f"{int(((sp > 1.25) & (sp < DOUBLED_RATIO)).sum())} between; "
        + (
            f"the other steps: spacing {float(np.median(r_sp[ok & ~dbl])):.2f} x, cadence_hz {float(np.median(r_cad[ok & ~dbl])):.2f} x"
            if (ok & ~dbl).any()
            else "no other steps"
        )
    )


def verdict_table(steps: pd.DataFrame, key=("motion", "person")) -> pd.DataFrame:
    """:func:`step_verdict`'s counts per ``key``: steps with a capture cadence, those reading a doubled ``cadence_hz``,
    the median ratio of their own spacing to the capture's, and how many are spaced doubled / like the capture."""
    ok = steps["mocap_hz"].notna() & steps["spacing_hz"].notna()
    d = steps[ok].assign(r_cad=lambda x: x["cadence_hz"] / x["mocap_hz"], r_sp=lambda x: x["spacing_hz"] / x["mocap_hz"])
    d = d.assign(dbl=d["r_cad"] >= DOUBLED_RATIO)
    rows = []
    for k, g in d.groupby(list(key)):
        b = g[g["dbl"]]
        rows.append(
            {
                **dict(zip(key, k, strict=True)),
                "steps": len(g),
                "cadence_hz doubled": len(b),
                "their spacing / capture": float(b["r_sp"].median()) if len(b) else np.nan,
                "spaced doubled": int((b["r_sp"] >= DOUBLED_RATIO).sum()),
                "spaced like capture": int(b["r_sp"].between(0.8, 1.25).sum()),
            }
        )
    return pd.DataFrame(rows)


def by_motion(df: pd.DataFrame, key=("motion",)) -> pd.DataFrame:
    """Per motion (and person): medians over recordings, the doubled steps summed."""
    g = df.groupby(list(key))
    out = g.agg(
        recordings=("steps", "size"),
        steps=("steps", "sum"),
        mocap_steps=("mocap steps", "sum"),
        cadence_hz=("cadence_hz", "median"),
        spacing=("spacing", "median"),
        mocap=("mocap", "median"),
        steps_with_mocap=("steps with mocap", "sum"),
        doubled=("doubled cadence_hz", "sum"),
        dbl_cad_ratio=("doubled: cadence/mocap", "median"),
        dbl_spacing_ratio=("doubled: spacing/mocap", "median"),
        other_spacing_ratio=("other: spacing/mocap", "median"),
    )
    out.insert(2, "count ratio", out["steps"] / out["mocap_steps"])
    return out.reset_index()


def run_windows(items, cache: Path | None, recipe: str = "a", model_dir: Path | None = None) -> pd.DataFrame:
    """Question 2: every walking window (label walk, >= half labelled) answered ``run`` (raw, after the correction, or
    moved by the rule) by the left-out person's fold model under ``cache`` (held out) or by ``model_dir`` on everyone
    (in sample), with the rule's cadence and the capture's."""
    from experiments.scripts.run20 import fold_model_dir
    from experiments.scripts.tyrex_steps import mocap_steps
    from gaitml.models import load_model, predict_recording
    from gaitml.models._predict import RUN_CADENCE_REACH_S, recording_steps, window_step_cadence

    rows, models = [], {}
    for it in items:
        person = it["subject"] if model_dir is None else ""
        if person not in models:
            models[person] = load_model(fold_model_dir(cache, recipe, person) if model_dir is None else model_dir)
        rec = it["recording"]
        p = predict_recording(models[person], rec)
        walk = ((p["label"].astype(str) == "walk") & (p["label_fraction"] >= 0.5)).to_numpy()
        raw_run = (p["mode_raw"].astype(str) == "run").to_numpy()
        out_run = (p["mode"].astype(str) == "run").to_numpy()
        sel = walk & (raw_run | out_run | p["run_at_walking_cadence"].to_numpy(bool))
        if not sel.any():
            continue
        cad = window_step_cadence(rec, p, RUN_CADENCE_REACH_S, steps=recording_steps(rec))
        cap = mocap_steps(it["truth"], it["motion"])
        ts = np.sort(np.asarray(cap["t_s"], dtype=float) - rec.meta["t0_original_s"])
        for i in np.flatnonzero(sel):
            a, b = float(p["t_start_s"].iat[i]), float(p["t_end_s"].iat[i])
            rows.append(
                {
                    "person": it["subject"],
                    "phone": it.get("phone", ""),
                    "motion": it["motion"],
                    "mode_raw": str(p["mode_raw"].iat[i]),
                    "mode": str(p["mode"].iat[i]),
                    "moved": bool(p["run_at_walking_cadence"].iat[i]),
                    "in_domain": p["in_domain"].iat[i],
                    "cadence": float(cad[i]),
                    "mocap": _mocap_rate(ts, cap["steps_per_event"], a - 1.0, b + 1.0),
                }
            )
    return pd.DataFrame(rows)


def md(df: pd.DataFrame) -> str:
    from experiments.scripts.tyrex_pdr import md as table

    return table(df.set_index(df.columns[0])) if len(df.columns) else ""


def q2_table(w: pd.DataFrame) -> tuple[pd.DataFrame, str]:
    """Question 2's table per person and motion, and its one-line total."""
    from gaitml.models._predict import RUN_MIN_CADENCE_HZ, RUN_STRIDE_CADENCE_HZ

    if w.empty:
        return w, "no walking window read run"
    kept = w["mode"] == "run"
    doubled = kept & (w["cadence"] >= RUN_MIN_CADENCE_HZ) & (w["mocap"] < RUN_MIN_CADENCE_HZ)
    movable = doubled & (w["mocap"] >= RUN_STRIDE_CADENCE_HZ)
    s = w.assign(kept=kept, doubled=doubled, movable=movable).groupby(["person", "motion"])
    t = s.agg(
        read_run=("mode_raw", lambda x: int((x == "run").sum())),
        moved=("moved", "sum"),
        kept_run=("kept", "sum"),
        kept_doubled=("doubled", "sum"),
        would_move=("movable", "sum"),
        cadence=("cadence", "median"),
        mocap=("mocap", "median"),
    ).reset_index()
    total = (
        f"total: {len(w)} walking windows read run (raw or after the correction); {int(w['moved'].sum())} moved by the rule; "
        f"{int(kept.sum())} answered run; {int(doubled.sum())} of those at a detector cadence >= {RUN_MIN_CADENCE_HZ:.2f} where the "
        f"capture counts less; {int(movable.sum())} of them with a capture cadence in [{RUN_STRIDE_CADENCE_HZ:.2f}, {RUN_MIN_CADENCE_HZ:.2f})"
    )
    return t, total


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--model-cache", type=Path, default=None, help="fold models (tyrex_modes --model-cache): question 2, held out")
    ap.add_argument("--model", type=Path, default=None, help="a model trained on all three people (models/demo): question 2, in sample")
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--rates", default="50", help="comma-separated rates (Hz) the recordings are taken to (50: as predict reads them)")
    ap.add_argument("--csv", default=None, help="write STEM-<rate>-recordings.csv (and STEM-<rate>-run-windows-<heldout|insample>.csv)")
    a = ap.parse_args(argv)
    if not (a.data / "tyrex-attitude").is_dir():
        ap.error(f"no tyrex-attitude under {a.data}; pass --data with the shared data folder")
    try:
        rates = [float(r) for r in a.rates.split(",") if r.strip()]
    except ValueError:
        ap.error(f"--rates takes comma-separated numbers (Hz), got {a.rates!r}")
    from experiments.scripts.tyrex_modes import at_rate, load_tyrex_labelled

    base = load_tyrex_labelled(a.data)
    print(f"{len(base)} tyrex recordings with motion capture (the longest segment)", file=sys.stderr)
    for fs in rates:
        items = at_rate(base, fs)
        tag = f"{fs:g}"
        rec, steps = recording_rows(items)
        if a.csv:
            rec.to_csv(f"{a.csv}-{tag}-recordings.csv", index=False)
        print(f"# {tag} Hz\n")
        print("All steps: " + step_verdict(steps) + "\n")
        for m in ("Phoning", "Texting", "BackPocket"):
            print(f"{m}: " + step_verdict(steps[steps["motion"] == m]) + "\n")
        print("## Steps reading a doubled cadence_hz, per motion and person\n\n" + md(verdict_table(steps)) + "\n")
        print("## Per motion\n\n" + md(by_motion(rec)) + "\n")
        print("## Per motion and person\n\n" + md(by_motion(rec, ("motion", "person"))) + "\n")
        calm = rec[rec["motion"].isin(["Phoning", "Texting", "BackPocket"])]
        print("## Phoning, Texting, BackPocket recordings with doubled steps\n\n" + md(calm[calm["doubled cadence_hz"] > 0]) + "\n")
        for name, kw in (("held out (fold models)", {"cache": a.model_cache}), ("in sample", {"cache": None, "model_dir": a.model})):
            if name.startswith("held") and a.model_cache is None or name == "in sample" and a.model is None:
                continue
            w = run_windows(items, recipe=a.recipe, **kw)
            if a.csv:
                w.to_csv(
                    f"{a.csv}-{tag}-run-windows-{name.split()[0].replace('held', 'heldout').replace('in', 'insample')}.csv", index=False
                )
            t, total = q2_table(w)
            print(f"## Walking windows read run, {name}\n\n" + (md(t) if len(t) else "") + "\n\n" + total + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
