"""Out-of-domain check of motion-mode models on real recordings unlike their training data (issue 12).

Run from the repository root::

    python -m experiments.scripts.domain_report [--data ../shared/data] [--out experiments/reports/model-domain.md]

Models (all trained on the simulator, hand-held phone flat or tilted, five modes, the
settings of ``experiments/demo.toml``):

- ``demo``: ``models/demo`` as committed (``all52+gyro``, phone frame);
- ``demo-acc``: ``models/demo-acc`` as committed (``experiments/demo-acc.toml``: the same
  config with ``features.set = "all52"``, no gyroscope, for the accelerometer-only Oxford
  and IFSM recordings), phone frame;
- ``acc-gravity``: ``experiments/demo-acc.toml`` with ``features.frame = "gravity"``,
  trained here into a temporary folder (``gaitml train`` with the override, no
  cross-validation), about a minute.

Tables: every real walking recording in the shared data (Oxford optimisation set per
carrying position, the IFSM flat-held phone, the gaitmap foot-mounted IMU) with the
fraction of windows flagged out of domain, the fraction read as ``walk`` among the
in-domain windows and among all, and the fraction *silently wrong* (in domain and not
``walk``: every real recording here is walking). Then held-out simulated subjects of
the training positions (new seeds), the same subjects with the phone held another way
(rotated copies), and the cost of the check.

``--shipped`` prints what the shipped hand-held models say in every simulated carrying
position instead (new subjects, seed 2024: flagged, mode accuracy in domain, silently
wrong; ``models/demo``'s multi-state PDR per position with the share of steps moved
forward as out of domain; about a minute)::

    python -m experiments.scripts.domain_report --shipped

``--positions`` prints the tables of the all-positions models instead (``positions``:
all52+gyro, ``positions-acc``: all52, trained with ``experiments/positions.toml`` /
``positions-acc.toml`` on every simulated carrying position; not shipped in ``models/``
because they do not hold on real phones, see the report): real walking per Oxford
position, IFSM and gaitmap; leave-one-position-out on the simulator (is a carrying
position left out of training flagged?); multi-state vs forward-only PDR on simulated
routes in each position (about 3-4 minutes after training)::

    gaitml train experiments/positions.toml --out runs/models/positions
    gaitml train experiments/positions-acc.toml --out runs/models/positions-acc
    python -m experiments.scripts.domain_report --positions [--models runs/models] [--data ../shared/data] [--out FILE]
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[2]
DEFAULT_DATA = ROOT.parent / "shared" / "data"
OXFORD_POSITIONS = {
    "inhand": "InHand",
    "frontpocket": "FrontPocket",
    "backpocket": "BackPocket",
    "purse": "Purse",
    "swingingarm": "SwingingArm",
    "neckpouch": "NeckPouch",
    "armband": "Armband",
}


def train_variant(out: Path, frame: str):
    """``experiments/demo-acc.toml`` in another feature frame, trained without CV."""
    from gaitml.pipeline.config import load_config
    from gaitml.pipeline.runner import train_config

    cfg = load_config(ROOT / "experiments" / "demo-acc.toml").with_values(
        {"features.frame": frame, "train.cross_validate": False, "name": f"demo-acc-{frame}"}
    )
    return train_config(cfg, out_dir=out, progress=False)


def score(model, rec) -> dict:
    """Windows, out-of-domain fraction, walk fractions of one recording."""
    from gaitml.models import predict_recording

    t = predict_recording(model, rec)
    ind = t["in_domain"].to_numpy(dtype=object)
    known = np.array([v is not None for v in ind])
    ok = np.array([bool(v) if v is not None else True for v in ind])
    walk = (t["mode"] == "walk").to_numpy()
    return {
        "windows": len(t),
        "ood": int((known & ~ok).sum()),
        "walk_in": int((walk & ok).sum()),
        "in": int(ok.sum()),
        "walk_all": int(walk.sum()),
        "silent": int((ok & ~walk).sum()),
    }


def _row(label: str, model: str, s: dict) -> dict:
    n = max(s["windows"], 1)
    return {
        "data": label,
        "model": model,
        "windows": s["windows"],
        "flagged out of domain": s["ood"] / n,
        "walk among in-domain": s["walk_in"] / s["in"] if s["in"] else float("nan"),
        "walk among all": s["walk_all"] / n,
        "silently wrong": s["silent"] / n,
    }


def add_scores(a: dict, b: dict) -> dict:
    """The counts of :func:`score` summed over recordings: ``a`` plus ``b``, key by key (the keys of ``b``)."""
    return {k: a.get(k, 0) + b[k] for k in b}


def real_table(data: Path, models: dict) -> pd.DataFrame:
    from gaitml.io import read_dataset, read_recording

    rows = []
    ox = data / "oxford-step-counter" / "optimisation"
    if ox.exists():
        recs = read_dataset(ox)
        by_pos: dict[str, list] = {}
        for r in recs:
            pos = OXFORD_POSITIONS.get(str(r.meta.get("position", "")).lower(), str(r.meta.get("position")))
            by_pos.setdefault(pos, []).append(r)
        for pos in OXFORD_POSITIONS.values():
            for name in ("demo-acc", "acc-gravity"):
                tot: dict = {}
                for r in by_pos.get(pos, []):
                    tot = add_scores(tot, score(models[name], r))
                if tot:
                    rows.append(_row(f"Oxford {pos} ({len(by_pos[pos])} walks)", name, tot))
    ifsm = data / "ifsm-flat-phone"
    if ifsm.exists():
        files = sorted(ifsm.glob("*.xlsx"))
        for name in ("demo-acc", "acc-gravity"):
            tot = {}
            for f in files:
                tot = add_scores(tot, score(models[name], read_recording(f)))
            rows.append(_row(f"IFSM flat-held phone ({len(files)} walks)", name, tot))
    gm = data / "gaitmap-example" / "imu_sample.csv.gz"
    if gm.exists():
        for name in ("demo", "demo-acc", "acc-gravity"):
            tot = {}
            for sensor in ("left", "right"):
                tot = add_scores(tot, score(models[name], read_recording(gm, sensor=sensor)))
            rows.append(_row("gaitmap foot-mounted IMU (both feet)", name, tot))
    return pd.DataFrame(rows)


def simulated_table(models: dict, seed: int = 2024, subjects: int = 8) -> pd.DataFrame:
    """Held-out simulated subjects (another seed than the models' 1000) and rotated copies."""
    from scipy.spatial.transform import Rotation

    from gaitml.models import predict_recording
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(n_subjects=subjects, duration_s=120.0, pose="mixed", seed=seed)
    cases = {
        "held-out subjects, phone in the hand (flat/tilted)": None,
        "same, phone turned upright (90 deg about x)": Rotation.from_euler("x", 90, degrees=True).as_matrix(),
        "same, phone upside down (180 deg about y)": Rotation.from_euler("y", 180, degrees=True).as_matrix(),
        "same, random constant rotation per subject": "random",
    }
    rows = []
    for label, q in cases.items():
        for name, model in models.items():
            tot, correct, n_lab = {}, 0, 0
            for i, r in enumerate(recs):
                if q is None:
                    rr = r
                else:
                    m = Rotation.random(random_state=seed + i).as_matrix() if isinstance(q, str) else q
                    rr = r.replace(acc=r.acc @ m.T, gyr=r.gyr @ m.T, check_units=False)
                t = predict_recording(model, rr)
                ind = t["in_domain"].to_numpy(dtype=object)
                ok = np.array([bool(v) for v in ind])
                tot = add_scores(tot, {"windows": len(t), "ood": int((~ok).sum())})
                lab = t["label"].to_numpy() if "label" in t else None
                if lab is not None:
                    sel = t["label_fraction"].to_numpy() >= 0.5
                    correct += int((t["mode"].to_numpy()[sel] == lab[sel]).sum())
                    n_lab += int(sel.sum())
            rows.append(
                {
                    "data": label,
                    "model": name,
                    "windows": tot["windows"],
                    "flagged out of domain": tot["ood"] / tot["windows"],
                    "mode accuracy (all windows)": correct / n_lab if n_lab else float("nan"),
                }
            )
    return pd.DataFrame(rows)


def frame_cv_table(seed: int = 5, subjects: int = 8) -> pd.DataFrame:
    """Leave-one-subject-out accuracy, phone vs gravity frame (simulated hand-held phones, five modes)."""
    from gaitml.evaluation.cv import cross_validate
    from gaitml.models import build_window_dataset
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(n_subjects=subjects, duration_s=150.0, pose="mixed", seed=seed)
    groups = [r.meta["subject"] for r in recs]
    rows = []
    for fset in ("all52", "all52+gyro"):
        for frame in ("phone", "gravity"):
            ds = build_window_dataset(recs, groups=groups, length_s=1.5, overlap=0.5, feature_set=fset, frame=frame)
            res = cross_validate(ds, "linear-ovo-svm", {"C": 1.0}, progress=False, seed=seed)
            pc = res.before["per_class"]
            rows.append(
                {
                    "data": f"{subjects} simulated subjects x 150 s, LOSO, SVM",
                    "model": f"{fset}, {frame} frame",
                    "mode accuracy (all windows)": res.before["accuracy"],
                    **{f"F1 {m}": pc[m]["f1"] for m in ("walk", "backward", "run", "side_left", "side_right")},
                }
            )
    return pd.DataFrame(rows)


def cost_table(model, repeats: int = 3) -> pd.DataFrame:
    """predict_recording time of a 10-minute recording with and without the domain check."""
    from gaitml.models import predict_recording
    from gaitml.simulate import simulate_dataset

    rec = simulate_dataset(n_subjects=1, duration_s=600.0, pose="mixed", seed=77)[0]
    dom = model.domain
    n = len(predict_recording(model, rec))
    out = []
    for label, d in (("without the domain check", None), ("with the domain check", dom)):
        model.domain = d
        best = min(_timed(lambda: predict_recording(model, rec)) for _ in range(repeats))
        out.append({"predict (10 min at 50 Hz)": label, "best of 3 (s)": best, "windows/s": n / best})
    model.domain = dom
    return pd.DataFrame(out)


def _timed(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


# ---------------------------------------------------------------- --silent (Oxford InHand, demo-acc)
_SHORT = {"walk": "w", "backward": "B", "side_left": "L", "side_right": "R", "run": "U"}


def silent_windows(model, rec) -> pd.DataFrame:
    """Every window of one Oxford walk with its mode, domain columns, foot-switch context and intensity.

    Columns besides :func:`gaitml.models.predict_recording`'s: ``silent`` (in domain
    and not ``walk``), ``outside_span`` (the window ends before the first or starts
    after the last foot-switch step), ``part`` (where the window's middle lies in the
    walking span: first 5 %, last 5 % or between), ``cadence`` (steps/s: median
    foot-switch step interval within +-3 s of the window's middle), ``irregularity``
    (std / mean of those intervals), ``pitch_deg`` (phone pitch from the window's
    gravity direction, asin of its y component) and ``acc_var`` (variance of |acc| in
    the window, m^2/s^4: the intensity of the steps).
    """
    from gaitml.models import predict_recording, resample_recording
    from gaitml.models.domain import window_gravity

    t = predict_recording(model, rec)
    r = resample_recording(rec, model.sampling_rate_hz)
    length = int(round(model.length_s * model.sampling_rate_hz))
    starts = t["start"].to_numpy(np.int64)
    g = window_gravity(r.acc, starts, length)
    mag = np.linalg.norm(r.acc, axis=1)
    steps = np.sort(np.asarray(rec.reference["steps_t_s"], dtype=float))
    mid = 0.5 * (t["t_start_s"].to_numpy() + t["t_end_s"].to_numpy())
    cad, irr = np.full(len(t), np.nan), np.full(len(t), np.nan)
    for i, m in enumerate(mid):
        iv = np.diff(steps[(steps > m - 3.0) & (steps < m + 3.0)])
        if len(iv):
            cad[i] = 1.0 / np.median(iv)
        if len(iv) > 2:
            irr[i] = np.std(iv) / np.mean(iv)
    frac = (mid - steps[0]) / (steps[-1] - steps[0])
    ok = np.array([bool(v) for v in t["in_domain"]])
    t["ok"] = ok
    t["silent"] = ok & (t["mode"] != "walk").to_numpy()
    t["outside_span"] = (t["t_end_s"].to_numpy() <= steps[0]) | (t["t_start_s"].to_numpy() >= steps[-1])
    t["part"] = np.where(frac < 0.05, "first 5 %", np.where(frac > 0.95, "last 5 %", "middle 90 %"))
    t["cadence"] = cad
    t["irregularity"] = irr
    t["pitch_deg"] = np.degrees(np.arcsin(np.clip(g[:, 1], -1.0, 1.0)))
    t["acc_var"] = np.array([np.var(mag[s : s + length]) for s in starts])
    t["recording"] = str(rec.meta.get("id"))
    t["position"] = str(rec.meta.get("position"))
    # does the window's mode beat walk in its own pairwise machine (linear OVO SVM)? (a vote artefact would not)
    est = model.estimator
    if hasattr(est, "pairwise_decision_function") and "walk" in list(est.classes_):
        from gaitml.models._predict import model_inputs

        dec = est.pairwise_decision_function(model_inputs(model, r, t))
        cls = [str(c) for c in est.classes_]
        iw = cls.index("walk")
        beats = np.zeros(len(t), dtype=bool)
        for k, (i, j) in enumerate(np.asarray(est.pairs_)):
            for winner, loser, sign in ((i, j, 1.0), (j, i, -1.0)):
                if loser == iw:
                    sel = (t["mode_raw"] == cls[winner]).to_numpy()
                    beats[sel] = sign * dec[sel, k] > 0
        t["beats_walk"] = beats
    return t


def silent_tables(data: Path, model) -> dict[str, pd.DataFrame]:
    """Where the silently wrong windows of hand-held Oxford walking are (model ``demo-acc``).

    Tables: per recording; by part of the walk; by local cadence; the domain distances of
    the silent windows against the thresholds; simulated walk vs backward (held-out
    subjects, seed 2024) for the intensity.
    """
    from gaitml.io import read_dataset
    from gaitml.simulate import simulate_dataset

    ALL = pd.concat([silent_windows(model, r) for r in read_dataset(data / "oxford-step-counter" / "optimisation")], ignore_index=True)
    span_rows = []
    for pos, d in ALL.groupby("position", sort=True):
        inside = d[~d["outside_span"]]
        span_rows.append(
            {
                "data": f"Oxford {pos}",
                "windows": len(d),
                "outside the step span": int(d["outside_span"].sum()),
                "silent windows outside the span": int((d["outside_span"] & d["silent"]).sum()),
                "silently wrong": float(np.mean(d["silent"])),
                "silently wrong inside the span only": float(np.mean(inside["silent"])),
            }
        )
    T = ALL[ALL["position"].str.lower() == "inhand"].reset_index(drop=True)
    per = []
    for name, d in T.groupby("recording", sort=True):
        sil = d[d["silent"]]
        per.append(
            {
                "data": name,
                "windows": len(d),
                "cadence (steps/s)": float(np.nanmedian(d["cadence"])),
                "pitch (deg)": float(np.median(d["pitch_deg"])),
                "|acc| variance (m2/s4)": float(np.median(d["acc_var"])),
                "flagged out of domain": float(np.mean(~d["ok"])),
                "walk among all": float(np.mean(d["mode"] == "walk")),
                "silently wrong": float(np.mean(d["silent"])),
                "silent modes": ", ".join(f"{m} {n}" for m, n in sil["mode"].value_counts().items()) or "-",
                "silent outside the step span": int(sil["outside_span"].sum()),
            }
        )
    per = pd.DataFrame(per).sort_values("cadence (steps/s)")

    def by(col, bins=None) -> pd.DataFrame:
        key = T[col] if bins is None else pd.cut(T[col], bins).astype(str)
        rows = []
        for k, d in T.groupby(key, sort=True):
            rows.append(
                {
                    "data": f"{col} {k}",
                    "windows": len(d),
                    "silently wrong": float(np.mean(d["silent"])),
                    "silent windows": int(d["silent"].sum()),
                }
            )
        return pd.DataFrame(rows)

    span = pd.concat(
        [
            pd.DataFrame(
                [
                    {
                        "data": "outside the foot-switch walking span",
                        "windows": int(T["outside_span"].sum()),
                        "silently wrong": float(np.mean(T.loc[T["outside_span"], "silent"])) if T["outside_span"].any() else float("nan"),
                        "silent windows": int((T["outside_span"] & T["silent"]).sum()),
                    }
                ]
            ),
            by("part"),
            by("cadence", [0, 1.5, 1.6, 1.7, 1.8, 1.9, 2.0, 3.0]),
            by("irregularity", list(np.nanquantile(T["irregularity"], [0, 0.2, 0.4, 0.6, 0.8, 1.0]).round(3))),
        ],
        ignore_index=True,
    )
    dom = model.domain
    dist_thr, grav_thr = dom.distance_threshold, float(np.degrees(dom.gravity_threshold_rad))
    ref = []
    for label, sel in (("silently wrong windows", T["silent"]), ("in-domain walk windows", T["ok"] & (T["mode"] == "walk"))):
        d = T[sel]
        ref.append(
            {
                "data": label,
                "windows": len(d),
                "gravity angle median (deg)": float(np.median(d["gravity_angle_deg"])),
                "gravity angle max (deg)": float(np.max(d["gravity_angle_deg"])),
                "feature distance median": float(np.median(d["domain_distance"])),
                "feature distance max": float(np.max(d["domain_distance"])),
                "within 10 % of the distance threshold": float(np.mean(d["domain_distance"] > 0.9 * dist_thr)),
            }
        )
    ref = pd.DataFrame(ref)
    if "beats_walk" in T:
        sil = T[T["silent"] & (T["mode_raw"] == T["mode"])]
        ref["its mode beats walk head-to-head"] = [float(np.mean(sil["beats_walk"])), float("nan")]
    ref.attrs["thresholds"] = (dist_thr, grav_thr)
    sim = []
    for r in simulate_dataset(n_subjects=8, duration_s=120.0, pose="mixed", seed=2024):
        from gaitml.features import make_windows

        w = make_windows(r, model.length_s, model.overlap, min_label_fraction=0.99)
        mag = np.linalg.norm(r.acc, axis=1)
        n = int(round(model.length_s * r.sampling_rate_hz))
        for s, lab in zip(w["start"].to_numpy(np.int64), w["label"].to_numpy(), strict=True):
            sim.append({"mode": lab, "acc_var": float(np.var(mag[s : s + n])), "pose": r.meta.get("pose", "")})
    sim = pd.DataFrame(sim)
    intensity = pd.DataFrame(
        [
            {
                "data": f"simulated {m} (8 held-out subjects, seed 2024)",
                "windows": int((sim["mode"] == m).sum()),
                "|acc| variance median (m2/s4)": float(sim.loc[sim["mode"] == m, "acc_var"].median()),
                "10 % quantile": float(sim.loc[sim["mode"] == m, "acc_var"].quantile(0.1)),
                "90 % quantile": float(sim.loc[sim["mode"] == m, "acc_var"].quantile(0.9)),
            }
            for m in ("walk", "backward")
        ]
        + [
            {
                "data": f"Oxford InHand {label}",
                "windows": int(sel.sum()),
                "|acc| variance median (m2/s4)": float(T.loc[sel, "acc_var"].median()),
                "10 % quantile": float(T.loc[sel, "acc_var"].quantile(0.1)),
                "90 % quantile": float(T.loc[sel, "acc_var"].quantile(0.9)),
            }
            for label, sel in (("read as walk", T["mode"] == "walk"), ("silently wrong", T["silent"]))
        ]
    )
    strips = {
        name: "".join(_SHORT[m] if ok else "." for m, ok in zip(d["mode"], d["ok"], strict=True)) for name, d in T.groupby("recording")
    }
    worst = per.sort_values("silently wrong", ascending=False)["data"].head(2)
    return {
        "per recording": per,
        "where": span,
        "span": pd.DataFrame(span_rows),
        "domain": ref,
        "intensity": intensity,
        "strips": {k: strips[k] for k in worst},
    }


def silent_main(args) -> int:
    """``--silent``: the silently wrong windows of Oxford InHand walking read by models/demo-acc."""
    from gaitml.models import load_model

    t0 = time.perf_counter()
    model = load_model(ROOT / "models" / "demo-acc")
    tabs = silent_tables(args.data, model)
    dist_thr, grav_thr = tabs["domain"].attrs["thresholds"]
    strips = "\n".join(f"{k}:\n    {v}" for k, v in tabs["strips"].items())
    return emit_tables(
        [
            "### Oxford InHand read by demo-acc, per walk (sorted by foot-switch cadence)\n\n" + _md(tabs["per recording"]),
            "### Where the silently wrong windows are\n\n" + _md(tabs["where"]),
            "### Windows outside the foot-switch walking span, every Oxford position (demo-acc)\n\n" + _md(tabs["span"]),
            f"### Domain check of the silently wrong windows (thresholds: distance {dist_thr:.2f}, gravity {grav_thr:.2f} deg)\n\n"
            + _md(tabs["domain"]),
            "### Step intensity: variance of |acc| per 1.5 s window\n\n" + _md(tabs["intensity"]),
            "### Window modes of the two worst walks (w walk, B backward, L/R side step, U run, . flagged)\n\n```\n" + strips + "\n```",
        ],
        args.out,
        t0,
    )


# ---------------------------------------------------------------- --positions (models for real phones)
#: Oxford carrying position -> the simulated position it corresponds to (None: not trained).
OXFORD_TRAINED = {
    "InHand": "hand-flat/hand-tilted",
    "FrontPocket": "front-pocket",
    "BackPocket": "back-pocket",
    "Purse": "bag",
    "SwingingArm": "swinging-hand",
    "NeckPouch": None,
    "Armband": None,
}


def positions_real_table(data: Path, models: dict) -> pd.DataFrame:
    """Real walking read by the all-positions accelerometer model (Oxford per position, IFSM) and both models (gaitmap foot IMU)."""
    from gaitml.io import read_dataset, read_recording

    rows = []
    ox = data / "oxford-step-counter" / "optimisation"
    if ox.exists():
        by_pos: dict[str, list] = {}
        for r in read_dataset(ox):
            pos = OXFORD_POSITIONS.get(str(r.meta.get("position", "")).lower(), str(r.meta.get("position")))
            by_pos.setdefault(pos, []).append(r)
        for pos, trained in OXFORD_TRAINED.items():
            tot: dict = {}
            for r in by_pos.get(pos, []):
                tot = add_scores(tot, score(models["positions-acc"], r))
            if tot:
                row = _row(f"Oxford {pos} ({len(by_pos[pos])} walks)", "positions-acc", tot)
                rows.append({"trained as": trained or "not trained", **row})
    ifsm = data / "ifsm-flat-phone"
    if ifsm.exists():
        files = sorted(ifsm.glob("*.xlsx"))
        tot = {}
        for f in files:
            tot = add_scores(tot, score(models["positions-acc"], read_recording(f)))
        rows.append({"trained as": "hand-flat", **_row(f"IFSM flat-held phone ({len(files)} walks)", "positions-acc", tot)})
    gm = data / "gaitmap-example" / "imu_sample.csv.gz"
    if gm.exists():
        for name in ("positions", "positions-acc"):
            tot = {}
            for sensor in ("left", "right"):
                tot = add_scores(tot, score(models[name], read_recording(gm, sensor=sensor)))
            rows.append({"trained as": "not trained (foot)", **_row("gaitmap foot-mounted IMU (both feet)", name, tot)})
    df = pd.DataFrame(rows)
    if df.empty:
        return df
    return df[["data", "trained as", *[c for c in df.columns if c not in ("data", "trained as")]]]


def _position_windows(recs, fset: str):
    """Features, gravity, labels, groups and positions of every 1.5 s window (the demo's windows)."""
    from gaitml.models import build_window_dataset
    from gaitml.models.domain import window_gravity

    ds = build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5, feature_set=fset)
    starts = ds.windows["start"].to_numpy(np.int64)
    length = int(ds.windows["end"].iloc[0] - starts[0])
    gravity = np.zeros((len(ds), 3))
    pos = np.empty(len(ds), dtype=object)
    for i in np.unique(ds.recording_index):
        rows = np.flatnonzero(ds.recording_index == i)
        gravity[rows] = window_gravity(recs[int(i)].acc, starts[rows], length)
        pos[rows] = recs[int(i)].meta["position"]
    return ds.inputs("features"), gravity, np.asarray(ds.y), np.asarray(ds.groups), pos


def leave_one_position_out_table(train_subjects: int = 8, test_subjects: int = 4, duration_s: float = 120.0) -> pd.DataFrame:
    """For each carrying position P: the domain fitted on the other positions, the share of P's windows it flags.

    Training: ``train_subjects`` simulated subjects (seed 1000, the models' seed) x
    ``duration_s`` in every position but P; the domain record (``fit_domain``, the
    one ``gaitml train`` writes: held-out 0.99 quantiles over the subjects) decides
    ``in_domain`` exactly as ``gaitml predict`` does. Test: ``test_subjects`` new
    subjects (seed 2024) in every position: P's windows (should be flagged) and the
    windows of the trained positions (should not).
    """
    from gaitml.features import feature_names
    from gaitml.models.domain import fit_domain
    from gaitml.simulate import POSITIONS, simulate_dataset

    train = simulate_dataset(n_subjects=train_subjects, duration_s=duration_s, pose="mixed", seed=1000, positions=POSITIONS)
    test = simulate_dataset(n_subjects=test_subjects, duration_s=duration_s, pose="mixed", seed=2024, positions=POSITIONS)
    rows = []
    for fset in ("all52+gyro", "all52"):
        Xtr, gtr, ytr, grtr, ptr = _position_windows(train, fset)
        Xte, gte, _, _, pte = _position_windows(test, fset)
        for held in POSITIONS:
            keep = ptr != held
            dom = fit_domain(
                Xtr[keep],
                ytr[keep],
                grtr[keep],
                gtr[keep],
                feature_names=feature_names(fset),
                feature_set=fset,
                frame="phone",
                positions=ptr[keep],
                seed=1000,
            )
            ok = dom.check(Xte, gte)["in_domain"]
            out = pte == held
            rows.append(
                {
                    "data": f"left out: {held}",
                    "model": fset,
                    "windows left out": int(out.sum()),
                    "left-out position flagged": float(np.mean(~ok[out])),
                    "trained positions flagged": float(np.mean(~ok[~out])),
                }
            )
    return pd.DataFrame(rows)


def positions_pdr_table(model, seeds=(0, 1, 2), routes=("rectangle", "arc"), out_of_domain: bool = False) -> pd.DataFrame:
    """Multi-state (model modes) vs forward-only PDR on simulated routes in every carrying position.

    ``out_of_domain``: a column with the share of the multi-state steps that the model's
    domain check moved forward (``out_of_domain_steps`` of ``gaitml pdr --json``).
    """
    from gaitml.pdr.pipeline import modes_from_labels
    from gaitml.pipeline.pdr_routes import VARIANTS, evaluate_route
    from gaitml.simulate import POSITIONS, simulate_route

    variants = [v for v in VARIANTS if v[0] in ("multi / model modes / hde", "forward-only / hde", "multi / true modes / hde")]
    long = []
    for pos in POSITIONS:
        for route in routes:
            for seed in seeds:
                rows = evaluate_route(route, seed, model=model, variants=variants, keep_results=True, position=pos)
                rec = simulate_route(route, seed=seed, position=pos)
                for r in rows:
                    res = r.pop("result")
                    if r["variant"] == "multi / model modes / hde":
                        r["ood_share"] = (res.info["out_of_domain_steps"] or 0) / max(res.n_steps, 1)
                    if "mode_accuracy" not in r and r["variant"].startswith("forward-only"):
                        st = res.steps
                        start = st["start"].to_numpy()
                        truth = modes_from_labels(rec.labels, start, np.maximum(st["end"].to_numpy(), start + 1))
                        r["mode_accuracy"] = float(np.mean(truth == "walk"))
                    long.append(r)
    df = pd.DataFrame(long)
    out = []
    for pos in POSITIONS:
        d = df[df["position"] == pos]
        row = {"data": pos}
        if out_of_domain:
            row["steps moved forward as out of domain"] = float(d["ood_share"].mean())
        for label, short in (
            ("multi / model modes / hde", "multi-state"),
            ("forward-only / hde", "forward-only"),
            ("multi / true modes / hde", "true modes"),
        ):
            v = d[d["variant"] == label]
            for route in routes:
                row[f"{short} {route} end error (% dist)"] = float(v[v["route"] == route]["end_error_pct"].mean())
            if short != "true modes":
                row[f"{short} step mode accuracy"] = float(v["mode_accuracy"].mean())
        out.append(row)
    return pd.DataFrame(out)


_PCT = (
    "flagged out of domain",
    "walk among in-domain",
    "walk among all",
    "silently wrong",
    "mode accuracy (all windows)",
    "F1 walk",
    "F1 backward",
    "F1 run",
    "F1 side_left",
    "F1 side_right",
    "left-out position flagged",
    "trained positions flagged",
    "multi-state step mode accuracy",
    "within 10 % of the distance threshold",
    "its mode beats walk head-to-head",
    "silently wrong inside the span only",
    "forward-only step mode accuracy",
    "mode accuracy among in-domain",
    "steps moved forward as out of domain",
)


def shipped_positions_table(models: dict, seed: int = 2024, subjects: int = 8, duration_s: float = 120.0) -> pd.DataFrame:
    """The shipped hand-held models on new simulated subjects in every carrying position.

    ``subjects`` new subjects (``seed``, not the models' 1000) x ``duration_s`` in each
    position of :data:`gaitml.simulate.POSITIONS`, all five modes; every window read
    through ``predict_recording`` as ``gaitml predict`` does. Trained positions: the
    fraction flagged is the false-alarm rate; the others were left out of training
    (flagged should be high). *Silently wrong*: in domain and not the true mode (a side step
    read as a side step with ``side_direction_unsure`` set counts as answered).
    """
    from gaitml.models import predict_recording
    from gaitml.simulate import POSITIONS, simulate_dataset

    recs = simulate_dataset(n_subjects=subjects, duration_s=duration_s, pose="mixed", seed=seed, positions=POSITIONS)
    rows = []
    for name, model in models.items():
        trained = set(model.domain.positions or ())
        for pos in POSITIONS:
            t = pd.concat([predict_recording(model, r) for r in recs if r.meta["position"] == pos])
            t = t[t["label"].notna()]
            ok = t["in_domain"].astype(bool).to_numpy()
            right = (t["mode"] == t["label"]).to_numpy().copy()
            # a side step read as a side step whose direction the model marks unsure is not silently wrong
            if "side_direction_unsure" in t.columns:
                side = t["label"].astype(str).str.startswith("side_") & t["mode"].astype(str).str.startswith("side_")
                right |= (side & t["side_direction_unsure"].astype(bool)).to_numpy()
            rows.append(
                {
                    "data": pos,
                    "trained as": "trained" if pos in trained else "left out",
                    "model": name,
                    "windows": len(t),
                    "flagged out of domain": float(np.mean(~ok)),
                    "mode accuracy among in-domain": float(right[ok].mean()) if ok.any() else float("nan"),
                    "silently wrong": float(np.mean(ok & ~right)),
                }
            )
    return pd.DataFrame(rows)


def emit_tables(sections: list[str], out, t0: float) -> int:
    """Print the markdown sections and the run time, write them to ``out`` too when given; exit status 0."""
    text = "\n\n".join([*sections, f"(run time {time.perf_counter() - t0:.0f} s)"])
    print(text)
    if out:
        out.write_text(text + "\n", encoding="utf-8")
    return 0


def _md(df: pd.DataFrame) -> str:
    """Markdown table; fractions as percentages, other floats with 3 significant digits."""
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "|".join("---" if c in ("data", "model", "trained as") else "---:" for c in cols) + "|"]
    for _, r in df.iterrows():
        cells = []
        for c in cols:
            v = r[c]
            if isinstance(v, float):
                cells.append("-" if not np.isfinite(v) else (f"{100 * v:.1f} %" if c in _PCT else f"{v:.3g}"))
            else:
                cells.append(str(v))
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--data", type=Path, default=DEFAULT_DATA, help="the shared data folder (default ../shared/data)")
    ap.add_argument("--out", type=Path, help="write the tables as markdown to this file")
    ap.add_argument(
        "--positions",
        action="store_true",
        help="the tables of the all-positions models (positions, positions-acc under --models) instead",
    )
    ap.add_argument(
        "--models",
        type=Path,
        default=ROOT / "runs" / "models",
        help="folder holding positions/ and positions-acc/ trained with experiments/positions*.toml (default runs/models)",
    )
    ap.add_argument(
        "--silent",
        action="store_true",
        help="where the silently wrong windows of Oxford InHand walking read by models/demo-acc are, instead",
    )
    ap.add_argument(
        "--shipped",
        action="store_true",
        help="models/demo and models/demo-acc on new simulated subjects in every carrying position, and models/demo's PDR per position, instead",
    )
    args = ap.parse_args(argv)
    from gaitml.models import load_model

    if args.shipped:
        return shipped_main(args)
    if args.positions:
        return positions_main(args)
    if args.silent:
        return silent_main(args)

    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as tmp:
        models = {"demo": load_model(ROOT / "models" / "demo"), "demo-acc": load_model(ROOT / "models" / "demo-acc")}
        print("training acc-gravity ...", file=sys.stderr, flush=True)
        train_variant(Path(tmp) / "acc-gravity", "gravity")
        models["acc-gravity"] = load_model(Path(tmp) / "acc-gravity")
        thresholds = pd.DataFrame(
            [
                {
                    "model": k,
                    "frame": m.frame,
                    "feature set": m.feature_set,
                    "distance threshold held out": m.domain.distance_threshold,
                    "in sample": m.domain.distance_threshold_in_sample,
                    "gravity threshold held out (deg)": np.degrees(m.domain.gravity_threshold_rad) if m.domain.gravity_check else np.nan,
                }
                for k, m in models.items()
            ]
        )
        print("real recordings ...", file=sys.stderr, flush=True)
        real = real_table(args.data, models)
        print("simulated ...", file=sys.stderr, flush=True)
        sim = simulated_table(models)
        cost = cost_table(models["demo"])
        print("phone vs gravity frame (cross-validation) ...", file=sys.stderr, flush=True)
        frames = frame_cv_table()
    return emit_tables(
        [
            "### Domain thresholds of the models\n\n" + _md(thresholds),
            "### Real walking recordings\n\n" + _md(real),
            "### Simulated held-out subjects (seed 2024, 8 subjects x 120 s, all five modes)\n\n" + _md(sim),
            "### Cost of the check\n\n" + _md(cost),
            "### Phone vs gravity frame on the simulator (seed 5, before the adjacent-window correction)\n\n" + _md(frames),
        ],
        args.out,
        t0,
    )


def shipped_main(args) -> int:
    """``--shipped``: what the shipped hand-held models say in every simulated carrying position (about a minute)."""
    from gaitml.models import load_model

    t0 = time.perf_counter()
    models = {name: load_model(ROOT / "models" / name) for name in ("demo", "demo-acc")}
    print("simulated positions ...", file=sys.stderr, flush=True)
    flags = shipped_positions_table(models)
    print("PDR routes per position ...", file=sys.stderr, flush=True)
    pdr = positions_pdr_table(models["demo"], out_of_domain=True)
    return emit_tables(
        [
            "### The shipped models in every simulated carrying position (8 new subjects, seed 2024, 120 s per position)\n\n" + _md(flags),
            "### Multi-state PDR per carrying position with models/demo (rectangle and arc, seeds 0-2, means)\n\n" + _md(pdr),
        ],
        args.out,
        t0,
    )


def positions_main(args) -> int:
    """``--positions``: the tables of the all-positions models (trained from experiments/positions*.toml, not shipped)."""
    from gaitml.models import load_model

    t0 = time.perf_counter()
    missing = [n for n in ("positions", "positions-acc") if not (args.models / n / "model.json").is_file()]
    if missing:
        print(
            f"domain_report: error: no trained {', '.join(missing)} in {args.models}; train them first: "
            + " && ".join(f"gaitml train experiments/{n}.toml --out {args.models / n}" for n in missing),
            file=sys.stderr,
        )
        return 2
    models = {name: load_model(args.models / name) for name in ("positions", "positions-acc")}
    print("real recordings ...", file=sys.stderr, flush=True)
    real = positions_real_table(args.data, models)
    print("leave one position out ...", file=sys.stderr, flush=True)
    lopo = leave_one_position_out_table()
    print("PDR routes per position ...", file=sys.stderr, flush=True)
    pdr = positions_pdr_table(models["positions"])
    return emit_tables(
        [
            "### Real walking read by the models for real phones\n\n" + _md(real),
            "### Leave one position out (simulator: 8 training subjects, seed 1000; 4 test subjects, seed 2024; 120 s each)\n\n"
            + _md(lopo),
            "### Multi-state PDR per carrying position (the all-positions gyro model; rectangle and arc, seeds 0-2, means)\n\n" + _md(pdr),
        ],
        args.out,
        t0,
    )


if __name__ == "__main__":
    raise SystemExit(main())
