"""Step counts on the tyrex recordings against steps counted from the motion capture (issue 30).

The tyrex benchmark (``../shared/data/tyrex-attitude``) has no step times. The reference count comes
from the phone's true trajectory and attitude (motion capture, 60 Hz), by this rule (:func:`mocap_steps`):

1. Where the phone follows one leg or one arm (``FrontPocket``, ``BackPocket``, ``Swinging``,
   ``RunningPocket``, and ``RunningHand``, whose phone swings with the running arm) its tilt swings once
   per stride: room-up in the phone's frame, band-passed to 0.3-3 Hz (zero-phase 2nd-order Butterworth),
   projected on its main direction of swing (first principal component), in degrees. Each stride is a
   maximum at least 0.45 s after the previous one (a running stride is ~0.7 s) that stands at least 8 deg
   above its surrounding minima, and counts two steps.
2. Where the phone rides on the trunk in front of the body (``Texting``, ``AR``, ``Phoning``) the body's
   vertical bounce is one cycle per step: each step is a minimum of the phone's height band-passed to
   0.7-5 Hz, at least 0.3 s after the previous one and at least 0.3 cm below its neighbouring maxima.
3. Only while the walker moves: the trajectory low-passed at 0.3 Hz faster than 0.05 m/s at a stride
   event (the swing itself is evidence of a step; steps while turning on the spot count), 0.15 m/s at a
   trunk event (a standing body's sway also moves the phone by a few millimetres).

Checked by eye on 25 s stretches of at least one recording per motion (the plots of ``--plot``): the
counts and their disagreements are in ``experiments/reports/tyrex-steps.md``. ``AR`` (mostly standing,
bounces below 0.5 cm) has no reliable reference and is reported apart.

Detectors are counted on the phone recording over the same span (the motion-capture frames' first and
last time), at their defaults. Two settings of ``adaptive`` (its gyroscope check: ``gyro_min_rms_rads``,
``gyro_phase_correlation``) were chosen on these recordings; their leave-one-person-out figures are printed by
:mod:`experiments.scripts.tyrex_steps_lopo`. Nothing else is tuned here; the per-person rows show how much a
figure moves from one person to the next.

    python -m experiments.scripts.tyrex_steps [--data ../shared/data] [--plot DIR] [--csv FILE]

``--plot`` writes one PNG per recording (25 s of the reference signal with the counted events).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import scipy.signal

#: motions whose phone swings once per stride with a leg or an arm (its tilt is the stride clock)
STRIDE_MOTIONS = ("FrontPocket", "BackPocket", "Swinging", "RunningPocket", "RunningHand")
#: motions where the phone rides the trunk's bounce in front of the body (one bounce per step)
STEP_MOTIONS = ("Texting", "AR", "Phoning")
STRIDE_BAND_HZ = (0.3, 3.0)
MIN_STRIDE_S = 0.45
MIN_SWING_DEG = 8.0
STEP_BAND_HZ = (0.7, 5.0)
MIN_STEP_S = 0.3
MIN_BOUNCE_CM = 0.3
SPEED_LOWPASS_HZ = 0.3
#: the walker's speed (trajectory low-passed at SPEED_LOWPASS_HZ) above which an event counts: low on a limb,
#: whose 8-degree swing is itself evidence of a step (steps while turning on the spot are real steps), higher on the
#: trunk, whose few-millimetre bounce is also made by a standing body's sway
MIN_SPEED_MS = {"stride": 0.05, "step": 0.15}
#: adaptive's steps with at least this per-step confidence are also counted apart (column "adaptive_conf>=0.5");
#: not gaitml's confident / unsure verdict (gaitml.steps.gait_confidence), which a per-step threshold does not make
CONFIDENCE_SHOWN = 0.5
DETECTORS = ("adaptive", "adfsm", "single-peak", "ifsm", "autocorr", "fsm-selflearn")
#: a phone segment (between two sensor gaps) shorter than this is a scrap, too short for any cadence estimate
MIN_SEGMENT_S = 10.0


def _skipped(info: dict | None, motions) -> bool:
    """An unparsable name, an extra take, or a motion not asked for."""
    return info is None or bool(info.get("take")) or (motions is not None and info["motion"] not in motions)


def _walk(name: str, info: dict, truth, rec) -> dict:
    recs = [r for r in (rec if isinstance(rec, list) else [rec]) if r.duration_s >= MIN_SEGMENT_S]
    ref = mocap_steps(truth, info["motion"])
    return {"name": name, "motion": info["motion"], "person": info["person"], "truth": truth, "ref": ref, "recs": recs}


def read_tyrex_walk(folder: Path, motions=None) -> dict | None:
    """One tyrex recording with its motion-capture step reference, or None for an extra take or a motion not in ``motions``.

    Returns ``name``, ``motion``, ``person``, ``truth`` (:func:`gaitml.io.tyrex.read_tyrex_truth`), ``ref``
    (:func:`mocap_steps`) and ``recs``: the phone recording's segments of at least :data:`MIN_SEGMENT_S`.
    Raises what the readers raise.
    """
    from gaitml.io.tyrex import parse_tyrex_name, read_tyrex, read_tyrex_truth

    info = parse_tyrex_name(folder.name)
    if _skipped(info, motions):
        return None
    return _walk(folder.name, info, read_tyrex_truth(folder), read_tyrex(folder, segments=True))


def tyrex_walks(data: str | Path, motions=None):
    """:func:`read_tyrex_walk` of every recording under ``data/tyrex-attitude``; one the readers refuse is reported on stderr and skipped."""
    from gaitml.io.tyrex import list_tyrex_folders, parse_tyrex_name, read_tyrex, read_tyrex_truth

    for folder in list_tyrex_folders(Path(data) / "tyrex-attitude"):
        info = parse_tyrex_name(folder.name)
        if _skipped(info, motions):
            continue
        try:
            truth = read_tyrex_truth(folder)
            rec = read_tyrex(folder, segments=True)
        except Exception as exc:  # noqa: BLE001 - a recording the reader refuses is reported, not fatal
            print(f"skip {folder.name}: {exc}", file=sys.stderr)
            continue
        yield _walk(folder.name, info, truth, rec)


def truth_clock_s(steps: pd.DataFrame, rec) -> np.ndarray:
    """The step times of ``steps`` (detected on segment ``rec``) on the motion capture's clock (s)."""
    return float(rec.meta.get("t0_original_s", 0.0)) + steps[steps.attrs.get("event", "t_peak_s")].to_numpy()


def in_reference_span(t_s: np.ndarray, ref: dict) -> np.ndarray:
    """Which times lie within the reference's first and last motion-capture frame."""
    return (t_s >= ref["t_first_s"]) & (t_s <= ref["t_last_s"])


def _lowpass(x: np.ndarray, fs: float, hz: float) -> np.ndarray:
    sos = scipy.signal.butter(2, hz, fs=fs, output="sos")
    return scipy.signal.sosfiltfilt(sos, x, axis=0)


def _filled(t: np.ndarray, x: np.ndarray, ok: np.ndarray) -> np.ndarray:
    """Columns of ``x`` with lost frames filled linearly in time (< 1 % of frames)."""
    out = np.array(x, dtype=float)
    for j in range(out.shape[1]):
        out[:, j] = np.interp(t, t[ok], out[ok, j])
    return out


def tilt_signal(truth) -> np.ndarray:
    """The phone's swing angle (deg): room-up in the phone's frame, band-passed, along its main direction of swing."""
    ok = truth.valid
    t = truth.t_s
    fs = float(truth.frame_rate_hz)
    up = np.einsum("nji,j->ni", np.nan_to_num(truth.rot), np.array([0.0, 0.0, 1.0]))
    up = _filled(t, up, ok)
    sos = scipy.signal.butter(2, list(STRIDE_BAND_HZ), btype="bandpass", fs=fs, output="sos")
    u = scipy.signal.sosfiltfilt(sos, up, axis=0)
    _, _, vt = np.linalg.svd(u - u.mean(axis=0), full_matrices=False)
    return np.degrees(np.arcsin(np.clip(u @ vt[0], -1.0, 1.0)))


def mocap_steps(truth, motion: str, min_speed_ms: float | None = None) -> dict:
    """Step times (phone clock, s) from the motion capture by the rule of the module docstring.

    ``min_speed_ms`` replaces the speed gate of rule 3 (to show how much the count depends on it).
    """
    ok = truth.valid
    t = truth.t_s
    fs = float(truth.frame_rate_hz)
    pos = _filled(t, truth.pos_m, ok)
    body = _lowpass(pos[:, :2], fs, SPEED_LOWPASS_HZ)
    speed = np.linalg.norm(np.gradient(body, 1.0 / fs, axis=0), axis=1)
    if motion in STRIDE_MOTIONS:
        sig = tilt_signal(truth)
        idx, _ = scipy.signal.find_peaks(sig, distance=int(MIN_STRIDE_S * fs), prominence=MIN_SWING_DEG)
        per = 2
        gate = MIN_SPEED_MS["stride"] if min_speed_ms is None else min_speed_ms
    else:
        sos = scipy.signal.butter(2, list(STEP_BAND_HZ), btype="bandpass", fs=fs, output="sos")
        sig = scipy.signal.sosfiltfilt(sos, pos[:, 2]) * 100.0
        idx, _ = scipy.signal.find_peaks(-sig, distance=int(MIN_STEP_S * fs), prominence=MIN_BOUNCE_CM)
        per = 1
        gate = MIN_SPEED_MS["step"] if min_speed_ms is None else min_speed_ms
    idx = idx[speed[idx] > gate]
    return {
        "t_s": t[idx],
        "n_steps": per * len(idx),
        "steps_per_event": per,
        "t_first_s": float(t[ok][0]),
        "t_last_s": float(t[ok][-1]),
        "signal": sig,
        "speed": speed,
        "t": t,
        "idx": idx,
    }


def table(data: str | Path, detectors=DETECTORS, plot_dir: str | None = None) -> pd.DataFrame:
    """One row per recording: motion, person, the motion-capture count and each detector's count over the same span."""
    from gaitml.steps import get_detector

    rows = []
    for walk in tyrex_walks(data):
        ref, truth, motion = walk["ref"], walk["truth"], walk["motion"]
        row = {"recording": walk["name"], "motion": motion, "person": walk["person"], "mocap_steps": ref["n_steps"]}
        # the reference's own sensitivity: the same rule with the speed gate at 0 and at 0.3 m/s
        row["mocap_gate0"] = mocap_steps(truth, motion, 0.0)["n_steps"]
        row["mocap_gate03"] = mocap_steps(truth, motion, 0.3)["n_steps"]
        n_conf = 0
        for d in detectors:
            n = 0
            for r in walk["recs"]:
                st = get_detector(d).detect(r).steps_
                inside = in_reference_span(truth_clock_s(st, r), ref)
                n += int(np.sum(inside))
                if d == "adaptive":
                    n_conf += int(np.sum(inside & (st["confidence"].to_numpy() >= CONFIDENCE_SHOWN)))
            row[d] = n
        row["adaptive_conf>=0.5"] = n_conf
        rows.append(row)
        if plot_dir is not None:
            _plot(ref, walk["name"], Path(plot_dir))
    return pd.DataFrame(rows)


def _plot(ref: dict, name: str, out: Path, start_s: float = 30.0, span_s: float = 25.0) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    t, sig, idx = ref["t"], ref["signal"], ref["idx"]
    a = t[0] + start_s
    m = (t > a) & (t < a + span_s)
    k = idx[(t[idx] > a) & (t[idx] < a + span_s)]
    fig, ax = plt.subplots(2, 1, figsize=(18, 6), sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax[0].plot(t[m], sig[m])
    ax[0].plot(t[k], sig[k], "rv")
    ax[1].plot(t[m], ref["speed"][m])
    ax[1].set_ylabel("speed m/s")
    what = "swing deg (one event per stride)" if ref["steps_per_event"] == 2 else "band-passed height cm (one per step)"
    ax[0].set_ylabel(what)
    ax[0].set_title(f"{name}: {len(k)} events in {span_s:.0f} s, {ref['n_steps']} steps in the recording")
    for x in ax:
        x.set_xticks(np.arange(np.ceil(a), a + span_s, 0.25), minor=True)
        x.grid(which="both", alpha=0.4)
    fig.tight_layout()
    fig.savefig(out / f"{name}.png", dpi=65)
    plt.close(fig)


def summary(df: pd.DataFrame, detectors=DETECTORS, by: str = "motion") -> pd.DataFrame:
    """Mean count accuracy (1 - |n - n_ref| / n_ref) per motion (or person) and detector, and the worst recording."""
    out = []
    for key, g in df.groupby(by):
        row = {by: key, "n_recordings": len(g), "mocap_steps_median": float(g["mocap_steps"].median())}
        for d in detectors:
            acc = 1 - (g[d] - g["mocap_steps"]).abs() / g["mocap_steps"].clip(lower=1)
            row[d] = float(acc.mean())
            row[f"{d}_worst"] = float(acc.min())
        out.append(row)
    return pd.DataFrame(out)


def _markdown(s: pd.DataFrame, by: str, detectors) -> str:
    cols = [by, "n", "mocap median", *detectors]
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for d in s.to_dict("records"):
        cells = [str(d[by]), str(d["n_recordings"]), f"{d['mocap_steps_median']:.0f}"]
        cells += [f"{d[x]:.3f} ({d[x + '_worst']:.2f})" for x in detectors]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    """Print the per-motion table (markdown) and optionally write the per-recording CSV."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--plot", metavar="DIR")
    ap.add_argument("--csv", metavar="FILE")
    a = ap.parse_args(argv)
    df = table(a.data, plot_dir=a.plot)
    if a.csv:
        df.to_csv(a.csv, index=False)
    dets = [*DETECTORS, "adaptive_conf>=0.5"]
    spread = df.assign(lo=df["mocap_gate03"] / df["mocap_steps"] - 1, hi=df["mocap_gate0"] / df["mocap_steps"] - 1)
    print("Reference sensitivity: median change of the motion-capture count with the speed gate at 0.3 m/s / at 0:\n")
    for motion, g in spread.groupby("motion"):
        print(f"- {motion}: {100 * g['lo'].median():+.1f} % / {100 * g['hi'].median():+.1f} %")
    print()
    print("Count accuracy per motion, mean (worst recording):\n")
    print(_markdown(summary(df, dets), "motion", dets))
    for motion in sorted(df["motion"].unique()):
        print(f"\n{motion}, per person (adaptive's gyroscope settings chosen on all three: see tyrex_steps_lopo):\n")
        print(_markdown(summary(df[df["motion"] == motion], dets, by="person"), "person", dets))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
