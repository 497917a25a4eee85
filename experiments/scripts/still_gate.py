"""The still gate on real carried phones: |acc| standard deviation against the |acc| range, each tyrex person left out.

``python -m experiments.scripts.still_gate [--data ../shared/data] [--config experiments/demo.toml] [--cache DIR] [--out FILE]``
from the repository root.

The still gate (:func:`gaitml.models._predict.still_windows`) answers ``still`` for a window
with no gait in it. Two rules: ``range`` (|acc| max - min below 2 m/s^2, the gate before) and
``std`` (|acc| standard deviation below a threshold). What the study does:

1. Trains recipe a of ``--config`` (the shipped ``models/demo`` settings,
   :func:`experiments.scripts.tyrex_modes.train_recipe`) on two tyrex people and predicts the
   third through :func:`gaitml.models.predict_recording` with the gate off (threshold 0), so
   that any gate can be applied afterwards to the same answers (cached under ``--cache``).
2. Chooses the ``std`` threshold on the two training people only: the threshold at which
   their standing windows (body slower than 0.3 m/s by the motion capture) are read ``still``
   as often as with the ``range`` rule (:func:`equal_standing_threshold`). It scores the left-out
   person with it: moving windows right / flagged / silently wrong (``still`` counts as wrong),
   standing windows read as a mode.
3. The same with the shipped model (in-sample: trained on all three) and the shipped threshold.
4. The trade-off: held-out figures for fixed thresholds, beside the simulator's non-gait
   recordings (:func:`gaitml.simulate.nongait.simulate_nongait` desk and gestures), its held-out
   walkers and the Oxford walks (the share of windows read still, model-free).
5. ``--explore``: how well other statistics separate moving from standing windows
   (:func:`explore_table`: the step-band power of |acc|, the gyroscope's rotation,
   periodicity, the default step detector's steps, and all of them combined, fitted on two
   people and scored on the third).
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

__all__ = ["candidate_statistics", "equal_standing_threshold", "explore_table", "gated_table", "main"]

PEOPLE = ("Guillaume", "Jakob", "Thibaud")
FIXED = (0.25, 0.3, 0.35, 0.4, 0.41, 0.45, 0.5)


def equal_standing_threshold(std_standing: np.ndarray, range_standing: np.ndarray, range_ms2: float) -> float:
    """The |acc| std threshold that reads as many standing windows still as the range rule does (2 decimals).

    ``std_standing``, ``range_standing``: the two statistics of the same standing windows.
    """
    share = float(np.mean(np.asarray(range_standing) < float(range_ms2)))
    return round(float(np.quantile(np.asarray(std_standing), share)), 2)


def _predictions(model, items) -> list[pd.DataFrame]:
    """Per item: predict_recording with the gate off, plus both gate statistics of every window."""
    from gaitml.models import predict_recording
    from gaitml.models._predict import still_statistic

    out = []
    for it in items:
        p = predict_recording(model, it["recording"], still_threshold_ms2=0.0)
        for rule in ("std", "range"):
            p[f"stat_{rule}"] = still_statistic(it["recording"], p, rule)
        out.append(p)
    return out


def gated_table(items, preds, rule: str, threshold) -> pd.DataFrame:
    """Per recording, as :func:`experiments.scripts.tyrex_modes.window_table`, with the gate ``rule`` < ``threshold``.

    ``threshold``: a float, or a dict person -> float (each left-out person's own).
    """
    from experiments.scripts.tyrex_modes import score_windows

    rows = []
    for it, p in zip(items, preds, strict=True):
        thr = threshold[it["subject"]] if isinstance(threshold, dict) else threshold
        q = p.copy()
        still = q[f"stat_{rule}"].to_numpy() < thr
        q["mode"] = np.where(still, "still", q["mode"].astype(str).to_numpy())
        s = score_windows(q, it["mode"])
        st = q[(q["label"].astype(str) == "still") & (q["label_fraction"] >= 0.5)]
        moded = int(sum((v is not False) and m != "still" for v, m in zip(st["in_domain"], st["mode"].astype(str), strict=True)))
        rows.append(
            {
                "subject": it["subject"],
                "left_out": it["subject"],
                "phone": it["phone"],
                "motion": it["motion"],
                **s,
                "n_still": len(st),
                "still_flagged": int(sum(v is False for v in st["in_domain"])),
                "still_moded": moded,
            }
        )
    return pd.DataFrame(rows)


def _standing_stats(items, preds):
    std, rng = [], []
    for _it, p in zip(items, preds, strict=True):
        st = (p["label"].astype(str) == "still") & (p["label_fraction"] >= 0.5)
        std.append(p.loc[st, "stat_std"].to_numpy())
        rng.append(p.loc[st, "stat_range"].to_numpy())
    return np.concatenate(std), np.concatenate(rng)


def per_person(t: pd.DataFrame) -> pd.DataFrame:
    """Right / flagged / silently wrong per motion and left-out person, and standing read as a mode."""
    from experiments.scripts.tyrex_modes import MOTION_ORDER

    rows = []
    for motion in [*MOTION_ORDER, "all"]:
        g = t if motion == "all" else t[t["motion"] == motion]
        row = {"motion": motion}
        for person in PEOPLE:
            h = g[g["subject"] == person]
            n, ns = h["n"].sum(), h["n_still"].sum()
            row[f"{person} out"] = f"{h['right'].sum() / n:.2f} / {h['flagged'].sum() / n:.2f} / {h['wrong'].sum() / n:.2f}"
            row[f"{person}: standing as a mode"] = f"{h['still_moded'].sum() / ns:.2f}" if ns else "-"
        rows.append(row)
    return pd.DataFrame(rows)


def _windows_still(recs, rule: str, thr: float, fs: float = 50.0) -> tuple[float, int]:
    """Share of the 1.5 s windows (50 % overlap, at ``fs``) of ``recs`` that the gate reads still (model-free)."""
    from gaitml.features import make_windows
    from gaitml.models import resample_recording
    from gaitml.models._predict import still_windows

    k = n = 0
    for r in recs:
        r = resample_recording(r, fs)
        if r.n_samples < int(1.5 * fs):
            continue
        w = make_windows(r, 1.5, 0.5, min_label_fraction=0.0)
        s = still_windows(r, w, rule, thr)
        k += int(s.sum())
        n += len(s)
    return (k / n if n else float("nan")), n


def other_data_sets(data: Path) -> list[tuple[str, list]]:
    """The model-free check's recordings, named: a phone on a table, simulated desk and gestures, simulator walkers
    in seven positions, and the Oxford walks per position (when ``data`` holds them)."""
    from gaitml.recording import Recording
    from gaitml.simulate import simulate_dataset
    from gaitml.simulate.nongait import simulate_nongait

    sets = []
    rng = np.random.default_rng(3)
    n = 3000
    acc = np.column_stack([np.zeros(n), np.zeros(n), np.full(n, 9.80665)]) + rng.normal(0, 0.02, (n, 3))
    sets.append(("phone lying on a table (noise 0.02 m/s^2)", [Recording(acc=acc, sampling_rate_hz=50.0)]))
    for kind in ("desk", "gestures"):
        sets.append((f"simulate_nongait {kind} (seeds 0-4, 120 s)", [simulate_nongait(kind, duration_s=120, seed=s) for s in range(5)]))
    sim = list(
        simulate_dataset(
            n_subjects=2,
            duration_s=60.0,
            modes=("walk", "run", "side_left", "side_right", "backward"),
            sampling_rate_hz=50.0,
            seed=2024,
            pose="mixed",
            positions=("hand-flat", "hand-tilted", "swinging-hand", "front-pocket", "back-pocket", "bag", "belt"),
        )
    )
    sets.append(("simulator walkers, 7 positions, 5 modes (seed 2024)", sim))
    ox = data / "oxford-step-counter" / "optimisation"
    if ox.exists():
        from gaitml.io import read_dataset

        recs = list(read_dataset(ox))
        for pos in sorted({str(r.meta.get("position", "")) for r in recs}):
            sets.append((f"Oxford {pos} walks", [r for r in recs if str(r.meta.get("position", "")) == pos]))
    return sets


def other_data(data: Path, thresholds) -> pd.DataFrame:
    """Share of windows read still, old rule and the ``std`` rule at ``thresholds``: non-gait, simulator walkers, Oxford."""
    sets = other_data_sets(data)
    rows = []
    for name, recs in sets:
        old, nw = _windows_still(recs, "range", 2.0)
        row = {"data": name, "windows": nw, "range < 2": old}
        for thr in thresholds:
            row[f"std < {thr:g}"] = _windows_still(recs, "std", thr)[0]
        rows.append(row)
    return pd.DataFrame(rows)


def candidate_statistics(rec, windows: pd.DataFrame) -> pd.DataFrame:
    """Per window, the statistics the study compared (all from the window's own samples, except ``steps``).

    ``acc_std``, ``acc_range``: of |acc| (the gate's two rules); ``acc_band``: RMS of |acc| in
    1-3.5 Hz (the step band; Hann-tapered FFT); ``gyr_std``: sqrt of the summed variances of the
    three gyroscope axes (the phone's rotation at the stride); ``gyr_mean``: mean |gyr|;
    ``acf``: the highest normalised autocorrelation of |acc| at 0.25-0.8 s (a step period);
    ``steps``: steps of the default detector (``adaptive``, gait check on, run on the whole
    recording) whose peak falls in the window.
    """
    from gaitml.steps import get_detector

    fs = rec.sampling_rate_hz
    mag = np.linalg.norm(rec.acc, axis=1)
    gyr = np.asarray(rec.gyr)
    peaks = get_detector("adaptive").detect(rec).steps_["peak"].to_numpy()
    lo, hi = int(0.25 * fs), int(0.8 * fs)
    rows = []
    for a, b in zip(windows["start"].to_numpy(), windows["end"].to_numpy(), strict=True):
        m, g = mag[a:b], gyr[a:b]
        x = (m - m.mean()) * np.hanning(len(m))
        spec = np.abs(np.fft.rfft(x, 256)) ** 2
        f = np.fft.rfftfreq(256, 1 / fs)
        band = float(np.sqrt(2 * spec[(f >= 1.0) & (f <= 3.5)].sum() / 256 / np.sum(np.hanning(len(m)) ** 2)))
        y = m - m.mean()
        acf = max(float(y[:-k] @ y[k:] / np.sqrt((y[:-k] @ y[:-k]) * (y[k:] @ y[k:]) + 1e-12)) for k in range(lo, hi + 1))
        rows.append(
            {
                "acc_std": float(m.std()),
                "acc_range": float(np.ptp(m)),
                "acc_band": band,
                "gyr_std": float(np.sqrt(g.var(axis=0).sum())),
                "gyr_mean": float(np.linalg.norm(g, axis=1).mean()),
                "acf": acf,
                "steps": int(np.sum((peaks >= a) & (peaks < b))),
            }
        )
    return pd.DataFrame(rows)


def explore_table(items, preds) -> pd.DataFrame:
    """How well each candidate statistic (:func:`candidate_statistics`) separates moving from standing windows.

    Per motion, the area under the ROC curve (moving = the recording's mode by the motion
    capture, standing = ``still``; 0.5 = no separation, 1 = perfect), and for ``combined`` a
    logistic regression on the logs of all statistics, fitted on two people and scored on the
    third (its area from the three left-out people's scores).
    """
    from sklearn.linear_model import LogisticRegression
    from sklearn.metrics import roc_auc_score

    from experiments.scripts.tyrex_modes import MOTION_ORDER

    parts = []
    for it, p in zip(items, preds, strict=True):
        keep = ((p["label"].astype(str) == it["mode"]) | (p["label"].astype(str) == "still")) & (p["label_fraction"] >= 0.5)
        w = p[keep].reset_index(drop=True)
        c = candidate_statistics(it["recording"], w)
        c["moving"] = (w["label"].astype(str) == it["mode"]).to_numpy()
        c["motion"], c["subject"] = it["motion"], it["subject"]
        parts.append(c)
    d = pd.concat(parts, ignore_index=True)
    names = ["acc_std", "acc_range", "acc_band", "gyr_std", "gyr_mean", "acf", "steps"]
    X = np.column_stack([np.log(np.maximum(d[n].to_numpy(float), 1e-3)) if n not in ("acf",) else d[n].to_numpy() for n in names])
    score = np.zeros(len(d))
    for person in PEOPLE:
        tr = (d["subject"] != person).to_numpy()
        lr = LogisticRegression(class_weight="balanced", max_iter=2000).fit(X[tr], d["moving"].to_numpy()[tr])
        score[~tr] = lr.decision_function(X[~tr])
    d["combined"] = score
    rows = []
    for motion in [*MOTION_ORDER, "all"]:
        g = d if motion == "all" else d[d["motion"] == motion]
        if g["moving"].all() or not g["moving"].any() or (~g["moving"]).sum() < 20:
            continue
        row = {"motion": motion, "moving": int(g["moving"].sum()), "standing": int((~g["moving"]).sum())}
        for n in [*names, "combined"]:
            row[n] = roc_auc_score(g["moving"], g[n])
        row["steps per moving window"] = float(g.loc[g["moving"], "steps"].mean())
        rows.append(row)
    return pd.DataFrame(rows)


def main(argv=None) -> int:
    from experiments.scripts import tyrex_modes as tm
    from gaitml.models import load_model
    from gaitml.models._predict import STILL_RANGE_MS2, STILL_STD_MS2
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--model", default="models/demo", help="the shipped model scored in-sample")
    ap.add_argument("--cache", type=Path, default=Path(tempfile.gettempdir()) / "gaitml-still-gate")
    ap.add_argument("--out", type=Path, default=None)
    ap.add_argument("--explore", action="store_true", help="also compare the candidate statistics (about 2 min more)")
    a = ap.parse_args(argv)
    a.cache.mkdir(parents=True, exist_ok=True)
    cfg = tm.simulated_part(load_config(a.config))
    t0 = time.perf_counter()
    items = tm.load_tyrex_labelled(a.data, cfg["data"]["resample_hz"])
    print(f"[still_gate] {len(items)} tyrex recordings read ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    text: list[str] = []

    def emit(s=""):
        print(s)
        text.append(s)

    # ---- held-out predictions (gate off), one model per left-out person
    sim_train = None
    held_items, held_preds = [], []
    for person in PEOPLE:
        f = a.cache / f"lopo-{person}.pkl"
        test = [it for it in items if it["subject"] == person]
        if f.exists():
            preds = pickle.loads(f.read_bytes())
        else:
            if sim_train is None:
                positions = cfg["data"]["simulated"]["positions"]
                sim_train = tm._sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], positions)
            train = [it for it in items if it["subject"] != person]
            with tempfile.TemporaryDirectory() as tmp:
                model, _n = tm.train_recipe(cfg, sim_train, train, "a", Path(tmp) / "m")
                preds = _predictions(model, test)
            f.write_bytes(pickle.dumps(preds))
        print(f"[still_gate] {person} left out ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        held_items += test
        held_preds += preds
    # ---- the std threshold chosen on the two training people of each fold
    chosen = {}
    emit("### The std threshold chosen on the two training people of each fold\n")
    emit("| left out | threshold (m/s^2) | training standing windows | read still: range < 2 | read still: std < threshold |")
    emit("|---|---|---|---|---|")
    for person in PEOPLE:
        tr = [(it, p) for it, p in zip(held_items, held_preds, strict=True) if it["subject"] != person]
        sd, rg = _standing_stats([x[0] for x in tr], [x[1] for x in tr])
        thr = equal_standing_threshold(sd, rg, STILL_RANGE_MS2)
        chosen[person] = thr
        emit(f"| {person} | {thr:.2f} | {len(sd)} | {np.mean(rg < STILL_RANGE_MS2):.2f} | {np.mean(sd < thr):.2f} |")
    sd, rg = _standing_stats(held_items, held_preds)
    emit(
        f"\nAll three people (the shipped default): {equal_standing_threshold(sd, rg, STILL_RANGE_MS2):.2f} m/s^2 "
        f"(gaitml's STILL_STD_MS2 = {STILL_STD_MS2:g})."
    )
    for name, rule, thr in (("range < 2 m/s^2 (the gate before)", "range", STILL_RANGE_MS2), ("std < the fold's threshold", "std", chosen)):
        t = gated_table(held_items, held_preds, rule, thr)
        emit(f"\n### Held out (each person left out: model and threshold chosen on the other two), {name}\n")
        emit(tm.md(tm.summarise(t, by="left_out")))
        emit("\nPer left-out person: right / flagged / silently wrong over the moving windows, and standing windows read as a mode\n")
        emit(tm.md(per_person(t)))
    # ---- in-sample: the shipped model, gate off, then each rule at its default
    f = a.cache / "shipped.pkl"
    if f.exists():
        ship = pickle.loads(f.read_bytes())
    else:
        ship = _predictions(load_model(a.model), items)
        f.write_bytes(pickle.dumps(ship))
    for name, rule, thr in (
        ("range < 2 m/s^2", "range", STILL_RANGE_MS2),
        (f"std < {STILL_STD_MS2:g} m/s^2 (shipped)", "std", STILL_STD_MS2),
    ):
        t = gated_table(items, ship, rule, thr)
        emit(f"\n### In-sample: {a.model} (trained on all three people), {name}\n")
        emit(tm.md(tm.summarise(t)))
    # ---- the trade-off: fixed thresholds, held out, beside other data
    emit("\n### The trade-off: held-out tyrex figures at fixed thresholds (LOPO models)\n")
    rows = []
    for rule, thr in [("range", STILL_RANGE_MS2)] + [("std", x) for x in FIXED]:
        t = gated_table(held_items, held_preds, rule, thr)
        s = tm.summarise(t, by="left_out").set_index("motion")
        rows.append(
            {
                "gate": f"{rule} < {thr:g}",
                "right, all": s.loc["all", "right"],
                "silently wrong, all": s.loc["all", "silently wrong"],
                "moving read still, all": s.loc["all", "of which still"],
                "right AR": s.loc["AR", "right"],
                "right Texting": s.loc["Texting", "right"],
                "right Phoning": s.loc["Phoning", "right"],
                "standing read as a mode": s.loc["all", "standing read as a mode"],
            }
        )
    emit(tm.md(pd.DataFrame(rows)))
    emit("\n### Other data: share of 1.5 s windows read still (model-free)\n")
    emit(tm.md(other_data(a.data, FIXED)))
    if a.explore:
        emit("\n### Candidate statistics: area under the ROC curve, moving against standing windows (all three people)\n")
        emit(tm.md(explore_table(held_items, held_preds)))
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
