"""Step counts on the tyrex recordings taken down to lower sampling rates, against the motion-capture count.

``python -m experiments.scripts.tyrex_steps_rates --data ../shared/data [--rates native,50,20,15,10]
[--detectors adaptive,single-peak|all] [--csv FILE] [--from-csv FILE] [--floors]`` from the repository root.

Each recording is taken down to each rate with :func:`gaitml.models.resample_recording` (a low-pass at 0.45 x the
new rate, then linear interpolation: what a phone logging at that rate delivers, up to its own filter), and each
detector counts its steps at its defaults over the motion-capture span; the reference is the motion-capture count
of :mod:`experiments.scripts.tyrex_steps`. Nothing is fitted. The table is the mean count accuracy
(1 - |n - n_ref| / n_ref) per motion, as in ``experiments/reports/tyrex-steps.md``.

``--floors`` also chooses each detector's lowest rate (its floor, :data:`gaitml.steps.MIN_RATE_HZ`) by a rule fixed
before the figures were read (:func:`choose_floor`: the lowest rate of the grid at which, and at every grid rate above
which, every scored motion's mean count accuracy is within :data:`FLOOR_DROP` of its native figure), on all three
people (in sample) and leave-one-person-out (chosen on two people, the third's drop at that floor; :func:`lopo_floors`).
``--from-csv`` reads the per-recording counts of an earlier ``--csv`` run instead of counting again.
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import pandas as pd


def count_table(data: str, rates: list[float | None], detectors: list[str]) -> pd.DataFrame:
    """One row per tyrex recording: motion, person, the motion-capture count and each detector's count at each rate."""
    from experiments.scripts.tyrex_steps import in_reference_span, truth_clock_s, tyrex_walks
    from gaitml.models import resample_recording
    from gaitml.steps import get_detector

    rows = []
    for walk in tyrex_walks(data):
        ref = walk["ref"]
        row = {"recording": walk["name"], "motion": walk["motion"], "person": walk["person"], "mocap_steps": ref["n_steps"]}
        for fs in rates:
            for d in detectors:
                n = 0
                for r in walk["recs"]:
                    rr = r if fs is None else resample_recording(r, fs)
                    st = get_detector(d).detect(rr).steps_
                    n += int(np.sum(in_reference_span(truth_clock_s(st, rr), ref)))
                row[f"{d} @ {'native' if fs is None else f'{fs:g} Hz'}"] = n
        rows.append(row)
        print(f"[tyrex_steps_rates] {walk['name']}", file=sys.stderr)
    return pd.DataFrame(rows)


#: the rate the Oxford walks are read at (their phones log irregularly at 100-405 Hz; gaitml's reader resamples)
OXFORD_NATIVE_HZ = 100.0


def oxford_count_table(data: str, rates: list[float | None], detectors: list[str]) -> pd.DataFrame:
    """One row per Oxford walk on the hard floor (the carpet walks' foot switches under-trigger, their README):
    ``motion`` is the carrying position, ``person`` the user, ``mocap_steps`` the foot-switch count of the whole
    walk (read at :data:`OXFORD_NATIVE_HZ`, accelerometer only), then each detector's count at each rate."""
    from pathlib import Path

    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder
    from gaitml.models import resample_recording
    from gaitml.steps import get_detector

    rows = []
    for folder in list_oxford_folders(Path(data) / "oxford-step-counter"):
        rec = read_oxford_folder(folder, sampling_rate_hz=OXFORD_NATIVE_HZ)
        if rec.meta.get("surface") != "Hard":
            continue
        row = {
            "recording": folder.name,
            "motion": rec.meta["position"],
            "person": rec.meta["user"],
            "mocap_steps": rec.reference["n_steps_true"],
        }
        for fs in rates:
            rr = rec if fs is None else resample_recording(rec, fs)
            for d in detectors:
                row[f"{d} @ {'native' if fs is None else f'{fs:g} Hz'}"] = len(get_detector(d).detect(rr).steps_)
        rows.append(row)
        print(f"[tyrex_steps_rates] oxford {folder.name}", file=sys.stderr)
    return pd.DataFrame(rows)


def accuracy(df: pd.DataFrame) -> pd.DataFrame:
    """Mean count accuracy per motion of every count column (``detector @ rate``)."""
    cols = [c for c in df.columns if " @ " in c]
    out = {}
    for motion, g in df.groupby("motion"):
        ref = g["mocap_steps"].clip(lower=1)
        out[motion] = {c: float((1 - (g[c] - g["mocap_steps"]).abs() / ref).mean()) for c in cols}
    return pd.DataFrame(out).T


#: the scored motions (AR has no reliable motion-capture reference; experiments.scripts.tyrex_steps_lopo)
SCORED = ("Texting", "Phoning", "FrontPocket", "BackPocket", "Swinging", "RunningHand", "RunningPocket")
#: the floor rule's largest loss of mean count accuracy against the native rate, in any scored motion
FLOOR_DROP = 0.05
#: the floor when even the highest grid rate loses more than FLOOR_DROP: the lowest native rate of the tyrex phones
#: (iPhone 4S / 5, about 100 Hz; the Nexus 5 records at 199 Hz)
NATIVE_FLOOR_HZ = 100.0


def per_motion(df: pd.DataFrame, people=None, motions=SCORED) -> pd.DataFrame:
    """:func:`accuracy` of the scored ``motions``, over the recordings of ``people`` (all when None)."""
    sub = df if people is None else df[df["person"].isin(list(people))]
    return accuracy(sub[sub["motion"].isin(list(motions))])


def worst_drop(acc: pd.DataFrame, detector: str, rate: float) -> float:
    """The largest loss of mean count accuracy from the native rate to ``rate`` over the scored motions (a rise counts 0)."""
    return float((acc[f"{detector} @ native"] - acc[f"{detector} @ {rate:g} Hz"]).clip(lower=0).max())


def choose_floor(acc: pd.DataFrame, detector: str, rates: list[float], drop: float = FLOOR_DROP) -> float:
    """The floor rule (fixed before reading the figures): the lowest of ``rates`` at which, and at every one of
    ``rates`` above which, every scored motion's accuracy is within ``drop`` of native; :data:`NATIVE_FLOOR_HZ` when
    the highest already loses more."""
    floor = NATIVE_FLOOR_HZ
    for r in sorted(rates, reverse=True):
        if worst_drop(acc, detector, r) > drop:
            break
        floor = r
    return floor


def lopo_floors(df: pd.DataFrame, detectors: list[str], rates: list[float], motions=SCORED) -> pd.DataFrame:
    """Per detector and left-out person: the floor chosen on the other two, the left-out person's worst drop at it and
    their own floor; a row ``all`` is the in-sample choice."""
    people = sorted(df["person"].unique())
    rows = []
    for d in detectors:
        for p in [*people, "all"]:
            train = [q for q in people if q != p] if p != "all" else people
            floor = choose_floor(per_motion(df, train, motions), d, rates)
            held = per_motion(df, [p] if p != "all" else people, motions)
            rows.append(
                {
                    "detector": d,
                    "left out": p,
                    "floor chosen (Hz)": floor,
                    "drop at floor (held out)": worst_drop(held, d, floor) if floor in rates else 0.0,
                    "own floor (Hz)": choose_floor(held, d, rates),
                }
            )
    return pd.DataFrame(rows)


def floor_tables(df: pd.DataFrame, detectors: list[str], rates: list[float], motions=SCORED) -> str:
    """Markdown: the worst drop per detector and rate (in sample) with the floor, and the leave-one-person-out floors."""
    acc = per_motion(df, None, motions)
    out = ["| detector | worst native accuracy | " + " | ".join(f"worst drop @ {r:g} Hz" for r in rates) + " | floor (Hz) |"]
    out.append("|---|---|" + "---|" * (len(rates) + 1))
    for d in detectors:
        cells = [f"{acc[f'{d} @ native'].min():.3f}"] + [f"{worst_drop(acc, d, r):.3f}" for r in rates]
        out.append(f"| {d} | " + " | ".join(cells) + f" | {choose_floor(acc, d, rates):g} |")
    lo = lopo_floors(df, detectors, rates, motions)
    out += ["", "| detector | " + " | ".join(f"{p}: floor (drop held out, own floor)" for p in lo["left out"].unique()) + " |"]
    out.append("|---|" + "---|" * lo["left out"].nunique())
    for d, g in lo.groupby("detector", sort=False):
        cells = [f"{r['floor chosen (Hz)']:g} ({r['drop at floor (held out)']:.3f}, {r['own floor (Hz)']:g})" for _, r in g.iterrows()]
        out.append(f"| {d} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--rates", default="native,50,20,15,10", help="comma-separated: 'native' and/or rates in Hz")
    ap.add_argument("--detectors", default="adaptive,single-peak")
    ap.add_argument("--csv", default=None, help="per-recording counts")
    ap.add_argument("--from-csv", default=None, help="read the per-recording counts of an earlier --csv run")
    ap.add_argument("--oxford", action="store_true", help="the Oxford walks on the hard floor (positions for motions) instead of tyrex")
    ap.add_argument("--floors", action="store_true", help="choose each detector's floor, in sample and leave-one-person-out")
    a = ap.parse_args(argv)
    rates = [None if r == "native" else float(r) for r in a.rates.split(",") if r]
    if a.detectors == "all":
        from gaitml.steps import detector_names

        detectors = list(detector_names())
    else:
        detectors = [d for d in a.detectors.split(",") if d]
    if a.from_csv:
        df = pd.read_csv(a.from_csv)
    else:
        df = (oxford_count_table if a.oxford else count_table)(a.data, rates, detectors)
    if a.floors:
        if None not in rates:
            ap.error("--floors needs 'native' in --rates (each floor is judged against the native figure)")
        motions = sorted(df["motion"].unique()) if a.oxford else SCORED
        print(floor_tables(df, detectors, [r for r in rates if r is not None], motions))
        print()
    if a.csv:
        df.to_csv(a.csv, index=False)
    acc = accuracy(df)
    cols = list(acc.columns)
    print("| motion | " + " | ".join(cols) + " |")
    print("|---|" + "---|" * len(cols))
    for motion, r in acc.iterrows():
        print(f"| {motion} | " + " | ".join(f"{r[c]:.3f}" for c in cols) + " |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
