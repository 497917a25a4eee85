"""How well the tempo copies' gravity is known on real running: the attitude filter's phone-frame up against the motion capture's.

``python -m experiments.scripts.tempo_gravity [--data ../shared/data] [--factors 0.87,1.15,0.8,1.25] [--csv FILE]``
from the repository root.

A tempo copy (:func:`gaitml.pipeline.augment.tempo_recording`) writes the accelerometer as
``s^2 (acc - g_up_b) + g_up_b``: an error ``e`` in the phone-frame gravity ``g_up_b`` becomes an error
``|1 - s^2| e`` in the copy. For every tyrex recording of a running motion (RunningHand, RunningPocket;
``--motions`` for others) at the model's 50 Hz, over the moving samples (body speed > 0.3 m/s, the labels of
:func:`experiments.scripts.tyrex_modes.load_tyrex_labelled`), this compares per sample

- ``filter``: :func:`gaitml.pipeline.augment.phone_up_gravity` (the package's attitude filter, what the copies use),
- ``lowpass``: the accelerometer low-passed at 0.3 Hz (:func:`gaitml.signal.gravity_direction`, the alternative),

with the truth ``R_mount^T rot^T (0, 0, 1)`` (the motion capture's attitude ``rot``, body to room, and the constant
phone-to-holder rotation of :func:`gaitml.io.tyrex.estimate_mount_rotation`). The truth is used only where that
rotation explains the gyroscope (its RMS residual below :data:`MAX_MOUNT_RESIDUAL` of the angular rate's RMS): in
several tyrex recordings (all the Nexus 5 runs among them) the motion capture's body rate does not match the
phone's gyroscope through any constant rotation (residual as large as the rate itself), so its attitude cannot serve
as the phone's truth there; those recordings are counted and left out. Printed per motion and phone: the
angle between the estimated and the true up (median, 95th percentile), the gravity vector error ``g |u - u_true|``
(m/s^2, 95th percentile), the copy's accelerometer error ``|1 - s^2| g |u - u_true|`` for each factor (95th
percentile) beside the RMS of the copy's linear acceleration ``s^2 |acc - g_up_b|`` (what the error is
to be read against). Nothing is fitted: no held-out split applies.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

#: the largest RMS residual of the mount rotation's fit (fraction of the angular rate's RMS) at which the motion
#: capture's attitude is taken as the phone's truth; a good fit leaves 0.1-0.4 of it (tyrex iPhone pockets)
MAX_MOUNT_RESIDUAL = 0.5


def up_errors(item: dict) -> dict:
    """Per moving sample of a labelled tyrex item: true up, the filter's and the low-pass's (unit vectors, phone frame)."""
    from gaitml.io.tyrex import estimate_mount_rotation
    from gaitml.pipeline.augment import phone_up_gravity
    from gaitml.signal import gravity_direction

    rec, truth = item["recording"], item["truth"]
    r_mount, info = estimate_mount_rotation(rec, truth)
    rot = truth.rotation_at(truth.recording_times(rec))
    up_true = np.einsum("ij,njk,k->ni", r_mount.T, np.transpose(rot, (0, 2, 1)), np.array([0.0, 0.0, 1.0]))
    g_b = phone_up_gravity(rec)
    up_f = g_b / np.linalg.norm(g_b, axis=1, keepdims=True)
    up_l = gravity_direction(rec.acc, rec.sampling_rate_hz, cutoff_hz=0.3)
    moving = (np.asarray(rec.labels, dtype=object).astype(str) == item["mode"]) & np.isfinite(up_true).all(axis=1)
    fit = info["rate_rms_residual_rads"] / max(info["rate_rms_rads"], 1e-9)
    out = {"true": up_true[moving], "filter": up_f[moving], "lowpass": up_l[moving], "acc": rec.acc[moving], "g_b": g_b[moving]}
    return out, fit


def main(argv=None) -> int:
    from experiments.scripts.tyrex_modes import load_tyrex_labelled
    from gaitml.consts import GRAVITY_MS2

    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--motions", default="RunningHand,RunningPocket")
    ap.add_argument("--factors", default="0.87,1.15,0.8,1.25")
    ap.add_argument("--csv", type=Path, default=None)
    a = ap.parse_args(argv)
    if not (a.data / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    motions = a.motions.split(",")
    try:
        factors = [float(f) for f in a.factors.split(",") if f]
    except ValueError:
        factors = []
    if not factors or not all(0 < s for s in factors):
        print(f"error: --factors must list positive tempo factors, e.g. 0.87,1.15; got {a.factors!r}", file=sys.stderr)
        return 2
    items = [it for it in load_tyrex_labelled(a.data, 50.0) if it["motion"] in motions]
    rows = []
    pooled: dict = {}
    left_out = []
    for it in items:
        e, fit = up_errors(it)
        if fit > MAX_MOUNT_RESIDUAL:
            left_out.append(f"{it['subject']} {it['phone']} {it['motion']} (residual {fit:.2f} of the rate)")
            continue
        key = (it["motion"], it["phone"])
        for k, v in e.items():
            pooled.setdefault(key, {}).setdefault(k, []).append(v)
        pooled.setdefault((it["motion"], "all"), {})
        for k, v in e.items():
            pooled[(it["motion"], "all")].setdefault(k, []).append(v)
    for (motion, phone), parts in sorted(pooled.items()):
        e = {k: np.concatenate(v) for k, v in parts.items()}
        row = {"motion": motion, "phone": phone, "samples": len(e["true"])}
        for est in ("filter", "lowpass"):
            cosang = np.clip(np.sum(e[est] * e["true"], axis=1), -1.0, 1.0)
            ang = np.degrees(np.arccos(cosang))
            gerr = GRAVITY_MS2 * np.linalg.norm(e[est] - e["true"], axis=1)
            row[f"{est} angle median deg"] = np.median(ang)
            row[f"{est} angle p95 deg"] = np.percentile(ang, 95)
            row[f"{est} g error p95 m/s2"] = np.percentile(gerr, 95)
        gerr = GRAVITY_MS2 * np.linalg.norm(e["filter"] - e["true"], axis=1)
        lin = np.linalg.norm(e["acc"] - e["g_b"], axis=1)
        for s in factors:
            row[f"copy error p95 at {s:g} m/s2"] = abs(1 - s**2) * np.percentile(gerr, 95)
            row[f"copy linear acc RMS at {s:g} m/s2"] = s**2 * np.sqrt(np.mean(lin**2))
        rows.append(row)
    t = pd.DataFrame(rows)
    print(f"{len(items) - len(left_out)} of {len(items)} recordings with a usable truth; left out: {'; '.join(left_out) or 'none'}")
    with pd.option_context("display.width", 250, "display.max_columns", 50):
        print(t.round(2).to_string(index=False))
    if a.csv is not None:
        t.to_csv(a.csv, index=False)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
