"""What the tyrex "moving" windows are: walking, or turning on the spot with the phone held out (motion capture only).

``python -m experiments.scripts.tyrex_ar_moving [--data ../shared/data] [--cache FILE] [--axes] [--plots DIR] [--out FILE]`` from the
repository root.

The speed rule of the modes study (:func:`experiments.scripts.tyrex_modes.moving_labels`) calls a
sample *moving* when the phone's true horizontal path, low-passed at 0.5 Hz
(:func:`gaitml.evaluation.trajectory.body_track`), is faster than 0.3 m/s. The motion capture
tracks the phone, not the body: a person who turns on the spot with the phone held out at arm's
length sweeps the phone round a circle of that radius, and at 0.6-0.8 rad/s the phone goes faster
than 0.3 m/s although nobody walks. This module measures, from the motion capture alone (never from
a classifier's answer), per 1.5 s window:

- ``speed``: the speed rule's body speed (m/s);
- ``speed_lever``: the speed of a lever-arm-corrected body point, the phone's position moved back
  along its own horizontal forward axis by an arm length ``lever_m``, low-passed as above. The
  forward axis (:data:`FORWARD_AXIS`, in the motion-capture holder's axes, which follow the phone's
  sensor axes to a few degrees: :func:`gaitml.io.tyrex.estimate_mount_rotation`) is the axis along
  which the person walks in that position: ``+y`` (the phone's top) held flat for Texting, ``+z``
  (the screen's normal) held upright in landscape for AR;
- ``yaw_rate``: the phone's turn rate about the vertical (rad/s), the net heading change over the
  window divided by its length;
- ``radius``: the curvature radius of the phone's 0.5 Hz path (m), median over the window;
- ``bounce_cm``: the vertical bounce in the step band, the phone's height band-passed
  :data:`BOUNCE_BAND_HZ` and expressed as a peak-to-peak amplitude ``2 sqrt(2) RMS`` over a centred
  1.5 s window (cm). Walking raises and lowers the body 1-5 cm once per step and the phone with it
  (a sinusoid's peak-to-peak is ``2 sqrt(2)`` times its RMS); turning in place does not.

The walking rule (stated from physics before any classifier figure was looked at): a sample is
*walking* when ``speed_lever > 0.3 m/s`` (the speed rule's threshold, applied to the corrected
point) AND ``bounce_cm >= 1.0`` (the low end of a walker's 1-5 cm). The arm length is a property
of the carrying position: :data:`LEVER_ARM_M` (0.4 m for the phone held in front, Texting and AR;
0 where the phone rides on the body or at the ear). Samples that the speed rule calls moving but
the walking rule does not are labelled :data:`NOT_WALKING` (neither a mode nor standing: not scored
either way); samples neither rule calls moving stay ``still``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

__all__ = [
    "BOUNCE_BAND_HZ",
    "BOUNCE_MIN_CM",
    "BOUNCE_VARIANTS_CM",
    "axis_table",
    "LEVER_ARM_M",
    "NOT_WALKING",
    "FORWARD_AXIS",
    "item_walking_labels",
    "mocap_signals",
    "walking_labels",
    "window_signals",
    "main",
]

#: arm length (m) from the body's vertical axis to the phone, per tyrex motion (the carrying position)
LEVER_ARM_M = {
    "Texting": 0.4,
    "AR": 0.4,
    "Phoning": 0.0,
    "Swinging": 0.0,
    "FrontPocket": 0.0,
    "BackPocket": 0.0,
    "RunningHand": 0.0,
    "RunningPocket": 0.0,
}
#: step band for the vertical bounce (Hz): walking 1.4-2.2 steps/s, running up to ~3.5
BOUNCE_BAND_HZ = (1.0, 4.0)
#: a walker's bounce is 1-5 cm peak-to-peak; the rule asks for the low end
BOUNCE_MIN_CM = 1.0
#: label of samples the speed rule calls moving and the walking rule does not
NOT_WALKING = "not-walking"
#: the phone's forward axis (holder axes) per motion where a lever arm applies: the direction the
#: walker faces. Texting: the phone lies nearly flat (the room's up within 15 deg of +z), top away
#: (+y). AR: the phone is upright in landscape (up along -x or +x) and the walking direction lies
#: along +z (:func:`axis_table` measures both).
FORWARD_AXIS = {"Texting": np.array([0.0, 1.0, 0.0]), "AR": np.array([0.0, 0.0, 1.0])}
#: the forward axis where no motion-specific one is known
DEFAULT_FORWARD_AXIS = np.array([0.0, 1.0, 0.0])


def _fill_rot(rot: np.ndarray) -> np.ndarray:
    """Rotation matrices with lost frames (NaN) replaced by the nearest earlier (or first) valid one."""
    ok = np.isfinite(rot).all(axis=(1, 2))
    if not ok.any():
        raise ValueError("the motion capture has no valid attitude; check the qualisys file.")
    idx = np.where(ok, np.arange(len(rot)), -1)
    idx = np.maximum.accumulate(idx)
    idx[idx < 0] = np.argmax(ok)
    return rot[idx]


def _lowpass(x: np.ndarray, fs: float, cutoff_hz: float) -> np.ndarray:
    from scipy.signal import butter, filtfilt

    b, a = butter(2, cutoff_hz / (0.5 * fs))
    return filtfilt(b, a, x, axis=0, padlen=min(len(x) - 1, 3 * int(fs / cutoff_hz)))


def mocap_signals(t_s, pos_m, rot, *, lever_m: float = 0.4, forward_axis=None, cutoff_hz: float | None = None) -> pd.DataFrame:
    """Per motion-capture sample: body speed, lever-corrected speed, yaw rate, curvature radius, bounce.

    Parameters
    ----------
    t_s : (m,) uniform times (s).
    pos_m : (m, 3) phone positions (room frame, z up; NaN where lost).
    rot : (m, 3, 3) body-to-room rotations of the phone (NaN where lost).
    lever_m : arm length (m) the corrected point lies behind the phone along its forward axis.
    forward_axis : (3,) the phone's forward axis in its own axes (default :data:`DEFAULT_FORWARD_AXIS`).
    cutoff_hz : the body low-pass (default :data:`gaitml.evaluation.trajectory.BODY_CUTOFF_HZ`).

    Returns
    -------
    DataFrame with ``t_s``, ``speed``, ``speed_lever``, ``yaw_rate`` (low-passed, rad/s),
    ``yaw`` (unwrapped, rad), ``radius`` (m), ``bounce_cm``, ``z`` (m).
    """
    from scipy.signal import butter, filtfilt
    from scipy.spatial.transform import Rotation

    from gaitml.evaluation.trajectory import BODY_CUTOFF_HZ, body_track

    fc = BODY_CUTOFF_HZ if cutoff_hz is None else float(cutoff_hz)
    t = np.asarray(t_s, dtype=float)
    fs = 1.0 / float(np.median(np.diff(t)))
    pos = np.asarray(pos_m, dtype=float)
    good = np.isfinite(pos).all(axis=1)
    pos = np.column_stack([np.interp(t, t[good], pos[good, j]) for j in range(3)])
    r = _fill_rot(np.asarray(rot, dtype=float))
    # forward axis in the room, horizontal part; hold the last direction where it is nearly vertical
    fa = DEFAULT_FORWARD_AXIS if forward_axis is None else np.asarray(forward_axis, dtype=float)
    f = r @ (fa / np.linalg.norm(fa))
    fh = f[:, :2]
    n = np.linalg.norm(fh, axis=1)
    okf = n > 0.2
    fh = np.where(okf[:, None], fh / np.maximum(n, 1e-9)[:, None], np.nan)
    if okf.any():
        first = int(np.argmax(okf))
        fh[:first] = fh[first]
        for k in range(first + 1, len(fh)):
            if not okf[k]:
                fh[k] = fh[k - 1]
    else:
        fh[:] = 0.0
    body = body_track(t, pos[:, :2], cutoff_hz=fc)
    speed = np.linalg.norm(np.gradient(body, t, axis=0), axis=1)
    corr = body_track(t, pos[:, :2] - float(lever_m) * fh, cutoff_hz=fc)
    speed_lever = np.linalg.norm(np.gradient(corr, t, axis=0), axis=1)
    # yaw: the room-frame rotation between frames, its vertical component
    rel = np.einsum("kij,klj->kil", r[1:], r[:-1])  # R_{k+1} R_k^T
    wz = Rotation.from_matrix(rel).as_rotvec()[:, 2] * fs
    yaw = np.concatenate([[0.0], np.cumsum(wz) / fs])
    yaw_rate = np.gradient(_lowpass(yaw, fs, fc), t)
    # curvature radius of the phone's low-passed path
    v = np.gradient(body, t, axis=0)
    a = np.gradient(v, t, axis=0)
    cross = np.abs(v[:, 0] * a[:, 1] - v[:, 1] * a[:, 0])
    radius = np.linalg.norm(v, axis=1) ** 3 / np.maximum(cross, 1e-9)
    # vertical bounce in the step band
    b, c = butter(2, [BOUNCE_BAND_HZ[0] / (0.5 * fs), BOUNCE_BAND_HZ[1] / (0.5 * fs)], btype="band")
    zb = filtfilt(b, c, pos[:, 2])
    k = max(1, int(round(1.5 * fs)))
    ms = np.convolve(zb**2, np.ones(k) / k, mode="same")
    bounce_cm = 100.0 * 2.0 * np.sqrt(2.0) * np.sqrt(ms)
    return pd.DataFrame(
        {
            "t_s": t,
            "speed": speed,
            "speed_lever": speed_lever,
            "yaw_rate": yaw_rate,
            "yaw": yaw,
            "radius": radius,
            "bounce_cm": bounce_cm,
            "z": pos[:, 2],
        }
    )


def walking_labels(
    t_s,
    truth_t_s,
    pos_m,
    rot,
    mode: str,
    *,
    lever_m: float = 0.4,
    forward_axis=None,
    min_speed_ms: float | None = None,
    min_bounce_cm: float = BOUNCE_MIN_CM,
) -> np.ndarray:
    """Per-sample labels by the walking rule: ``mode``, :data:`NOT_WALKING`, ``still`` or ``unlabelled``.

    A sample (at times ``t_s`` on the truth's clock) is walking when the lever-corrected
    body point moves faster than ``min_speed_ms`` and the step-band bounce reaches
    ``min_bounce_cm``; :data:`NOT_WALKING` when it is not walking but the speed rule
    (the phone's 0.5 Hz path faster than ``min_speed_ms``) calls it moving; ``still``
    otherwise; ``unlabelled`` outside the capture.
    """
    from gaitml.evaluation.trajectory import MOVING_SPEED_MS

    v_min = MOVING_SPEED_MS if min_speed_ms is None else float(min_speed_ms)
    s = mocap_signals(truth_t_s, pos_m, rot, lever_m=lever_m, forward_axis=forward_axis)
    tt = s["t_s"].to_numpy()
    q = np.asarray(t_s, dtype=float).reshape(-1)
    sp = np.interp(q, tt, s["speed"].to_numpy())
    sl = np.interp(q, tt, s["speed_lever"].to_numpy())
    bo = np.interp(q, tt, s["bounce_cm"].to_numpy())
    walking = (sl > v_min) & (bo >= float(min_bounce_cm))
    out = np.where(walking, mode, np.where(sp > v_min, NOT_WALKING, "still")).astype(object)
    out[(q < tt[0]) | (q > tt[-1])] = "unlabelled"
    return out


def item_walking_labels(item: dict) -> np.ndarray:
    """:func:`walking_labels` at the samples of a tyrex item (``recording`` on the phone clock, ``truth``, ``motion``,
    ``mode``), with the motion's arm length and forward axis."""
    rec, truth = item["recording"], item["truth"]
    tt = truth.t_s - rec.meta["t0_original_s"]
    motion = item["motion"]
    return walking_labels(
        rec.t_s, tt, truth.pos_m, truth.rot, item["mode"], lever_m=LEVER_ARM_M.get(motion, 0.0), forward_axis=FORWARD_AXIS.get(motion)
    )


def window_signals(rec, sig: pd.DataFrame, truth_t_rec: np.ndarray, length_s: float = 1.5, overlap: float = 0.5) -> pd.DataFrame:
    """The recording's 1.5 s windows (as :func:`gaitml.models.predict_recording` cuts them) with the window label and
    the motion-capture signals summarised over each window (medians; ``yaw_rate`` as net heading change / length)."""
    from gaitml.features import make_windows

    w = make_windows(rec, length_s, overlap, min_label_fraction=0.0).reset_index(drop=True)
    t = rec.t_s
    tt = truth_t_rec
    rows = []
    for s0, e0 in zip(w["start"].to_numpy(), w["end"].to_numpy(), strict=True):
        a, b = t[s0], t[e0 - 1]
        m = (tt >= a) & (tt <= b)
        if m.sum() < 5:
            rows.append(dict.fromkeys(("speed", "speed_lever", "yaw_rate", "radius", "bounce_cm"), np.nan))
            continue
        g = sig[m]
        yaw = g["yaw"].to_numpy()
        rows.append(
            {
                "speed": float(g["speed"].median()),
                "speed_lever": float(g["speed_lever"].median()),
                "yaw_rate": abs(yaw[-1] - yaw[0]) / max(b - a, 1e-9),
                "radius": float(g["radius"].median()),
                "bounce_cm": float(g["bounce_cm"].median()),
            }
        )
    return pd.concat([w[["start", "end", "t_start_s", "label", "label_fraction"]], pd.DataFrame(rows)], axis=1)


#: bounce thresholds (cm) reported beside the rule's, for the sensitivity tables (motion capture only)
BOUNCE_VARIANTS_CM = {"_b07": 0.7, "_b15": 1.5}


def _variants(motion: str) -> dict[str, tuple[float, float]]:
    """(arm length, bounce threshold) per reported variant: the rule's, 0 / 0.3 / 0.5 m where the phone is held in
    front, and the bounce thresholds of :data:`BOUNCE_VARIANTS_CM`."""
    own = LEVER_ARM_M[motion]
    out = {"": (own, BOUNCE_MIN_CM)}
    if own > 0:
        out.update({"_l0": (0.0, BOUNCE_MIN_CM), "_l03": (0.3, BOUNCE_MIN_CM), "_l05": (0.5, BOUNCE_MIN_CM)})
    out.update({k: (own, v) for k, v in BOUNCE_VARIANTS_CM.items()})
    return out


def axis_table(items: list[dict], min_speed_ms: float = 0.5) -> pd.DataFrame:
    """Per Texting / AR recording: the room's up in the phone's axes and the cosine of each phone axis's horizontal
    part with the walking direction (the 0.5 Hz path where it goes faster than ``min_speed_ms``), medians."""
    from gaitml.evaluation.trajectory import body_track

    rows = []
    for it in items:
        if it["motion"] not in FORWARD_AXIS:
            continue
        tr = it["truth"]
        t = tr.t_s
        ok = np.isfinite(tr.pos_m).all(axis=1)
        xy = np.column_stack([np.interp(t, t[ok], tr.pos_m[ok, j]) for j in range(2)])
        r = _fill_rot(tr.rot)
        v = np.gradient(body_track(t, xy), t, axis=0)
        sp = np.linalg.norm(v, axis=1)
        m = sp > min_speed_ms
        row = {"recording": Path(str(it["file"])).name, "up in phone axes": np.array2string(np.median(r[:, 2, :], axis=0), precision=2)}
        row["walking samples"] = int(m.sum())
        for name, ax in (("+x", 0), ("+y", 1), ("+z", 2)):
            f = r[m][:, :2, ax]
            n = np.linalg.norm(f, axis=1)
            c = np.sum(f * v[m], axis=1) / np.maximum(n * sp[m], 1e-9)
            row[f"cos {name}"] = float(np.median(c)) if m.any() else float("nan")
        rows.append(row)
    return pd.DataFrame(rows)


def window_table(items: list[dict], *, progress: bool = True) -> pd.DataFrame:
    """Every window of every tyrex recording: the speed rule's and the walking rule's labels and the mocap summaries."""
    rows = []
    for i, it in enumerate(items):
        rec, truth = it["recording"], it["truth"]
        tt = truth.t_s - rec.meta["t0_original_s"]
        base = None
        for suffix, (lever, bounce) in _variants(it["motion"]).items():
            fa = FORWARD_AXIS.get(it["motion"])
            sig = mocap_signals(tt, truth.pos_m, truth.rot, lever_m=lever, forward_axis=fa)
            w = window_signals(rec, sig, tt)
            wl = walking_labels(rec.t_s, tt, truth.pos_m, truth.rot, it["mode"], lever_m=lever, forward_axis=fa, min_bounce_cm=bounce)
            wr = window_signals(rec.replace(labels=wl, check_units=False), sig, tt)
            if base is None:
                base = w.rename(columns={"label": "label_speed", "label_fraction": "fraction_speed"})
                base["label_walking"] = wr["label"].to_numpy()
                base["fraction_walking"] = wr["label_fraction"].to_numpy()
            else:
                base["speed_lever" + suffix] = w["speed_lever"].to_numpy()
                base["label_walking" + suffix] = wr["label"].to_numpy()
                base["fraction_walking" + suffix] = wr["label_fraction"].to_numpy()
        for k in ("subject", "phone", "motion", "mode", "file"):
            base[k] = it[k] if k in it else ""
        rows.append(base)
        if progress:
            print(f"[tyrex_ar_moving] {i + 1}/{len(items)} {it['subject']} {it['phone']} {it['motion']}", file=sys.stderr)
    return pd.concat(rows, ignore_index=True)


def _cls(label, frac, mode) -> np.ndarray:
    """Window class: 'moving' (the mode), 'standing', 'not-walking' or '' (no majority / outside)."""
    lab = np.asarray(label).astype(str)
    ok = np.asarray(frac, dtype=float) >= 0.5
    out = np.full(len(lab), "", dtype=object)
    out[ok & (lab == np.asarray(mode).astype(str))] = "moving"
    out[ok & (lab == "still")] = "standing"
    out[ok & (lab == NOT_WALKING)] = NOT_WALKING
    return out


def change_table(w: pd.DataFrame, suffix: str = "") -> pd.DataFrame:
    """Per motion: speed-rule moving windows, how many the walking rule keeps, how many become not-walking or standing."""
    from experiments.scripts.tyrex_modes import MOTION_ORDER

    rows = []
    for motion in [*MOTION_ORDER, "all"]:
        g = w if motion == "all" else w[w["motion"] == motion]
        lab = "label_walking" + suffix
        if lab not in g or g[lab].isna().all():
            continue
        g = g[g[lab].notna()]
        a = _cls(g["label_speed"], g["fraction_speed"], g["mode"])
        b = _cls(g[lab], g["fraction_walking" + suffix], g["mode"])
        mv = a == "moving"
        per = pd.DataFrame({"s": g["subject"], "mv": mv, "keep": mv & (b == "moving")}).groupby("s")[["mv", "keep"]].sum()
        share = per["keep"] / per["mv"].where(per["mv"] > 0)
        rows.append(
            {
                "motion": motion,
                "moving (speed rule)": int(mv.sum()),
                "walking (walking rule)": int((b == "moving").sum()),
                "moving -> walking": int((mv & (b == "moving")).sum()),
                "moving -> not walking": int((mv & (b == NOT_WALKING)).sum()),
                "moving -> standing / no majority": int((mv & ~np.isin(b, ["moving", NOT_WALKING])).sum()),
                "standing -> walking": int(((a == "standing") & (b == "moving")).sum()),
                "kept per person": f"{share.min():.2f}-{share.max():.2f}",
            }
        )
    return pd.DataFrame(rows)


def signal_table(w: pd.DataFrame) -> pd.DataFrame:
    """Per motion and speed-rule class (moving windows by the walking rule's verdict, standing): medians of the mocap summaries."""
    from experiments.scripts.tyrex_modes import MOTION_ORDER

    a = _cls(w["label_speed"], w["fraction_speed"], w["mode"])
    b = _cls(w["label_walking"], w["fraction_walking"], w["mode"])
    grp = np.where(
        a == "moving", np.where(b == "moving", "moving, walking", "moving, not walking"), np.where(a == "standing", "standing", "")
    )
    rows = []
    for motion in MOTION_ORDER:
        for gname in ("moving, walking", "moving, not walking", "standing"):
            g = w[(w["motion"] == motion) & (grp == gname)]
            if g.empty:
                continue
            rows.append(
                {
                    "motion": motion,
                    "windows (speed rule)": gname,
                    "n": len(g),
                    "speed m/s": g["speed"].median(),
                    "lever-corrected m/s": g["speed_lever"].median(),
                    "yaw rate rad/s": g["yaw_rate"].median(),
                    "radius m": g["radius"].median(),
                    "bounce cm p-p": g["bounce_cm"].median(),
                    "bounce >= 1 cm": float(np.mean(g["bounce_cm"] >= BOUNCE_MIN_CM)),
                }
            )
    return pd.DataFrame(rows)


def plot_recording(it: dict, out: Path) -> None:
    """Time series of one recording's mocap: speed and lever-corrected speed, yaw rate, bounce, and the two rules' labels."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rec, truth = it["recording"], it["truth"]
    tt = truth.t_s - rec.meta["t0_original_s"]
    lever = LEVER_ARM_M[it["motion"]]
    fa = FORWARD_AXIS.get(it["motion"])
    s = mocap_signals(tt, truth.pos_m, truth.rot, lever_m=lever, forward_axis=fa)
    wl = walking_labels(tt, tt, truth.pos_m, truth.rot, it["mode"], lever_m=lever, forward_axis=fa)
    fig, ax = plt.subplots(4, 1, figsize=(11, 8), sharex=True)
    ax[0].plot(tt, s["speed"], label="speed rule (phone, 0.5 Hz)")
    ax[0].plot(tt, s["speed_lever"], label=f"lever-corrected ({lever} m)")
    ax[0].axhline(0.3, color="k", lw=0.5)
    ax[0].set_ylabel("m/s")
    ax[0].legend(loc="upper right", fontsize=8)
    ax[1].plot(tt, s["yaw_rate"])
    ax[1].set_ylabel("yaw rate rad/s")
    ax[2].plot(tt, s["bounce_cm"])
    ax[2].axhline(BOUNCE_MIN_CM, color="k", lw=0.5)
    ax[2].set_ylabel("bounce cm p-p")
    sp = (s["speed"] > 0.3).astype(int)
    ax[3].plot(tt, sp + 0.05, label="speed rule moving")
    ax[3].plot(tt, (wl == it["mode"]).astype(int) - 0.05, label="walking rule walking")
    ax[3].legend(loc="upper right", fontsize=8)
    ax[3].set_xlabel("s")
    fig.suptitle(f"{it['subject']} {it['phone']} {it['motion']} ({Path(str(it.get('file', ''))).name})")
    fig.tight_layout()
    fig.savefig(out, dpi=80)
    plt.close(fig)


def md(df: pd.DataFrame) -> str:
    from experiments.scripts.tyrex_modes import md as _md

    return _md(df)


def main(argv=None) -> int:
    from experiments.scripts.tyrex_modes import load_tyrex_labelled

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", type=Path, default=Path("../shared/data"))
    ap.add_argument("--cache", type=Path, default=None, help="per-window table (pickle): read when it exists, written otherwise")
    ap.add_argument("--plots", type=Path, default=None, help="write time-series plots of the AR recordings here")
    ap.add_argument("--out", type=Path, default=None, help="write the markdown tables here too")
    ap.add_argument("--axes", action="store_true", help="also print the forward-axis check of Texting and AR")
    a = ap.parse_args(argv)
    items = None
    if a.cache is not None and a.cache.exists():
        w = pd.read_pickle(a.cache)
    else:
        items = load_tyrex_labelled(a.data)
        w = window_table(items)
        if a.cache is not None:
            a.cache.parent.mkdir(parents=True, exist_ok=True)
            w.to_pickle(a.cache)
    text = []

    def emit(s=""):
        print(s)
        text.append(s)

    emit(f"### windows that change class (walking rule: lever-corrected speed > 0.3 m/s and bounce >= {BOUNCE_MIN_CM:g} cm)\n")
    emit(md(change_table(w)))
    for suffix, name in (("_l0", "0 (no lever-arm correction: the bounce alone decides)"), ("_l03", "0.3 m"), ("_l05", "0.5 m")):
        emit(f"\n### the same with the arm length {name} (Texting and AR)\n")
        t = change_table(w, suffix)
        emit(md(t[t["motion"].isin(["Texting", "AR"])]))
    for suffix, cm in BOUNCE_VARIANTS_CM.items():
        emit(f"\n### the same with the bounce threshold {cm:g} cm (sensitivity; motion capture only)\n")
        emit(md(change_table(w, suffix)))
    emit("\n### motion-capture summaries per motion (medians over the windows)\n")
    emit(md(signal_table(w)))
    emit("\n### AR recordings: speed-rule moving windows, kept as walking / turned not-walking\n")
    ar = w[w["motion"] == "AR"]
    ra = _cls(ar["label_speed"], ar["fraction_speed"], ar["mode"])
    rb = _cls(ar["label_walking"], ar["fraction_walking"], ar["mode"])
    per = (
        pd.DataFrame({"recording": ar["file"].astype(str), "moving": ra == "moving", "walking": (ra == "moving") & (rb == "moving")})
        .groupby("recording")[["moving", "walking"]]
        .sum()
        .reset_index()
    )
    emit(md(per))
    if a.axes:
        if items is None:
            items = load_tyrex_labelled(a.data)
        emit("\n### the forward axis: room up in the phone's axes, cosine of each axis with the walking direction (medians)\n")
        emit(md(axis_table(items)))
    if a.plots is not None:
        a.plots.mkdir(parents=True, exist_ok=True)
        if items is None:
            items = load_tyrex_labelled(a.data)
        for it in items:
            if it["motion"] == "AR" or (it["motion"] == "Texting" and it["phone"] == "Nexus5"):
                name = f"{Path(str(it.get('file', ''))).name}.png"
                plot_recording(it, a.plots / name)
        print(f"[tyrex_ar_moving] plots in {a.plots}", file=sys.stderr)
    if a.out:
        a.out.write_text("\n".join(text) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
