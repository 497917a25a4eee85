"""Why gaitml's step heading drifts more than the plain gyroscope in the back pocket, and what the 10 s error is made of.

``python -m experiments.scripts.tyrex_bpheading [--data ../shared/data] [--cache FILE] [--csv PREFIX] [--out FILE]``
from the repository root (about 1.5 minutes on the 2-core machine; ``--cache`` keeps the
per-recording rows so a rerun only prints). For every tyrex recording with motion capture
(read as :mod:`experiments.scripts.tyrex_pdr` reads them):

**Heading decomposition** (:func:`heading_rows`). ``gaitml pdr``'s default steps and step
lengths with the gyro heading (HDE held off, as its structure guard holds it in every
recording but four Texting ones), forward-only; only the heading per step changes between
the variants, so every difference in walking-direction drift
(:func:`gaitml.evaluation.trajectory.walking_direction_drift`) is the heading's:

- ``gaitml``: the library's gyro step heading (:class:`gaitml.pdr.attitude.AttitudeEstimator`
  at its defaults, the compass heading of the phone's y axis projected on the horizontal,
  averaged over each step window);
- ``gaitml, bias off``: the same with ``gyro_bias='off'`` (the gyroscope as logged);
- ``true attitude``: the same projection and averaging applied to the motion-capture attitude
  (the capture body's rotation times the holder's mount rotation,
  :func:`gaitml.io.tyrex.estimate_mount_rotation`): what the heading definition gives with a
  perfect attitude;
- ``true tilt, gaitml yaw``: the true-attitude heading minus the yaw of the attitude's error
  rotation ``R_est R_true^T`` (the attitude's heading error about the vertical, as
  ``tyrex_attitude.py`` measures it): ``gaitml`` minus this is what the estimated *tilt* adds
  through the projection (the y axis is 60-80 deg from horizontal in a pocket);
- ``horizontal axis``: the estimated attitude, but the heading of the phone axis that is
  horizontal at the recording's mean attitude (the y axis with its component along the mean
  "up" removed) instead of the y axis;
- ``calibration bias``: the library's attitude with the phone's static calibration bias given
  (:data:`CALIBRATION_FOLDERS`: the median rate of the still ``calib_gyr_<phone>_d*`` logs of the
  data set, never a walk) in place of the online estimate;
- ``calibration bias, then tracked``: the default attitude (``gyro_bias='auto'``) started from that bias instead of
  the recording's still stretches, then tracked online as ``auto`` tracks
  (``AttitudeEstimator.estimate(still_bias=...)``);
- ``baseline heading``: ``tyrex_pdr.py``'s baseline heading (the rate about the gravity
  low-passed at 0.3 Hz, integrated; no bias removed), sampled at these steps' events;
- ``baseline heading, true rates``: the same integral of the capture's angular rate (the
  baseline's method with a perfect gyroscope: its own error, without the sensor's);
- ``baseline``: ``tyrex_pdr.py``'s baseline on its own steps (peak steps, 0.7 m; the drift does
  not depend on a constant length).

**10 s error decomposition** (:func:`error_rows`), ``gaitml pdr``'s defaults (HDE guarded):
each step's true walked length and true walking direction are the motion-capture body's
(:func:`step_truth`: the low-passed track between consecutive step times); the trajectory is
rebuilt from ``ours`` or ``true`` lengths and headings in the four combinations and scored
with :func:`gaitml.evaluation.trajectory.walk_scores`. ``true length + true heading`` is the
scoring's floor (the body track sampled at the step times).

Nothing is fitted: no figure here is chosen on tyrex, so in-sample and held-out are the
same numbers; the per-person tables give the spread.
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
    baseline_steps,
    gyro_heading_about_gravity,
    load_tyrex,
    md,
)

__all__ = [
    "CALIBRATION_FOLDERS",
    "calibration_bias",
    "error_rows",
    "heading_rows",
    "horizontal_axis_heading",
    "main",
    "paired",
    "projected_heading",
    "rate_about",
    "score_steps",
    "step_truth",
]

#: The data set's still calibration logs of each phone's gyroscope (README: ``calib_{acc,gyr,mag}_<phone>_d<N>``).
CALIBRATION_FOLDERS = {
    "Nexus5": "android/calib_gyr_Nexus5_d*",
    "iPhone4S": "ios/calib_gyr_iPhone4S_d*",
    "iPhone5": "ios/calib_gyr_iPhone5_d*",
}
#: A calibration log counts as still when every axis' rate std is below this (rad/s); ``calib_gyr_Nexus5_d4`` moves (0.2-0.6).
CALIBRATION_MAX_STD_RADS = 0.05
#: The motions whose 10 s error issue 27's round left above 1.25 x the bound.
ERROR_MOTIONS = ("Texting", "Phoning", "FrontPocket", "BackPocket")
HEADING_VARIANTS = (
    "gaitml",
    "gaitml, bias off",
    "true attitude",
    "true tilt, gaitml yaw",
    "horizontal axis",
    "calibration bias",
    "calibration bias, then tracked",
    "baseline heading",
    "baseline heading, true rates",
    "baseline",
)
ERROR_VARIANTS = (
    "ours",
    "true length + our heading",
    "our length + true heading",
    "true length + true heading",
    "true length + baseline heading",
    "true length + calibration-bias heading",
)


def projected_heading(rot_mats: np.ndarray, axis_body) -> np.ndarray:
    """Compass heading (rad, clockwise from north) of a phone axis projected on the horizontal.

    ``rot_mats``: (n, 3, 3) phone-to-navigation rotations (x east, y north, z up); ``axis_body``:
    (3,) or (n, 3) the axis in phone coordinates.
    """
    a = np.asarray(axis_body, dtype=float)
    v = rot_mats @ a if a.ndim == 1 else np.einsum("nij,nj->ni", rot_mats, a)
    return np.arctan2(v[:, 0], v[:, 1])


def horizontal_axis_heading(rot_mats: np.ndarray, axis_body=(0.0, 1.0, 0.0)) -> np.ndarray:
    """Heading of the phone axis that is horizontal at the mean attitude: ``axis_body`` minus its part along the mean up.

    The mean "up" in phone coordinates is the mean over the samples of ``R^T e_z``. Raises
    ValueError when ``axis_body`` lies along it (no horizontal component).
    """
    up = rot_mats[:, 2, :].mean(axis=0)
    up = up / np.linalg.norm(up)
    a = np.asarray(axis_body, dtype=float)
    f = a - (a @ up) * up
    if np.linalg.norm(f) < 1e-6:
        raise ValueError("the axis lies along the mean up; choose another axis")
    return projected_heading(rot_mats, f / np.linalg.norm(f))


def rate_about(rates_body: np.ndarray, up_body: np.ndarray, sampling_rate_hz: float) -> np.ndarray:
    """Compass heading change (rad, starts at 0) integrating the rate about ``up_body`` (trapezoidal): ``-int w . up dt``."""
    r = np.sum(np.asarray(rates_body, dtype=float) * np.asarray(up_body, dtype=float), axis=1)
    return -np.concatenate([[0.0], np.cumsum(0.5 * (r[1:] + r[:-1]))]) / float(sampling_rate_hz)


def step_truth(t_step, true_t_s, true_xy) -> tuple[np.ndarray, np.ndarray]:
    """Each step's true walked length (m) and walking direction (rad, compass) from the body track.

    The body track (:func:`gaitml.evaluation.trajectory.body_track`) is sampled at the step
    times; step ``i`` is the displacement from step ``i - 1`` (the first from one median step
    interval before it, or from the track's start). Its length is the body path length over
    that interval, its direction that of the displacement.
    """
    from gaitml.evaluation.trajectory import body_track

    t = np.asarray(t_step, dtype=float)
    tt = np.asarray(true_t_s, dtype=float)
    body = body_track(tt, true_xy)
    if len(t) == 0:
        return np.zeros(0), np.zeros(0)
    dt0 = float(np.median(np.diff(t))) if len(t) > 1 else 0.5
    edges = np.concatenate([[max(tt[0], t[0] - dt0)], t])
    cum = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(body, axis=0), axis=1))])
    length = np.diff(np.interp(edges, tt, cum))
    p = np.column_stack([np.interp(edges, tt, body[:, j]) for j in range(2)])
    d = np.diff(p, axis=0)
    return length, np.arctan2(d[:, 0], d[:, 1])


def score_steps(t_step, length_m, heading_rad, t_end_s: float, true_t_s, true_xy) -> dict:
    """:func:`gaitml.evaluation.trajectory.walk_scores` of the trajectory built from per-step lengths and headings."""
    from gaitml.evaluation.trajectory import walk_scores

    t, xy = _trajectory_from_steps(np.asarray(t_step, dtype=float), length_m, heading_rad)
    if t[-1] < t_end_s:
        t, xy = np.append(t, t_end_s), np.vstack([xy, xy[-1:]])
    return walk_scores(t, xy, true_t_s, true_xy)


def calibration_bias(data: Path) -> dict[str, np.ndarray]:
    """Per phone, the median over its still calibration logs of the median gyroscope rate (rad/s, phone axes)."""
    from gaitml.io import read_segments

    out = {}
    for phone, pattern in CALIBRATION_FOLDERS.items():
        meds = []
        for d in sorted((data / "tyrex-attitude").glob(pattern)):
            rec = max(read_segments(d), key=lambda r: r.n_samples)
            if np.max(np.std(rec.gyr, axis=0)) < CALIBRATION_MAX_STD_RADS:
                meds.append(np.median(rec.gyr, axis=0))
        if meds:
            out[phone] = np.median(np.asarray(meds), axis=0)
    return out


def _true_rotations(item) -> np.ndarray:
    """Phone-to-room rotation per sample from the capture (nearest known frame across lost ones)."""
    from gaitml.io.tyrex import estimate_mount_rotation

    rec, truth = item["recording"], item["truth"]
    r_mount, _ = estimate_mount_rotation(rec, truth)
    rot = truth.rotation_at(truth.recording_times(rec))
    ok = np.isfinite(rot).all(axis=(1, 2))
    good = np.flatnonzero(ok)
    near = good[np.clip(np.searchsorted(good, np.arange(len(rot))), 0, len(good) - 1)]
    return rot[near] @ r_mount


def heading_rows(item, calib: dict | None = None) -> list[dict]:
    """Walking-direction drift (signed, deg/min) of every heading variant on ``gaitml pdr``'s steps; one row per variant."""
    from scipy.spatial.transform import Rotation

    from gaitml.pdr import run_pdr
    from gaitml.pdr.attitude import AttitudeEstimator, step_headings
    from gaitml.signal import GyroBias, gravity_direction

    rec = item["recording"]
    fs = rec.sampling_rate_hz
    tt, xy = _truth_on_recording(item)
    res = run_pdr(rec, modes="forward", heading="gyro")
    st = res.steps
    keys = {k: item[k] for k in ("file", "subject", "phone", "motion", "disturbance")}
    if len(st) < 2:
        return []
    event = st.attrs.get("event", "t_peak_s")
    t_step = st[event].to_numpy(float)
    length = st["step_length_m"].to_numpy(float)
    s0 = st["start"].to_numpy(np.int64)
    s1 = np.maximum(st["end"].to_numpy(np.int64), s0 + 1)
    ev = np.clip(np.round(t_step * fs).astype(int), 0, rec.n_samples - 1)

    r_true = _true_rotations(item)
    r_est = AttitudeEstimator().estimate(rec).rotation_.as_matrix()
    y = (0.0, 1.0, 0.0)
    e = r_est @ np.transpose(r_true, (0, 2, 1))
    yaw_err = np.unwrap(np.arctan2(e[:, 1, 0] - e[:, 0, 1], e[:, 0, 0] + e[:, 1, 1]))  # counter-clockwise
    h_true = projected_heading(r_true, y)
    w_true = Rotation.from_matrix(np.transpose(r_true[:-1], (0, 2, 1)) @ r_true[1:]).as_rotvec() * fs
    w_true = np.vstack([w_true, w_true[-1:]])
    per_sample = {
        "true attitude": h_true,
        "true tilt, gaitml yaw": h_true - yaw_err,
        "horizontal axis": horizontal_axis_heading(r_est, y),
        "baseline heading, true rates": rate_about(w_true, gravity_direction(rec.acc, fs, cutoff_hz=0.3), fs),
    }
    per_sample["gaitml, bias off"] = AttitudeEstimator(gyro_bias="off").estimate(rec).heading_rad_
    if calib and item["phone"] in calib:
        att = AttitudeEstimator(gyro_bias=calib[item["phone"]]).estimate(rec)
        per_sample["calibration bias"] = att.heading_rad_
        start = GyroBias(np.asarray(calib[item["phone"]], dtype=float), "given", note="the phone's calibration bias")
        per_sample["calibration bias, then tracked"] = AttitudeEstimator().estimate(rec, still_bias=start).heading_rad_
    per_step = {"gaitml": st["heading_rad"].to_numpy(float)}
    per_step.update({k: step_headings(v, s0, s1) for k, v in per_sample.items()})
    per_step["baseline heading"] = gyro_heading_about_gravity(rec)[ev]
    rows = []
    for name in HEADING_VARIANTS:
        if name == "baseline":
            bs = baseline_steps(rec)
            psi = gyro_heading_about_gravity(rec)
            s = score_steps(bs / fs, np.full(len(bs), 0.7), psi[bs], float(rec.t_s[-1]), tt, xy)
            n = len(bs)
        elif name in per_step:
            s = score_steps(t_step, length, per_step[name], float(rec.t_s[-1]), tt, xy)
            n = len(st)
        else:
            continue
        rows.append(
            {**keys, "variant": name, "drift_deg_per_min": s["drift_deg_per_min"], "error_10s_pct": s["error_10s_pct"], "n_steps": n}
        )
    return rows


def error_rows(item, calib: dict | None = None) -> list[dict]:
    """The 10 s error of ``gaitml pdr``'s defaults split into distance and heading: ours / true lengths x headings.

    Also the true lengths with the baseline's heading (at these steps' events) and with the library's gyro heading
    given the phone's calibration bias (``calib``, :func:`calibration_bias`; HDE as at the defaults)."""
    from experiments.scripts.tyrex_steps import mocap_steps
    from gaitml.evaluation.trajectory import walked_distance_ratio
    from gaitml.pdr import run_pdr

    rec = item["recording"]
    tt, xy = _truth_on_recording(item)
    res = run_pdr(rec, modes="forward")
    st = res.steps
    keys = {k: item[k] for k in ("file", "subject", "phone", "motion", "disturbance")}
    if len(st) < 2:
        return []
    event = st.attrs.get("event", "t_peak_s")
    t_step = st[event].to_numpy(float)
    ours_l, ours_h = st["step_length_m"].to_numpy(float), st["heading_rad"].to_numpy(float)
    true_l, true_h = step_truth(t_step, tt, xy)
    ref = mocap_steps(item["truth"], item["motion"])
    t_phone = t_step + float(rec.meta["t0_original_s"])  # the reference's clock
    n_span = int(np.sum((t_phone >= ref["t_first_s"]) & (t_phone <= ref["t_last_s"])))
    t0 = float(rec.meta["t0_original_s"])
    span = [max(0.0, ref["t_first_s"] - t0), min(float(rec.t_s[-1]), ref["t_last_s"] - t0)]
    walked = float(walked_distance_ratio(span, np.zeros((2, 2)), tt, xy)["true_m"])  # body path over the span
    combos = {
        "ours": (ours_l, ours_h),
        "true length + our heading": (true_l, ours_h),
        "our length + true heading": (ours_l, true_h),
        "true length + true heading": (true_l, true_h),
    }
    combos["true length + baseline heading"] = (
        true_l,
        gyro_heading_about_gravity(rec)[np.clip(np.round(t_step * rec.sampling_rate_hz).astype(int), 0, rec.n_samples - 1)],
    )
    if calib and item["phone"] in calib:
        from gaitml.pdr.attitude import AttitudeEstimator

        cal = run_pdr(rec, modes="forward", attitude=AttitudeEstimator(gyro_bias=calib[item["phone"]])).steps  # the same steps
        if np.array_equal(cal[event].to_numpy(float), t_step):
            combos["true length + calibration-bias heading"] = (true_l, cal["heading_rad"].to_numpy(float))
    rows = []
    for name, (ln, hd) in combos.items():
        s = score_steps(t_step, ln, hd, float(rec.t_s[-1]), tt, xy)
        rows.append(
            {
                **keys,
                "variant": name,
                "error_10s_pct": s["error_10s_pct"],
                "distance_ratio": s["distance_ratio"],
                "drift_deg_per_min": s["drift_deg_per_min"],
                "n_steps": len(st),
                "true_m": s["true_m"],
                "mean_step_m": float(np.mean(ln)),
                "true_mean_step_m": float(np.mean(true_l)),
                "n_reference_steps": int(ref["n_steps"]),
                "count_ratio": n_span / ref["n_steps"] if ref["n_steps"] else float("nan"),
                "reference_step_m": walked / ref["n_steps"] if ref["n_steps"] else float("nan"),
            }
        )
    return rows


def paired(df: pd.DataFrame, variant: str, against: str = "gaitml", value: str = "drift_deg_per_min") -> pd.DataFrame:
    """Per motion, recording by recording: how often ``|variant|`` is below / above ``|against|``, the median of
    the paired difference of the absolute values and both means (a median over 9 or 18 recordings moves by a
    few recordings; the paired count does not)."""
    d = df.assign(v=df[value].abs()).pivot_table(index=["file", "motion"], columns="variant", values="v").reset_index()
    d = d.dropna(subset=[variant, against])
    rows = []
    for m in [m for m in MOTION_ORDER if m in set(d["motion"])]:
        s = d[d["motion"] == m]
        diff = s[variant] - s[against]
        rows.append(
            {
                "motion": m,
                "recordings": len(s),
                "lower": int((diff < 0).sum()),
                "higher": int((diff > 0).sum()),
                "median difference": float(diff.median()),
                f"mean {against}": float(s[against].mean()),
                f"mean {variant}": float(s[variant].mean()),
            }
        )
    return pd.DataFrame(rows).set_index("motion")


def _median_table(df: pd.DataFrame, value: str, variants, *, absolute: bool = False, by: str = "motion") -> pd.DataFrame:
    d = df.assign(v=df[value].abs() if absolute else df[value])
    piv = d.pivot_table(index="variant", columns=by, values="v", aggfunc="median")
    cols = [c for c in MOTION_ORDER if c in piv.columns] if by == "motion" else list(piv.columns)
    return piv.reindex(index=[v for v in variants if v in piv.index], columns=cols)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_bpheading", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--cache", metavar="FILE", help="pickle of the per-recording rows: read if it exists, else written")
    p.add_argument("--csv", metavar="PREFIX", help="write PREFIX-heading.csv and PREFIX-error.csv (one row per recording and variant)")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    cache = Path(args.cache) if args.cache else None
    if cache is not None and cache.exists():
        head, err = pickle.loads(cache.read_bytes())
        print(f"per-recording rows read from {cache}", file=sys.stderr)
    else:
        data = Path(args.data)
        calib = calibration_bias(data)
        items = load_tyrex(data)
        print(f"{len(items)} recordings read ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        hrows, erows = [], []
        for i, it in enumerate(items):
            hrows += heading_rows(it, calib)
            if it["motion"] in ERROR_MOTIONS:
                erows += error_rows(it, calib)
            if (i + 1) % 20 == 0:
                print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        head, err = pd.DataFrame(hrows), pd.DataFrame(erows)
        if cache is not None:
            cache.parent.mkdir(parents=True, exist_ok=True)
            cache.write_bytes(pickle.dumps((head, err)))
    if args.csv:
        head.to_csv(f"{args.csv}-heading.csv", index=False)
        err.to_csv(f"{args.csv}-error.csv", index=False)
    lines = []
    for subset, sel in (("NoDist (9 per motion)", head["disturbance"] == "NoDist"), ("all", head.index >= 0)):
        lines += [
            f"### |walking-direction drift| deg/min, median, {subset}",
            md(_median_table(head[sel], "drift_deg_per_min", HEADING_VARIANTS, absolute=True), "{:.1f}"),
            "",
        ]
    for v in ("true attitude", "horizontal axis", "calibration bias", "calibration bias, then tracked", "baseline heading", "baseline"):
        lines += [f"### |drift| recording by recording, all: {v} against gaitml", md(paired(head, v), "{:.1f}"), ""]
    bp = head[head["motion"] == "BackPocket"]
    lines += ["### BackPocket, |drift| deg/min, median per person (all 18)"]
    lines += [md(_median_table(bp, "drift_deg_per_min", HEADING_VARIANTS, absolute=True, by="subject"), "{:.1f}"), ""]
    lines += ["### BackPocket, |drift| deg/min, median per phone (all 18)"]
    lines += [md(_median_table(bp, "drift_deg_per_min", HEADING_VARIANTS, absolute=True, by="phone"), "{:.1f}"), ""]
    wide = bp.pivot_table(index=["file"], columns="variant", values="drift_deg_per_min").reindex(columns=list(HEADING_VARIANTS))
    wide.index = [f.split("/")[-1] for f in wide.index]
    lines += [
        "### BackPocket per recording, signed drift deg/min (negative: the estimate turns counter-clockwise of the truth)",
        md(wide, "{:.1f}"),
        "",
    ]
    for subset, sel in (("NoDist", err["disturbance"] == "NoDist"), ("all", err.index >= 0)):
        e = err[sel]
        lines += [f"### 10 s error %, median, {subset}", md(_median_table(e, "error_10s_pct", ERROR_VARIANTS), "{:.1f}"), ""]
        lines += [f"### distance ratio, median, {subset}", md(_median_table(e, "distance_ratio", ERROR_VARIANTS)), ""]
    ours = err[err["variant"] == "ours"]
    per_person = ours.pivot_table(index="subject", columns="motion", values="count_ratio", aggfunc="median").reindex(
        columns=list(ERROR_MOTIONS)
    )
    lines += [
        "### step count ratio (ours in the capture span / motion-capture reference, tyrex_steps.mocap_steps), median per person",
        md(per_person),
        "",
    ]
    lines += [
        "### our steps against the truth, median, all",
        md(
            ours.groupby("motion")[["n_steps", "n_reference_steps", "count_ratio", "mean_step_m", "true_mean_step_m", "reference_step_m"]]
            .median()
            .reindex([m for m in MOTION_ORDER if m in set(ours["motion"])]),
            "{:.2f}",
        ),
        "",
    ]
    for v in ("ours", "true length + our heading", "our length + true heading"):
        piv = err[err["variant"] == v].pivot_table(index="subject", columns="motion", values="error_10s_pct", aggfunc="median")
        lines += [f"### 10 s error %, median per person (all): {v}", md(piv.reindex(columns=list(ERROR_MOTIONS)), "{:.1f}"), ""]
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
