"""Steps the detectors count while real people stand: the tyrex standing stretches as real non-gait data (issue 30).

The simulated non-gait motion of :mod:`gaitml.simulate.nongait` (gestures, a phone handled at a desk) is where the
project measures "no gait, no steps". The tyrex recordings hold real phones (in the hand held flat, in an AR pose, at
the ear, in pockets) of people who stand still for long stretches, with motion-capture truth. This module:

1. finds the *standing stretches* from the motion capture alone, by the rule fixed before any step was counted
   (``experiments/reports/nongait.md``, standsteps section; :func:`standing_stretches`): the lever-corrected body
   speed of :func:`experiments.scripts.tyrex_ar_moving.mocap_signals` below :data:`MAX_SPEED_MS` and its step-band
   bounce below :data:`MAX_BOUNCE_CM`, on tracked frames (a lost-frame gap longer than :data:`MAX_GAP_S` breaks a
   run), for runs of at least :data:`MIN_RUN_S` trimmed by :data:`TRIM_S` at each end, clipped to the phone segments
   the detectors ran on;
2. counts, per motion and person, the steps each detector of :data:`experiments.scripts.tyrex_steps.DETECTORS` gives
   inside them (steps per standing minute; raw, per-step ``confidence >= 0.5`` where the detector has that column,
   and gaitml's confident verdict :func:`gaitml.steps.confident_steps` over the segment's table);
3. does the same for ``adaptive`` at the opt-in settings of the three failed rounds (:data:`SETTINGS`), beside the
   simulated desk and gesture steps per minute the same settings give on the selection seeds 0-39 (and, with
   ``--heldout``, the held-out seeds 100-119).

Nothing is fitted or chosen here. Detector runs are cached per detector and setting in ``--cache`` (pickles; empty
the folder after any change to ``gaitml``). ``--plot DIR`` draws the recordings with the most ``adaptive`` standing
steps and one AR recording: motion-capture speed and bounce with the stretches shaded, the phone's |acc| and rotation
rate, and the detectors' steps.

    python -m experiments.scripts.tyrex_standing_steps --data ../shared/data --cache /tmp/standsteps   # ~30 s
    python -m experiments.scripts.tyrex_standing_steps --data ../shared/data --cache /tmp/standsteps --heldout --plot DIR
"""

from __future__ import annotations

import argparse
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_ar_moving import BOUNCE_MIN_CM, FORWARD_AXIS, LEVER_ARM_M, md, mocap_signals
from experiments.scripts.tyrex_steps import CONFIDENCE_SHOWN, DETECTORS, truth_clock_s, tyrex_walks
from experiments.scripts.tyrex_steps_joint import _cached

#: standing: the lever-corrected body speed (m/s, 0.5 Hz body track) below this (report, standsteps section, rule 1)
MAX_SPEED_MS = 0.10
#: the sensitivity variant of rule 4: the step reference's trunk gate (tyrex_steps.MIN_SPEED_MS["step"])
VARIANT_SPEED_MS = 0.15
#: standing: the step-band bounce (cm peak-to-peak) below the walking rule's low end of a walker's 1-5 cm
MAX_BOUNCE_CM = BOUNCE_MIN_CM
#: a lost motion-capture gap longer than this (s) breaks a standing run
MAX_GAP_S = 0.25
#: a standing run must last at least this long (s) before trimming
MIN_RUN_S = 3.0
#: trimmed from each end of a run (s): a step taken into or out of a stop is not a standing step
TRIM_S = 1.0
#: adaptive at its defaults and at the opt-in settings of the three failed rounds (experiments/reports/tyrex-steps.md:
#: texstep round 1 ``min_rms_ms2``, round 2 ``min_rms_slow_ms2``, perio round 3 ``rhythm_min_periodicity``)
SETTINGS: dict[str, dict] = {
    "default": {},
    "F0.15 (round 1)": {"min_rms_ms2": 0.15},
    "S0.15 (round 2)": {"min_rms_slow_ms2": 0.15},
    "P0.2 (round 3)": {"rhythm_min_periodicity": 0.2},
}
#: motions in the order the tables print them
MOTIONS = ("AR", "Texting", "Phoning", "FrontPocket", "BackPocket", "Swinging", "RunningHand", "RunningPocket")


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Maximal runs of True in ``mask`` as (first, one past last) index pairs."""
    m = np.concatenate([[False], np.asarray(mask, dtype=bool), [False]])
    d = np.diff(m.astype(np.int8))
    return list(zip(np.flatnonzero(d == 1).tolist(), np.flatnonzero(d == -1).tolist(), strict=True))


def tracked(t_s: np.ndarray, valid: np.ndarray, max_gap_s: float = MAX_GAP_S) -> np.ndarray:
    """Frames that are tracked or lie in a lost-frame gap no longer than ``max_gap_s``."""
    out = np.asarray(valid, dtype=bool).copy()
    for a, b in runs(~out):
        lo = t_s[a - 1] if a > 0 else -np.inf
        hi = t_s[b] if b < len(t_s) else np.inf
        if hi - lo <= max_gap_s:
            out[a:b] = True
    return out


def standing_masks(
    t_s, pos_m, rot, motion: str, *, max_speed_ms: float = MAX_SPEED_MS, max_bounce_cm: float = MAX_BOUNCE_CM, max_gap_s: float = MAX_GAP_S
) -> dict[str, np.ndarray]:
    """Per motion-capture sample: ``slow`` (lever-corrected body speed below ``max_speed_ms``), ``calm`` (bounce below
    ``max_bounce_cm``), ``tracked`` (:func:`tracked`), ``standing`` (all three) and the ``bounce_cm`` itself.

    ``pos_m`` (m, 3) and ``rot`` (m, 3, 3) are the phone's tracked position and attitude (NaN where lost) at the
    uniform times ``t_s``; ``motion`` picks the arm length and forward axis (:data:`LEVER_ARM_M`, :data:`FORWARD_AXIS`).
    """
    t = np.asarray(t_s, dtype=float)
    pos = np.asarray(pos_m, dtype=float)
    r = np.asarray(rot, dtype=float)
    valid = np.isfinite(pos).all(axis=1) & np.isfinite(r).all(axis=(1, 2))
    if valid.sum() < 2:
        z = np.zeros(len(t), dtype=bool)
        return {"slow": z, "calm": z, "tracked": z, "standing": z, "bounce_cm": np.full(len(t), np.nan)}
    s = mocap_signals(t, pos, r, lever_m=LEVER_ARM_M.get(motion, 0.0), forward_axis=FORWARD_AXIS.get(motion))
    slow = s["speed_lever"].to_numpy() < max_speed_ms
    bounce = s["bounce_cm"].to_numpy()
    calm = bounce < max_bounce_cm
    tr = tracked(t, valid, max_gap_s)
    return {"slow": slow, "calm": calm, "tracked": tr, "standing": slow & calm & tr, "bounce_cm": bounce}


def stretches_of(t_s, standing: np.ndarray, *, min_run_s: float = MIN_RUN_S, trim_s: float = TRIM_S) -> list[tuple[float, float]]:
    """Runs of ``standing`` lasting at least ``min_run_s``, trimmed by ``trim_s`` at each end (rule 2)."""
    t = np.asarray(t_s, dtype=float)
    out = []
    for a, b in runs(standing):
        t0, t1 = t[a], t[b - 1]
        if t1 - t0 >= min_run_s:
            out.append((float(t0 + trim_s), float(t1 - trim_s)))
    return out


def standing_stretches(
    t_s,
    pos_m,
    rot,
    motion: str,
    *,
    max_speed_ms: float = MAX_SPEED_MS,
    max_bounce_cm: float = MAX_BOUNCE_CM,
    min_run_s: float = MIN_RUN_S,
    trim_s: float = TRIM_S,
    max_gap_s: float = MAX_GAP_S,
) -> list[tuple[float, float]]:
    """The standing stretches (start, end), on the motion capture's clock, by rules 1-2 of the module docstring
    (:func:`standing_masks`, :func:`stretches_of`)."""
    m = standing_masks(t_s, pos_m, rot, motion, max_speed_ms=max_speed_ms, max_bounce_cm=max_bounce_cm, max_gap_s=max_gap_s)
    return stretches_of(t_s, m["standing"], min_run_s=min_run_s, trim_s=trim_s)


def clip(stretches: list[tuple[float, float]], spans: list[tuple[float, float]]) -> list[tuple[float, float]]:
    """The parts of ``stretches`` that lie inside one of ``spans`` (rule 3: the phone segments the detectors ran on)."""
    out = []
    for a, b in stretches:
        for c, d in spans:
            lo, hi = max(a, c), min(b, d)
            if hi > lo:
                out.append((lo, hi))
    return out


def inside(t: np.ndarray, stretches: list[tuple[float, float]]) -> np.ndarray:
    """Which times lie inside one of the stretches (ends included)."""
    t = np.asarray(t, dtype=float)
    m = np.zeros(len(t), dtype=bool)
    for a, b in stretches:
        m |= (t >= a) & (t <= b)
    return m


def minutes(stretches: list[tuple[float, float]]) -> float:
    return float(sum(b - a for a, b in stretches)) / 60.0


def segment_spans(walk: dict) -> list[tuple[float, float]]:
    """The phone segments' first and last sample on the motion capture's clock."""
    return [(float(r.meta.get("t0_original_s", 0.0) + r.t_s[0]), float(r.meta.get("t0_original_s", 0.0) + r.t_s[-1])) for r in walk["recs"]]


def detector_steps(walk: dict, detector: str = "adaptive", **kw) -> dict[str, np.ndarray]:
    """The detector's steps over every phone segment of ``walk``: times on the motion capture's clock, per-step
    ``confidence`` (NaN without that column) and gaitml's confident verdict (over each segment's whole table)."""
    from gaitml.steps import confident_steps, get_detector

    t, c, v = [], [], []
    for r in walk["recs"]:
        st = get_detector(detector, **kw).detect(r).steps_
        t.append(truth_clock_s(st, r))
        c.append(st["confidence"].to_numpy(dtype=float) if "confidence" in st else np.full(len(st), np.nan))
        v.append(confident_steps(st)[0] if len(st) else np.zeros(0, dtype=bool))
    cat = (lambda x: np.concatenate(x)) if t else (lambda x: np.zeros(0))
    return {"t": cat(t), "confidence": cat(c), "confident": cat(v).astype(bool)}


def _key(name: str) -> str:
    return name.split(" ")[0].replace(".", "p")


def stretch_table(walks: list[dict]) -> dict[str, dict]:
    """Per recording: the standing stretches clipped to its phone segments per speed threshold (rule and variant), the
    mocap times and bounce (``t``, ``bounce_cm``), and the minutes each condition of the rule leaves (``budget``, at
    :data:`MAX_SPEED_MS`: inside the phone segments, tracked, + slow, + calm, in runs of ``MIN_RUN_S``, trimmed)."""
    out = {}
    for w in walks:
        tr = w["truth"]
        t = np.asarray(tr.t_s, dtype=float)
        dt = float(np.median(np.diff(t)))
        spans = segment_spans(w)
        cov = inside(t, spans)
        entry = {"t": t}
        for v in (MAX_SPEED_MS, VARIANT_SPEED_MS):
            m = standing_masks(t, tr.pos_m, tr.rot, w["motion"], max_speed_ms=v)
            entry[v] = clip(stretches_of(t, m["standing"]), spans)
            if v == MAX_SPEED_MS:
                entry["bounce_cm"] = m["bounce_cm"]
                long_runs = np.zeros(len(t), dtype=bool)
                for i, j in runs(m["standing"]):
                    if t[j - 1] - t[i] >= MIN_RUN_S:
                        long_runs[i:j] = True
                entry["budget"] = {
                    "segments": cov.sum() * dt / 60,
                    "tracked": (cov & m["tracked"]).sum() * dt / 60,
                    "slow": (cov & m["tracked"] & m["slow"]).sum() * dt / 60,
                    "slow and calm": (cov & m["standing"]).sum() * dt / 60,
                    "runs >= 3 s": (cov & long_runs).sum() * dt / 60,
                    "stretches": minutes(entry[v]),
                }
        out[w["name"]] = entry
    return out


def budget_table(walks: list[dict], stretches: dict) -> list[str]:
    """Minutes per motion that each condition of the rule leaves (all people)."""
    keys = ["segments", "tracked", "slow", "slow and calm", "runs >= 3 s", "stretches"]
    tot: dict[str, dict[str, float]] = defaultdict(lambda: dict.fromkeys(keys, 0.0))
    for w in walks:
        for k in keys:
            tot[w["motion"]][k] += stretches[w["name"]]["budget"][k]
    names = [
        "phone segments",
        "+ tracked",
        f"+ speed < {MAX_SPEED_MS:g} m/s",
        f"+ bounce < {MAX_BOUNCE_CM:g} cm",
        f"+ runs >= {MIN_RUN_S:g} s",
        f"+ trimmed {TRIM_S:g} s (stretches)",
    ]
    lines = ["| motion | " + " | ".join(names) + " |", "|" + "---|" * (len(names) + 1)]
    for motion in [m for m in MOTIONS if m in tot]:
        lines.append(f"| {motion} | " + " | ".join(f"{tot[motion][k]:.1f}" for k in keys) + " |")
    return lines


#: a standing step in a chain of the same detector's steps (consecutive steps no more than this many seconds apart)
#: that also has a step outside every stretch is counted as a bout running in from outside (a description, not part
#: of the rule)
EDGE_S = 2.0
#: the bounce (cm) the standing steps are split at: a standing body's sway against 0.5-1 cm near the rule's limit
SPLIT_BOUNCE_CM = 0.5


def step_kinds(walks: list[dict], stretches: dict, runs_: dict[str, dict], speed: float = MAX_SPEED_MS) -> pd.DataFrame:
    """Per run: its standing steps split into bout edges (:data:`EDGE_S`) and wholly inside, and by the mocap bounce
    at the step (below :data:`SPLIT_BOUNCE_CM` or not)."""
    rows = []
    for run, per in runs_.items():
        c = dict.fromkeys(("steps", "edge", "inside", "bounce<0.5", "bounce 0.5-1"), 0)
        for w in walks:
            e = stretches[w["name"]]
            st = e[speed]
            t = np.sort(per[w["name"]]["t"])
            m = inside(t, st)
            if not m.any():
                continue
            chain = np.concatenate([[0], np.cumsum(np.diff(t) > EDGE_S)])  # steps no more than EDGE_S apart
            from_outside = np.isin(chain, chain[~m])
            for i in np.flatnonzero(m):
                c["edge" if from_outside[i] else "inside"] += 1
                b = float(np.interp(t[i], e["t"], e["bounce_cm"]))
                c["bounce<0.5" if b < SPLIT_BOUNCE_CM else "bounce 0.5-1"] += 1
            c["steps"] += int(m.sum())
        rows.append({"run": run, **c})
    lo = hi = 0.0
    for w in walks:  # the standing minutes on each side of SPLIT_BOUNCE_CM (mocap samples inside the stretches)
        e = stretches[w["name"]]
        m = inside(e["t"], e[speed])
        dt = float(np.median(np.diff(e["t"])))
        lo += float(np.sum(m & (e["bounce_cm"] < SPLIT_BOUNCE_CM))) * dt / 60
        hi += float(np.sum(m & (e["bounce_cm"] >= SPLIT_BOUNCE_CM))) * dt / 60
    out = pd.DataFrame(rows)
    out["per min, bounce<0.5"] = [f"{x / lo:.2f} ({lo:.1f} min)" if lo > 0 else "-" for x in out["bounce<0.5"]]
    out["per min, bounce 0.5-1"] = [f"{x / hi:.2f} ({hi:.1f} min)" if hi > 0 else "-" for x in out["bounce 0.5-1"]]
    return out


def count_rows(walks: list[dict], stretches: dict, runs_: dict[str, dict[str, dict]], speed: float = MAX_SPEED_MS) -> pd.DataFrame:
    """One row per recording and run (detector or setting): standing minutes, steps inside, their confident parts,
    and the motion-capture reference's steps inside."""
    rows = []
    for w in walks:
        st = stretches[w["name"]][speed]
        ref = w["ref"]
        n_ref = int(inside(ref["t_s"], st).sum()) * int(ref["steps_per_event"])
        for run, per in runs_.items():
            d = per[w["name"]]
            m = inside(d["t"], st)
            rows.append(
                {
                    "recording": w["name"],
                    "motion": w["motion"],
                    "person": w["person"],
                    "run": run,
                    "minutes": minutes(st),
                    "stretches": len(st),
                    "steps": int(m.sum()),
                    "conf>=0.5": int(np.sum(m & (d["confidence"] >= CONFIDENCE_SHOWN)))
                    if np.isfinite(d["confidence"]).any() or not len(d["t"])
                    else -1,
                    "confident": int(np.sum(m & d["confident"])),
                    "mocap_steps": n_ref,
                }
            )
    return pd.DataFrame(rows)


def _rate(n: float, mins: float) -> str:
    return f"{n / mins:.2f}" if mins > 0 else "-"


def minutes_table(df: pd.DataFrame) -> list[str]:
    """Standing minutes (stretches) per motion and person, and the reference's steps inside."""
    d = df[df["run"] == df["run"].iloc[0]]
    people = sorted(d["person"].unique())
    lines = ["| motion | " + " | ".join(people) + " | all | mocap reference steps inside |", "|" + "---|" * (len(people) + 3)]
    for motion in [m for m in MOTIONS if m in set(d["motion"])]:
        g = d[d["motion"] == motion]
        cells = []
        for p in people:
            h = g[g["person"] == p]
            cells.append(f"{h['minutes'].sum():.1f} ({int(h['stretches'].sum())})")
        lines.append(
            f"| {motion} | "
            + " | ".join(cells)
            + f" | {g['minutes'].sum():.1f} ({int(g['stretches'].sum())}) | {int(g['mocap_steps'].sum())} |"
        )
    lines.append(
        "| all | "
        + " | ".join(f"{d[d['person'] == p]['minutes'].sum():.1f}" for p in people)
        + f" | {d['minutes'].sum():.1f} | {int(d['mocap_steps'].sum())} |"
    )
    return lines


def rate_table(df: pd.DataFrame, runs_: list[str]) -> list[str]:
    """Steps per standing minute per motion (rows) and run (columns): raw (confidence >= 0.5) [confident verdict];
    then the spread over people (min-max of the per-person raw rate)."""
    lines = ["| motion | minutes | " + " | ".join(runs_) + " |", "|" + "---|" * (len(runs_) + 2)]
    for motion in [*[m for m in MOTIONS if m in set(df["motion"])], "all"]:
        g = df if motion == "all" else df[df["motion"] == motion]
        mins = g[g["run"] == runs_[0]]["minutes"].sum()
        cells = []
        for run in runs_:
            h = g[g["run"] == run]
            c = h["conf>=0.5"]
            conf = f" ({_rate(c.sum(), mins)})" if (c >= 0).all() else ""
            per = [
                h[h["person"] == p]["steps"].sum() / h[h["person"] == p]["minutes"].sum()
                for p in sorted(h["person"].unique())
                if h[h["person"] == p]["minutes"].sum() > 0
            ]
            spread = f" {{{min(per):.1f}-{max(per):.1f}}}" if per else ""
            cells.append(f"{_rate(h['steps'].sum(), mins)}{conf} [{_rate(h['confident'].sum(), mins)}]{spread}")
        lines.append(f"| {motion} | {mins:.1f} | " + " | ".join(cells) + " |")
    return lines


def person_table(df: pd.DataFrame, run: str) -> list[str]:
    """One run's steps per standing minute per motion and person (raw, steps / minutes)."""
    people = sorted(df["person"].unique())
    lines = ["| motion | " + " | ".join(people) + " |", "|" + "---|" * (len(people) + 1)]
    d = df[df["run"] == run]
    for motion in [m for m in MOTIONS if m in set(d["motion"])]:
        g = d[d["motion"] == motion]
        cells = []
        for p in people:
            h = g[g["person"] == p]
            cells.append(f"{_rate(h['steps'].sum(), h['minutes'].sum())} ({int(h['steps'].sum())} / {h['minutes'].sum():.1f})")
        lines.append(f"| {motion} | " + " | ".join(cells) + " |")
    return lines


def recording_table(df: pd.DataFrame, run: str, top: int = 10) -> list[str]:
    """The recordings with the most standing steps of ``run``."""
    d = df[(df["run"] == run) & (df["steps"] > 0)].sort_values("steps", ascending=False).head(top)
    lines = ["| recording | standing min | steps | per min | conf >= 0.5 | confident |", "|---|---|---|---|---|---|"]
    for r in d.to_dict("records"):
        lines.append(
            f"| {r['recording']} | {r['minutes']:.1f} | {r['steps']} | {_rate(r['steps'], r['minutes'])} | {r['conf>=0.5']} | {r['confident']} |"
        )
    return lines


def simulated_rates(seeds, cache: Path | None, runs_: dict[str, tuple[str, dict]]) -> dict[str, dict[str, float]]:
    """Per run (detector, keywords): mean steps per minute on the simulated gestures and desk of ``seeds``: raw, per-step
    confidence >= 0.5, confident verdict."""
    from experiments.scripts.tyrex_steps_joint import nongait_recordings
    from gaitml.steps import confident_steps, get_detector

    recs = nongait_recordings(seeds, cache)

    def make(det, kw):
        out = {}
        for kind in ("gestures", "desk"):
            raw, c5, cv = [], [], []
            for s in seeds:
                rec = recs[(kind, s)]
                st = get_detector(det, **kw).detect(rec).steps_
                mins = rec.duration_s / 60.0
                raw.append(len(st) / mins)
                c5.append(float(np.sum(st["confidence"].to_numpy() >= CONFIDENCE_SHOWN)) / mins if "confidence" in st else np.nan)
                cv.append(float(np.sum(confident_steps(st)[0])) / mins if len(st) else 0.0)
            out[kind], out[f"{kind}_conf"], out[f"{kind}_confident"] = float(np.mean(raw)), float(np.mean(c5)), float(np.mean(cv))
        return out

    return {
        name: _cached(cache, f"sim_{seeds[0]}_{seeds[-1]}_{_key(name)}", lambda d=d, kw=kw: make(d, kw)) for name, (d, kw) in runs_.items()
    }


def _sim_cell(r: dict, kind: str) -> str:
    conf = f" ({r[kind + '_conf']:.2f})" if np.isfinite(r[kind + "_conf"]) else ""
    return f"{r[kind]:.2f}{conf} [{r[kind + '_confident']:.2f}]"


def plot_stretches(walk: dict, stretches: list[tuple[float, float]], runs_: dict[str, dict], out: Path, span_s: float = 60.0) -> None:
    """``span_s`` around the stretch with the most steps of the first run in ``runs_`` (else the longest): motion-capture speed and bounce (standing shaded), the
    phone's |acc| and rotation rate, and each run's steps."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    tr = walk["truth"]
    s = mocap_signals(tr.t_s, tr.pos_m, tr.rot, lever_m=LEVER_ARM_M.get(walk["motion"], 0.0), forward_axis=FORWARD_AXIS.get(walk["motion"]))
    first = next(iter(runs_.values()))[walk["name"]]["t"]
    a, b = max(stretches, key=lambda x: (int(inside(first, [x]).sum()), x[1] - x[0]))  # most steps of the first run
    c = 0.5 * (a + b)
    lo, hi = c - span_s / 2, c + span_s / 2
    fig, ax = plt.subplots(4, 1, figsize=(12, 8), sharex=True)
    m = (tr.t_s >= lo) & (tr.t_s <= hi)
    ax[0].plot(tr.t_s[m], s["speed_lever"].to_numpy()[m], label="lever-corrected body speed")
    ax[0].axhline(MAX_SPEED_MS, color="k", lw=0.6)
    ax[0].set_ylabel("m/s")
    ax[1].plot(tr.t_s[m], s["bounce_cm"].to_numpy()[m])
    ax[1].axhline(MAX_BOUNCE_CM, color="k", lw=0.6)
    ax[1].set_ylabel("bounce cm p-p")
    for r in walk["recs"]:
        t = r.meta.get("t0_original_s", 0.0) + r.t_s
        k = (t >= lo) & (t <= hi)
        if not k.any():
            continue
        acc = np.linalg.norm(np.asarray(r.acc, dtype=float)[k], axis=1)
        ax[2].plot(t[k], acc, lw=0.5, color="C0")
        if r.gyr is not None:
            ax[3].plot(t[k], np.linalg.norm(np.asarray(r.gyr, dtype=float)[k], axis=1), lw=0.5, color="C1")
    ax[2].set_ylabel("|acc| m/s^2")
    ax[3].set_ylabel("|gyro| rad/s")
    ymax = ax[2].get_ylim()[1]
    for i, (name, per) in enumerate(runs_.items()):
        t = per[walk["name"]]["t"]
        t = t[(t >= lo) & (t <= hi)]
        ax[2].plot(t, np.full(len(t), ymax - 0.4 * i), "v", ms=5, label=name)
    ax[2].set_ylim(top=ymax + 0.3)
    ax[2].legend(loc="upper right", fontsize=7)
    for x in ax:
        for p, q in stretches:
            if q > lo and p < hi:
                x.axvspan(p, q, color="0.85", zorder=0)
        x.grid(alpha=0.3)
    ax[3].set_xlabel("s (motion-capture clock); grey: standing stretches")
    fig.suptitle(f"{walk['name']}: standing stretches and steps")
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=65)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    """Print the standing minutes, the detectors' standing steps per minute and the opt-in settings' comparison."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_standing_steps", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--cache", default=None, help="folder for detector runs and simulated recordings (pickles)")
    ap.add_argument("--heldout", action="store_true", help="also the simulated held-out seeds 100-119")
    ap.add_argument("--plot", metavar="DIR", help="plots of the recordings with the most adaptive standing steps")
    ap.add_argument("--nplots", type=int, default=3)
    a = ap.parse_args(argv)
    if not (Path(a.data) / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    from experiments.scripts.tyrex_steps_joint import HELDOUT_SEEDS, SELECTION_SEEDS

    cache = Path(a.cache) if a.cache else None
    walks = list(tyrex_walks(a.data))
    for w in walks:
        w["ref"] = {k: w["ref"][k] for k in ("t_s", "steps_per_event", "n_steps")}  # the reference's signals are not needed
    stretches = stretch_table(walks)
    dets = {d: _cached(cache, f"tyrex_{d}", lambda d=d: {w["name"]: detector_steps(w, d) for w in walks}) for d in DETECTORS}
    sets = {
        k: dets["adaptive"]
        if not kw
        else _cached(cache, f"tyrex_adaptive_{_key(k)}", lambda kw=kw: {w["name"]: detector_steps(w, "adaptive", **kw) for w in walks})
        for k, kw in SETTINGS.items()
    }
    names = {w["name"] for w in walks}
    for d in (*dets.values(), *sets.values()):
        if set(d) != names:
            print("error: a cached detector run does not hold these recordings; empty the --cache folder", file=sys.stderr)
            return 2
    print(
        f"{len(walks)} tyrex recordings. Cells: steps per standing minute, raw (per-step confidence >= {CONFIDENCE_SHOWN}) "
        "[gaitml's confident verdict] {min-max over people, raw}.\n"
    )
    for speed in (MAX_SPEED_MS, VARIANT_SPEED_MS):
        tag = "the rule" if speed == MAX_SPEED_MS else "sensitivity"
        df = count_rows(walks, stretches, dets, speed)
        print(f"## Standing minutes (stretches) per motion and person, speed < {speed:g} m/s ({tag})\n")
        print("\n".join(minutes_table(df)) + "\n")
        if speed == MAX_SPEED_MS:
            print("### minutes each condition of the rule leaves, per motion (all people)\n")
            print("\n".join(budget_table(walks, stretches)) + "\n")
        print(f"## Detectors at their defaults, steps per standing minute (speed < {speed:g} m/s)\n")
        print("\n".join(rate_table(df, list(DETECTORS))) + "\n")
        if speed == MAX_SPEED_MS:
            for d in ("adaptive", "adfsm", "ifsm"):
                print(f"### {d} per motion and person: steps per standing minute (steps / minutes)\n")
                print("\n".join(person_table(df, d)) + "\n")
            print("### the recordings with the most adaptive standing steps\n")
            print("\n".join(recording_table(df, "adaptive")) + "\n")
            print(
                f"### standing steps: in a chain of steps (gaps <= {EDGE_S:g} s) that runs in from outside a stretch (edge) or wholly inside; mocap bounce at the step\n"
            )
            print(md(step_kinds(walks, stretches, dets, speed)) + "\n")
        ds = count_rows(walks, stretches, sets, speed)
        print(f"## adaptive at the failed rounds' opt-in settings, steps per standing minute (speed < {speed:g} m/s)\n")
        print("\n".join(rate_table(ds, list(SETTINGS))) + "\n")
        print(md(step_kinds(walks, stretches, sets, speed)) + "\n")
        base = ds[ds["run"] == "default"].set_index("recording")
        for k in list(SETTINGS)[1:]:
            o = ds[ds["run"] == k].set_index("recording")
            delta = (o["steps"] - base["steps"]).sum()
            dconf = (o["confident"] - base["confident"]).sum()
            changed = ", ".join(
                f"{r} {base.loc[r, 'steps']}->{o.loc[r, 'steps']}" for r in o.index if o.loc[r, "steps"] != base.loc[r, "steps"]
            )
            print(
                f"- {k}: {delta:+d} standing steps ({dconf:+d} confident) over {base['minutes'].sum():.1f} standing minutes"
                + (f": {changed}" if changed else "")
            )
        print()
    sim_runs = {**{d: (d, {}) for d in DETECTORS}, **{k: ("adaptive", kw) for k, kw in list(SETTINGS.items())[1:]}}
    seed_sets = [("selection seeds 0-39", SELECTION_SEEDS)] + ([("held-out seeds 100-119", HELDOUT_SEEDS)] if a.heldout else [])
    for label, seeds in seed_sets:
        sim = simulated_rates(seeds, cache, sim_runs)
        print(f"## Simulated non-gait, {label} (120 s each): steps per minute, raw (confidence >= 0.5) [confident verdict]\n")
        print("| run | gestures | desk |\n|---|---|---|")
        for k, r in sim.items():
            print(f"| {k} | {_sim_cell(r, 'gestures')} | {_sim_cell(r, 'desk')} |")
        print()
    if a.plot:
        df = count_rows(walks, stretches, dets)
        ad = df[df["run"] == "adaptive"].sort_values("steps", ascending=False)
        chosen = list(ad[ad["steps"] > 0]["recording"].head(a.nplots))
        ar = ad[(ad["motion"] == "AR") & (ad["minutes"] > 0)]["recording"]
        if len(ar) and not set(chosen) & set(ar):
            chosen.append(ar.iloc[0])
        ds = count_rows(walks, stretches, sets)
        gain = (
            ds[ds["run"] == "F0.15 (round 1)"].set_index("recording")["steps"] - ds[ds["run"] == "default"].set_index("recording")["steps"]
        )
        if gain.max() > 0 and gain.idxmax() not in chosen:
            chosen.append(gain.idxmax())  # where round 1's floor adds the most standing steps
        by = {w["name"]: w for w in walks}
        show = {"adaptive": dets["adaptive"], "adaptive F0.15": sets["F0.15 (round 1)"], "adfsm": dets["adfsm"], "ifsm": dets["ifsm"]}
        for name in chosen:
            plot_stretches(by[name], stretches[name][MAX_SPEED_MS], show, Path(a.plot) / f"standsteps_{name}.png")
        print(f"plots: {', '.join(chosen)} in {a.plot}", file=sys.stderr)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
