"""Side-step direction of a phone held upright, read in the walker's body frame (issue 27; simulator only). Lab study.

``python -m experiments.scripts.side_direction [--seeds 2024,2025,2026] [--subjects 4] [--models models/demo]
[--walking read|labels] [--scope recording|before] [--oracle] [--out FILE]`` from the repository root.

The idea. A phone held flat in front of the walker has its x axis to the walker's right, so the phone-frame features
of paper 003 (sec. 3.2) tell ``side_left`` from ``side_right``. A phone held upright (trouser pocket, swinging hand) may
sit on either leg with its screen in or out and either way up: its lateral axis is tied to the walker's only through the
placement, which flips it (``gaitml predict`` marks those windows ``side_direction_unsure``,
:func:`gaitml.models._predict.side_direction_unsure`). Within one recording the placement stays the same (the simulator
draws it once per walker and position, :meth:`gaitml.simulate.positions.Placement.random`), so the walker's frame in
the phone can be read from the recording's own walking and carried into its side steps:

1. Forward, with its sign, from walking (:func:`window_vectors`, ``forward``). In walking the body vaults over the
   stance leg as an inverted pendulum: fastest along the direction of walking at double support (heel strike, where the
   vertical acceleration peaks), slowest at mid-stance (Cavagna, Heglund & Taylor 1977, "Mechanical work in terrestrial
   locomotion: two basic mechanisms for minimizing energy expenditure", Am. J. Physiol. 233(5); the pattern
   :func:`gaitml.simulate.modes.mode_gait` gives simulated walking). So the forward acceleration goes with the rate of
   change of the vertical acceleration, and the horizontal acceleration's covariance with that rate points forward,
   sign included: the principal horizontal axis of walking used for the walking direction (Kunze et al. 2009, "Which way
   am I facing: inferring horizontal device orientation from an accelerometer signal", ISWC; Steinhoff & Schiele 2010,
   "Dead reckoning from the pocket - an experimental study", PerCom; paper 002's dynamic-window PCA,
   :mod:`gaitml.pdr.dwpca`, resolves its 180 deg ambiguity from the same gait phase), weighted by the gait phase so that
   the axis and its sign come at once and the sway (at half the step frequency) drops out. The windows read ``walk``
   (``--walking read``, in domain, as ``gaitml predict`` answers) or labelled walk (``--walking labels``, a diagnostic:
   a classifier that never confuses walking) are summed: one placement, one forward axis in the phone frame.
2. The side step's direction (:func:`body_frame_side_directions`). In each side-step window the walker's right is
   forward x up (up: the window's mean acceleration), the forward axis projected on that window's horizontal plane (a
   thigh or an arm turns about the walker's left-right axis: the phone's pitch against the body moves the forward axis
   in the phone frame, not the right). The lead foot lands and brakes the sideways motion hardest at impact, where the
   vertical acceleration peaks (:func:`gaitml.simulate.modes.mode_gait`, side steps), so a step to the right has the
   rightward acceleration's covariance with the vertical one below zero.

Which quantities can tell the direction at all: mirroring the walker (left <-> right) maps a phone on the left leg
stepping left onto a phone on the right leg stepping right. Every true scalar of a window (norms, the vertical
component, dot products of horizontal vectors) is the same for the two, so features invariant to a turn about gravity
that are true scalars cannot give the direction, only "towards the carrying leg's side or away"; the direction needs a
quantity that changes sign under the mirror (here the walker's forward axis crossed with up). The simulator models that
chirality: its phone is a proper, right-handed frame on a mirrored leg (``Placement.side``, the lever and the lead leg
follow it).

Simulates ``--subjects`` walkers x 120 s per seed in the five positions the shipped models are trained on (hand-flat,
hand-tilted, swinging-hand, front-pocket, back-pocket; all five modes) and predicts every recording through
:func:`gaitml.models.predict_recording` (today's answer: the phone-frame direction, ``side_direction_unsure`` on an
upright phone); the body frame then decides the direction of every unsure side-step window (``after``). Scored over the
windows labelled ``side_left`` / ``side_right`` (label fraction >= 0.5) that the model reads, in domain, as a side step
of either direction: *direction right*, before and after, the share still unsure after, and the spread over walkers;
per mode over all its windows: *right* (in domain, the labelled mode), before and after. ``--oracle``: the direction
rule of 2 on the simulator's true body frame (its attitude and facing heading), every side-step window, no classifier.

Seeds: 7 and 8 chose the rule (scope ``recording`` over ``before``; the sum of the walking windows' vectors over
their principal axis); 2024 (the held-out seed of ``experiments/reports/default-model.md``), 2025 and 2026 score it.
The adoption rule, fixed before the held-out seeds were simulated: on the held-out seeds, pooled, with the shipped
``models/demo``, (a) in front-pocket, back-pocket and swinging-hand the direction is right in >= 0.90 of the windows read
as a side step, for side_left and side_right each; (b) in hand-flat and hand-tilted no figure falls by more than 0.01;
(c) the real tyrex figures of ``tyrex_modes`` are not worse. Measured: (a) fails (report section "Side-step direction
in the body frame"), so nothing of this is in the library.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError

SIDE = ("side_left", "side_right")
POSITIONS = ("hand-flat", "hand-tilted", "swinging-hand", "front-pocket", "back-pocket")
SELECTION_SEEDS = (7, 8)
HELDOUT_SEEDS = (2024, 2025, 2026)
WALKING_SOURCES = ("read", "labels")

#: Walking windows needed for a body frame: 4 windows of 1.5 s at half overlap, about 3 s (three strides) of walking.
#: Not fitted (a floor that keeps a lone misread window from deciding); with less the window stays unsure.
SIDE_BODY_MIN_WALK_WINDOWS = 4
#: Which walking gives a side step its forward axis: ``"recording"``, every window read ``walk`` in the recording (the
#: placement is taken to stay the same through one recording), or ``"before"``, only the windows before the side step.
SIDE_BODY_SCOPES = ("recording", "before")
SIDE_BODY_SCOPE = "recording"


def window_vectors(acc: np.ndarray, starts, ends, *, dynamic: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per window ``[start, end)`` of ``acc`` (n, 3, phone frame): up, the forward vector of walking, the lateral one.

    ``dynamic`` (n, 3), optional: the acceleration the covariances read (e.g. ``acc`` band-passed to the gait band,
    :func:`gait_band`); ``up`` always comes from ``acc``.

    Returns
    -------
    up : (m, 3) unit mean acceleration of the window (gravity's direction, pointing up in the phone frame).
    forward : (m, 3) ``sum_t a_h(t) r(t) / (m_w sd(r))``: the horizontal acceleration's (gravity removed, the
        window's mean removed, projected off ``up``) covariance with the rate of change ``r`` of the vertical
        acceleration (m/s^2). In walking it points along the walker's forward axis (module docstring, 1).
    lateral : (m, 3) ``sum_t (a(t) - mean) (a_v(t) - mean) / m_w``: the covariance of each axis with the vertical
        acceleration ((m/s^2)^2); its dot product with a horizontal unit vector ``e`` is the covariance of the
        acceleration along ``e`` with the vertical one (module docstring, 2).

    A window shorter than 3 samples or with no acceleration gives NaN rows.
    """
    a = np.asarray(acc, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3:
        raise InputError(f"`acc` must have shape (n, 3), got {a.shape}.")
    dyn = a if dynamic is None else np.asarray(dynamic, dtype=float)
    if dyn.shape != a.shape:
        raise InputError(f"`dynamic` must have the shape of `acc` {a.shape}, got {dyn.shape}.")
    starts = np.asarray(starts, dtype=np.int64)
    ends = np.minimum(np.asarray(ends, dtype=np.int64), len(a))
    m = len(starts)
    up = np.full((m, 3), np.nan)
    forward = np.full((m, 3), np.nan)
    lateral = np.full((m, 3), np.nan)
    for i in range(m):
        x = a[starts[i] : ends[i]]
        if len(x) < 3:
            continue
        mean = x.mean(axis=0)
        g = float(np.linalg.norm(mean))
        if g == 0:
            continue
        u = mean / g
        d = x - mean if dynamic is None else dyn[starts[i] : ends[i]] - dyn[starts[i] : ends[i]].mean(axis=0)
        av = d @ u
        rate = np.gradient(av)
        sd = float(rate.std())
        up[i] = u
        lateral[i] = (d * av[:, None]).sum(axis=0) / len(x)
        if sd > 0:
            ah = d - av[:, None] * u
            forward[i] = (ah * rate[:, None]).sum(axis=0) / (len(x) * sd)
        else:
            forward[i] = 0.0
    return up, forward, lateral


def body_frame_side_directions(
    modes,
    unsure,
    walking,
    up: np.ndarray,
    forward: np.ndarray,
    lateral: np.ndarray,
    *,
    min_walk_windows: int = SIDE_BODY_MIN_WALK_WINDOWS,
    scope: str = SIDE_BODY_SCOPE,
) -> tuple[np.ndarray, np.ndarray]:
    """The direction of every ``unsure`` side-step window read in the walker's body frame (module docstring).

    Parameters
    ----------
    modes : (m,) str, the windows' modes in time order; ``unsure`` windows are ``side_left`` or ``side_right``.
    unsure : (m,) bool, side steps whose phone-frame direction is unsure (a phone held upright).
    walking : (m,) bool, windows whose walking may give the forward axis (read ``walk``, in domain, not still).
    up, forward, lateral : (m, 3), :func:`window_vectors` of the same windows.
    min_walk_windows : the walking windows needed (:data:`SIDE_BODY_MIN_WALK_WINDOWS`).
    scope : ``"recording"`` (the walking windows of the whole recording) or ``"before"`` (only those before each side
        step); :data:`SIDE_BODY_SCOPE`.

    Returns
    -------
    modes : (m,) str, ``side_right`` where the body frame says right, ``side_left`` where left; the others unchanged.
    decided : (m,) bool, the side steps whose direction the body frame decided (the rest of ``unsure`` stays unsure).

    The walking windows' forward vectors are summed: one placement, one forward axis in the phone frame.
    """
    modes = np.asarray(modes).astype(str).astype(object)  # object: a longer name fits (side_left -> side_right)
    unsure = np.asarray(unsure, dtype=bool)
    walking = np.asarray(walking, dtype=bool)
    m = len(modes)
    if not (len(unsure) == len(walking) == len(up) == len(forward) == len(lateral) == m):
        raise InputError("body_frame_side_directions needs one modes / unsure / walking / vector row per window.")
    if scope not in SIDE_BODY_SCOPES:
        raise InputError(f"`scope` must be one of {', '.join(SIDE_BODY_SCOPES)}, got {scope!r}.")
    if min_walk_windows < 1:
        raise InputError(f"`min_walk_windows` must be >= 1, got {min_walk_windows}.")
    decided = np.zeros(m, dtype=bool)
    if not unsure.any():
        return modes.astype(str), decided
    ok = walking & np.isfinite(forward).all(axis=1)
    f_cum = np.cumsum(np.where(ok[:, None], forward, 0.0), axis=0)
    n_cum = np.cumsum(ok)
    for i in np.flatnonzero(unsure):
        k = m - 1 if scope == "recording" else i - 1  # the last window whose walking counts
        if k < 0 or n_cum[k] < min_walk_windows or not np.isfinite(up[i]).all() or not np.isfinite(lateral[i]).all():
            continue
        f = f_cum[k]
        f_h = f - (f @ up[i]) * up[i]
        norm = float(np.linalg.norm(f_h))
        if norm == 0:
            continue
        right = np.cross(f_h / norm, up[i])
        c = float(right @ lateral[i])
        if c == 0:
            continue
        modes[i] = "side_right" if c < 0 else "side_left"
        decided[i] = True
    return modes.astype(str), decided


def simulate(seed: int, subjects: int, positions=POSITIONS) -> list:
    from gaitml.simulate import simulate_dataset

    return list(simulate_dataset(n_subjects=subjects, duration_s=120.0, pose="mixed", seed=seed, positions=positions))


def score_recording(model, rec, walking_source: str = "read", scope: str = SIDE_BODY_SCOPE) -> list[dict]:
    """Rows per labelled window (label fraction >= 0.5): today's answer and the body frame's."""
    from gaitml.models import predict_recording, resample_recording

    if walking_source not in WALKING_SOURCES:
        raise InputError(f"`walking_source` must be one of {', '.join(WALKING_SOURCES)}, got {walking_source!r}.")
    p = predict_recording(model, rec)
    lab = p["label"].astype(str).to_numpy()
    ok = (p["label_fraction"] >= 0.5).to_numpy()
    inside = p["in_domain"].map(lambda v: v is not False).to_numpy(bool)
    mb = p["mode"].astype(str).to_numpy()
    unsure = p["side_direction_unsure"].to_numpy(bool)
    walking = ((mb == "walk") & inside) if walking_source == "read" else ((lab == "walk") & ok)
    at_rate = resample_recording(rec, model.sampling_rate_hz)
    up, fw, lat = window_vectors(at_rate.acc, p["start"], p["end"])
    ma, body = body_frame_side_directions(mb, unsure, walking, up, fw, lat, scope=scope)
    rows = []
    for i in np.flatnonzero(ok):
        rows.append(
            {
                "seed": rec.meta["seed"],
                "subject": rec.meta["subject"],
                "position": rec.meta["position"],
                "label": lab[i],
                "read_side": bool(inside[i] and mb[i] in SIDE),
                "right_before": bool(inside[i] and mb[i] == lab[i]),
                "right_after": bool(inside[i] and ma[i] == lab[i]),
                "unsure_before": bool(unsure[i]),
                "unsure_after": bool(unsure[i] and not body[i]),
            }
        )
    return rows


def _true_right(rec) -> np.ndarray:
    """The walker's right in the phone frame per sample (the simulator's attitude and facing heading)."""
    from scipy.spatial.transform import Rotation

    q = rec.reference["attitude_wxyz"]
    att = Rotation.from_quat(np.column_stack([q[:, 1:], q[:, :1]])).as_matrix()
    th = rec.reference["trajectory"]["heading_rad"].to_numpy()
    right_nav = np.column_stack([np.cos(th), -np.sin(th), np.zeros_like(th)])  # facing heading, clockwise from north
    return np.einsum("nji,nj->ni", att, right_nav)


def walker_row(model, rec) -> dict:
    """One simulated recording: the summed forward vector of the windows read ``walk`` against the true forward axis
    (angle, deg), and each true mode's part of that sum along the true axis (its windows read ``walk``)."""
    from gaitml.models import predict_recording, resample_recording

    p = predict_recording(model, rec)
    at_rate = resample_recording(rec, model.sampling_rate_hz)
    right = _true_right(at_rate)
    up, fw, _ = window_vectors(at_rate.acc, p["start"], p["end"])
    inside = p["in_domain"].map(lambda v: v is not False).to_numpy(bool)
    walking = (p["mode"].astype(str).to_numpy() == "walk") & inside
    lab = p["label"].astype(str).to_numpy()
    row = {"seed": rec.meta["seed"], "position": rec.meta["position"], "subject": rec.meta["subject"]}
    total, true_sum = np.zeros(3), np.zeros(3)
    parts: dict[str, float] = {}
    for i in np.flatnonzero(walking):
        tf = np.cross(up[i], right[p["start"].iloc[i] : p["end"].iloc[i]].mean(axis=0))
        tf /= np.linalg.norm(tf)
        total += fw[i]
        true_sum += tf
        key = f"{lab[i]} read walk"
        parts[key] = parts.get(key, 0.0) + float(fw[i] @ tf)
        parts[f"n {lab[i]}"] = parts.get(f"n {lab[i]}", 0) + 1
    cos = float(total @ true_sum) / max(np.linalg.norm(total) * np.linalg.norm(true_sum), 1e-12)
    return {**row, "angle (deg)": float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))), **parts}


def oracle_rows(rec) -> list[dict]:
    """The simulator's true body frame, no classifier: the direction rule on every side-step window, and the sign
    of every walk and backward window's forward vector along the true forward axis and along the phone's y axis."""
    from gaitml.models._predict import _windows_for

    right = _true_right(rec)
    w = _windows_for(rec, 1.5, 0.5)
    up, fw, lateral = window_vectors(rec.acc, w["start"], w["end"])
    rows = []
    for i, (s, e, lab, frac) in enumerate(w[["start", "end", "label", "label_fraction"]].itertuples(index=False)):
        if frac < 0.5 or lab not in (*SIDE, "walk", "backward"):
            continue
        r = right[s:e].mean(axis=0)
        r = r - (r @ up[i]) * up[i]
        row = {"seed": rec.meta["seed"], "subject": rec.meta["subject"], "position": rec.meta["position"], "label": lab}
        if lab in SIDE:
            rows.append({**row, "kind": "side", "right": (float(r @ lateral[i]) < 0) == (lab == "side_right")})
            continue
        y = np.array([0.0, 1.0, 0.0]) - up[i][1] * up[i]
        forward_says_walk = float(fw[i] @ np.cross(up[i], r)) > 0
        rows.append(
            {
                **row,
                "kind": "walk/backward",
                "right": forward_says_walk == (lab == "walk"),
                "right_phone_y": (float(fw[i] @ y) > 0) == (lab == "walk"),
            }
        )
    return rows


def gait_band(acc: np.ndarray, fs: float, band_hz: tuple[float, float]) -> np.ndarray:
    """``acc`` band-passed to ``band_hz`` (zero-phase Butterworth, order 2): the gait's step rhythm without the
    heel-strike impacts and the slow turns (a lab option of the real-data check, not chosen by any fold)."""
    from scipy.signal import butter, sosfiltfilt

    sos = butter(2, band_hz, btype="band", fs=fs, output="sos")
    return sosfiltfilt(sos, np.asarray(acc, dtype=float), axis=0)


def tyrex_forward_rows(data: Path, band_hz: tuple[float, float] | None = None) -> list[dict]:
    """Real carried phones: the forward vector of every moving window against the true walking direction (tyrex).

    The true walking direction in the phone frame: the walker's horizontal velocity (the motion capture's path
    low-passed, :func:`gaitml.signal.body_track`) turned into the rigid body's frame (``TyrexTruth.rot``, within a few
    degrees of the phone's), averaged over the window. Per window, whether its forward vector points within 90 deg of
    it (the time-odd sign a walk has and a backward walk would not); per recording, the angle between the sum over
    its moving windows (as :func:`body_frame_side_directions` sums them) and the mean true direction. In the face-up
    windows (gravity within ``FACE_UP_MAX_DEG`` of the phone's +z), whether the forward vector points along the
    phone's +y, as a walk-or-backward rule on a hand-held phone would read it. ``band_hz``: the
    covariances read the acceleration band-passed to it (:func:`gait_band`).
    """
    from experiments.scripts.tyrex_modes import load_tyrex_labelled
    from gaitml.models._predict import FACE_UP_MAX_DEG, _windows_for
    from gaitml.signal import body_track

    rows = []
    for item in load_tyrex_labelled(data):
        rec, truth = item["recording"], item["truth"]
        mode = "run" if str(item["motion"]).startswith("Running") else "walk"
        tt = truth.t_s - rec.meta["t0_original_s"]
        ok = truth.valid
        xy = body_track(tt, truth.pos_m[:, :2])
        v = np.gradient(xy, tt, axis=0)
        v_room = np.column_stack([v, np.zeros(len(v))])
        rot = np.where(ok[:, None, None], truth.rot, np.nan)
        fwd_body = np.einsum("nji,nj->ni", rot, v_room)  # room -> rigid body (phone)
        idx = np.clip(np.searchsorted(tt, rec.t_s), 0, len(tt) - 1)
        true_f = fwd_body[idx]
        w = _windows_for(rec, 1.5, 0.5)
        dyn = None if band_hz is None else gait_band(rec.acc, rec.sampling_rate_hz, band_hz)
        up, fw, _ = window_vectors(rec.acc, w["start"], w["end"], dynamic=dyn)
        moving = ((w["label"].astype(str) == mode) & (w["label_fraction"] >= 0.5)).to_numpy()
        tf_sum, f_sum = np.zeros(3), np.zeros(3)
        agree, along_y = [], []
        for i in np.flatnonzero(moving):
            t = true_f[w["start"].iloc[i] : w["end"].iloc[i]]
            t = t[np.isfinite(t).all(axis=1)]
            if len(t) == 0 or not np.isfinite(fw[i]).all():
                continue
            tf = t.mean(axis=0)
            tf = tf - (tf @ up[i]) * up[i]
            if np.linalg.norm(tf) == 0:
                continue
            tf_sum += tf / np.linalg.norm(tf)
            f_sum += fw[i]
            agree.append(float(fw[i] @ tf) > 0)
            if up[i][2] >= np.cos(np.radians(FACE_UP_MAX_DEG)):  # face up: the phone's y is the walker's forward
                along_y.append(float(fw[i] @ (np.array([0.0, 1.0, 0.0]) - up[i][1] * up[i])) > 0)
        if not agree:
            continue
        cos = float(f_sum @ tf_sum) / (np.linalg.norm(f_sum) * np.linalg.norm(tf_sum))
        rows.append(
            {
                "motion": item["motion"],
                "person": item["subject"],
                "phone": rec.meta.get("device", ""),
                "windows": len(agree),
                "window forward within 90 deg": float(np.mean(agree)),
                "face-up windows": len(along_y),
                "face-up: forward along the phone's +y": float(np.mean(along_y)) if along_y else np.nan,
                "recording sum: angle (deg)": float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))),
            }
        )
    return rows


def time_reversal_changes(recs, subset: str = "all52+gyro") -> pd.DataFrame:
    """Which features of a window change when its motion runs backwards in time (acc reversed, gyroscope reversed and
    negated), over every window of ``recs``: the share of windows in which each feature changes (relative 1e-9)."""
    from gaitml.features import feature_names
    from gaitml.features._extract import features_from_arrays
    from gaitml.models._predict import _windows_for

    names = feature_names(subset)
    changed, n = np.zeros(len(names)), 0
    for rec in recs:
        acc, gyr = np.asarray(rec.acc), np.asarray(rec.gyr)
        w = _windows_for(rec, 1.5, 0.5)
        length = int(w["end"].iloc[0] - w["start"].iloc[0])
        f = features_from_arrays(acc, gyr, fs=rec.sampling_rate_hz, starts=w["start"].to_numpy(), length=length, subset=subset)
        back = np.concatenate([acc[s : s + length][::-1] for s in w["start"]])
        gback = np.concatenate([-gyr[s : s + length][::-1] for s in w["start"]])
        starts = np.arange(len(w)) * length
        b = features_from_arrays(back, gback, fs=rec.sampling_rate_hz, starts=starts, length=length, subset=subset)
        changed += (np.abs(f - b) > 1e-9 * (1.0 + np.abs(f))).sum(axis=0)
        n += len(w)
    return pd.DataFrame({"feature": names, "changed": changed / max(n, 1)})


def direction_table(df: pd.DataFrame) -> pd.DataFrame:
    """Per position and direction: windows read as a side step, direction right before / after, unsure, spread."""
    out = []
    for (pos, lab), g in df[df["label"].isin(SIDE)].groupby(["position", "label"], sort=False):
        s = g[g["read_side"]]
        per = s.groupby(["seed", "subject"])["right_after"].mean()
        out.append(
            {
                "position": pos,
                "mode": lab,
                "windows read as a side step": len(s),
                "direction right, before": s["right_before"].mean(),
                "after": s["right_after"].mean(),
                "unsure before": s["unsure_before"].mean(),
                "unsure after": s["unsure_after"].mean(),
                "after, per walker (min-max)": f"{per.min():.2f}-{per.max():.2f}" if len(per) else "-",
            }
        )
    return pd.DataFrame(out)


def mode_table(df: pd.DataFrame) -> pd.DataFrame:
    """Per position and labelled mode: right (in domain, the labelled mode) before / after."""
    g = df.groupby(["position", "label"], sort=False)
    return g.agg(windows=("right_before", "size"), before=("right_before", "mean"), after=("right_after", "mean")).reset_index()


def md(df: pd.DataFrame) -> str:
    from experiments.scripts.default_model import md as table

    return table(df)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", default=",".join(map(str, HELDOUT_SEEDS)))
    ap.add_argument("--subjects", type=int, default=4)
    ap.add_argument("--models", default="models/demo")
    ap.add_argument(
        "--walking", default="read", choices=WALKING_SOURCES, help="read: windows the model reads walk; labels: the true walking"
    )
    ap.add_argument("--scope", default=SIDE_BODY_SCOPE, choices=SIDE_BODY_SCOPES)
    ap.add_argument("--oracle", action="store_true", help="the rule on the true body frame (no classifier)")
    ap.add_argument("--walkers", action="store_true", help="per recording: the walking sum's angle and what it is made of")
    ap.add_argument("--reversal", action="store_true", help="which features change when a window runs backwards in time")
    ap.add_argument("--tyrex", action="store_true", help="also the forward vector on the real tyrex walks and runs (motion capture)")
    ap.add_argument("--band", default=None, metavar="LO,HI", help="with --tyrex: also the forward vector band-passed to LO-HI Hz")
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--out", type=Path, default=None)
    a = ap.parse_args(argv)
    from gaitml.models import load_model

    seeds = [int(s) for s in a.seeds.split(",") if s]
    text = []

    def emit(s=""):
        print(s)
        text.append(s)

    if a.reversal:
        t = time_reversal_changes(simulate(seeds[0] if seeds else HELDOUT_SEEDS[0], 1, ("hand-flat",)))
        ch = t[t["changed"] > 0]
        emit("### Features that change when the motion runs backwards in time (hand-flat walker, every window)\n")
        emit(f"{len(ch)} of {len(t)}: " + (", ".join(ch["feature"]) if len(ch) else "none"))
        emit("")
    for band in [None, *([tuple(float(v) for v in a.band.split(","))] if a.band else [])] if a.tyrex else []:
        t = pd.DataFrame(tyrex_forward_rows(a.data, band))
        t["flipped"] = t["recording sum: angle (deg)"] > 90.0
        per = t.groupby("motion", sort=False).agg(
            recordings=("windows", "size"),
            windows=("windows", "sum"),
            within=("window forward within 90 deg", "mean"),
            within_min=("window forward within 90 deg", "min"),
            angle_median=("recording sum: angle (deg)", "median"),
            angle_max=("recording sum: angle (deg)", "max"),
            flipped=("flipped", "sum"),
            face_up=("face-up windows", "sum"),
            face_up_along_y=("face-up: forward along the phone's +y", "mean"),
        )
        what = "as recorded" if band is None else f"band-passed {band[0]:g}-{band[1]:g} Hz"
        emit(f"### Real carried phones (tyrex, moving windows by the speed rule): the forward vector ({what}) against the motion capture\n")
        emit(md(per.reset_index()))
        emit("")
    recs = []
    for seed in seeds:
        recs += simulate(seed, a.subjects)
        print(f"[side_direction] simulated seed {seed}", file=sys.stderr)
    emit(
        f"## Seeds {', '.join(map(str, seeds))} ({a.subjects} walkers x 120 s per seed and position; walking {a.walking}, scope {a.scope})\n"
    )
    if a.oracle:
        o = pd.DataFrame([r for rec in recs for r in oracle_rows(rec)])
        side = o[o["kind"] == "side"]
        t = side.groupby(["position", "label"], sort=False)["right"].agg(["size", "mean"]).reset_index()
        emit("### The rule on the true body frame (every side-step window, no classifier)\n")
        emit(md(t.rename(columns={"size": "windows", "mean": "direction right"})))
        wb = o[o["kind"] == "walk/backward"]
        t = wb.groupby(["position", "label"], sort=False).agg(
            windows=("right", "size"), true_frame=("right", "mean"), phone_y=("right_phone_y", "mean")
        )
        emit("\n### Walk or backward from the sign of the forward vector (true forward axis; the phone's y axis)\n")
        emit(md(t.reset_index()))
    for name in [m for m in a.models.split(",") if m]:
        model = load_model(name)
        df = pd.DataFrame([r for rec in recs for r in score_recording(model, rec, a.walking, a.scope)])
        emit(f"\n### {name}: side-step direction (windows read, in domain, as a side step)\n")
        emit(md(direction_table(df)))
        emit(f"\n### {name}: right per mode (in domain, the labelled mode), before -> after\n")
        emit(md(mode_table(df)))
        if a.walkers:
            w = pd.DataFrame([walker_row(model, rec) for rec in recs if rec.meta["position"] not in ("hand-flat", "hand-tilted")])
            cols = ["seed", "position", "subject", "angle (deg)"] + sorted(c for c in w.columns if c.endswith("read walk"))
            w = w[cols + sorted(c for c in w.columns if c.startswith("n "))].fillna(0.0)
            emit(f"\n### {name}: per walker, the forward axis from the windows read walk (sum along the true axis by true mode)\n")
            emit(md(w))
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
