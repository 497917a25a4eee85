"""``gaitml pdr --gyro-bias-from STILL`` on every tyrex walk and run: the gyroscope bias from a still recording of the same phone.

``python -m experiments.scripts.tyrex_gyrocal [--data ../shared/data] [--cache FILE] [--csv FILE] [--out FILE]``
from the repository root (a few minutes on the 2-core machine; ``--cache`` keeps the per-recording rows so a rerun
only prints). For every tyrex recording with motion capture (read as :mod:`experiments.scripts.tyrex_pdr` reads
them) it scores, with :func:`gaitml.evaluation.trajectory.walk_scores` (walking-direction drift deg/min, the 10 s
error %, the walked-distance ratio):

- ``default``: :func:`gaitml.pdr.run_pdr` as ``gaitml pdr WALK`` runs it (forward-only, its default detector, HDE
  with its structure guard, ``--gyro-bias auto``: the walk's own still stretches, then tracked online);
- ``still log, held``: as ``gaitml pdr WALK --gyro-bias-from LOG --gyro-bias still``: the bias of the phone's still
  calibration log (:func:`gaitml.signal.gyro_bias_from_still` of ``calib_gyr_<phone>_d<N>``, read as the CLI reads
  it), held for the whole walk;
- ``still log, tracked``: ``--gyro-bias-from LOG --gyro-bias auto``: started from that bias, then tracked online as
  the default tracks;
- ``held, <log>``: the held variant with each of the phone's other still logs (how much the choice of the
  calibration day moves the drift);
- ``baseline``: :mod:`experiments.scripts.tyrex_pdr`'s plain PDR (peak steps, one constant step length per gait
  fitted on the other two people, the gyroscope integrated about gravity with nothing removed);
- ``baseline, still-log bias``: the same with the same still-log bias subtracted from the gyroscope first (the
  fair comparison: the plain heading given what gaitml is given);
- ``standing still``: a trajectory that never moves.

LOG, per phone, is fixed by a rule written before measuring: the phone's still gyroscope log with the most still
seconds (:data:`CALIBRATION_GLOBS`; what a user would pick, the longest rest). It is chosen on no walk.

Also per recording (:func:`walk_bias`): the gyroscope's bias *during the walk*, the median over the samples of the
logged rate minus the motion capture's rate (the capture's rotation differentiated, in phone axes through the
holder's mount rotation), and the heading drift a bias error about the vertical gives: ``(b_log - b_walk) . up``,
up the phone's low-passed gravity direction, as deg/min. This says whether a log over-corrects because the phone's
bias on the calibration day differs from the walk day's.

Nothing is fitted on tyrex but the baseline's step length (on the other two people, as in ``tyrex_pdr``): the
in-sample and held-out figures are the same numbers; the per-person tables give the spread.
"""

from __future__ import annotations

import argparse
import pickle
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_bpheading import paired
from experiments.scripts.tyrex_pdr import MOTION_ORDER, baseline_counts, baseline_steps, load_tyrex, md

__all__ = [
    "CALIBRATION_GLOBS",
    "VARIANTS",
    "adoption",
    "heading_about_gravity",
    "main",
    "still_logs",
    "walk_bias",
]

#: Each phone's still gyroscope logs in the data set (README: ``calib_{acc,gyr,mag}_<phone>_d<N>``).
CALIBRATION_GLOBS = {
    "Nexus5": "android/calib_gyr_Nexus5_d*",
    "iPhone4S": "ios/calib_gyr_iPhone4S_d*",
    "iPhone5": "ios/calib_gyr_iPhone5_d*",
}
VARIANTS = (
    "default",
    "still log, held",
    "still log, tracked",
    "baseline",
    "baseline, still-log bias",
    "standing still",
)
#: The motions the adoption rule counts (AR is mostly standing: reported, not scored, as in issue 27).
RULE_MOTIONS = ("Texting", "Phoning", "Swinging", "FrontPocket", "BackPocket", "RunningHand", "RunningPocket")
#: ``tracked`` becomes ``--gyro-bias-from``'s default when its median |drift| (all recordings) is lower than
#: ``held``'s in at least this many of :data:`RULE_MOTIONS` ...
RULE_MIN_MOTIONS = 5
#: ... and it is lower in more recordings than higher, over all recordings of those motions (paired).


def still_logs(data: Path) -> dict[str, list[tuple[str, object]]]:
    """Per phone, ``(log name, GyroBias)`` of every still gyroscope log the CLI accepts, the most still seconds first."""
    from gaitml.errors import InputError
    from gaitml.io import read_recording
    from gaitml.signal import gyro_bias_from_still

    out = {}
    for phone, pattern in CALIBRATION_GLOBS.items():
        logs = []
        for d in sorted((data / "tyrex-attitude").glob(pattern)):
            try:
                logs.append((d.name, gyro_bias_from_still(read_recording(d), source=d.name)))
            except InputError as exc:  # reported, not used
                print(f"{d.name}: refused: {exc}", file=sys.stderr)
        out[phone] = sorted(logs, key=lambda x: -x[1].still_s)
    return out


def heading_about_gravity(recording, bias_rads=None, *, cutoff_hz: float = 0.3) -> np.ndarray:
    """:func:`experiments.scripts.tyrex_pdr.gyro_heading_about_gravity` with ``bias_rads`` subtracted from the rate first."""
    from gaitml.signal import gravity_direction

    fs = recording.sampling_rate_hz
    gyr = recording.gyr if bias_rads is None else recording.gyr - np.asarray(bias_rads, dtype=float)
    up = gravity_direction(recording.acc, fs, cutoff_hz=cutoff_hz)
    rate = np.sum(gyr * up, axis=1)
    return -np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]))]) / fs


def walk_bias(item, log_bias) -> dict:
    """The gyroscope bias during the walk (median of logged minus captured rate, phone axes, rad/s), the drift it gives
    uncorrected and the drift that the log's bias error about the vertical, ``(log - walk) . up``, gives (deg/min, in
    :func:`gaitml.evaluation.trajectory.walking_direction_drift`'s sign: positive counter-clockwise)."""
    from scipy.spatial.transform import Rotation

    from gaitml.io.tyrex import estimate_mount_rotation
    from gaitml.signal import gravity_direction

    rec, truth = item["recording"], item["truth"]
    fs = rec.sampling_rate_hz
    r_mount, _ = estimate_mount_rotation(rec, truth)
    rot = truth.rotation_at(truth.recording_times(rec))  # spherical interpolation between frames; NaN where lost
    known = np.isfinite(rot).all(axis=(1, 2))
    r_true = np.where(known[:, None, None], rot, np.eye(3)) @ r_mount
    w_true = Rotation.from_matrix(np.transpose(r_true[:-1], (0, 2, 1)) @ r_true[1:]).as_rotvec() * fs
    ok = known[:-1] & known[1:] & np.isfinite(rec.gyr[:-1]).all(axis=1)
    gyr = rec.gyr[:-1]
    b_walk = np.median(gyr[ok] - w_true[ok], axis=0)
    up = gravity_direction(rec.acc, fs, cutoff_hz=0.3)
    err = np.asarray(log_bias, dtype=float) - b_walk
    # in walk_scores' sign (the direction angle counter-clockwise, arctan2(dy, dx)): a rate b left in about up turns the
    # estimate counter-clockwise by b . up rad/s; one removed in excess (e = log - walk) turns it clockwise by e . up
    return {
        "walk_bias_rads": b_walk,
        "log_error_vertical_deg_per_min": float(-np.degrees(np.median(up @ err)) * 60.0),
        "walk_bias_vertical_deg_per_min": float(np.degrees(np.median(up @ b_walk)) * 60.0),
    }


def per_log_lines(table: pd.DataFrame, logs: dict) -> list[str]:
    """Per phone and still log (held), the median |drift| and 10 s error over its recordings of every motion but AR,
    beside the default's: how much the calibration day moves the figures."""
    t = table[table["motion"] != "AR"]
    rows = []
    for phone, pl in logs.items():
        tp = t[t["phone"] == phone]
        d = tp[tp["variant"] == "default"]
        rows.append(
            {
                "phone": phone,
                "bias from": "default (auto)",
                "abs drift deg/min": d["drift_deg_per_min"].abs().median(),
                "10 s error %": d["error_10s_pct"].median(),
            }
        )
        for k, (name, _gb) in enumerate(pl):
            v = "still log, held" if k == 0 else f"held, {name.rsplit('_', 1)[-1]}"
            h = tp[tp["variant"] == v]
            rows.append(
                {
                    "phone": phone,
                    "bias from": name,
                    "abs drift deg/min": h["drift_deg_per_min"].abs().median(),
                    "10 s error %": h["error_10s_pct"].median(),
                }
            )
    out = pd.DataFrame(rows).set_index("phone")
    return ["### per phone and still log (held): median over the phone's recordings of every motion but AR", md(out, "{:.1f}"), ""]


def walk_bias_lines(wb: pd.DataFrame, logs: dict) -> list[str]:
    """Per phone, the gyroscope's bias during its hand-held (Texting) walks beside each still log's, and the heading
    drift each log's error about the vertical gives there.

    Only the Texting walks are used: the phone turns slowly there, so the capture's differentiated attitude is its
    true rate to about 0.01 rad/s (the Nexus 5, whose gyroscope Android calibrates, reads -0.010 to +0.007 rad/s on
    every axis there). In pockets, swinging and running its 10-90 % spread on the Nexus 5 is 0.02-0.04 rad/s (the
    fast rotations turn small errors of time alignment and of the mount rotation into rate errors), larger than
    the iPhone 4S's whole bias, so those walks cannot tell the walk day's bias.
    """
    tex = wb[wb["motion"] == "Texting"]
    b = np.vstack(tex["walk_bias_rads"].to_numpy())
    lines = [
        "### the gyroscope's bias during the hand-held (Texting) walks (logged minus captured rate, median per walk) "
        "against each still log, rad/s",
        "",
        "| phone | source | x | y | z |",
        "|---|---|---|---|---|",
    ]
    for phone in logs:
        m = (tex["phone"] == phone).to_numpy()
        if not m.any():
            continue
        lo, med, hi = np.min(b[m], axis=0), np.median(b[m], axis=0), np.max(b[m], axis=0)
        cells = [f"{med[j]:+.4f} ({lo[j]:+.4f} to {hi[j]:+.4f})" for j in range(3)]
        lines.append(f"| {phone} | {int(m.sum())} Texting walks: median (min to max) | " + " | ".join(cells) + " |")
        for name, gb in logs[phone]:
            lines.append(f"| {phone} | {name} | " + " | ".join(f"{v:+.4f}" for v in gb.bias_rads) + " |")
    lines.append("")
    cols = [c for c in wb.columns if c.startswith("log_error_vertical_deg_per_min_")]
    e = tex.groupby("phone")[cols].median()
    e.columns = [c.rsplit("_", 1)[-1] for c in cols]
    lines += [
        "### the drift a log's bias error about the vertical gives in the Texting walks ((log - walk) . up, deg/min, "
        "median per phone; the drift's sign: positive counter-clockwise)",
        md(e, "{:+.1f}"),
        "",
    ]
    return lines


def _trajectory(t_step, length_m, heading_rad):
    d = np.column_stack([np.sin(heading_rad), np.cos(heading_rad)]) * np.asarray(length_m, dtype=float)[:, None]
    return np.concatenate([[0.0], t_step]), np.vstack([[0.0, 0.0], np.cumsum(d, axis=0)])


def score_item(item, logs: dict, step_length_by_mode: dict) -> tuple[list[dict], dict]:
    """Every variant of one recording, scored (one row each), and the walk-bias record."""
    from gaitml.evaluation.trajectory import walk_scores
    from gaitml.pdr import run_pdr

    rec = item["recording"]
    truth = item["truth"]
    tt, xy = truth.t_s - rec.meta["t0_original_s"], truth.pos_m[:, :2]
    keys = {k: item[k] for k in ("file", "subject", "phone", "motion", "mode", "disturbance")}
    rows = []

    def add(variant, t, exy, **extra):
        if t[-1] < rec.t_s[-1]:
            t, exy = np.append(t, rec.t_s[-1]), np.vstack([exy, exy[-1:]])
        rows.append({**keys, "variant": variant, **walk_scores(t, exy, tt, xy), **extra})

    def add_pdr(variant, log="", **kw):
        res = run_pdr(rec, modes="forward", **kw)
        tj = res.trajectory
        add(
            variant,
            tj["t_s"].to_numpy(),
            tj[["x_m", "y_m"]].to_numpy(),
            n_steps=res.n_steps,
            bias_method=res.info["gyro_bias"]["method"],
            log=log,
        )

    phone_logs = logs.get(item["phone"], [])
    add_pdr("default")
    if phone_logs:
        name, gb = phone_logs[0]
        add_pdr("still log, held", gyro_bias="still", gyro_bias_start=gb, log=name)
        add_pdr("still log, tracked", gyro_bias="auto", gyro_bias_start=gb, log=name)
        for other, ogb in phone_logs[1:]:
            add_pdr(f"held, {other.rsplit('_', 1)[-1]}", gyro_bias="still", gyro_bias_start=ogb)
    steps = baseline_steps(rec)
    length = step_length_by_mode.get(item["mode"], 0.7)
    fs = rec.sampling_rate_hz
    for variant, b in (("baseline", None), ("baseline, still-log bias", phone_logs[0][1].bias_rads if phone_logs else None)):
        if variant != "baseline" and b is None:
            continue
        psi = heading_about_gravity(rec, b)
        t_b, xy_b = _trajectory(steps / fs, np.full(len(steps), length), psi[steps])
        add(variant, t_b, xy_b, n_steps=len(steps))
    add("standing still", np.array([0.0, rec.t_s[-1]]), np.zeros((2, 2)))
    wb = {**keys, **walk_bias(item, phone_logs[0][1].bias_rads)} if phone_logs else {**keys}
    if phone_logs:
        for other, ogb in phone_logs:
            wb[f"log_error_vertical_deg_per_min_{other.rsplit('_', 1)[-1]}"] = walk_bias(item, ogb.bias_rads)[
                "log_error_vertical_deg_per_min"
            ]
    return rows, wb


def _abs_median(df: pd.DataFrame, value: str, variants, by: str = "motion") -> pd.DataFrame:
    d = df.assign(v=df[value].abs())
    piv = d.pivot_table(index="variant", columns=by, values="v", aggfunc="median")
    cols = [c for c in MOTION_ORDER if c in piv.columns] if by == "motion" else list(piv.columns)
    return piv.reindex(index=[v for v in variants if v in piv.index], columns=cols)


def adoption(table: pd.DataFrame) -> dict:
    """The rule fixed before measuring: ``tracked`` over ``held`` iff its median |drift| (all recordings) is lower in at
    least :data:`RULE_MIN_MOTIONS` of :data:`RULE_MOTIONS` and it is lower in more recordings than higher (paired)."""
    t = table[table["motion"].isin(RULE_MOTIONS)]
    med = _abs_median(t, "drift_deg_per_min", ("still log, held", "still log, tracked"))
    wins = [m for m in med.columns if med.loc["still log, tracked", m] < med.loc["still log, held", m]]
    p = paired(t, "still log, tracked", "still log, held")
    lower, higher = int(p["lower"].sum()), int(p["higher"].sum())
    adopt = len(wins) >= RULE_MIN_MOTIONS and lower > higher
    return {"tracked_lower_median_in": wins, "paired_lower": lower, "paired_higher": higher, "adopt_tracked": adopt}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_gyrocal", description=__doc__.split("\n")[0])
    p.add_argument("--data", default="../shared/data", help="the shared data folder (holds tyrex-attitude/)")
    p.add_argument("--cache", metavar="FILE", help="pickle of the per-recording rows: read if it exists, else written")
    p.add_argument("--csv", metavar="FILE", help="write the long table (one row per recording and variant)")
    p.add_argument("--out", metavar="FILE", help="write the printed tables to this markdown file too")
    args = p.parse_args(argv)
    t0 = time.perf_counter()
    cache = Path(args.cache) if args.cache else None
    data = Path(args.data)
    logs = still_logs(data)
    if cache is not None and cache.exists():
        table, wb = pickle.loads(cache.read_bytes())
        print(f"per-recording rows read from {cache}", file=sys.stderr)
    else:
        items = load_tyrex(data)
        print(f"{len(items)} recordings read ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        counts = pd.DataFrame(
            [{"subject": it["subject"], "mode": it["mode"], **dict(zip(("n", "m"), baseline_counts(it), strict=True))} for it in items]
        )
        lengths = {}
        for s in sorted(counts["subject"].unique()):
            other = counts[counts["subject"] != s].groupby("mode")[["n", "m"]].sum()
            lengths[s] = (other["m"] / other["n"]).to_dict()
        rows, wbs = [], []
        for i, it in enumerate(items):
            r, w = score_item(it, logs, lengths[it["subject"]])
            rows += r
            wbs.append(w)
            if (i + 1) % 20 == 0:
                print(f"  {i + 1}/{len(items)} ({time.perf_counter() - t0:.0f} s)", file=sys.stderr)
        table, wb = pd.DataFrame(rows), pd.DataFrame(wbs)
        if cache is not None:
            cache.parent.mkdir(parents=True, exist_ok=True)
            cache.write_bytes(pickle.dumps((table, wb)))
    if args.csv:
        table.to_csv(args.csv, index=False)
    lines = ["### The still logs (gaitml.signal.gyro_bias_from_still, as `--gyro-bias-from` reads them), most still first", ""]
    lines += ["| phone | log | still s | bias rad/s (x, y, z) |", "|---|---|---|---|"]
    for phone, pl in logs.items():
        for name, gb in pl:
            lines.append(f"| {phone} | {name} | {gb.still_s:.1f} | ({', '.join(f'{v:+.4f}' for v in gb.bias_rads)}) |")
    lines.append("")
    variants = list(VARIANTS) + sorted(v for v in table["variant"].unique() if v.startswith("held, "))
    for subset, sel in (
        ("NoDist (9 per motion)", table["disturbance"] == "NoDist"),
        ("all (18 per walking motion, 9 running)", table.index >= 0),
    ):
        t = table[sel]
        lines += [
            f"### |walking-direction drift| deg/min, median, {subset}",
            md(_abs_median(t, "drift_deg_per_min", variants), "{:.1f}"),
            "",
        ]
        err = t.pivot_table(index="variant", columns="motion", values="error_10s_pct", aggfunc="median")
        err = err.reindex(index=[v for v in variants if v in err.index], columns=[m for m in MOTION_ORDER if m in err.columns])
        lines += [f"### 10 s error %, median, {subset}", md(err, "{:.1f}"), ""]
    for v, against in (
        ("still log, held", "default"),
        ("still log, tracked", "default"),
        ("still log, tracked", "still log, held"),
        ("baseline, still-log bias", "baseline"),
        ("still log, held", "baseline, still-log bias"),
        ("still log, tracked", "baseline, still-log bias"),
        ("still log, tracked", "baseline"),
    ):
        lines += [f"### |drift| recording by recording, all: {v} against {against}", md(paired(table, v, against), "{:.1f}"), ""]
        lines += [
            f"### 10 s error recording by recording, all: {v} against {against}",
            md(paired(table, v, against, "error_10s_pct"), "{:.1f}"),
            "",
        ]
    rule = adoption(table)
    lines += [f"### The rule (fixed before measuring): {rule}", ""]
    for by in ("subject", "phone"):
        for v in ("default", "still log, held", "still log, tracked", "baseline", "baseline, still-log bias"):
            piv = table[table["variant"] == v].assign(a=lambda d: d["drift_deg_per_min"].abs())
            piv = piv.pivot_table(index=by, columns="motion", values="a", aggfunc="median")
            lines += [
                f"### |drift| median per {by} (all): {v}",
                md(piv.reindex(columns=[m for m in MOTION_ORDER if m in piv.columns]), "{:.1f}"),
                "",
            ]
    lines += per_log_lines(table, logs)
    sig = table[(table["phone"] == "iPhone5") & table["variant"].isin(["default", "still log, held", "still log, tracked"])]
    wide = sig.pivot_table(index=["file"], columns="variant", values="drift_deg_per_min")
    wide.index = [f.split("/")[-1] for f in wide.index]
    if len(wb) and "walk_bias_rads" in wb:
        w = wb.set_index(wb["file"].map(lambda f: f.split("/")[-1]))
        wide = wide.join(w[["walk_bias_vertical_deg_per_min", "log_error_vertical_deg_per_min"]])
    lines += [
        "### iPhone 5, signed drift deg/min per recording (positive counter-clockwise), and the log's bias error about the vertical",
        md(wide, "{:.1f}"),
        "",
    ]
    if len(wb) and "walk_bias_rads" in wb:
        lines += walk_bias_lines(wb, logs)
    text = "\n".join(lines)
    print(text)
    if args.out:
        Path(args.out).write_text(text + "\n")
    print(f"done in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
