"""Where adaptive's periodicity-floor relief can act: the diagnosis behind round 3 of ``tyrex_steps_floor`` (issue 30).

Nothing is fitted. Three parts (experiments/reports/tyrex-steps.md, perio section):

- *Stage-4 counts* (``--part counts``): per lower floor (0.2, 0.15), the peaks only the periodicity floor removes with
  a periodicity at or above the lower floor, and those the relief keeps (``steps_.attrs["rhythm"]`` of
  :class:`gaitml.steps.adaptive.AdaptiveStepDetector` with ``rhythm_min_periodicity``), on the simulated non-gait
  selection seeds 0-39 (gestures, desk) and on every tyrex motion.
- *Weak windows* (``--part windows``): adaptive's cadence windows (at its defaults) whose periodicity lies in
  [:data:`LOWER`, ``MIN_PERIODICITY``), by the first test of the relief each fails: the swing's RMS under
  ``GYRO_MIN_RMS_RADS``, its stride correlation under ``MIN_PERIODICITY``, no anti-phase at half its stride, or the
  swing's step (half the stride) against the window's step period (match within ``RHYTHM_STEP_TOLERANCE``; about
  twice it: a half-step window; about half; another ratio). Tyrex Texting and Phoning per person, and the selection seeds.
- *Added non-gait steps* (``--part added``): the selection-seed recordings whose steps change with the relief at 0.2,
  with the new steps' times, their distance to the nearest step of the default and their periodicity.

    python -m experiments.scripts.tyrex_steps_perio --data ../shared/data --cache /tmp/perio   # all three, ~2 min
"""

from __future__ import annotations

import argparse
import sys
from collections import defaultdict
from pathlib import Path

import numpy as np

from experiments.scripts.tyrex_steps_joint import SELECTION_SEEDS, nongait_recordings
from experiments.scripts.tyrex_steps_lopo import _load

#: the lower floors of round 3's grid (report, perio section)
FLOORS = (0.2, 0.15)
#: the weak windows read by ``--part windows``: periodicity in [LOWER, MIN_PERIODICITY) (round 3's lowest floor)
LOWER = 0.15
#: the classes of a weak window, in the order the relief tests them
WINDOW_CLASSES = ("rms<0.2", "corr<0.3", "half>0", "match", "swing step ~2T", "swing step ~T/2", "other ratio")


def window_class(rms: float, corr: float, half: float, swing_step: float, period: float) -> str:
    """The first test of the relief a weak window fails (or ``match``), from its swing's RMS (rad/s), stride correlation,
    correlation at half the stride, the swing's step and the window's step period (same units)."""
    from gaitml.steps import adaptive as ad

    if rms < ad.GYRO_MIN_RMS_RADS:
        return "rms<0.2"
    if not np.isfinite(swing_step) or not corr >= ad.MIN_PERIODICITY:
        return "corr<0.3"
    if not half <= -ad.GYRO_SWING_HALF_CORRELATION:
        return "half>0"
    r = swing_step / period
    if abs(r - 1.0) <= ad.RHYTHM_STEP_TOLERANCE:
        return "match"
    if abs(r - 2.0) <= 2.0 * ad.RHYTHM_STEP_TOLERANCE:
        return "swing step ~2T"
    if abs(r - 0.5) <= 0.5 * ad.RHYTHM_STEP_TOLERANCE:
        return "swing step ~T/2"
    return "other ratio"


def weak_windows(rec) -> dict[str, int]:
    """Counts of :data:`WINDOW_CLASSES` over the recording's weak cadence windows (adaptive at its defaults)."""
    from gaitml.signal import bandpass
    from gaitml.steps import adaptive as ad
    from gaitml.steps import get_detector

    cad = get_detector("adaptive").detect(rec).cadence_
    fs = rec.sampling_rate_hz
    q = ad.cadence_decimation(fs)
    g = np.asarray(rec.gyr, dtype=float)
    g = bandpass(g - g.mean(axis=0), ad.GYRO_BAND_HZ[0], min(ad.GYRO_BAND_HZ[1], 0.45 * fs), fs, order=2)[::q]
    L = min(len(g), int(round(ad.WINDOW_S * fs / q)))
    H = max(1, int(round(ad.HOP_S * fs / q)))
    nw = len(cad)
    proj, rms = ad.swing_projection(g, L, H, (len(g) - L) // H + 1)
    proj, rms = proj[:nw], rms[:nw]
    per = cad["periodicity"].to_numpy()
    T = cad["period_s"].to_numpy() * fs / q
    P, corr, half = ad.swing_stride(proj, fs / q)
    out: dict[str, int] = defaultdict(int)
    for i in np.flatnonzero((per < ad.MIN_PERIODICITY) & (per >= LOWER)):
        out[window_class(rms[i], corr[i], half[i], P[i] / 2.0, T[i])] += 1
    return out


def counts(items: list[dict], ng: dict) -> list[str]:
    from gaitml.steps import get_detector

    lines = ["| lower floor | set | candidates | kept by the relief | recordings with any kept |", "|---|---|---|---|---|"]
    for lower in FLOORS:
        tot: dict[str, list[int]] = defaultdict(lambda: [0, 0, 0])
        for (kind, _), rec in ng.items():
            a = get_detector("adaptive", rhythm_min_periodicity=lower).detect(rec).steps_.attrs["rhythm"]
            c = tot[f"{kind}, seeds 0-39"]
            c[0], c[1], c[2] = c[0] + a["candidates"], c[1] + a["peaks"], c[2] + int(a["peaks"] > 0)
        for it in items:
            for r in it["recs"]:
                a = get_detector("adaptive", rhythm_min_periodicity=lower).detect(r).steps_.attrs["rhythm"]
                c = tot[it["motion"]]
                c[0], c[1], c[2] = c[0] + a["candidates"], c[1] + a["peaks"], c[2] + int(a["peaks"] > 0)
        lines += [f"| {lower} | {k} | {v[0]} | {v[1]} | {v[2]} |" for k, v in tot.items()]
    return lines


def windows(items: list[dict], ng: dict) -> list[str]:
    tot: dict[str, dict[str, int]] = defaultdict(lambda: defaultdict(int))
    for it in items:
        if it["motion"] not in ("Texting", "Phoning"):
            continue
        for r in it["recs"]:
            for k, v in weak_windows(r).items():
                tot[f"{it['motion']} {it['person']}"][k] += v
    for (kind, _), rec in ng.items():
        for k, v in weak_windows(rec).items():
            tot[f"{kind}, seeds 0-39"][k] += v
    lines = ["| set | weak windows | " + " | ".join(WINDOW_CLASSES) + " |", "|" + "---|" * (len(WINDOW_CLASSES) + 2)]
    for k, v in tot.items():
        lines.append(f"| {k} | {sum(v.values())} | " + " | ".join(str(v.get(c, 0)) for c in WINDOW_CLASSES) + " |")
    return lines


def added(ng: dict, lower: float = FLOORS[0]) -> list[str]:
    from gaitml.steps import get_detector

    lines = []
    for (kind, s), rec in ng.items():
        a = get_detector("adaptive").detect(rec).steps_
        b = get_detector("adaptive", rhythm_min_periodicity=lower).detect(rec).steps_
        ta, tb = a["t_peak_s"].to_numpy(), b["t_peak_s"].to_numpy()
        if np.array_equal(ta, tb):
            continue
        new = ~np.isin(tb, ta)
        gap = [float(np.min(np.abs(ta - x))) if len(ta) else float("inf") for x in tb[new]]
        lines.append(
            f"- {kind} seed {s}: {len(ta)} -> {len(tb)} steps; new at {np.round(tb[new], 2).tolist()} s, nearest default "
            f"step {np.round(gap, 1).tolist()} s, periodicity {np.round(b['correlation'].to_numpy()[new], 2).tolist()}"
        )
    return lines


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_perio", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--cache", default=None, help="folder for the simulated non-gait recordings (pickles)")
    ap.add_argument("--part", choices=("counts", "windows", "added", "all"), default="all")
    a = ap.parse_args(argv)
    if a.part in ("counts", "windows", "all") and not (Path(a.data) / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    ng = nongait_recordings(SELECTION_SEEDS, Path(a.cache) if a.cache else None)
    items = _load(a.data) if a.part != "added" else []
    if a.part in ("counts", "all"):
        print("## Stage-4 peaks only the periodicity floor removes, at or above the lower floor\n")
        print("\n".join(counts(items, ng)) + "\n")
    if a.part in ("windows", "all"):
        print(f"## Weak cadence windows (periodicity in [{LOWER}, 0.3)) by the relief's first failing test\n")
        print("\n".join(windows(items, ng)) + "\n")
    if a.part in ("added", "all"):
        print(f"## Selection-seed recordings whose steps change with the relief at {FLOORS[0]}\n")
        print("\n".join(added(ng)) or "(none)")
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
