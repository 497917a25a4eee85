"""What AD-FSM picks on hand-held Texting that adaptive does not, step by step (issue 30, diagnosis).

Per motion-capture reference step of the tyrex ``Texting`` recordings (:func:`experiments.scripts.tyrex_steps.mocap_steps`:
one height minimum of the phone per step), which detector hits it: a reference step is *hit* by a detected step
matched to it one-to-one within :data:`COVER_S` (the greedy matching of
:func:`experiments.scripts.tyrex_steps_octave.match_steps`, the one behind the per-step F1 of the earlier sections).
Each reference step is then *adaptive only*, *AD-FSM only*, *both* or *neither*.

Where adaptive loses a step it misses: adaptive is re-run with its rules switched off one after another
(:data:`CASCADE`, each row keeps the earlier rows' switches), and the step is put on the first rule whose switch
gives it a step within :data:`COVER_S` (it was a candidate that rule removed); *no candidate* where none does.
Beside that, the state of adaptive's cadence window nearest the step (:func:`window_class`: its step period against
the reference's local step interval, or a periodicity below the floor) and the walker's speed (below 0.3 m/s:
:func:`experiments.scripts.tyrex_steps_misses.body_state`).

Adaptive's *extras* (detected steps matched to no reference step) are described by where they sit: *outside walking*
(no reference step within :data:`OUTSIDE_S`: the reference's speed gate, stops), else by their phase in the reference
step they fall in (0 at a reference step, 0.5 half-way to the next) and by the nearest window's class.

Nothing is fitted or chosen here. Every detector runs at its defaults.

    python -m experiments.scripts.tyrex_steps_texting --data ../shared/data [--motion Texting] [--plot DIR]   # ~30 s
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps_lopo import PEOPLE

#: a reference step is hit by a detected step matched to it within this (s), as tyrex_steps_octave.match_steps
COVER_S = 0.45
#: an extra step with no reference step within this (s) lies outside the reference's walking (a stop, the speed gate)
OUTSIDE_S = 1.5
#: adaptive's rules switched off one after another (cumulative): the first switch that gives a missed reference step
#: a step within COVER_S names the rule that removed it. Stage 5b runs before the (then absent) gait check from the
#: first row on, so turning the check off does not also turn stage 5b off.
CASCADE: dict[str, dict] = {
    "gait check": {"gait_check": False, "episode_before_gait_check": True},
    "short-bout rule": {"short_bout_steps": 0},
    "edge / min-bout rules": {"min_bout_steps": 1, "edge_confidence_ratio": 0.0},
    "periodicity floor": {"min_periodicity": 0.0},
    "noise floor": {"min_rms_ms2": 0.0},
    "peak spacing": {"min_distance_ratio": 0.3},
    "fold": {"fold": False},
}
#: window classes: adaptive's step period / the reference's local step interval below HALF_RATIO reads half steps,
#: at or above STRIDE_RATIO strides (the fourth helper's 0.8 / 1.25 "match" band, widened to the octave midpoints)
HALF_RATIO = 0.75
STRIDE_RATIO = 1.5
#: adaptive's periodicity floor (its default MIN_PERIODICITY): a window below it gives no step
MIN_PERIODICITY = 0.3
#: the reference's local step interval: median interval of its steps within this many seconds
LOCAL_S = 2.5
#: the interval used for a reference step with no neighbour within LOCAL_S (s): a slow step
RMS_FALLBACK_S = 0.8
#: adaptive's noise floor (its default MIN_RMS_MS2, m/s^2), for the share of steps under it
NOISE_FLOOR_MS2 = 0.2
WINDOW_CLASSES = ("half", "match", "stride", "low periodicity", "no window")


def match_flags(t: np.ndarray, ref: np.ndarray, tol: float = COVER_S) -> tuple[np.ndarray, np.ndarray]:
    """The greedy one-to-one matching of :func:`experiments.scripts.tyrex_steps_octave.match_steps` with its pairs:
    (per reference step: hit, per detected step in sorted order: matched)."""
    ref = np.asarray(ref, dtype=float)
    t = np.sort(np.asarray(t, dtype=float))
    used = np.zeros(len(ref), dtype=bool)
    matched = np.zeros(len(t), dtype=bool)
    for i, x in enumerate(t):
        j = np.flatnonzero(~used & (np.abs(ref - x) <= tol))
        if len(j):
            used[j[np.argmin(np.abs(ref[j] - x))]] = True
            matched[i] = True
    return used, matched


def near(ref: np.ndarray, t: np.ndarray, tol: float = COVER_S) -> np.ndarray:
    """Per reference step, whether any time of ``t`` lies within ``tol`` (not one-to-one)."""
    ref = np.asarray(ref, dtype=float)
    if not len(t):
        return np.zeros(len(ref), dtype=bool)
    return np.min(np.abs(ref[:, None] - np.asarray(t, dtype=float)[None, :]), axis=1) <= tol


def local_interval(ref: np.ndarray, x: float) -> float:
    """Median interval of the reference steps within :data:`LOCAL_S` of ``x`` (nan with fewer than two)."""
    loc = ref[np.abs(ref - x) <= LOCAL_S]
    return float(np.median(np.diff(loc))) if len(loc) > 1 else float("nan")


def window_class(period_s: float, periodicity: float, interval_s: float) -> str:
    """The state of a cadence window against the reference: ``low periodicity`` (no step there), else the window's
    step period over the reference's local interval read as ``half`` / ``match`` / ``stride`` (``match`` when the
    reference has no local interval)."""
    if not np.isfinite(periodicity) or periodicity < MIN_PERIODICITY:
        return "low periodicity"
    if not np.isfinite(interval_s) or interval_s <= 0:
        return "match"
    r = period_s / interval_s
    return "half" if r < HALF_RATIO else ("stride" if r >= STRIDE_RATIO else "match")


def phase_in_step(ref: np.ndarray, x: float) -> float:
    """Where ``x`` falls in the reference step it lies in: 0 at a reference step, 0.5 half-way to the next (nan
    outside the reference's first and last step)."""
    k = int(np.searchsorted(ref, x))
    if k == 0 or k >= len(ref):
        return float("nan")
    a, b = ref[k - 1], ref[k]
    return float((x - a) / (b - a)) if b > a else float("nan")


def step_rms(items_recs: list, x: float, interval_s: float, band_hz: tuple[float, float] = (0.5, 4.0)) -> float:
    """Adaptive's noise-floor measure at a reference step ``x`` (s): the band-passed |acc| RMS over one reference step
    interval before ``x`` and over one after it, the smaller (nan where the recording does not cover both)."""
    for t0, fs, y in items_recs:
        k, n = int(round((x - t0) * fs)), int(round(interval_s * fs))
        if n > 0 and n <= k < len(y) - n:
            return float(min(np.sqrt(np.mean(y[k - n : k] ** 2)), np.sqrt(np.mean(y[k : k + n] ** 2))))
    return float("nan")


def _bandpassed(rec, band_hz: tuple[float, float] = (0.5, 4.0)) -> tuple[float, float, np.ndarray]:
    from gaitml.signal import bandpass
    from gaitml.steps._common import acc_magnitude

    x = acc_magnitude(rec)
    fs = rec.sampling_rate_hz
    return float(rec.meta.get("t0_original_s", 0.0)), fs, bandpass(x - np.median(x), band_hz[0], band_hz[1], fs, order=2)


def _run(rec, **kw) -> dict:
    """Adaptive (``kw`` over its defaults) on one recording piece: step times (reference clock), confidence and the
    cadence windows."""
    from gaitml.steps import get_detector

    det = get_detector("adaptive", **kw).detect(rec)
    t0 = float(rec.meta.get("t0_original_s", 0.0))
    c = det.cadence_
    return {
        "steps": t0 + det.steps_["t_peak_s"].to_numpy(),
        "confidence": det.steps_["confidence"].to_numpy(),
        "t": t0 + c["t_s"].to_numpy(),
        "period": c["period_s"].to_numpy(),
        "periodicity": c["periodicity"].to_numpy(),
    }


def _in_span(t: np.ndarray, ref: dict) -> np.ndarray:
    return (t >= ref["t_first_s"]) & (t <= ref["t_last_s"])


def _joined(runs: list[dict], key: str, it: dict) -> np.ndarray:
    t = np.concatenate([r["steps"] for r in runs]) if runs else np.zeros(0)
    v = np.concatenate([r[key] for r in runs]) if runs else np.zeros(0)
    order = np.argsort(t, kind="stable")
    t, v = t[order], v[order]
    return v[_in_span(t, it["ref"])]


def _nearest_window(runs: list[dict], x: float) -> tuple[float, float]:
    best = (np.inf, np.nan, np.nan)
    for g in runs:
        if len(g["t"]):
            j = int(np.argmin(np.abs(g["t"] - x)))
            if abs(g["t"][j] - x) < best[0]:
                best = (abs(g["t"][j] - x), g["period"][j], g["periodicity"][j])
    return best[1], best[2]


def analyse(items: list[dict], base: dict | None = None) -> tuple[pd.DataFrame, pd.DataFrame]:
    """Per reference step (``steps``) and per adaptive extra step (``extras``) of every recording in ``items``
    (dicts of :func:`experiments.scripts.tyrex_steps.tyrex_walks` whose reference counts steps); adaptive with the
    keywords ``base`` (its defaults if None), the cascade on top of them."""
    base = dict(base or {})
    from experiments.scripts.tyrex_steps_joint import step_times
    from experiments.scripts.tyrex_steps_misses import SLOW_MS, body_state

    adfsm = step_times(items, "adfsm")
    srows, xrows = [], []
    for it, tf in zip(items, adfsm, strict=True):
        ref = np.asarray(it["ref"]["t_s"], dtype=float)
        chance = chance_hits(tf, ref, (it["ref"]["t_first_s"], it["ref"]["t_last_s"]))
        runs = [_run(r, **base) for r in it["recs"]]
        ta = _joined(runs, "steps", it)
        conf = _joined(runs, "confidence", it)
        hit_a, matched_a = match_flags(ta, ref)
        hit_f, _ = match_flags(tf, ref)
        kw: dict = dict(base)
        found = {}
        for name, sw in CASCADE.items():
            kw = {**kw, **sw}
            found[name] = near(ref, _joined([_run(r, **kw) for r in it["recs"]], "steps", it))
        t_b, speed, _ = body_state(it["truth"])
        sig = [_bandpassed(r) for r in it["recs"]]

        def slow(x: float, t_b=t_b, speed=speed) -> bool:
            return bool(speed[int(np.clip(np.searchsorted(t_b, x), 0, len(t_b) - 1))] < SLOW_MS)

        for i, x in enumerate(ref):
            period, periodicity = _nearest_window(runs, x)
            cause = ""
            if not hit_a[i]:
                cause = "no candidate"
                if near(np.array([x]), ta)[0]:
                    cause = "taken by another"  # a detected step within COVER_S, matched to a neighbouring reference step
                else:
                    cause = next((c for c in CASCADE if found[c][i]), "no candidate")
            srows.append(
                {
                    "recording": it["name"],
                    "person": it["person"],
                    "t": x,
                    "adaptive": bool(hit_a[i]),
                    "adfsm": bool(hit_f[i]),
                    "cause": cause,
                    "window": "no window" if not np.isfinite(period) else window_class(period, periodicity, local_interval(ref, x)),
                    "slow": slow(x),
                    "adfsm_chance": chance / max(len(ref), 1),
                    "rms": step_rms(sig, x, local_interval(ref, x) if np.isfinite(local_interval(ref, x)) else RMS_FALLBACK_S),
                }
            )
        for x, c in zip(ta[~matched_a], conf[~matched_a], strict=True):
            d = float(np.min(np.abs(ref - x))) if len(ref) else np.inf
            period, periodicity = _nearest_window(runs, x)
            xrows.append(
                {
                    "recording": it["name"],
                    "person": it["person"],
                    "t": x,
                    "outside": d > OUTSIDE_S,
                    "phase": phase_in_step(ref, x),
                    "window": "no window" if not np.isfinite(period) else window_class(period, periodicity, local_interval(ref, x)),
                    "slow": slow(x),
                    "confidence": float(c),
                }
            )
    return pd.DataFrame(srows), pd.DataFrame(xrows)


#: the chance control: each recording's AD-FSM step times shifted circularly (within the reference's span) by this
#: many random offsets of at least CHANCE_MIN_SHIFT_S, the hits averaged: what a detector of the same density and rhythm
#: hits by chance within COVER_S
CHANCE_SHIFTS = 20
CHANCE_MIN_SHIFT_S = 5.0


def chance_hits(t: np.ndarray, ref: np.ndarray, span: tuple[float, float], seed: int = 0, tol: float = COVER_S) -> float:
    """Mean hits (:func:`match_flags`) of ``t`` shifted circularly inside ``span`` by :data:`CHANCE_SHIFTS` random
    offsets (at least :data:`CHANCE_MIN_SHIFT_S` from no shift either way)."""
    lo, hi = span
    width = hi - lo
    if width <= 2 * CHANCE_MIN_SHIFT_S or not len(t):
        return float("nan")
    rng = np.random.default_rng(seed)
    hits = []
    for d in rng.uniform(CHANCE_MIN_SHIFT_S, width - CHANCE_MIN_SHIFT_S, CHANCE_SHIFTS):
        hits.append(int(match_flags(lo + np.mod(np.asarray(t) - lo + d, width), ref, tol)[0].sum()))
    return float(np.mean(hits))


#: the tighter matching window of the F1 table (s): the matched pairs' offsets lie within -0.04..+0.11 s (10th-90th
#: percentile, both detectors, every person), so a window of 0.15 s keeps true pairs and leaves little room for chance
TIGHT_S = 0.15


def f1_table(items: list[dict], base: dict | None = None) -> str:
    """Per person: per-step F1 of adaptive (keywords ``base`` over its defaults) and AD-FSM at the usual window
    (:data:`COVER_S`) and the tight one (:data:`TIGHT_S`), each beside the F1 of the same steps shifted at random
    (:func:`chance_hits`)."""
    from experiments.scripts.tyrex_steps_joint import step_times

    runs = {"adaptive": step_times(items, **(base or {})), "AD-FSM": step_times(items, "adfsm")}
    cols = ["person", "detector", "detected / reference"]
    cols += [f"F1 within {tol:g} s (shifted at random)" for tol in (COVER_S, TIGHT_S)]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for p in (*PEOPLE, "all"):
        for det, times in runs.items():
            sel = [(it, t) for it, t in zip(items, times, strict=True) if p in (it["person"], "all")]
            n_ref = sum(len(it["ref"]["t_s"]) for it, _ in sel)
            n_det = sum(len(t) for _, t in sel)
            cells = [p, det, f"{n_det / max(n_ref, 1):.2f}"]
            for tol in (COVER_S, TIGHT_S):
                h = sum(int(match_flags(t, np.asarray(it["ref"]["t_s"]), tol)[0].sum()) for it, t in sel)
                c = sum(
                    chance_hits(t, np.asarray(it["ref"]["t_s"]), (it["ref"]["t_first_s"], it["ref"]["t_last_s"]), tol=tol) for it, t in sel
                )
                cells.append(f"{2 * h / (n_det + n_ref):.3f} ({2 * c / (n_det + n_ref):.3f})")
            out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def _people(df: pd.DataFrame) -> list[tuple[str, pd.DataFrame]]:
    return [(p, df[df["person"] == p]) for p in PEOPLE] + [("all", df)]


def who_table(steps: pd.DataFrame) -> str:
    """Per person: reference steps hit by both, AD-FSM only, adaptive only, neither."""
    cols = [
        "person",
        "reference",
        "both",
        "AD-FSM only",
        "adaptive only",
        "neither",
        "adaptive misses slow (< 0.3 m/s)",
        "AD-FSM hits shifted at random (chance)",
    ]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for p, d in _people(steps):
        a, f = d["adaptive"], d["adfsm"]
        miss = d[~a]
        out.append(
            f"| {p} | {len(d)} | {int((a & f).sum())} | {int((f & ~a).sum())} | {int((a & ~f).sum())} | {int((~a & ~f).sum())} "
            f"| {int(miss['slow'].sum())} of {len(miss)} | {d['adfsm_chance'].sum():.0f} |"
        )
    return "\n".join(out)


CAUSES = ("taken by another", *CASCADE, "no candidate")


def cause_table(steps: pd.DataFrame) -> str:
    """Adaptive's missed reference steps per person by the rule that removed them (cells: missed (of them AD-FSM hits))."""
    cols = ["person", "missed", *CAUSES]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for p, d in _people(steps):
        m = d[~d["adaptive"]]
        cells = [p, f"{len(m)} ({int(m['adfsm'].sum())})"]
        cells += [f"{int((m['cause'] == c).sum())} ({int((m['adfsm'] & (m['cause'] == c)).sum())})" for c in CAUSES]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def rms_table(steps: pd.DataFrame) -> str:
    """Per person: the noise-floor measure (:func:`step_rms`) at the steps adaptive hits and at those each rule
    removed: 10th / 50th / 90th percentile and the share under :data:`NOISE_FLOOR_MS2`."""
    groups = {"hit": lambda d: d["adaptive"], "missed": lambda d: ~d["adaptive"]}
    groups.update(
        {c: (lambda d, c=c: d["cause"] == c) for c in ("noise floor", "periodicity floor", "short-bout rule", "edge / min-bout rules")}
    )
    cols = ["person", *groups]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for p, d in _people(steps):
        cells = [p]
        for sel in groups.values():
            v = d.loc[sel(d), "rms"].dropna().to_numpy()
            if len(v):
                q = np.percentile(v, [10, 50, 90])
                cells.append(f"{q[0]:.2f} / {q[1]:.2f} / {q[2]:.2f} ({100 * np.mean(v < NOISE_FLOOR_MS2):.0f} %)")
            else:
                cells.append("-")
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def window_table(steps: pd.DataFrame, extras: pd.DataFrame) -> str:
    """Per person: reference steps hit / missed and adaptive's extras inside walking, by the class of the nearest
    cadence window (cells: hit / missed / extra)."""
    cols = ["person", *WINDOW_CLASSES]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for (p, d), (_, x) in zip(_people(steps), _people(extras), strict=True):
        x = x[~x["outside"]]
        cells = [p]
        for w in WINDOW_CLASSES:
            dw = d[d["window"] == w]
            cells.append(f"{int(dw['adaptive'].sum())} / {int((~dw['adaptive']).sum())} / {int((x['window'] == w).sum())}")
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def extras_table(extras: pd.DataFrame) -> str:
    """Adaptive's extra steps per person: outside walking, and inside it by phase in the reference step."""
    cols = [
        "person",
        "extras",
        "outside walking",
        "phase 0.3-0.7 (mid-step)",
        "phase < 0.3 or > 0.7",
        "slow (< 0.3 m/s)",
        "median confidence",
    ]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for p, x in _people(extras):
        inside = x[~x["outside"]]
        mid = inside["phase"].between(0.3, 0.7)
        out.append(
            f"| {p} | {len(x)} | {int(x['outside'].sum())} | {int(mid.sum())} | {int((~mid).sum())} | {int(inside['slow'].sum())} "
            f"| {float(inside['confidence'].median()) if len(inside) else float('nan'):.2f} |"
        )
    return "\n".join(out)


def plots(items: list[dict], steps: pd.DataFrame, extras: pd.DataFrame, out: Path, example: str, span: tuple[float, float]) -> list[Path]:
    """Three figures: adaptive's misses by rule per person; the phase of adaptive's extras and of AD-FSM's steps in
    the reference step cycle; one stretch of ``example`` with the band-passed |acc|, the reference and both detectors."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from experiments.scripts.tyrex_steps_joint import step_times
    from gaitml.signal import bandpass
    from gaitml.steps._common import acc_magnitude

    out.mkdir(parents=True, exist_ok=True)
    paths = []
    fig, ax = plt.subplots(figsize=(8, 3.6))
    bottom = np.zeros(len(PEOPLE))
    for c in CAUSES:
        v = np.array([int(((steps["person"] == p) & ~steps["adaptive"] & (steps["cause"] == c)).sum()) for p in PEOPLE])
        ax.barh(PEOPLE, v, left=bottom, label=c)
        bottom += v
    ax.set_xlabel("reference steps adaptive misses (Texting)")
    ax.legend(fontsize=7, ncol=5, loc="upper center", bbox_to_anchor=(0.5, -0.25))
    fig.tight_layout()
    paths.append(out / "texstep-miss-causes.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    fig, axes = plt.subplots(1, len(PEOPLE), figsize=(10, 3), sharey=True)
    adfsm = step_times(items, "adfsm")
    bins = np.linspace(0, 1, 21)
    for ax, p in zip(axes, PEOPLE, strict=True):
        ph = []
        for it, tf in zip(items, adfsm, strict=True):
            if it["person"] == p:
                ref = np.asarray(it["ref"]["t_s"], dtype=float)
                ph += [phase_in_step(ref, x) for x in tf]
        ph = np.asarray(ph)
        ax.hist(ph[np.isfinite(ph)], bins=bins, histtype="step", label="AD-FSM, all steps")
        xp = extras.loc[(extras["person"] == p) & ~extras["outside"], "phase"].to_numpy()
        ax.hist(xp[np.isfinite(xp)], bins=bins, label="adaptive, extras")
        ax.set_title(p)
        ax.set_xlabel("phase in the reference step")
    axes[0].set_ylabel("steps")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    paths.append(out / "texstep-phase.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)

    it = next(i for i in items if i["name"] == example)
    fig, ax = plt.subplots(figsize=(11, 4.2))
    for r in it["recs"]:
        t0 = float(r.meta.get("t0_original_s", 0.0))
        t = t0 + np.arange(r.n_samples) / r.sampling_rate_hz
        sel = (t >= span[0]) & (t <= span[1])
        if sel.any():
            x = acc_magnitude(r)
            y = bandpass(x - np.median(x), 0.5, 4.0, r.sampling_rate_hz, order=2)
            ax.plot(t[sel], y[sel], lw=0.8, color="0.4", label="|acc| band-passed")
    ref = np.asarray(it["ref"]["t_s"], dtype=float)
    d = steps[steps["recording"] == example]
    tf = adfsm[items.index(it)]
    ta = np.concatenate([_run(r)["steps"] for r in it["recs"]])
    for v, y0, lab, kw in (
        (ref, 2.2, "reference (hit by adaptive)", {"color": "g", "marker": "v"}),
        (d.loc[~d["adaptive"], "t"].to_numpy(), 2.2, "reference (missed by adaptive)", {"color": "r", "marker": "v"}),
        (ta, 1.6, "adaptive", {"color": "b", "marker": "o"}),
        (tf, 1.0, "AD-FSM", {"color": "m", "marker": "x"}),
    ):
        v = v[(v >= span[0]) & (v <= span[1])]
        ax.scatter(v, np.full(len(v), y0), s=18, label=lab, **kw)
    for x, c in d.loc[~d["adaptive"], ["t", "cause"]].itertuples(index=False):
        if span[0] <= x <= span[1]:
            ax.annotate(c, (x, 2.3), rotation=60, fontsize=6, color="r")
    ax.set_xlim(*span)
    ax.set_ylim(top=3.6)
    ax.set_xlabel("s (motion-capture clock)")
    ax.set_title(f"{example}, {span[0]:g}-{span[1]:g} s")
    ax.legend(fontsize=7, ncol=5, loc="lower left")
    fig.tight_layout()
    paths.append(out / "texstep-example.png")
    fig.savefig(paths[-1], dpi=90)
    plt.close(fig)
    return paths


def main(argv: list[str] | None = None) -> int:
    """Print the tables (markdown); ``--plot DIR`` writes the figures."""
    from experiments.scripts.tyrex_steps import tyrex_walks

    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_texting", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--motion", default="Texting", choices=("Texting", "Phoning", "FrontPocket", "BackPocket", "Swinging"))
    ap.add_argument("--plot", default=None, help="folder for the three figures")
    ap.add_argument("--example", default="Guillaume_Nexus5_NoDist_Texting", help="recording of the example figure")
    ap.add_argument("--span", default="44,64", help="its stretch, s on the motion-capture clock: START,END")
    ap.add_argument("--min-rms", type=float, default=None, help="adaptive's noise floor min_rms_ms2 (default: its default)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="another adaptive keyword (a number), repeatable")
    a = ap.parse_args(argv)
    try:
        extra = {k.strip(): float(v) for k, v in (item.split("=", 1) for item in a.set)}
        lo, hi = (float(v) for v in a.span.split(","))
    except ValueError:
        print(f"error: --set takes KEY=NUMBER (an adaptive keyword) and --span START,END; got {a.set!r}, {a.span!r}", file=sys.stderr)
        return 2
    base = {**({} if a.min_rms is None else {"min_rms_ms2": a.min_rms}), **extra} or None
    if base:
        from gaitml.errors import InputError
        from gaitml.steps import get_detector

        try:
            get_detector("adaptive", **base)._validate_params()
        except (InputError, TypeError) as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
    items = list(tyrex_walks(a.data, (a.motion,)))
    if not items:
        print(f"error: no tyrex {a.motion} recording under {a.data}; give --data the folder holding tyrex-attitude", file=sys.stderr)
        return 2
    steps, extras = analyse(items, base)
    print(f"## {a.motion}: who hits each reference step (hit = matched one-to-one within {COVER_S} s)\n")
    print(who_table(steps))
    print("\n## adaptive's misses by the rule that removed them (cells: missed (of them hit by AD-FSM))\n")
    print(cause_table(steps))
    print(f"\n## band-passed |acc| RMS at the reference steps, m/s^2 (10th / 50th / 90th percentile (share under {NOISE_FLOOR_MS2}))\n")
    print(rms_table(steps))
    print("\n## by adaptive's nearest cadence window (cells: reference hit / missed / adaptive extras inside walking)\n")
    print(window_table(steps, extras))
    print("\n## per-step F1 against chance (the same steps shifted at random)\n")
    print(f1_table(items, base))
    print("\n## adaptive's extras\n")
    print(extras_table(extras))
    if a.plot:
        for p in plots(items, steps, extras, Path(a.plot), a.example, (lo, hi)):
            print(f"wrote {p}", file=sys.stderr)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
