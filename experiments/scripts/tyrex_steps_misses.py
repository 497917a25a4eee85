"""Where adaptive's missing steps are on the tyrex walking recordings (issue 30, diagnosis).

For each walking recording (``Texting``, ``Phoning``, ``FrontPocket``, ``BackPocket``, ``Swinging``), the
motion-capture reference steps of :func:`experiments.scripts.tyrex_steps.mocap_steps` are matched to
``adaptive``'s steps (at its defaults) and each reference step is labelled:

- *covered*: an adaptive step lies within ``COVER_S`` of it (adaptive accepts the stretch it lies in; for the
  stride motions a reference event stands for two steps, so it is covered by adaptive steps within one stride);
- and by what the walker was doing at that moment, from the trajectory low-passed at 0.3 Hz (the reference's own
  body speed): *turning* where the direction of travel turns faster than ``TURN_DEG_S``, *slow* where the body moves
  slower than ``SLOW_MS`` (stops, starts, shuffling), *straight* otherwise.

Printed per recording: reference and adaptive counts, the share of reference steps not covered and where those lie,
adaptive's steps that no reference step is near (extra), the median body speed, and the periodicity of adaptive's
cadence windows at the uncovered reference steps. Nothing is fitted.

    python -m experiments.scripts.tyrex_steps_misses [--data ../shared/data] [--csv FILE] [--plot DIR]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps import _filled, _lowpass, mocap_steps, read_tyrex_walk

WALK_MOTIONS = ("Texting", "Phoning", "FrontPocket", "BackPocket", "Swinging")
#: adaptive's cadence window (s) and periodicity floor (its defaults)
WINDOW_S = 5.0
MIN_PERIODICITY = 0.3
#: a reference step is covered by an adaptive step closer than this (s): half a slow step period
COVER_S = 0.45
#: the direction of travel turns faster than this (deg/s) in a turn
TURN_DEG_S = 60.0
#: the body moves slower than this (m/s) in a stop, start or shuffle
SLOW_MS = 0.3


def body_state(truth) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Time, speed (m/s) and turn rate (deg/s) of the trajectory low-passed at 0.3 Hz."""
    ok = truth.valid
    t = truth.t_s
    fs = float(truth.frame_rate_hz)
    pos = _filled(t, truth.pos_m, ok)
    body = _lowpass(pos[:, :2], fs, 0.3)
    v = np.gradient(body, 1.0 / fs, axis=0)
    speed = np.linalg.norm(v, axis=1)
    heading = np.unwrap(np.arctan2(v[:, 1], v[:, 0]))
    turn = np.degrees(np.abs(np.gradient(heading, 1.0 / fs)))
    turn[speed < 0.05] = 0.0  # the heading of a body at rest is noise
    return t, speed, turn


def recording_row(folder: Path, plot_dir: Path | None = None) -> dict | None:
    from gaitml.steps import get_detector

    walk = read_tyrex_walk(folder, WALK_MOTIONS)
    if walk is None:
        return None
    truth, ref = walk["truth"], walk["ref"]
    per = ref["steps_per_event"]
    tp, cad_t, cad_p = [], [], []
    for r in walk["recs"]:
        det = get_detector("adaptive").detect(r)
        t0 = float(r.meta.get("t0_original_s", 0.0))
        tp.append(t0 + det.steps_["t_peak_s"].to_numpy())
        cad_t.append(t0 + det.cadence_["t_s"].to_numpy())
        cad_p.append(det.cadence_["periodicity"].to_numpy())
    ad = np.sort(np.concatenate(tp)) if tp else np.zeros(0)
    ad = ad[(ad >= ref["t_first_s"]) & (ad <= ref["t_last_s"])]
    cad_t = np.concatenate(cad_t) if cad_t else np.zeros(0)
    cad_p = np.concatenate(cad_p) if cad_p else np.zeros(0)
    rt = ref["t_s"]
    win = COVER_S * (2 if per == 2 else 1)

    def near(a, b, w):
        if len(b) == 0:
            return np.zeros(len(a), dtype=bool)
        j = np.clip(np.searchsorted(b, a), 1, len(b) - 1) if len(b) > 1 else np.zeros(len(a), dtype=int)
        d = np.minimum(np.abs(b[j] - a), np.abs(b[np.maximum(j - 1, 0)] - a))
        return d <= w

    covered = near(rt, ad, win)
    extra = ~near(ad, rt, win)
    t, speed, turn = body_state(truth)
    k = np.searchsorted(t, rt).clip(0, len(t) - 1)
    state = np.where(speed[k] < SLOW_MS, "slow", np.where(turn[k] > TURN_DEG_S, "turning", "straight"))
    miss = ~covered
    period_at = np.interp(rt, cad_t, cad_p) if len(cad_t) else np.full(len(rt), np.nan)
    row = {
        "recording": folder.name,
        "motion": walk["motion"],
        "person": walk["person"],
        "ref": ref["n_steps"],
        "adaptive": len(ad),
        "missed_ref": per * int(miss.sum()),
        "extra_adaptive": int(extra.sum()),
        "ref_straight": per * int((state == "straight").sum()),
        "ref_turning": per * int((state == "turning").sum()),
        "ref_slow": per * int((state == "slow").sum()),
        "miss_straight": per * int((miss & (state == "straight")).sum()),
        "miss_turning": per * int((miss & (state == "turning")).sum()),
        "miss_slow": per * int((miss & (state == "slow")).sum()),
        "speed_median": float(np.median(speed[ref["idx"]])) if len(rt) else float("nan"),
        "periodicity_at_miss": float(np.nanmedian(period_at[miss])) if miss.any() else float("nan"),
        "periodicity_at_hit": float(np.nanmedian(period_at[covered])) if covered.any() else float("nan"),
    }
    if plot_dir is not None:
        _plot(plot_dir, folder.name, ref, ad, t, speed, turn, cad_t, cad_p, covered)
    return row


#: adaptive with its bout stages switched off one after another (which stage drops the missing steps)
ABLATIONS = {
    "default": {},
    "no_short_bout": {"short_bout_steps": 0},
    "no_bout_rules": {"short_bout_steps": 0, "min_bout_steps": 1, "edge_confidence_ratio": 0.0},
    "no_bout_rules_periodicity_0": {"short_bout_steps": 0, "min_bout_steps": 1, "edge_confidence_ratio": 0.0, "min_periodicity": 0.0},
}


def ablation_row(folder: Path) -> dict | None:
    """Reference count and adaptive's count over the reference span with each of :data:`ABLATIONS`."""
    from gaitml.steps import get_detector

    walk = read_tyrex_walk(folder, WALK_MOTIONS)
    if walk is None:
        return None
    ref = walk["ref"]
    row = {"recording": folder.name, "motion": walk["motion"], "person": walk["person"], "ref": ref["n_steps"]}
    for name, kw in ABLATIONS.items():
        n = 0
        for r in walk["recs"]:
            tt = float(r.meta.get("t0_original_s", 0.0)) + get_detector("adaptive", **kw).detect(r).steps_["t_peak_s"].to_numpy()
            n += int(np.sum((tt >= ref["t_first_s"]) & (tt <= ref["t_last_s"])))
        row[name] = n
    return row


def window_rows(folder: Path) -> list[dict]:
    """Adaptive's cadence windows against the reference, one row per window with at least 3 reference events.

    Each window (5 s, adaptive's own) is labelled by adaptive's step period against the median interval of the
    reference's steps in it: ``match`` (ratio 0.8-1.25), ``half`` (0.4-0.8: adaptive's period is a fraction of a
    step), ``double`` (1.6-2.5), ``other``, or ``low_periodicity`` (below adaptive's 0.3, no steps there); prefixed
    ``slow:`` where the body's median speed is below ``SLOW_MS``. ``n_ref`` / ``n_ad`` are the reference's and
    adaptive's steps inside the window (windows overlap: use the ratios, not the sums, as counts).
    """
    from gaitml.steps import get_detector

    walk = read_tyrex_walk(folder, WALK_MOTIONS)
    if walk is None:
        return []
    ref = walk["ref"]
    rt, per = ref["t_s"], ref["steps_per_event"]
    t, speed, _ = body_state(walk["truth"])
    rows = []
    for r in walk["recs"]:
        t0 = float(r.meta.get("t0_original_s", 0.0))
        det = get_detector("adaptive").detect(r)
        ad = t0 + det.steps_["t_peak_s"].to_numpy()
        half_w = WINDOW_S / 2
        for tc, period, periodicity in zip(t0 + det.cadence_["t_s"], det.cadence_["period_s"], det.cadence_["periodicity"], strict=True):
            a, b = tc - half_w, tc + half_w
            k = rt[(rt >= a) & (rt < b)]
            if len(k) < 3:
                continue
            ratio = period / (float(np.median(np.diff(k))) / per)
            if periodicity < MIN_PERIODICITY:
                cat = "low_periodicity"
            elif 0.8 < ratio < 1.25:
                cat = "match"
            elif 0.4 < ratio <= 0.8:
                cat = "half"
            elif 1.6 < ratio < 2.5:
                cat = "double"
            else:
                cat = "other"
            if np.median(speed[(t >= a) & (t < b)]) < SLOW_MS:
                cat = "slow:" + cat
            n_ad = int(np.sum((ad >= a) & (ad < b)))
            rows.append(
                {
                    "recording": folder.name,
                    "motion": walk["motion"],
                    "person": walk["person"],
                    "cat": cat,
                    "n_ref": per * len(k),
                    "n_ad": n_ad,
                }
            )
    return rows


#: reference cross-check windows (s) and the swing band (Hz) of the motion capture's own angular rate
CHECK_WINDOW_S = 5.0
CHECK_HOP_S = 2.5
CHECK_BAND_HZ = (0.3, 4.0)


def reference_check(truth, motion: str) -> dict[str, int]:
    """Does the trunk reference's step period agree with the body's rotation, a signal the reference does not use?

    The trunk rocks (yaw and roll) once per stride and reverses between the left and the right step (Meyns, Bruijn &
    Duysens 2013), so the motion capture's angular rate of the phone, band-passed to 0.3-4 Hz and projected on its
    principal axis, is in anti-phase at the step period T and in phase at 2T. In each 5 s window (hop 2.5 s) where the
    body moves faster than ``SLOW_MS`` and the reference has at least 3 events, T is the median interval of the
    reference's steps; the window is *consistent* (corr(T) < 0 < corr(2T)), *stride* (corr(T) > 0 > corr(T/2): the
    reference took a stride for a step and missed half the steps) or *unclear*.
    """
    import scipy.signal

    from gaitml.io.tyrex import body_rates

    ref = mocap_steps(truth, motion)
    tm, om = body_rates(truth)
    fs = float(truth.frame_rate_hz)
    tg = np.arange(tm[0], tm[-1], 1.0 / fs)
    om = np.column_stack([np.interp(tg, tm, om[:, j]) for j in range(3)])
    sos = scipy.signal.butter(2, list(CHECK_BAND_HZ), btype="bandpass", fs=fs, output="sos")
    om = scipy.signal.sosfiltfilt(sos, om, axis=0)
    t, speed, _ = body_state(truth)
    rt = ref["t_s"]
    per = ref["steps_per_event"]
    counts = {"consistent": 0, "stride": 0, "unclear": 0}
    for a in np.arange(tg[0], tg[-1] - CHECK_WINDOW_S, CHECK_HOP_S):
        b = a + CHECK_WINDOW_S
        k = rt[(rt >= a) & (rt < b)]
        if len(k) < 3 or np.median(speed[(t >= a) & (t < b)]) < SLOW_MS:
            continue
        T = float(np.median(np.diff(k))) / per
        w = om[(tg >= a) & (tg < b)]
        w = w - w.mean(axis=0)
        proj = w @ np.linalg.eigh(w.T @ w)[1][:, -1]

        def r(lag_s, proj=proj):
            m = int(round(lag_s * fs))
            if m < 1 or m >= len(proj) - 2:
                return np.nan
            x, y = proj[:-m], proj[m:]
            return float(np.dot(x, y) / np.sqrt(np.dot(x, x) * np.dot(y, y)))

        cT, c2T, ch = r(T), r(2 * T), r(T / 2)
        if cT < 0 < c2T:
            counts["consistent"] += 1
        elif cT > 0 > ch:
            counts["stride"] += 1
        else:
            counts["unclear"] += 1
    return counts


def reference_check_row(folder: Path) -> dict | None:
    """:func:`reference_check` of one trunk recording (``Texting``, ``Phoning``)."""
    from gaitml.io.tyrex import parse_tyrex_name, read_tyrex_truth

    info = parse_tyrex_name(folder.name)
    if info is None or info.get("take") or info["motion"] not in ("Texting", "Phoning"):
        return None
    counts = reference_check(read_tyrex_truth(folder), info["motion"])
    return {"recording": folder.name, "motion": info["motion"], "person": info["person"], **counts}


def _plot(out: Path, name, ref, ad, t, speed, turn, cad_t, cad_p, covered) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(3, 1, figsize=(20, 7), sharex=True)
    rt = ref["t_s"]
    ax[0].plot(ref["t"], ref["signal"], lw=0.6)
    ax[0].plot(rt[covered], np.interp(rt[covered], ref["t"], ref["signal"]), "g^", ms=4, label="ref covered")
    ax[0].plot(rt[~covered], np.interp(rt[~covered], ref["t"], ref["signal"]), "rv", ms=6, label="ref missed")
    y0 = np.nanmin(ref["signal"])
    ax[0].plot(ad, np.full(len(ad), y0), "k|", ms=8, label="adaptive")
    ax[0].legend(loc="upper right", fontsize=7)
    ax[0].set_title(name)
    ax[1].plot(t, speed, label="speed m/s")
    ax[1].plot(t, np.minimum(turn, 360) / 360, label="turn rate / 360 deg/s")
    ax[1].axhline(SLOW_MS, color="k", lw=0.5)
    ax[1].legend(loc="upper right", fontsize=7)
    ax[2].plot(cad_t, cad_p, ".-", label="adaptive periodicity")
    ax[2].axhline(0.3, color="k", lw=0.5)
    ax[2].legend(loc="upper right", fontsize=7)
    fig.tight_layout()
    fig.savefig(out / f"{name}.png", dpi=60)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    from gaitml.io.tyrex import list_tyrex_folders

    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_misses", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--csv", metavar="FILE")
    ap.add_argument("--plot", metavar="DIR")
    ap.add_argument("--ablation", action="store_true", help="count with adaptive's bout stages switched off instead")
    ap.add_argument("--windows", action="store_true", help="adaptive's cadence windows against the reference's step period")
    ap.add_argument("--reference-check", action="store_true", help="check the trunk reference against the body's rotation")
    a = ap.parse_args(argv)
    if a.windows:
        df = pd.DataFrame([r for f in list_tyrex_folders(Path(a.data) / "tyrex-attitude") for r in window_rows(f)])
        if a.csv:
            df.to_csv(a.csv, index=False)
        for by in (["motion", "cat"], ["motion", "person", "cat"]):
            g = df.groupby(by)[["n_ref", "n_ad"]].sum()
            g["ad/ref"] = g["n_ad"] / g["n_ref"]
            g["share_of_ref"] = g["n_ref"] / g.groupby(by[:-1])["n_ref"].transform("sum")
            print(g.round(3).to_string(), end="\n\n")
        return 0
    if a.reference_check:
        rows = [r for f in list_tyrex_folders(Path(a.data) / "tyrex-attitude") if (r := reference_check_row(f)) is not None]
        df = pd.DataFrame(rows)
        print(df.to_string(index=False))
        print(df.groupby("motion")[["consistent", "stride", "unclear"]].sum().to_string())
        return 0
    if a.ablation:
        rows = [r for f in list_tyrex_folders(Path(a.data) / "tyrex-attitude") if (r := ablation_row(f)) is not None]
        df = pd.DataFrame(rows)
        if a.csv:
            df.to_csv(a.csv, index=False)
        out = {}
        for motion, g in df.groupby("motion"):
            out[motion] = {k: float((1 - (g[k] - g["ref"]).abs() / g["ref"]).mean()) for k in ABLATIONS}
            out[motion].update({f"{k}_sum/ref": float(g[k].sum() / g["ref"].sum()) for k in ABLATIONS})
        print(pd.DataFrame(out).T.round(3).to_string())
        return 0
    rows = []
    for folder in list_tyrex_folders(Path(a.data) / "tyrex-attitude"):
        try:
            r = recording_row(folder, Path(a.plot) if a.plot else None)
        except Exception as exc:  # noqa: BLE001 - a recording the reader refuses is reported, not fatal
            print(f"skip {folder.name}: {exc}", file=sys.stderr)
            continue
        if r is not None:
            rows.append(r)
            print(f"{r['recording']}: ref {r['ref']} adaptive {r['adaptive']} missed {r['missed_ref']}", file=sys.stderr)
    df = pd.DataFrame(rows)
    if a.csv:
        df.to_csv(a.csv, index=False)
    cols = ["ref", "adaptive", "missed_ref", "extra_adaptive", "ref_straight", "ref_turning", "ref_slow"]
    cols += ["miss_straight", "miss_turning", "miss_slow"]
    for by in (["motion"], ["motion", "person"]):
        g = df.groupby(by)[cols].sum()
        g["miss_share"] = g["missed_ref"] / g["ref"]
        for s in ("straight", "turning", "slow"):
            g[f"miss_rate_{s}"] = g[f"miss_{s}"] / g[f"ref_{s}"].clip(lower=1)
        print(g.round(3).to_string(), end="\n\n")
    print()
    worst = df.assign(acc=1 - (df["adaptive"] - df["ref"]).abs() / df["ref"].clip(lower=1)).sort_values("acc").head(12)
    print(worst.round(3).to_string(index=False))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
