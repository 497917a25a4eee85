"""Cached person-out fold models of a tyrex recipe, and their per-window predictions (diagnosis of misread windows).

``python -m experiments.scripts.tyrex_folds --config experiments/demo.toml [--recipe a] [--cache /tmp/runswing] [--tag NAME]
[--augment N [--augment-positions P,..] [--share-time]] [--flips x,y,z [--flip-positions P,..]] [--score-flipped] [--diagnose MOTION,..]``
from the repository root.

Trains :func:`experiments.scripts.tyrex_modes.train_recipe` once per left-out tyrex person
(the same folds and settings as ``tyrex_modes --recipes a``) and keeps the models under
``CACHE/TAG/fold-PERSON``; then writes every left-out window's prediction
(:func:`gaitml.models.predict_recording`) with the domain columns and which test flagged it
(feature distance, gravity angle, dynamics span) to ``CACHE/TAG/windows.pkl``. A rerun
reuses the cached models. ``--diagnose`` prints, for the named motions, what the misread
windows were read as, which domain test flagged the flagged ones, the recordings that
carry them, and per recording what physically differs (:func:`physical_table`).
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd


def load_items(data: Path, fs: float, cache: Path) -> list[dict]:
    """:func:`tyrex_modes.load_tyrex_labelled`, pickled under ``cache``."""
    from experiments.scripts.tyrex_modes import load_tyrex_labelled

    f = cache / f"items-{fs:g}.pkl"
    if f.exists():
        return pickle.loads(f.read_bytes())
    items = load_tyrex_labelled(data, fs)
    f.write_bytes(pickle.dumps(items))
    return items


def fold_predictions(model, items: list[dict]) -> pd.DataFrame:
    """Per window of ``items``: prediction, label, domain columns, and which domain test failed."""
    from gaitml.models import predict_recording

    dom = model.domain
    rows = []
    for it in items:
        p = predict_recording(model, it["recording"])
        p = p.assign(subject=it["subject"], phone=it["phone"], motion=it["motion"], true_mode=it["mode"], recording=str(it.get("file", "")))
        p["fail_distance"] = p["domain_distance"] > dom.distance_threshold
        p["fail_gravity"] = (p["gravity_angle_deg"] > np.degrees(dom.gravity_threshold_rad)) if dom.gravity_check else False
        if "dynamics_distance" in p:
            p["fail_dynamics"] = p["dynamics_distance"] > dom.dynamics["threshold"]
        rows.append(p)
    return pd.concat(rows, ignore_index=True)


def _clipped(rec, limit_ms2: float):
    """``rec`` as read by an accelerometer whose range stops at +-``limit_ms2`` per axis."""
    return rec.replace(acc=np.clip(rec.acc, -limit_ms2, limit_ms2), check_units=False)


def _moving(t: pd.DataFrame) -> pd.DataFrame:
    w = t[(t["label"].astype(str) == t["true_mode"]) & (t["label_fraction"] >= 0.5)].copy()
    w["flag"] = w["in_domain"].map(lambda v: v is False)
    w["right"] = ~w["flag"] & (w["mode"] == w["true_mode"])
    w["wrong"] = ~w["flag"] & ~w["right"]
    return w


def diagnose(t: pd.DataFrame, motions) -> str:
    """Markdown: per motion and left-out person, right / flagged / wrong, the modes of the wrong windows, the failing tests, the worst recordings."""
    from experiments.scripts.tyrex_modes import md

    w = _moving(t)
    rows, recs = [], []
    for (motion, person), g in w[w["motion"].isin(motions)].groupby(["motion", "left_out"]):
        wrong = g[g["wrong"]]["mode"].value_counts()
        f = g[g["flag"]]
        rows.append(
            {
                "motion": motion,
                "left out": person,
                "windows": len(g),
                "right": g["right"].mean(),
                "flagged": g["flag"].mean(),
                "wrong": g["wrong"].mean(),
                "wrong read as": ", ".join(f"{m} {n}" for m, n in wrong.items()) or "-",
                "flagged by distance / gravity / dynamics": f"{int(f['fail_distance'].sum())} / {int(f['fail_gravity'].sum())} / "
                f"{int(f['fail_dynamics'].sum()) if 'fail_dynamics' in f else 0}",
            }
        )
        for rec, h in g.groupby("recording"):
            if (~h["right"]).mean() > 0.1:
                recs.append({"motion": motion, "recording": rec, "windows": len(h), "not right": (~h["right"]).mean()})
    return md(pd.DataFrame(rows)) + "\n\nrecordings with more than 10 % of their moving windows not right:\n\n" + md(pd.DataFrame(recs))


def physical_table(items: list[dict], motions) -> pd.DataFrame:
    """Per recording of ``motions``, over its moving samples: what a carried phone's signal is made of.

    body speed (median of the motion capture's low-passed path speed where above 0.3 m/s), the
    dominant |acc| frequency (0.6-4 Hz), |acc| median and 95th percentile, the largest |axis| (a
    sensor range: Nexus 5 and iPhone 4S stop near 2 g), the share of samples with an axis above 19
    m/s^2, gyroscope RMS, the swing axis (:func:`gaitml.pipeline.augment.swing_axis`) and the
    cosine of gravity to it (0: the phone turns about a horizontal axis), and the mean gravity
    direction in the phone frame (the grip).
    """
    from gaitml.evaluation.trajectory import body_track
    from gaitml.pipeline.augment import swing_axis

    rows = []
    for it in items:
        if it["motion"] not in motions:
            continue
        r = it["recording"]
        mv = r.labels.astype(str) == it["mode"]
        tr = it["truth"]
        b = body_track(tr.t_s, tr.pos_m[:, :2])
        v = np.linalg.norm(np.gradient(b, axis=0), axis=1) / np.median(np.diff(tr.t_s))
        m = np.linalg.norm(r.acc, axis=1)[mv]
        x = m - m.mean()
        f = np.fft.rfftfreq(len(x), 1 / r.sampling_rate_hz)
        p = np.abs(np.fft.rfft(x)) ** 2
        band = (f > 0.6) & (f < 4.0)
        g = r.gyr[mv]
        ax = swing_axis(r.gyr, r.sampling_rate_hz)
        ax = ax * np.sign(ax[np.argmax(np.abs(ax))])
        gu = r.acc[mv].mean(0)
        gu = gu / np.linalg.norm(gu)
        rows.append(
            {
                "motion": it["motion"],
                "recording": str(it["file"]).split("/")[-1],
                "body m/s": round(float(np.median(v[v > 0.3])), 2),
                "acc-norm Hz": round(float(f[band][np.argmax(p[band])]), 2),
                "acc-norm p50": round(float(np.percentile(m, 50)), 1),
                "acc-norm p95": round(float(np.percentile(m, 95)), 1),
                "max axis": round(float(np.abs(r.acc[mv]).max()), 1),
                "share > 19": round(float(np.mean(np.abs(r.acc[mv]).max(1) > 19.0)), 2),
                "gyro rms": round(float(np.sqrt((g**2).sum(1).mean())), 2),
                "swing axis": str(np.round(ax, 2).tolist()),
                "cos(g, axis)": round(float(abs(gu @ ax)), 2),
                "gravity in phone": str(np.round(gu, 2).tolist()),
            }
        )
    return pd.DataFrame(rows).sort_values(["motion", "recording"])


def orientation_table(items: list[dict], motions) -> pd.DataFrame:
    """Per recording of ``motions``: which way round the phone is carried, in the walker's frame.

    Over the moving samples: ``up`` is the mean specific force (gravity's opposite, from the
    accelerometer), ``forward`` the motion capture's walking direction (the body track's horizontal
    velocity turned into the phone frame by the captured attitude, mean, made perpendicular to up),
    ``left = up x forward``. The phone's top (+y) and screen normal (+z) are given on (up, forward,
    left): top up / down, screen forward / backward / to the walker's left or right. The swing axis
    (:func:`gaitml.pipeline.augment.swing_axis`, sign chosen to point left) on the same frame: its
    ``up`` part is the tilt a turn of the phone cannot change (a rigid turn of the phone frame keeps
    every angle between gravity, the walking direction and the swing axis).
    """
    from gaitml.evaluation.trajectory import body_track
    from gaitml.pipeline.augment import swing_axis

    rows = []
    for it in items:
        if it["motion"] not in motions:
            continue
        tr, r = it["truth"], it["recording"]
        b = body_track(tr.t_s, tr.pos_m[:, :2])
        v = np.gradient(b, axis=0) / np.median(np.diff(tr.t_s))
        sp = np.linalg.norm(v, axis=1)
        m = (sp > 0.3) & tr.valid
        f = np.zeros((int(m.sum()), 3))
        f[:, :2] = v[m] / sp[m, None]
        fwd = np.einsum("nji,nj->ni", tr.rot[m], f).mean(0)  # room -> phone frame: rot^T f
        mv = r.labels.astype(str) == it["mode"]
        up = r.acc[mv].mean(0)
        up /= np.linalg.norm(up)
        fwd = fwd - (fwd @ up) * up
        fwd /= np.linalg.norm(fwd)
        left = np.cross(up, fwd)
        ax = swing_axis(r.gyr, r.sampling_rate_hz)
        ax = ax if ax @ left >= 0 else -ax
        rows.append(
            {
                "motion": it["motion"],
                "person": it["subject"],
                "recording": str(it["file"]).split("/")[-1],
                "top (y) on up / fwd / left": f"{up[1]:+.2f} / {fwd[1]:+.2f} / {left[1]:+.2f}",
                "screen (z) on up / fwd / left": f"{up[2]:+.2f} / {fwd[2]:+.2f} / {left[2]:+.2f}",
                "swing axis on up / fwd / left": f"{ax @ up:+.2f} / {ax @ fwd:+.2f} / {ax @ left:+.2f}",
            }
        )
    return pd.DataFrame(rows).sort_values(["motion", "recording"])


def flipped_table(out: Path, items: list[dict], motions=("FrontPocket", "BackPocket", "RunningPocket")) -> pd.DataFrame:
    """Each fold model of ``out`` on its left-out person's ``motions`` as recorded and flipped 180 deg about the phone's x, y, z.

    A phone put into the pocket another way round (:func:`gaitml.pipeline.augment.flip_rotation`);
    per motion, flip and left-out person: right / flagged / silently wrong over the moving windows,
    and the share flagged by the gravity-angle test.
    """
    from gaitml.models import load_model
    from gaitml.pipeline.augment import FLIP_AXES, flip_rotation, rotate_recording

    rows = []
    for person in sorted({it["subject"] for it in items}):
        model = load_model(out / f"fold-{person}")
        mine = [it for it in items if it["subject"] == person and it["motion"] in motions]
        for ax in ("none", *FLIP_AXES):
            its = [
                it if ax == "none" else {**it, "recording": rotate_recording(it["recording"], flip_rotation(ax), f"flipped about {ax}")}
                for it in mine
            ]
            w = _moving(fold_predictions(model, its))
            for motion, g in w.groupby("motion"):
                rows.append(
                    {
                        "motion": motion,
                        "flip": ax,
                        "left out": person,
                        "windows": len(g),
                        "right": g["right"].mean(),
                        "flagged": g["flag"].mean(),
                        "wrong": g["wrong"].mean(),
                        "flagged by gravity": (g["flag"] & g["fail_gravity"]).mean(),
                    }
                )
    return pd.DataFrame(rows).sort_values(["motion", "flip", "left out"])


def main(argv=None) -> int:
    from experiments.scripts.tyrex_modes import _sim, simulated_part, train_recipe
    from gaitml.models import load_model
    from gaitml.pipeline.config import load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--config", type=Path, default=Path("experiments/demo.toml"))
    ap.add_argument("--recipe", default="a")
    ap.add_argument("--cache", type=Path, default=Path("/tmp/runswing"))
    ap.add_argument("--tag", default="base")
    ap.add_argument("--augment", type=int, default=0, help="rotated copies per real recording (the phone turned about its swing axis)")
    ap.add_argument("--augment-positions", default=None, help="comma-separated positions to augment (default: the swinging ones)")
    ap.add_argument("--share-time", action="store_true", help="the original and its copies share the recording's time")
    ap.add_argument("--flips", default="", help="pocket flips: comma-separated phone axes (x,y,z) the copies are turned 180 deg about")
    ap.add_argument("--flip-positions", default=None, help="comma-separated positions given the flips (default: the pockets)")
    ap.add_argument(
        "--clip-ms2",
        type=float,
        default=0.0,
        help="lab experiment: clip every accelerometer axis at +-this (e.g. 19.6, the 2 g range of the Nexus 5 and "
        "iPhone 4S) in training and in the left-out recordings alike (0: off)",
    )
    ap.add_argument(
        "--acc-range-ms2",
        type=float,
        default=None,
        help="override features.acc_range_ms2: the fold models read every phone through this range in gaitml's own "
        "training and predict path (the left-out recordings are passed as recorded)",
    )
    ap.add_argument(
        "--score-flipped",
        action="store_true",
        help="also score each left-out person's pocket recordings flipped 180 deg about the phone's x, y, z (a phone put in another way round)",
    )
    ap.add_argument("--diagnose", default="", help="comma-separated motions to diagnose (e.g. Swinging,RunningHand,RunningPocket)")
    a = ap.parse_args(argv)
    cfg_full = load_config(a.config)
    if a.acc_range_ms2 is not None:
        cfg_full = cfg_full.with_values({"features.acc_range_ms2": a.acc_range_ms2})
    cfg = simulated_part(cfg_full)
    out = a.cache / a.tag
    out.mkdir(parents=True, exist_ok=True)
    items = load_items(a.data, cfg["data"]["resample_hz"], a.cache)
    if a.clip_ms2 > 0:
        items = [{**it, "recording": _clipped(it["recording"], a.clip_ms2)} for it in items]
    sim_train = None
    tabs = []
    for person in sorted({it["subject"] for it in items}):
        t0 = time.perf_counter()
        mdir = out / f"fold-{person}"
        if not (mdir / "model.json").exists():
            if sim_train is None:
                sim_train = _sim(cfg, cfg.seed, cfg["data"]["simulated"]["subjects"], cfg["data"]["simulated"]["positions"])
                if a.clip_ms2 > 0:
                    sim_train = [_clipped(r, a.clip_ms2) for r in sim_train]
            train_recipe(
                cfg,
                sim_train,
                [it for it in items if it["subject"] != person],
                a.recipe,
                mdir,
                augment=a.augment,
                augment_positions=a.augment_positions.split(",") if a.augment_positions else None,
                share_time=a.share_time,
                flips=[f for f in a.flips.split(",") if f],
                flip_positions=a.flip_positions.split(",") if a.flip_positions else None,
            )
        model = load_model(mdir)
        tabs.append(fold_predictions(model, [it for it in items if it["subject"] == person]).assign(left_out=person))
        print(f"[tyrex_folds] {a.tag}: {person} out, {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    t = pd.concat(tabs, ignore_index=True)
    t.to_pickle(out / "windows.pkl")
    print(f"[tyrex_folds] wrote {out / 'windows.pkl'} ({len(t)} windows)", file=sys.stderr)
    if a.diagnose:
        from experiments.scripts.tyrex_modes import md

        motions = a.diagnose.split(",")
        print(diagnose(t, motions))
        print("\nper recording, over its moving samples:\n")
        print(md(physical_table(items, motions)))
        print("\nwhich way round the phone is carried (per recording, walker's frame from the motion capture):\n")
        print(md(orientation_table(items, motions)))
    if a.score_flipped:
        from experiments.scripts.tyrex_modes import md

        print("\nthe left-out person's pockets as recorded and put in another way round (fold models):\n")
        print(md(flipped_table(out, items)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
