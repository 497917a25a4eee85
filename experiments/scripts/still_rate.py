"""The still gate at 20 Hz and at the native rate: the low-passed |acc| std (``std_lp``) against ``std`` and ``range``.

``python -m experiments.scripts.still_rate [--data ../shared/data] [--config experiments/demo.toml] [--cache DIR] [--out FILE]``
from the repository root.

What the study does (the still-gate study's criterion, :mod:`experiments.scripts.still_gate`):

1. Trains recipe a of ``--config`` with the config's own augmentation (swing turns, pocket flips and the
   20 Hz rate copies, as ``models/demo`` is trained; :func:`experiments.scripts.tyrex_modes.train_recipe`)
   on two tyrex people and predicts the third through :func:`gaitml.models.predict_recording` with the gate
   off, at the native rate (50 Hz) and as a phone recording at 20 Hz would give it
   (:func:`experiments.scripts.tyrex_modes.at_rate`); the predictions are cached under ``--cache``.
2. Every gate statistic of every window, as predict computes it: ``std`` and ``range`` on the recording at the
   model's rate, ``std_lp`` on the recording as recorded (``recorded=``).
3. How close a window's statistic at 20 Hz comes to the same window's at 50 Hz, per rule and motion.
4. Chooses the ``std_lp`` threshold on the two training people only, at the native rate: the threshold at
   which their standing windows are read ``still`` as often as with the ``range`` rule
   (:func:`experiments.scripts.still_gate.equal_standing_threshold`); then scores the left-out person with it
   at 50 Hz and at 20 Hz, beside ``std < 0.41`` (the gate before) and ``range < 2``.
5. The same with the shipped model (in-sample).
6. Model-free checks at 50 Hz and at 20 Hz: the simulator's desk and gesture recordings, a phone on a table,
   the simulator's walkers and the Oxford walks (share of windows read still).
7. The adoption rule, fixed before the runs: adopt ``std_lp`` if at the native rate no motion's right share
   falls by more than its fold spread (max - min over the left-out people) and standing-read-as-a-mode does not
   rise by more than 0.02, and at 20 Hz the hand-held (Texting, AR, Phoning) silently-wrong share falls.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["add_statistics", "main", "other_data_at", "rate_agreement"]

PEOPLE = ("Guillaume", "Jakob", "Thibaud")
HAND = ("Texting", "AR", "Phoning")
RATES = (50.0, 20.0)


def add_statistics(model, items, preds) -> None:
    """Add ``stat_std``, ``stat_range`` (recording at the model's rate) and ``stat_std_lp`` (as recorded) to ``preds``."""
    from gaitml.models import resample_recording
    from gaitml.models._predict import still_statistic

    for it, p in zip(items, preds, strict=True):
        rec = resample_recording(it["recording"], model.sampling_rate_hz)
        for rule in ("std", "range"):
            p[f"stat_{rule}"] = still_statistic(rec, p, rule)
        p["stat_std_lp"] = still_statistic(rec, p, "std_lp", recorded=it["recording"])


def rate_agreement(items, p50, p20) -> pd.DataFrame:
    """Per rule and motion: median and 10-90 % range of a window's statistic at 20 Hz / at 50 Hz (moving and standing windows)."""
    from experiments.scripts.tyrex_modes import MOTION_ORDER

    parts = []
    for it, a, b in zip(items, p50, p20, strict=True):
        m = min(len(a), len(b))
        a, b = a.iloc[:m].reset_index(drop=True), b.iloc[:m].reset_index(drop=True)
        if not np.allclose(a["t_start_s"], b["t_start_s"], atol=0.03):
            raise RuntimeError(f"windows at 50 and 20 Hz do not line up in {it['motion']} of {it['subject']}")
        lab = a["label"].astype(str)
        keep = ((lab == it["mode"]) | (lab == "still")) & (a["label_fraction"] >= 0.5)
        d = pd.DataFrame({"motion": it["motion"], "moving": (lab == it["mode"])[keep].to_numpy()})
        for rule in ("std", "range", "std_lp"):
            d[rule] = b.loc[keep, f"stat_{rule}"].to_numpy() / np.maximum(a.loc[keep, f"stat_{rule}"].to_numpy(), 1e-9)
        parts.append(d)
    d = pd.concat(parts, ignore_index=True)
    rows = []
    for what, sel in (("moving", d["moving"]), ("standing", ~d["moving"])):
        for motion in [*MOTION_ORDER, "all"]:
            g = d[sel] if motion == "all" else d[sel & (d["motion"] == motion)]
            if len(g) < 20:
                continue
            row = {"windows": what, "motion": motion, "n": len(g)}
            for rule in ("std", "range", "std_lp"):
                q = g[rule].quantile([0.1, 0.5, 0.9]).to_numpy()
                row[f"{rule}: 20 Hz / 50 Hz (p10-p90)"] = f"{q[1]:.3f} ({q[0]:.2f}-{q[2]:.2f})"
            rows.append(row)
    return pd.DataFrame(rows)


def other_data_at(data: Path, gates, rate: float) -> pd.DataFrame:
    """Share of 1.5 s windows read still (model-free, as predict reads them at 50 Hz), the recordings made at ``rate``."""
    from experiments.scripts.still_gate import other_data_sets
    from gaitml.features import make_windows
    from gaitml.models import resample_recording
    from gaitml.models._predict import still_windows

    sets = other_data_sets(data)
    rows = []
    for name, recs in sets:
        counts = {g: [0, 0] for g in gates}
        for r in recs:
            made = resample_recording(r, rate)
            at50 = resample_recording(made, 50.0)
            if at50.n_samples < 75:
                continue
            w = make_windows(at50, 1.5, 0.5, min_label_fraction=0.0)
            for g in gates:
                rule, thr = g
                s = still_windows(at50, w, rule, thr, recorded=made)
                counts[g][0] += int(s.sum())
                counts[g][1] += len(s)
        row = {"data": name, "recorded at": f"{rate:g} Hz", "windows": counts[gates[0]][1]}
        for g in gates:
            k, nw = counts[g]
            row[f"{g[0]} < {g[1]:g}"] = k / nw if nw else float("nan")
        rows.append(row)
    return pd.DataFrame(rows)


def _train_and_predict(a, items, items20):
    """Held-out (per left-out person) and in-sample predictions with the gate off, at 50 and 20 Hz (cached)."""
    from experiments.scripts import tyrex_modes as tm
    from gaitml.models import load_model, predict_recording
    from gaitml.pipeline.config import load_config

    cfg_full = load_config(a.config)
    turns, turn_positions, share_time = tm.augment_of(cfg_full)
    flips, flip_positions = tm.flips_of(cfg_full)
    rates = [float(r) for r in cfg_full["data"]["augment"]["rates"]]
    cfg = tm.simulated_part(cfg_full)

    def preds(model, its):
        return [predict_recording(model, it["recording"], still_threshold_ms2=0.0) for it in its]

    t0 = time.perf_counter()
    f = a.cache / "shipped.pkl"
    shipped_model = load_model(a.model)
    if f.exists():
        ship = pickle.loads(f.read_bytes())
    else:
        ship = {"50": preds(shipped_model, items), "20": preds(shipped_model, items20)}
        f.write_bytes(pickle.dumps(ship))
    print(f"[still_rate] shipped model predicted ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    held = {}
    sim_train = None
    for person in PEOPLE:
        f = a.cache / f"lopo-{person}.pkl"
        mdir = a.cache / "models" / person
        if (mdir / "model.json").exists():
            model = load_model(mdir)
        else:
            if sim_train is None:
                sim_train = tm._sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], cfg["data"]["simulated"]["positions"])
            train = [it for it in items if it["subject"] != person]
            model, _ = tm.train_recipe(
                cfg,
                sim_train,
                train,
                "a",
                mdir,
                augment=turns,
                augment_positions=turn_positions,
                share_time=share_time,
                flips=flips,
                flip_positions=flip_positions,
                rates=rates,
            )
        test = [i for i, it in enumerate(items) if it["subject"] == person]
        if f.exists():
            d = pickle.loads(f.read_bytes())
        else:
            d = {"idx": test, "50": preds(model, [items[i] for i in test]), "20": preds(model, [items20[i] for i in test])}
            f.write_bytes(pickle.dumps(d))
        held[person] = (model, d)
        print(f"[still_rate] {person} left out ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return shipped_model, ship, held


def main(argv=None) -> int:
    from experiments.scripts import tyrex_modes as tm
    from experiments.scripts.still_gate import _standing_stats, equal_standing_threshold, gated_table, per_person
    from gaitml.models._predict import STILL_RANGE_MS2, STILL_STD_LP_MS2, STILL_STD_MS2

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--model", default="models/demo", help="the shipped model scored in-sample")
    ap.add_argument("--cache", type=Path, default=Path(tempfile.gettempdir()) / "gaitml-still-rate")
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    a.cache.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    items = tm.load_tyrex_labelled(a.data, 50.0)
    items20 = tm.at_rate(items, 20.0)
    print(f"[still_rate] {len(items)} tyrex recordings read ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    shipped_model, ship, held = _train_and_predict(a, items, items20)
    text: list[str] = []

    def emit(s=""):
        print(s)
        text.append(s)

    by_rate = {"50": items, "20": items20}
    add_statistics(shipped_model, items, ship["50"])
    add_statistics(shipped_model, items20, ship["20"])
    h_items = {r: [] for r in by_rate}
    h_preds = {r: [] for r in by_rate}
    for person in PEOPLE:
        model, d = held[person]
        for r, its in by_rate.items():
            sel = [its[i] for i in d["idx"]]
            add_statistics(model, sel, d[r])
            h_items[r] += sel
            h_preds[r] += d[r]
    print(f"[still_rate] statistics ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    emit("### A window's statistic at 20 Hz against the same window at 50 Hz (the shipped model's windows, all three people)\n")
    emit(tm.md(rate_agreement(items, ship["50"], ship["20"])))
    # ---- threshold chosen on the two training people of each fold, at the native rate
    chosen = {}
    emit("\n### The std_lp threshold chosen on the two training people of each fold (native rate)\n")
    emit("| left out | threshold (m/s^2) | training standing windows | read still: range < 2 | read still: std_lp < threshold |")
    emit("|---|---|---|---|---|")
    for person in PEOPLE:
        tr = [(it, p) for it, p in zip(h_items["50"], h_preds["50"], strict=True) if it["subject"] != person]
        sd = np.concatenate(
            [p.loc[(p["label"].astype(str) == "still") & (p["label_fraction"] >= 0.5), "stat_std_lp"].to_numpy() for _, p in tr]
        )
        _, rg = _standing_stats([x[0] for x in tr], [x[1] for x in tr])
        thr = equal_standing_threshold(sd, rg, STILL_RANGE_MS2)
        chosen[person] = thr
        emit(f"| {person} | {thr:.2f} | {len(sd)} | {np.mean(rg < STILL_RANGE_MS2):.2f} | {np.mean(sd < thr):.2f} |")
    sd = np.concatenate(
        [p.loc[(p["label"].astype(str) == "still") & (p["label_fraction"] >= 0.5), "stat_std_lp"].to_numpy() for p in h_preds["50"]]
    )
    _, rg = _standing_stats(h_items["50"], h_preds["50"])
    emit(
        f"\nAll three people: {equal_standing_threshold(sd, rg, STILL_RANGE_MS2):.2f} m/s^2 "
        f"(gaitml's STILL_STD_LP_MS2 = {STILL_STD_LP_MS2:g})."
    )
    gates = (
        ("range < 2 (the earliest gate)", "range", STILL_RANGE_MS2),
        (f"std < {STILL_STD_MS2:g} (the gate before)", "std", STILL_STD_MS2),
        ("std_lp < the fold's threshold", "std_lp", chosen),
    )
    summary = {}
    for r in by_rate:
        for name, rule, thr in gates:
            t = gated_table(h_items[r], h_preds[r], rule, thr)
            summary[(r, rule)] = tm.summarise(t, by="left_out").set_index("motion")
            emit(f"\n### Held out, recorded at {r} Hz, {name}\n")
            emit(tm.md(tm.summarise(t, by="left_out")))
            emit("\nPer left-out person: right / flagged / silently wrong over the moving windows; standing windows read as a mode\n")
            emit(tm.md(per_person(t)))
    for r in by_rate:
        for name, rule, thr in (
            ("range < 2", "range", STILL_RANGE_MS2),
            (f"std < {STILL_STD_MS2:g}", "std", STILL_STD_MS2),
            (f"std_lp < {STILL_STD_LP_MS2:g} (shipped)", "std_lp", STILL_STD_LP_MS2),
        ):
            t = gated_table(by_rate[r], ship[r], rule, thr)
            emit(f"\n### In-sample: {a.model} (trained on all three people), recorded at {r} Hz, {name}\n")
            emit(tm.md(tm.summarise(t)))
    # ---- the adoption rule
    emit("\n### The adoption rule (fixed before the runs): std_lp (fold thresholds) against std < 0.41, held out\n")
    ok = True
    rows = []
    for motion in [*tm.MOTION_ORDER]:
        old, new = summary[("50", "std")].loc[motion], summary[("50", "std_lp")].loc[motion]
        lo, hi = (float(x) for x in old["right per left-out"].split("-"))
        fall = old["right"] - new["right"]
        passed = fall <= hi - lo + 1e-9
        ok &= bool(passed)
        rows.append(
            {
                "check": f"native {motion}: right",
                "before": old["right"],
                "after": new["right"],
                "allowed": f"fall <= {hi - lo:.2f}",
                "pass": passed,
            }
        )
    o, nw = summary[("50", "std")].loc["all", "standing read as a mode"], summary[("50", "std_lp")].loc["all", "standing read as a mode"]
    ok &= bool(nw - o <= 0.02 + 1e-9)
    rows.append(
        {"check": "native: standing read as a mode", "before": o, "after": nw, "allowed": "rise <= 0.02", "pass": nw - o <= 0.02 + 1e-9}
    )

    def hand_wrong(r, rule):
        t = gated_table(h_items[r], h_preds[r], rule, chosen if rule == "std_lp" else STILL_STD_MS2)
        t = t[t["motion"].isin(HAND)]
        return t["wrong"].sum() / t["n"].sum()

    o, nw = hand_wrong("20", "std"), hand_wrong("20", "std_lp")
    ok &= bool(nw < o)
    rows.append(
        {
            "check": "20 Hz: hand-held (Texting, AR, Phoning) silently wrong",
            "before": o,
            "after": nw,
            "allowed": "must fall",
            "pass": nw < o,
        }
    )
    emit(tm.md(pd.DataFrame(rows)))
    emit(f"\nVerdict: {'adopt' if ok else 'do not adopt'} std_lp.")
    # ---- model-free checks
    emit("\n### Other data: share of 1.5 s windows read still (model-free), recorded at 50 Hz and at 20 Hz\n")
    g = (("range", STILL_RANGE_MS2), ("std", STILL_STD_MS2), ("std_lp", STILL_STD_LP_MS2))
    emit(tm.md(pd.concat([other_data_at(a.data, g, 50.0), other_data_at(a.data, g, 20.0)], ignore_index=True)))
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    print(f"[still_rate] done ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
