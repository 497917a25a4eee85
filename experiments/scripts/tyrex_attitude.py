"""gaitml's attitude and heading sources against the tyrex motion capture: tilt error and heading drift per motion.

``python -m experiments.scripts.tyrex_attitude [--data ../shared/data] [--csv FILE] [--out FILE] [--no-headings]``
from the repository root (about 5 minutes). For every tyrex recording with motion capture
(read as in :mod:`experiments.scripts.tyrex_pdr`):

- the phone's true attitude is the motion-capture body's attitude times the holder's mount
  rotation, estimated per recording from the gyroscope against the capture's angular rate
  (:func:`gaitml.io.tyrex.estimate_mount_rotation`; a fixed mechanical offset of a few degrees);
- attitude sources (:class:`gaitml.pdr.attitude.AttitudeEstimator`): ``gaitml`` (the default,
  gyroscope with a complementary pull toward the gravity low-passed at 0.3 Hz, gain 0.5 1/s, the
  gyroscope bias removed: ``gyro_bias='auto'``), ``gaitml-still`` (the bias from still stretches
  only), ``gaitml-nobias`` (the bias as logged), ``paper003`` (``gravity_gain_hz=0``, bias as
  logged: pure quaternion integration from the first second's tilt, paper 003 sec. 4.2), and
  ``gravity`` (the low-passed accelerometer direction alone: tilt only, no gyroscope);
- tilt error: angle between the estimated and the true "up" in the phone's axes, per sample
  (20 Hz), mean over the capture per recording;
- heading drift of the attitude: the yaw of the error rotation ``R_est R_true^T`` (a rotation
  about the vertical when the tilt is right: the unknown start heading plus the drift),
  unwrapped, fitted by a line: its slope in deg/min (absolute);
- heading sources per step (``--no-headings`` skips them): ``gaitml pdr --detector adaptive``
  with ``--heading gyro | hde | dwpca | dwpca-hde``: the walking-direction drift of the
  trajectory against the walker's (:func:`gaitml.evaluation.trajectory.walking_direction_drift`).

Tables: median over the recordings of each motion; per person.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_pdr import MOTION_ORDER, load_tyrex, md

__all__ = ["attitude_scores", "heading_source_drifts", "main"]

EVAL_RATE_HZ = 20.0


def _attitude_sources() -> dict:
    from gaitml.pdr.attitude import AttitudeEstimator

    return {
        "gaitml": AttitudeEstimator(),  # the default: bias from still stretches, then tracked online
        "gaitml-still": AttitudeEstimator(gyro_bias="still"),
        "gaitml-nobias": AttitudeEstimator(gyro_bias="off"),
        "paper003": AttitudeEstimator(gravity_gain_hz=0.0, gyro_bias="off"),
    }


ATTITUDE_SOURCES = _attitude_sources()
HEADING_SOURCES = ("gyro", "hde", "dwpca", "dwpca-hde")


def _yaw_of(e: np.ndarray) -> np.ndarray:
    """Angle about the vertical of rotation matrices (n, 3, 3) that are (nearly) rotations about z."""
    return np.arctan2(e[:, 1, 0] - e[:, 0, 1], e[:, 0, 0] + e[:, 1, 1])


def attitude_scores(item) -> list[dict]:
    """Tilt error and attitude heading drift of each attitude source on one recording."""
    from sklearn.base import clone

    from gaitml.io.tyrex import estimate_mount_rotation
    from gaitml.signal import gravity_direction

    rec, truth = item["recording"], item["truth"]
    r_mount, minfo = estimate_mount_rotation(rec, truth)
    fs = rec.sampling_rate_hz
    step = max(1, int(round(fs / EVAL_RATE_HZ)))
    idx = np.arange(0, rec.n_samples, step)
    tp = truth.recording_times(rec)[idx]
    rot = truth.rotation_at(tp)
    ok = np.isfinite(rot).all(axis=(1, 2))
    idx, tp, rot = idx[ok], tp[ok], rot[ok]
    r_true = rot @ r_mount  # phone -> room
    up_true = r_true[:, 2, :]  # room up in phone axes: R^T e_z
    t_min = (tp - tp[0]) / 60.0
    base = {k: item[k] for k in ("file", "subject", "phone", "motion", "disturbance")}
    base.update(mount_deg=minfo["angle_from_identity_deg"], mount_rate_residual_rads=minfo["rate_rms_residual_rads"])
    rows = []

    def tilt_deg(up_est):
        cos = np.sum(up_est * up_true, axis=1) / np.linalg.norm(up_est, axis=1)
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))

    for name, est in ATTITUDE_SOURCES.items():
        est = clone(est).estimate(rec)
        r_est = est.rotation_[idx].as_matrix()  # phone -> nav
        tilt = tilt_deg(r_est[:, 2, :])
        e = r_est @ np.transpose(r_true, (0, 2, 1))
        yaw = np.unwrap(_yaw_of(e))
        slope = float(np.polyfit(t_min, np.degrees(yaw), 1)[0])
        rows.append(
            {
                **base,
                "source": name,
                "tilt_mean_deg": float(tilt.mean()),
                "tilt_median_deg": float(np.median(tilt)),
                "tilt_p95_deg": float(np.percentile(tilt, 95)),
                "heading_drift_deg_per_min": abs(slope),
                "heading_change_deg": float(np.degrees(abs(yaw[-1] - yaw[0]))),
                "bias_method": est.gyro_bias_.method,
                "still_s": est.gyro_bias_.still_s,
                **{f"bias_{ax}_rads": float(v) for ax, v in zip("xyz", est.gyro_bias_.bias_rads, strict=True)},
            }
        )
    up_g = gravity_direction(rec.acc, fs, cutoff_hz=0.3)[idx]
    tilt = tilt_deg(up_g)
    rows.append(
        {
            **base,
            "source": "gravity",
            "tilt_mean_deg": float(tilt.mean()),
            "tilt_median_deg": float(np.median(tilt)),
            "tilt_p95_deg": float(np.percentile(tilt, 95)),
            "heading_drift_deg_per_min": float("nan"),
            "heading_change_deg": float("nan"),
        }
    )
    return rows


def heading_source_drifts(item) -> list[dict]:
    """Walking-direction drift of ``gaitml pdr --detector adaptive --heading X`` for every heading source."""
    from gaitml.evaluation.trajectory import walking_direction_drift
    from gaitml.pdr import run_pdr

    rec, truth = item["recording"], item["truth"]
    tt = truth.t_s - rec.meta["t0_original_s"]
    xy = truth.pos_m[:, :2]
    base = {k: item[k] for k in ("file", "subject", "phone", "motion", "disturbance")}
    rows = []
    for h in HEADING_SOURCES:
        res = run_pdr(rec, detector="adaptive", modes="forward", heading=h)
        tj = res.trajectory
        t = np.append(tj["t_s"].to_numpy(), rec.t_s[-1])
        exy = np.vstack([tj[["x_m", "y_m"]].to_numpy(), tj[["x_m", "y_m"]].to_numpy()[-1:]])
        d = walking_direction_drift(t, exy, tt, xy)
        rows.append(
            {**base, "source": f"steps/{h}", "heading_drift_deg_per_min": abs(d["drift_deg_per_min"]), "max_jump_deg": d["max_jump_deg"]}
        )
    return rows


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_attitude", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--csv", metavar="FILE", help="write the long table (one row per recording and source)")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    p.add_argument("--no-headings", action="store_true", help="skip the per-step heading sources (PDR runs)")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    items = load_tyrex(Path(args.data))
    rows = []
    for i, it in enumerate(items):
        rows += attitude_scores(it)
        if not args.no_headings:
            rows += heading_source_drifts(it)
        if (i + 1) % 20 == 0:
            print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
    table = pd.DataFrame(rows)
    if args.csv:
        table.to_csv(args.csv, index=False)
    cols = [m for m in MOTION_ORDER if m in set(table["motion"])]
    lines = []
    for col, name in (
        ("tilt_mean_deg", "tilt error, mean over the recording (deg)"),
        ("tilt_p95_deg", "tilt error, 95th percentile over the recording (deg)"),
        ("heading_drift_deg_per_min", "heading drift, |slope| (deg/min)"),
    ):
        piv = table.pivot_table(index="source", columns="motion", values=col, aggfunc="median").reindex(columns=cols)
        piv = piv.dropna(how="all")
        lines += [f"### {name}, median over recordings (all: 18 per walking motion, 9 running)", md(piv, "{:.1f}"), ""]
    lines.append("### heading drift of the attitude before/after removing the gyroscope bias, per phone (deg/min, median)")
    att = table[table["source"].isin(list(ATTITUDE_SOURCES))]
    for phone, sub in att.groupby("phone"):
        piv = sub.pivot_table(index="source", columns="motion", values="heading_drift_deg_per_min", aggfunc="median")
        lines += [f"{phone}:", md(piv.reindex(columns=[c for c in cols if c in piv.columns]), "{:.1f}"), ""]
    lines.append("### tilt error before/after removing the gyroscope bias, per phone (deg, median of the recording means)")
    for phone, sub in att.groupby("phone"):
        piv = sub.pivot_table(index="source", columns="motion", values="tilt_mean_deg", aggfunc="median")
        lines += [f"{phone}:", md(piv.reindex(columns=[c for c in cols if c in piv.columns]), "{:.1f}"), ""]
    dflt = att[att["source"] == "gaitml"]
    lines.append("### the default's removed bias per phone (rad/s, median over recordings; method counts)")
    for phone, sub in dflt.groupby("phone"):
        b = sub[["bias_x_rads", "bias_y_rads", "bias_z_rads"]].median().to_numpy()
        lines.append(f"- {phone}: ({b[0]:.3f}, {b[1]:.3f}, {b[2]:.3f}); {sub['bias_method'].value_counts().to_dict()}")
    lines.append("")
    lines.append("### per person: median tilt error of the default attitude (deg) and heading drift of its steps' HDE (deg/min)")
    for src, col in (("gaitml", "tilt_mean_deg"), ("gaitml", "heading_drift_deg_per_min"), ("steps/hde", "heading_drift_deg_per_min")):
        sub = table[table["source"] == src]
        if sub.empty:
            continue
        piv = sub.pivot_table(index="subject", columns="motion", values=col, aggfunc="median").reindex(columns=cols)
        lines += [f"{src} {col}:", md(piv, "{:.1f}"), ""]
    m = table.drop_duplicates("file")
    lines.append(
        f"mount rotation (holder to phone axes) from the gyroscope: {m['mount_deg'].median():.1f} deg from identity (median; "
        f"{m['mount_deg'].min():.1f}-{m['mount_deg'].max():.1f}); angular rate left unexplained {m['mount_rate_residual_rads'].median():.2f} rad/s (median)"
    )
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
