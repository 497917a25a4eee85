"""Modes on real carried phones (issue 27): the shipped models and three training recipes, one tyrex person left out at a time.

``python -m experiments.scripts.tyrex_modes [--data ../shared/data] [--features all52+gyro|all52] [--recipes sim,a,b,c]
[--holdout person|person-phone] [--still-rule std|range] [--still-threshold MS2] [--moving-rule speed|walking]
[--out FILE] [--csv FILE]``
from the repository root.

Moving windows (the speed rule): the phone's true path from the motion capture is
low-passed at 0.5 Hz (:func:`gaitml.evaluation.trajectory.body_track`, the walker's
path); a sample is *moving* when that body speed exceeds
:data:`gaitml.evaluation.trajectory.MOVING_SPEED_MS` (0.3 m/s). Moving samples take the
recording's mode (``walk``, or ``run`` for RunningHand / RunningPocket), the others
``still``, samples outside the capture ``unlabelled``; a window takes the majority label
of its samples when that majority is at least half the window (``min_label_fraction``),
so a *moving window* is one in which the body moves faster than 0.3 m/s for more than
half of the 1.5 s. Standing windows are neither walk nor any other mode and are not scored.

``--moving-rule walking`` scores over the windows of the walking rule instead
(:func:`experiments.scripts.tyrex_ar_moving.walking_labels`: the speed of a body point corrected
for the phone's lever arm above 0.3 m/s AND a vertical bounce of at least 1 cm peak-to-peak in the
step band); windows the speed rule calls moving and the walking rule does not are scored neither
as moving nor as standing. The rule changes only what is scored (the denominator): the recipes
are trained on the speed rule's windows under either rule, so the models are the same.

Scores per motion over the moving windows (``gaitml predict``'s own path,
:func:`gaitml.models.predict_recording`, adjacent-window correction on): *right* (in
domain and the recording's mode), *flagged* (out of domain, or marked ``still_unsure``), *silently wrong* (in domain,
another mode). They add up to 1.

Recipes (the project's training path: :func:`gaitml.pipeline.runner.build_dataset`,
:func:`gaitml.models.make_model` (the linear OVO SVM of paper 003),
:func:`gaitml.pipeline.runner.fit_training_domain`, :func:`gaitml.models.save_model`),
the simulated part from ``experiments/tyrex-modes.toml`` (five positions tyrex covers):

- ``a``: real moving windows of the two training people + simulated walk, run, side steps
  and backward in those positions;
- ``b``: real windows for walk and run, simulated windows only for side steps and backward;
- ``sim``: the simulator alone in the same positions (a reference: what the real windows add);
- ``c``: as ``b`` with the real windows counted twice (weight 2: a linear SVM's hinge loss
  sums over windows), so that the real walking and running outweigh the simulated side
  steps and backward walking they border.

Each recipe is trained once per left-out tyrex person (3 folds; ``--holdout person-phone``: per
person x phone, trained on the other people's other phones, 9 folds) and scored on what was left out;
the tables give the pooled figure and the spread over the three left-out people. Side steps
and backward walking are scored on held-out simulator seeds (seed 2024) per position; the
domain check (fitted on the training windows) on the simulator's bag and belt (held-out seed),
the gaitmap foot-mounted IMU, and (accelerometer-only models) the Oxford positions tyrex
does not cover (armband, neck pouch, purse).
"""

from __future__ import annotations

import argparse
import functools
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = ["RECIPES", "moving_labels", "score_windows", "window_table", "main"]

MOTION_ORDER = ("Texting", "AR", "Phoning", "Swinging", "FrontPocket", "BackPocket", "RunningHand", "RunningPocket")
SIDE_MODES = ("side_left", "side_right", "backward")
#: recipe -> (simulated modes kept, weight of the real windows)
RECIPES = {
    "a": (("walk", "run", "side_left", "side_right", "backward"), 1),
    "b": (SIDE_MODES, 1),
    "c": (SIDE_MODES, 2),
    # reference: the simulator alone in the same positions (no real window)
    "sim": (("walk", "run", "side_left", "side_right", "backward"), 0),
}
#: tyrex motion -> the carrying position a position recogniser is asked for (RunningPocket: which pocket is not known)
COARSE_POSITION = {
    "Texting": "hand",
    "AR": "hand",
    "Phoning": "hand",
    "RunningHand": "hand",
    "Swinging": "swinging-hand",
    "FrontPocket": "pocket",
    "BackPocket": "pocket",
    "RunningPocket": "pocket",
}
HELDOUT_SEED = 2024
OXFORD_UNCOVERED = {"armband": "Armband", "neckpouch": "NeckPouch", "purse": "Purse"}
#: lab: a post-hoc flag of :mod:`experiments.scripts.run20` applied to every prediction table (``--candidate``; None: predict's own)
CANDIDATE: str | None = None


def _predict(model, rec, gate: dict | None = None) -> pd.DataFrame:
    """:func:`gaitml.models.predict_recording` of ``rec``, then the lab candidate :data:`CANDIDATE` (if any)."""
    from experiments.scripts.run20 import apply_candidate
    from gaitml.models import predict_recording

    return apply_candidate(predict_recording(model, rec, **(gate or {})), model, rec, CANDIDATE)


def moving_labels(t_s, truth_t_s, truth_xy, mode: str, *, min_speed_ms: float | None = None) -> np.ndarray:
    """Per-sample labels from the motion capture's body speed: ``mode`` when moving, ``still``, or ``unlabelled``.

    The rule of :func:`gaitml.evaluation.trajectory.moving_samples` (the pipeline's
    ``data.labelling.moving_speed_ms``), as labels.

    Parameters
    ----------
    t_s : (n,) sample times of the recording (s, on the truth's clock).
    truth_t_s, truth_xy : the motion-capture times (s) and horizontal positions (m), uniform rate.
    mode : the recording's mode (``walk`` | ``run``).
    min_speed_ms : body speed above which a sample is moving (default
        :data:`gaitml.evaluation.trajectory.MOVING_SPEED_MS`).
    """
    from gaitml.evaluation.trajectory import MOVING_SPEED_MS, moving_samples

    v_min = MOVING_SPEED_MS if min_speed_ms is None else float(min_speed_ms)
    m = moving_samples(t_s, truth_t_s, truth_xy, min_speed_ms=v_min)
    out = np.where(m == 1, mode, np.where(m == 0, "still", "unlabelled")).astype(object)
    return out


def out_of_domain_windows(pred: pd.DataFrame) -> np.ndarray:
    """Which windows of a prediction table are out of domain (``in_domain`` False; None, the rate check's "not
    checked", is not)."""
    return pred["in_domain"].map(lambda v: v is False or v == False).to_numpy(bool)  # noqa: E712 (object column of True/False)


def flagged_windows(pred: pd.DataFrame) -> np.ndarray:
    """Which windows of a prediction table claim no answer: out of domain (``in_domain`` False), or reported ``still``
    and marked ``still_unsure`` (the still gate and the gyroscope's stride rhythm disagree: the table says it does not
    know whether the body stands or walks, as it does for a window out of domain; experiments/reports/still-gate.md,
    stillflag)."""
    flagged = out_of_domain_windows(pred)
    if "still_unsure" in pred:
        flagged = flagged | pred["still_unsure"].to_numpy(bool)
    return flagged


def score_windows(pred: pd.DataFrame, true_mode: str) -> dict:
    """Right / flagged / silently wrong over the windows of ``pred`` whose label is ``true_mode`` (counts).

    ``as_still`` counts the silently wrong windows the still gate of ``gaitml predict`` answered
    ``still`` (no step in the window) rather than one of the five modes.
    """
    w = pred[(pred["label"].astype(str) == true_mode) & (pred["label_fraction"] >= 0.5)]
    flagged = flagged_windows(w)
    right = (~flagged) & (w["mode"].astype(str).to_numpy() == true_mode)
    still = (~flagged) & (w["mode"].astype(str).to_numpy() == "still")
    return {
        "n": len(w),
        "right": int(right.sum()),
        "flagged": int(flagged.sum()),
        "wrong": int((~flagged & ~right).sum()),
        "as_still": int(still.sum()),
    }


def load_tyrex_labelled(data: Path, fs: float = 50.0) -> list[dict]:
    """Every tyrex recording with motion capture at ``fs`` with :func:`moving_labels` (and its manifest row)."""
    from experiments.scripts.tyrex_pdr import load_tyrex
    from gaitml.models import resample_recording

    out = []
    for item in load_tyrex(data):
        rec = resample_recording(item["recording"], fs)
        tt = item["truth"].t_s - rec.meta["t0_original_s"]
        labels = moving_labels(rec.t_s, tt, item["truth"].pos_m[:, :2], item["mode"])
        meta = {**rec.meta, "subject": item["subject"], "position": item["position"], "motion": item["motion"]}
        out.append({**item, "recording": rec.replace(labels=labels, meta=meta, check_units=False)})
    return out


def at_rate(items: list[dict], fs: float) -> list[dict]:
    """``items`` as phones recording at ``fs`` Hz would give them: each recording resampled to ``fs``
    (:func:`gaitml.models.resample_recording`), its labels (and the walking rule's) carried over by the nearest sample."""
    from gaitml.models import resample_recording

    out = []
    for it in items:
        new = dict(it)
        for key in ("recording", "score_recording"):
            if key not in it:
                continue
            rec = it[key]
            if abs(rec.sampling_rate_hz - fs) <= 1e-9 * fs:
                continue
            low = resample_recording(rec, fs)
            idx = np.clip(np.rint((low.t_s - rec.t_s[0]) * rec.sampling_rate_hz).astype(int), 0, rec.n_samples - 1)
            new[key] = low.replace(labels=np.asarray(rec.labels, dtype=object)[idx], check_units=False)
        out.append(new)
    return out


def without_rate_check(model):
    """``model`` with its domain record's rate dropped (``min_rate_hz`` None): what the classifier and the feature
    checks alone answer at any rate (a context manager)."""
    import contextlib

    @contextlib.contextmanager
    def cm():
        dom = getattr(model, "domain", None)
        keep = None if dom is None else dom.min_rate_hz
        if dom is not None:
            dom.min_rate_hz = None
        try:
            yield model
        finally:
            if dom is not None:
                dom.min_rate_hz = keep

    return cm()


def window_table(model, items: list[dict], gate: dict | None = None) -> pd.DataFrame:
    """Per recording: right / flagged / wrong counts over its moving windows, and its still windows flagged.

    The windows are labelled from ``item["score_recording"]`` when present (the walking rule),
    else from ``item["recording"]`` (the speed rule).

    ``gate``: keyword arguments of :func:`gaitml.models.predict_recording` for its still gate
    (``still_rule``, ``still_threshold_ms2``); None for its defaults.
    """
    from experiments.scripts.tyrex_ar_moving import NOT_WALKING

    rows = []
    for it in items:
        p = _predict(model, it.get("score_recording", it["recording"]), gate)
        s = score_windows(p, it["mode"])
        still = p[(p["label"].astype(str) == "still") & (p["label_fraction"] >= 0.5)]
        still_flags = flagged_windows(still)
        n_still_flagged = int(still_flags.sum())
        # of those, out of domain (the domain check's false alarms; the rest are marked still_unsure)
        n_still_out = int(out_of_domain_windows(still).sum())
        # standing windows answered with one of the five modes (neither 'still' nor flagged)
        n_still_moded = int(np.sum(~still_flags & (still["mode"].astype(str).to_numpy() != "still")))
        # moving by speed but not walking (the walking rule's third class): how they were answered
        nw = p[(p["label"].astype(str) == NOT_WALKING) & (p["label_fraction"] >= 0.5)]
        nw_in = ~flagged_windows(nw)
        rows.append(
            {
                "subject": it["subject"],
                "phone": it["phone"],
                "motion": it["motion"],
                **s,
                "n_still": len(still),
                "still_flagged": n_still_flagged,
                "still_out_of_domain": n_still_out,
                "still_moded": n_still_moded,
                "n_notwalk": len(nw),
                "notwalk_mode": int(np.sum(nw_in & (nw["mode"].astype(str).to_numpy() == it["mode"]))),
                "notwalk_still": int(np.sum(nw_in & (nw["mode"].astype(str).to_numpy() == "still"))),
            }
        )
    return pd.DataFrame(rows)


def summarise(t: pd.DataFrame, by: str = "subject") -> pd.DataFrame:
    """Per motion: pooled shares over the moving windows, and the min-max of `right` and `wrong` over ``by`` (the left-out people)."""
    rows = []
    for motion in [*MOTION_ORDER, "all"]:
        g = t if motion == "all" else t[t["motion"] == motion]
        if g.empty:
            continue
        n = g["n"].sum()
        per = g.groupby(by)[["right", "n", "wrong", "flagged"]].sum()
        ns = g["n_still"].sum()
        r_p = per["right"] / per["n"].where(per["n"] > 0)
        w_p = per["wrong"] / per["n"].where(per["n"] > 0)
        rows.append(
            {
                "motion": motion,
                "moving windows": int(n),
                "right": g["right"].sum() / n,
                "flagged": g["flagged"].sum() / n,
                "silently wrong": g["wrong"].sum() / n,
                "of which still": g["as_still"].sum() / n,
                "right per left-out": f"{r_p.min():.2f}-{r_p.max():.2f}",
                "wrong per left-out": f"{w_p.min():.2f}-{w_p.max():.2f}",
                "standing windows": int(ns),
                "standing read as a mode": g["still_moded"].sum() / ns if ns else float("nan"),
            }
        )
        nw = int(g["n_notwalk"].sum()) if "n_notwalk" in g else 0
        if "n_notwalk" in t and t["n_notwalk"].sum() > 0:
            rows[-1]["not-walking windows"] = nw
            rows[-1]["not-walking read as the mode / still"] = (
                f"{g['notwalk_mode'].sum() / nw:.2f} / {g['notwalk_still'].sum() / nw:.2f}" if nw else "-"
            )
    return pd.DataFrame(rows)


def _sim(cfg, seed: int, subjects: int, positions) -> list:
    from gaitml.simulate import simulate_dataset

    s = cfg["data"]["simulated"]
    return list(
        simulate_dataset(
            n_subjects=subjects,
            duration_s=s["duration_s"],
            modes=tuple(s["modes"]),
            sampling_rate_hz=cfg["data"]["resample_hz"],
            seed=seed,
            pose=s["pose"],
            positions=tuple(positions),
        )
    )


def keep_modes(rec, modes) -> object:
    lab = np.asarray(rec.labels).astype(object)
    lab = np.where(np.isin(lab.astype(str), list(modes)), lab, "unlabelled").astype(object)
    return rec.replace(labels=lab, check_units=False)


def train_recipe(
    cfg,
    sim_recs,
    real_items,
    recipe: str,
    out_dir: Path,
    augment: int = 0,
    augment_positions=None,
    share_time=False,
    flips=(),
    flip_positions=None,
    flip_simulated=False,
    rates=(),
    rate_sources="all",
    tempo=(),
    tempo_labels=("run",),
    tempo_domain=True,
    tempo_positions=(),
):
    """Train recipe ``recipe`` on the simulated recordings and the real training people; return the loaded model.

    ``rates``: every training recording (simulated and real, copies included) also trains as a copy taken down to
    each rate and back up (:func:`gaitml.pipeline.augment.rate_copies`, ``data.augment.rates``), as gaitml train does;
    ``rate_sources = "real"`` (lab): the real recordings only.

    ``augment``: rotated copies per real recording in ``augment_positions``
    (:func:`gaitml.pipeline.augment.augment_recordings`, the phone turned about its swing axis; seed ``cfg.seed``),
    counted with the real windows' weight; ``share_time``: the original and its copies share the recording's time;
    ``flips``: pocket flips (180 deg turns about the named phone axes) of the recordings in ``flip_positions``;
    ``flip_simulated``: the simulated recordings in those positions flipped too (every mode, sharing their time).
    ``tempo``: every real training recording labelled one of ``tempo_labels`` also trains replayed at each tempo factor
    (:func:`gaitml.pipeline.augment.tempo_copies`, ``data.augment.tempo``), appended after the real recordings before
    the turns and flips (which then apply to the copies too), as gaitml train does; the copies enter the domain record
    unless ``tempo_domain = False`` (``data.augment.tempo_in_domain``: they train the classifier only, like the other
    copies); ``tempo_positions`` (``data.augment.tempo_positions``): only the recordings carried there (empty: any).
    """
    from gaitml.consts import MOTION_MODES
    from gaitml.features import feature_names
    from gaitml.models import load_model, make_model, save_model
    from gaitml.pipeline.runner import PreparedData, _through_acc_range, _window_info, build_dataset, fit_training_domain

    sim_modes, weight = RECIPES[recipe]
    recs = [keep_modes(r, sim_modes) for r in sim_recs]
    groups = [f"sim-{r.meta['subject']}" for r in sim_recs]
    if flips and flip_simulated:
        from gaitml.pipeline.augment import POCKET_POSITIONS, augmented_set

        fpos = POCKET_POSITIONS if flip_positions is None else tuple(flip_positions)
        recs, _ = augmented_set(recs, 0, seed=cfg.seed, share_time=True, flips=tuple(flips), flip_positions=fpos)
        groups = [f"sim-{r.meta['subject']}" for r in recs]
    real = [it["recording"] for it in real_items]
    if tempo and weight:
        from gaitml.pipeline.augment import tempo_copies

        extra = tempo_copies(real, tempo, tempo_labels, positions=list(tempo_positions) or None, in_domain=tempo_domain)
        real = real + extra
    if (augment or flips) and weight:
        from gaitml.pipeline.augment import POCKET_POSITIONS, SWING_POSITIONS, augmented_set

        pos = SWING_POSITIONS if augment_positions is None else tuple(augment_positions)
        fpos = POCKET_POSITIONS if flip_positions is None else tuple(flip_positions)
        real, _ = augmented_set(real, augment, pos, seed=cfg.seed, share_time=share_time, flips=tuple(flips), flip_positions=fpos)
    for r in real:
        for _ in range(weight):
            recs.append(r)
            groups.append(f"tyrex-{r.meta['subject']}")
    notes = [f"recipe {recipe}"]
    if rates:
        from gaitml.pipeline.augment import rate_copies

        pick = [i for i, r in enumerate(recs) if rate_sources == "all" or r.meta.get("source") != "gaitml.simulate"]
        extra = rate_copies([recs[i] for i in pick], rates)
        groups = groups + [groups[i] for i in pick for _ in rates]
        recs = recs + extra
        notes.append(f"rate copies at {list(rates)} Hz")
    # features.acc_range_ms2: every training recording read through the range, as gaitml train does (after the turns)
    recs = _through_acc_range(recs, cfg["features"]["acc_range_ms2"], notes)
    data = PreparedData(recs, groups, notes, keep_labels=list(MOTION_MODES))
    ds = build_dataset(cfg, data, use_cache=False)
    model = make_model(cfg["model"]["kind"], cfg["model"]["params"], seed=cfg.seed)
    model.fit(ds.inputs("features"), ds.y)
    fset = cfg["features"]["set"]
    info = {
        "name": f"{cfg.name}-{recipe}",
        "model_kind": cfg["model"]["kind"],
        "model_params": cfg["model"]["params"],
        "input_kind": "features",
        "feature_set": fset,
        "feature_names": list(feature_names(fset)),
        "raw_channels": [],
        "window": _window_info(cfg),
        "sampling_rate_hz": ds.sampling_rate_hz,
        "labels": [str(x) for x in model.classes_],
        "postprocess": cfg["postprocess"],
        "training_config": cfg.resolved(),
        "training_data": {"n_windows": len(ds), "n_recordings": len(recs), "groups": sorted(set(groups)), "notes": data.notes},
        "feature_frame": cfg["features"]["frame"],
    }
    if cfg["features"]["acc_range_ms2"]:  # predict reads the left-out people through the model's range
        info["acc_range_ms2"] = float(cfg["features"]["acc_range_ms2"])
    domain = fit_training_domain(cfg, data, ds, model)
    save_model(out_dir, model, info, domain=domain, card=False)
    return load_model(out_dir), len(ds)


def position_table(cfg, items: list[dict]) -> pd.DataFrame:
    """Position recognition, one tyrex person left out: per motion, the share of moving windows given the right position.

    A linear OVO SVM (paper 003, the config's features and windows) on the moving windows of
    the other two people, labelled :data:`COARSE_POSITION` (hand, swinging hand, pocket).
    """
    from gaitml.models import build_window_dataset, make_model

    w = cfg["windows"]
    fset = cfg["features"]["set"]

    def dataset(its):
        recs = []
        for it in its:
            lab = it["recording"].labels.astype(str)
            recs.append(
                it["recording"].replace(
                    labels=np.where(lab == it["mode"], COARSE_POSITION[it["motion"]], "x").astype(object), check_units=False
                )
            )
        return build_window_dataset(
            recs,
            groups=[it["subject"] for it in its],
            length_s=w["length_s"],
            overlap=w["overlap"],
            min_label_fraction=w["min_label_fraction"],
            feature_set=fset,
            keep_labels=sorted(set(COARSE_POSITION.values())),
        )

    rows = []
    for person in sorted({it["subject"] for it in items}):
        train = dataset([it for it in items if it["subject"] != person])
        model = make_model(cfg["model"]["kind"], cfg["model"]["params"], seed=cfg.seed).fit(train.inputs("features"), train.y)
        for motion in MOTION_ORDER:
            its = [it for it in items if it["subject"] == person and it["motion"] == motion]
            test = dataset(its)
            pred = model.predict(test.inputs("features"))
            rows.append({"left_out": person, "motion": motion, "n": len(test), "right": int(np.sum(pred == test.y))})
    t = pd.DataFrame(rows)
    g = t.groupby("motion", sort=False)[["n", "right"]].sum().reset_index()
    g["accuracy"] = g["right"] / g["n"]
    per = t.assign(a=t["right"] / t["n"]).groupby("motion", sort=False)["a"].agg(["min", "max"]).reset_index()
    g["per person"] = [f"{lo:.2f}-{hi:.2f}" for lo, hi in zip(per["min"], per["max"], strict=True)]
    g.insert(1, "position asked", [COARSE_POSITION[m] for m in g["motion"]])
    return g.drop(columns=["right"])


def sim_side_table(model, recs, gate: dict | None = None) -> pd.DataFrame:
    """Held-out simulated recordings: per position and mode, right / flagged / wrong, and read as a side step of either direction."""
    rows = []
    for r in recs:
        p = _predict(model, r, gate)
        inside = p["in_domain"].map(lambda v: v is not False).to_numpy(bool)
        side = inside & p["mode"].astype(str).isin(["side_left", "side_right"]).to_numpy()
        for m in ("walk", "run", *SIDE_MODES):
            w = ((p["label"].astype(str) == m) & (p["label_fraction"] >= 0.5)).to_numpy()
            rows.append({"position": r.meta["position"], "mode": m, **score_windows(p, m), "side": int(np.sum(side & w))})
    t = pd.DataFrame(rows).groupby(["position", "mode"], sort=False)[["n", "right", "flagged", "wrong", "side"]].sum()
    return t.reset_index()


@functools.cache
def _oxford(folder: Path) -> tuple:
    from gaitml.io import read_dataset

    return tuple(read_dataset(folder))


def untrained_table(model, sim_recs, data: Path, fs: float | None = None) -> list[dict]:
    """Share of windows flagged out of domain on what the recipes were not trained on (``fs``: recorded at that rate)."""
    from gaitml.io import read_recording
    from gaitml.models import resample_recording

    def flagged_share(recs):
        n = k = 0
        for r in recs:
            try:
                p = _predict(model, r if fs is None else resample_recording(r, fs))
            except Exception as exc:  # a model that needs a gyroscope cannot read an accelerometer-only set
                return f"n/a ({type(exc).__name__})", 0
            n += len(p)
            k += int(sum(v is False for v in p["in_domain"]))
        return (k / n if n else float("nan")), n

    rows = []
    for pos in ("bag", "belt"):
        share, n = flagged_share([r for r in sim_recs if r.meta["position"] == pos])
        rows.append({"what": f"simulator {pos} (held-out seed)", "windows": n, "flagged": share})
    gm = data / "gaitmap-example" / "imu_sample.csv.gz"
    if gm.exists():
        share, n = flagged_share([read_recording(gm, sensor=s) for s in ("left", "right")])
        rows.append({"what": "gaitmap foot-mounted IMU (both feet)", "windows": n, "flagged": share})
    ox = data / "oxford-step-counter" / "optimisation"
    if ox.exists() and "gyro" not in model.feature_set:
        recs = _oxford(ox)
        for key, name in OXFORD_UNCOVERED.items():
            share, n = flagged_share([r for r in recs if str(r.meta.get("position", "")).lower() == key])
            rows.append({"what": f"Oxford {name} (no gyroscope)", "windows": n, "flagged": share})
    return rows


def rate_flags(model, fs: float) -> bool:
    """Whether ``model``'s rate check flags a recording made at ``fs`` Hz (:func:`gaitml.models.rate_reason`)."""
    from gaitml.models import rate_reason

    return bool(rate_reason(model, fs))


def side_summary(sides: list) -> pd.DataFrame:
    """The held-out simulator's table summed over folds: right / flagged / silently wrong per position and mode, right per fold."""
    s = pd.concat(sides, ignore_index=True)
    g = s.groupby(["position", "mode"], sort=False)[["n", "right", "flagged", "wrong", "side"]].sum().reset_index()
    per = s.assign(r=s["right"] / s["n"]).groupby(["position", "mode"], sort=False)["r"].agg(["min", "max"]).reset_index()
    g["right"] = g["right"] / g["n"]
    g["flagged"] = g["flagged"] / g["n"]
    g["silently wrong"] = g["wrong"] / g["n"]
    g["side step, either direction"] = g.pop("side") / g["n"]
    g["right over folds"] = [f"{lo:.2f}-{hi:.2f}" for lo, hi in zip(per["min"], per["max"], strict=True)]
    return g.drop(columns=["wrong"])


def untrained_summary(untr: list) -> pd.DataFrame:
    """Flagged shares of the untrained positions, one figure per fold."""
    u = pd.DataFrame(untr)
    ug = u.groupby("what", sort=False).agg(
        windows=("windows", "first"), flagged=("flagged", lambda v: "/".join(f"{x:.2f}" if isinstance(x, float) else str(x) for x in v))
    )
    return ug.reset_index()


def md(df: pd.DataFrame) -> str:
    """A DataFrame as a markdown table, shares to 2 decimals."""
    cols = list(df.columns)
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for r in df.to_dict("records"):
        out.append("| " + " | ".join(f"{v:.2f}" if isinstance(v, float) else str(v) for v in r.values()) + " |")
    return "\n".join(out)


def simulated_part(cfg):
    """The simulated part of ``cfg``: a shipped folder config (``data.add_simulated``, e.g. ``experiments/demo.toml``)
    becomes its ``[data.simulated]`` subjects alone, so that the recipes train exactly the shipped settings;
    a simulated config is returned as it is."""
    from gaitml.pipeline.augment import POCKET_POSITIONS, SWING_POSITIONS, TEMPO_LABELS

    if cfg["data"]["source"] == "simulated":
        return cfg
    if not cfg["data"]["add_simulated"]:
        raise SystemExit(f"{cfg.name}: a folder config needs data.add_simulated = true (its simulated part is the recipes' simulator).")
    return cfg.with_values(
        {
            "data.source": "simulated",
            "data.path": "",
            "data.label": "label",
            "data.labels": [],
            "data.add_simulated": False,
            "data.labelling.moving_speed_ms": 0.0,
            # the copies belong to the real part (train_recipe adds them): every augment key back to its default,
            # which a simulated source requires
            "data.augment.swing_turns": 0,
            "data.augment.share_time": False,
            "data.augment.positions": list(SWING_POSITIONS),
            "data.augment.flips": [],
            "data.augment.flip_positions": list(POCKET_POSITIONS),
            "data.augment.tempo": [],
            "data.augment.tempo_labels": list(TEMPO_LABELS),
            "data.augment.tempo_positions": [],
            "data.augment.tempo_in_domain": True,
        }
    )


def augment_of(cfg) -> tuple[int, list[str], bool]:
    """A folder config's ``[data.augment]`` (rotated copies of the real swinging recordings), or no copies."""
    aug = cfg["data"]["augment"]
    turns = int(aug["swing_turns"]) if cfg["data"]["source"] == "folder" else 0
    return turns, list(aug["positions"]), bool(aug["share_time"])


def flips_of(cfg) -> tuple[list[str], list[str]]:
    """A folder config's pocket flips (``data.augment.flips``, ``flip_positions``), or none."""
    aug = cfg["data"]["augment"]
    return (list(aug["flips"]) if cfg["data"]["source"] == "folder" else []), list(aug["flip_positions"])


def main(argv=None) -> int:
    from gaitml.models import load_model
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument(
        "--config",
        type=Path,
        default=Path("experiments/tyrex-modes.toml"),
        help="the recipes' settings and simulated part: a simulated config, or a shipped folder config such as experiments/demo.toml",
    )
    ap.add_argument("--features", default=None, help="override features.set (all52 for the accelerometer-only twin)")
    ap.add_argument("--recipes", default="sim,a,b,c")
    ap.add_argument("--holdout", choices=("person", "person-phone"), default="person", help="what each fold leaves out")
    ap.add_argument("--baseline", default="models/demo,models/demo-acc", help="shipped models to score first ('' = none)")
    ap.add_argument("--sim-subjects", type=int, default=None, help="override data.simulated.subjects")
    ap.add_argument("--share-time", choices=("on", "off"), default=None, help="override data.augment.share_time")
    ap.add_argument(
        "--swing-turns",
        type=int,
        default=None,
        help="override data.augment.swing_turns (rotated copies of the real recordings in data.augment.positions; "
        "default: the config's, 0 for a simulated config)",
    )
    ap.add_argument(
        "--acc-range-ms2",
        type=float,
        default=None,
        help="override features.acc_range_ms2 (the accelerometer range the recipes' models read every phone through; 0 = none)",
    )
    ap.add_argument(
        "--flips",
        default=None,
        help="override data.augment.flips: comma-separated phone axes of the pocket flips ('' = none; default: the config's)",
    )
    ap.add_argument(
        "--flip-simulated", action="store_true", help="lab: flip the simulated recordings in the flip positions too (every mode)"
    )
    ap.add_argument(
        "--rates",
        default=None,
        help="override data.augment.rates: comma-separated sampling rates (Hz) every training recording also trains at, "
        "taken down and back up ('' = none; default: the config's)",
    )
    ap.add_argument(
        "--tempo",
        default=None,
        help="override data.augment.tempo: comma-separated tempo factors the real running recordings (data.augment.tempo_labels) "
        "also train at, replayed faster or slower ('' = none; default: the config's)",
    )
    ap.add_argument(
        "--tempo-domain",
        choices=("on", "off"),
        default=None,
        help="override data.augment.tempo_in_domain: off keeps the tempo copies out of the domain record (they train the "
        "classifier only; default: the config's)",
    )
    ap.add_argument(
        "--tempo-positions",
        default=None,
        help="override data.augment.tempo_positions: comma-separated carrying positions (meta position, e.g. pocket) whose "
        "running recordings get the tempo copies ('' = every position; default: the config's)",
    )
    ap.add_argument(
        "--score-rates",
        default=None,
        help="comma-separated rates (Hz) the left-out people's recordings (and the held-out simulator) are scored at, "
        "as phones recording at that rate (default: the model's rate only)",
    )
    ap.add_argument("--heldout-seed", type=int, default=HELDOUT_SEED, help="seed of the held-out simulated subjects (default %(default)s)")
    ap.add_argument("--rate-sources", choices=("all", "real"), default="all", help="lab: which training recordings get the rate copies")
    ap.add_argument("--cache", type=Path, default=None, help="keep the trained fold models here and reuse them (e.g. /tmp/rates)")
    ap.add_argument("--no-positions", dest="positions", action="store_false", help="skip the position recognition table")
    ap.add_argument("--out", type=Path, default=None, help="write the markdown tables here too")
    ap.add_argument("--csv", type=Path, default=None, help="per-recording rows of every model and fold")
    ap.add_argument("--still-rule", choices=("std", "range"), default=None, help="the still gate's rule (default: gaitml's)")
    ap.add_argument("--still-threshold", type=float, default=None, metavar="MS2", help="the still gate's threshold (default: the rule's)")
    ap.add_argument(
        "--moving-rule",
        choices=("speed", "walking"),
        default="speed",
        help="which windows are scored as moving: the body speed rule (default) or the walking rule (speed of the "
        "lever-corrected body point and step-band bounce); training uses the speed rule either way",
    )
    ap.add_argument(
        "--run-cadence",
        default=None,
        metavar="on|off|HZ",
        help="the run-cadence rule (gaitml predict --run-cadence): on (gaitml.models._predict.RUN_MIN_CADENCE_HZ), off, or steps/s; "
        "default: the library's",
    )
    ap.add_argument(
        "--model-cache",
        type=Path,
        default=None,
        help="the same as --cache (kept for the run-cadence report's commands)",
    )
    ap.add_argument(
        "--candidate",
        choices=("walk-cadence", "walk-run-nearest"),
        default=None,
        help="lab: a post-hoc flag of experiments.scripts.run20 on every prediction table (the report's 'Running in a pocket at 20 Hz')",
    )
    a = ap.parse_args(argv)
    global CANDIDATE
    CANDIDATE = a.candidate
    if a.cache is None:
        a.cache = a.model_cache
    gate = {k: v for k, v in (("still_rule", a.still_rule), ("still_threshold_ms2", a.still_threshold)) if v is not None}
    if a.run_cadence is not None:
        from gaitml.commands.predict import run_cadence_arg

        gate["run_min_cadence_hz"] = run_cadence_arg(a.run_cadence)
    cfg_full = load_config(a.config)
    if a.acc_range_ms2 is not None:
        cfg_full = cfg_full.with_values({"features.acc_range_ms2": a.acc_range_ms2})
    turns, turn_positions, share_time = augment_of(cfg_full)
    if a.swing_turns is not None:
        turns = a.swing_turns
    if a.share_time is not None:
        share_time = a.share_time == "on"
    flips, flip_positions = flips_of(cfg_full)
    if a.flips is not None:
        flips = [f for f in a.flips.split(",") if f]
    tempo = [float(f) for f in cfg_full["data"]["augment"]["tempo"]] if cfg_full["data"]["source"] == "folder" else []
    if a.tempo is not None:
        tempo = [float(f) for f in a.tempo.split(",") if f]
    tempo_labels = list(cfg_full["data"]["augment"]["tempo_labels"])
    tempo_positions = list(cfg_full["data"]["augment"]["tempo_positions"])
    if a.tempo_positions is not None:
        tempo_positions = [p for p in a.tempo_positions.split(",") if p]
    tempo_domain = bool(cfg_full["data"]["augment"]["tempo_in_domain"])
    if a.tempo_domain is not None:
        tempo_domain = a.tempo_domain == "on"
    if tempo and tempo_positions:
        from gaitml.io.tyrex import TYREX_MODES, TYREX_POSITIONS

        known = sorted({TYREX_POSITIONS[m] for m, mode in TYREX_MODES.items() if mode in tempo_labels})
        unknown = [p for p in tempo_positions if p not in known]
        if unknown:
            raise SystemExit(
                f"--tempo-positions has {unknown}, no {'/'.join(tempo_labels)} recording's position; positions: {', '.join(known)}."
            )
    rates = [float(r) for r in cfg_full["data"]["augment"]["rates"]]
    if a.rates is not None:
        rates = [float(r) for r in a.rates.split(",") if r]
    cfg = simulated_part(cfg_full)
    over = {}
    if a.features:
        over["features.set"] = a.features
    if a.sim_subjects:
        over["data.simulated.subjects"] = a.sim_subjects
    if over:
        cfg = cfg.with_values(over)
    fs = float(cfg["data"]["resample_hz"])
    score_rates = [fs] if a.score_rates is None else [float(r) for r in a.score_rates.split(",") if r]
    t0 = time.perf_counter()
    items = load_tyrex_labelled(a.data, fs)
    print(f"[tyrex_modes] {len(items)} tyrex recordings read ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    if a.moving_rule == "walking":
        from experiments.scripts.tyrex_ar_moving import item_walking_labels

        for it in items:
            it["score_recording"] = it["recording"].replace(labels=item_walking_labels(it), check_units=False)
    text: list[str] = []
    rows_all = []

    def emit(s=""):
        print(s)
        text.append(s)

    n_moving = sum(int(np.sum(it["recording"].labels.astype(str) == it["mode"])) for it in items)
    n_in = sum(int(np.sum(it["recording"].labels.astype(str) != "unlabelled")) for it in items)
    emit(f"moving samples (body speed > 0.3 m/s): {n_moving / n_in:.3f} of the captured samples")
    if a.moving_rule == "walking":
        n_walk = sum(int(np.sum(it["score_recording"].labels.astype(str) == it["mode"])) for it in items)
        emit(
            f"scored: the walking rule's windows (lever-corrected speed > 0.3 m/s and step-band bounce >= 1 cm): walking samples "
            f"{n_walk / n_in:.3f} of the captured samples; the models are trained on the speed rule's windows as before"
        )
    for mdir in [m for m in a.baseline.split(",") if m]:
        model = load_model(mdir)
        seen = sorted(set((model.info.get("training_data") or {}).get("groups") or []) & {it["subject"] for it in items})
        how = f"in-sample: trained on {', '.join(seen)}" if seen else "trained on none of them"
        for sr in score_rates:
            t = window_table(model, items if sr == fs else at_rate(items, sr), gate)
            t["model"], t["score_rate_hz"] = mdir, sr
            rows_all.append(t)
            at = "" if sr == fs else f", recorded at {sr:g} Hz"
            emit(
                f"\n### {mdir} as it is, all 3 people ({how}){at}{' (windows by the walking rule)' if a.moving_rule == 'walking' else ''}\n"
            )
            emit(md(summarise(t)))
            if rate_flags(model, sr):
                with without_rate_check(model):
                    t2 = window_table(model, at_rate(items, sr), gate)
                t2["model"], t2["score_rate_hz"] = f"{mdir} (rate check off)", sr
                rows_all.append(t2)
                emit("\nthe same without the rate check (every window above is flagged for the rate; what the features alone answer):\n")
                emit(md(summarise(t2)))
    if a.positions and a.holdout == "person":
        emit(f"\n### position recognition ({cfg['features']['set']}, real tyrex moving windows only), each person left out in turn\n")
        emit(md(position_table(cfg, items)))
    positions = cfg["data"]["simulated"]["positions"]
    sim_train = _sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], positions)
    sim_test = _sim(cfg, a.heldout_seed, 2, [*positions, "bag", "belt"])
    if a.holdout == "person":
        folds = [(p, None) for p in sorted({it["subject"] for it in items})]
    else:  # another person AND another phone: train on the other two people's other two phones
        folds = sorted({(it["subject"], it["phone"]) for it in items})
    from gaitml.models import resample_recording

    for recipe in [r for r in a.recipes.split(",") if r]:
        tabs, sides, untr, tabs_speed = [], [], [], []
        by_rate: dict = {sr: {"tabs": [], "off": [], "sides": [], "sides_off": [], "untr": []} for sr in score_rates if sr != fs}
        for person, phone in folds:
            t1 = time.perf_counter()
            train = [it for it in items if it["subject"] != person and (phone is None or it["phone"] != phone)]
            test = [it for it in items if it["subject"] == person and (phone is None or it["phone"] == phone)]
            person = person if phone is None else f"{person}/{phone}"
            kw = dict(
                augment=turns,
                augment_positions=turn_positions,
                share_time=share_time,
                flips=flips,
                flip_positions=flip_positions,
                flip_simulated=a.flip_simulated,
                rates=rates,
                rate_sources=a.rate_sources,
            )
            if tempo:  # only when set: the cache key of the fold models without tempo copies stays as it was
                kw.update(tempo=tempo, tempo_labels=tempo_labels)
                if not tempo_domain:
                    kw["tempo_domain"] = False
                if tempo_positions:  # likewise: round 1's caches (every position) keep their key
                    kw["tempo_positions"] = tempo_positions
            with tempfile.TemporaryDirectory() as tmp:
                mdir = Path(tmp) / "m"
                if a.cache is not None:
                    import hashlib
                    import json

                    key = json.dumps(
                        [cfg.resolved(), recipe, person, str(a.data), {k: list(v) if isinstance(v, tuple) else v for k, v in kw.items()}],
                        sort_keys=True,
                        default=str,
                    )
                    mdir = (
                        a.cache
                        / "models"
                        / f"{cfg.name}-{recipe}-{person.replace('/', '_')}-{hashlib.sha256(key.encode()).hexdigest()[:12]}"
                    )
                if (mdir / "model.json").exists():
                    model = load_model(mdir)
                    n_win = model.info["training_data"]["n_windows"]
                else:
                    model, n_win = train_recipe(cfg, sim_train, train, recipe, mdir, **kw)
            t = window_table(model, test, gate)
            t["model"], t["left_out"] = f"recipe {recipe} ({cfg['features']['set']})", person
            tabs.append(t)
            if a.moving_rule == "walking":  # the same model scored over the speed rule's windows, side by side
                ts = window_table(model, [{k: v for k, v in it.items() if k != "score_recording"} for it in test], gate)
                ts["model"], ts["left_out"] = f"recipe {recipe} ({cfg['features']['set']}), speed rule", person
                tabs_speed.append(ts)
            sim_in = [r for r in sim_test if r.meta["position"] in positions]
            s = sim_side_table(model, sim_in, gate)
            s["left_out"] = person
            sides.append(s)
            for row in untrained_table(model, sim_test, a.data):
                untr.append({**row, "left_out": person})
            for sr, acc in by_rate.items():  # the left-out person and the held-out simulator recorded at a lower rate
                test_r = at_rate(test, sr)
                sim_r = [resample_recording(r, sr) for r in sim_in]
                t_r = window_table(model, test_r, gate)
                t_r["model"], t_r["left_out"], t_r["score_rate_hz"] = f"recipe {recipe} ({cfg['features']['set']})", person, sr
                acc["tabs"].append(t_r)
                s_r = sim_side_table(model, sim_r, gate)
                s_r["left_out"] = person
                acc["sides"].append(s_r)
                if rate_flags(model, sr):
                    with without_rate_check(model):
                        t_o = window_table(model, test_r, gate)
                        s_o = sim_side_table(model, sim_r, gate)
                    t_o["model"], t_o["left_out"], t_o["score_rate_hz"] = f"recipe {recipe} (rate check off)", person, sr
                    s_o["left_out"] = person
                    acc["off"].append(t_o)
                    acc["sides_off"].append(s_o)
                for row in untrained_table(model, sim_test, a.data, fs=sr):
                    acc["untr"].append({**row, "left_out": person})
            print(
                f"[tyrex_modes] recipe {recipe}, {person} left out: {n_win} training windows, {time.perf_counter() - t1:.0f} s",
                file=sys.stderr,
            )
        t = pd.concat(tabs, ignore_index=True)
        rows_all.append(t)
        what = (
            "each tyrex person left out in turn"
            if a.holdout == "person"
            else "each person x phone left out (trained on the other people's other phones)"
        )
        rule = " (windows by the walking rule)" if a.moving_rule == "walking" else ""
        aug = (
            f", the real {'/'.join(turn_positions)} recordings turned about the swing axis ({turns} copies"
            + (", sharing the recording's time)" if share_time else ")")
            if turns
            else ""
        ) + (
            f", pocket flips about {'/'.join(flips)} in {'/'.join(flip_positions)}" + (" (real and simulated)" if a.flip_simulated else "")
            if flips
            else ""
        )
        if tempo:
            aug += (
                f", the real {'/'.join(tempo_labels)} recordings"
                + (f" in {'/'.join(tempo_positions)}" if tempo_positions else "")
                + f" also at tempo {'/'.join(f'{f:g}' for f in tempo)} (data.augment.tempo"
                + (", not in the domain record)" if not tempo_domain else ")")
            )
        if rates:
            which = "every training recording" if a.rate_sources == "all" else "every real training recording (not the simulated)"
            aug += f", {which} also at {'/'.join(f'{r:g}' for r in rates)} Hz (data.augment.rates)"
        emit(f"\n### recipe {recipe} ({cfg['features']['set']}){aug}, {what}{rule}\n")
        emit(md(summarise(t, by="left_out")))
        if tabs_speed:
            ts = pd.concat(tabs_speed, ignore_index=True)
            rows_all.append(ts)
            emit(f"\n### the same models over the speed rule's windows (recipe {recipe}, {what})\n")
            emit(md(summarise(ts, by="left_out")))
        ns, nf = t["n_still"].sum(), t["still_flagged"].sum()
        no = t["still_out_of_domain"].sum() if "still_out_of_domain" in t else nf
        emit(
            f"\nstill windows of the left-out people flagged: {nf / max(ns, 1):.2f} of {ns} "
            f"(out of domain, the domain check's false alarms: {no / max(ns, 1):.3f}; marked still_unsure: {(nf - no) / max(ns, 1):.3f})"
        )
        emit(f"\nheld-out simulator (seed {a.heldout_seed}, 2 subjects, windows summed over the {len(folds)} folds' models)\n")
        emit(md(side_summary(sides)))
        emit(
            "\nnot trained on, flagged (one figure per fold, in the order "
            + ", ".join(p if q is None else f"{p}/{q}" for p, q in folds)
            + ")\n"
        )
        emit(md(untrained_summary(untr)))
        for sr, acc in by_rate.items():
            tr = pd.concat(acc["tabs"], ignore_index=True)
            rows_all.append(tr)
            emit(f"\n#### recipe {recipe}{aug}: the left-out people recorded at {sr:g} Hz ({what})\n")
            emit(md(summarise(tr, by="left_out")))
            if acc["off"]:
                to = pd.concat(acc["off"], ignore_index=True)
                rows_all.append(to)
                emit(f"\nthe same without the rate check (what the features alone answer at {sr:g} Hz):\n")
                emit(md(summarise(to, by="left_out")))
            emit(f"\nheld-out simulator recorded at {sr:g} Hz (seed {a.heldout_seed})\n")
            emit(md(side_summary(acc["sides"])))
            if acc["sides_off"]:
                emit(f"\nthe same without the rate check (held-out simulator at {sr:g} Hz):\n")
                emit(md(side_summary(acc["sides_off"])))
            emit(f"\nnot trained on, recorded at {sr:g} Hz, flagged (one figure per fold)\n")
            emit(md(untrained_summary(acc["untr"])))
    if a.csv:
        pd.concat(rows_all, ignore_index=True).to_csv(a.csv, index=False)
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
