"""Fit the pitch of the simulator's tilted hand-held phone to real hand-held walks, and hold each user out.

How steeply people hold a phone they look at decides where gravity lies in the phone frame,
and the shipped models' domain check compares each window's gravity direction with the
training ones (within about 7 deg). The simulator drew a "tilted" (reading) pose at 30-50 deg of
pitch; the real Oxford ``InHand`` phones are held at about 20-36 deg, so most of their windows
were flagged out of domain although they were read right. This script fits the tilted range
(:data:`gaitml.simulate.subject.HAND_TILTED_PITCH_DEG`) by a rule on a real signal, not on a
classifier's score (the rule's form was chosen after two variants had been scored on the
Oxford walks: ``experiments/reports/model-domain.md`` discloses them):

- **Real walks** (:func:`real_pitch`): the two IFSM flat-held walkers (``ifsm-1``, ``ifsm-2``)
  and every Oxford ``InHand`` walk (users Jamie, Carmelo, Dario; both surfaces), over the walking
  span from the sample of the first step to the sample after the last (the steps of
  :func:`experiments.scripts.hand_gain.real_hand_walks`: IFSM peaks, Oxford foot switches).
- **Statistic**: the phone's holding angle, pitch and roll in the simulator's convention
  (``pitch_rad``, ``roll_rad`` of :class:`~gaitml.simulate.subject.Subject`) of the mean
  acceleration direction of every 2 s chunk, and their median over the walk (per walk, the
  10 % and 90 % quantiles of the pitch too).
- **Rule** (:func:`fit_tilted`; written after two variants had been scored on the Oxford walks, which the report discloses): walks with a
  median pitch above ``FLAT_MAX_DEG`` (12 deg, the top of the flat pose) are tilted; the lower
  end of the tilted range is their smallest median pitch less ``MARGIN_DEG`` (5 deg), floored
  to a whole degree; the upper end is the larger of the prior 50 deg and their largest median
  plus the margin.
- **Held out** (:func:`leave_one_user_out`): the range is fitted without each user in turn and
  that user's walks are checked: is each walk's median pitch inside the flat range (3-12 deg)
  or the fitted tilted range?
- ``--models``: each Oxford user's ``InHand`` walks read by the accelerometer-only demo model
  (``experiments/demo-acc.toml`` without its cross-validation) trained with the range fitted
  without that user, with the range fitted on everybody (in sample) and with the former 30-50
  deg (before): windows read as walk, flagged out of domain, silently wrong.

Roll is reported, not fitted (the simulated roll stays +-5 deg; the real walks' medians reach
-11.2 deg in the simulator's convention: the next lead, left alone).

Run from the repository root (a few seconds; about 15 s with ``--models``)::

    python -m experiments.scripts.hand_pose --data ../shared/data [--models] [--out report.md]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.domain_report import emit_tables
from experiments.scripts.hand_gain import _user_recordings, real_hand_recordings, subject_setting, train_without_cv
from experiments.scripts.realism import _markdown

__all__ = [
    "FLAT_MAX_DEG",
    "MARGIN_DEG",
    "PRIOR_TILTED_DEG",
    "BEFORE_TILTED_DEG",
    "holding_angles",
    "real_pitch",
    "fit_tilted",
    "leave_one_user_out",
    "heldout_models",
    "main",
]

#: The top of the simulator's flat pose (u(0.05, 0.21) rad: 2.9-12.0 deg); walks above it are tilted.
FLAT_MAX_DEG = 12.0
#: The flat pose's range (deg), for the coverage check.
FLAT_DEG = (math.degrees(0.05), math.degrees(0.21))
#: Added below and above the real tilted walks' medians.
MARGIN_DEG = 5.0
#: The prior upper end of the tilted pose (deg): kept when the real walks lie below it.
PRIOR_TILTED_DEG = 50.0
#: The tilted range before this fit (deg).
BEFORE_TILTED_DEG = (math.degrees(0.52), math.degrees(0.87))
#: Length of the chunks whose mean acceleration gives the gravity direction (s).
CHUNK_S = 2.0


def holding_angles(acc: np.ndarray, fs: float, span: tuple[int, int] | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Pitch and roll (deg) of the mean acceleration direction of every ``CHUNK_S`` chunk of ``acc[span]``.

    The simulator's convention: a phone at pitch p and roll r reads gravity along
    (-sin r cos p, sin p, cos r cos p), so pitch = asin(g_y) and roll = atan2(-g_x, g_z); a
    phone lying flat, screen up, reads (0, 0).
    """
    a = np.asarray(acc, dtype=float)
    if span is not None:
        a = a[span[0] : span[1]]
    n = int(round(CHUNK_S * fs))
    k = len(a) // n
    if k == 0:
        raise ValueError(f"a walk shorter than one {CHUNK_S} s chunk has no holding angle")
    g = a[: k * n].reshape(k, n, 3).mean(axis=1)
    g /= np.linalg.norm(g, axis=1, keepdims=True)
    return np.degrees(np.arcsin(np.clip(g[:, 1], -1, 1))), np.degrees(np.arctan2(-g[:, 0], g[:, 2]))


def real_pitch(shared_data: str | Path) -> pd.DataFrame:
    """One row per real hand-held walk: user, walk, surface, median pitch and roll, pitch 10-90 % quantiles."""
    rows = []
    for user, walk, surface, rec, steps_t_s in real_hand_recordings(shared_data):
        fs = rec.sampling_rate_hz
        span = (int(np.floor(steps_t_s[0] * fs)), int(np.ceil(steps_t_s[-1] * fs)) + 1)
        p, r = holding_angles(rec.acc, fs, span)
        rows.append(
            {
                "user": user,
                "walk": walk,
                "surface": surface,
                "pitch_deg": float(np.median(p)),
                "pitch_p10_deg": float(np.percentile(p, 10)),
                "pitch_p90_deg": float(np.percentile(p, 90)),
                "roll_deg": float(np.median(r)),
            }
        )
    return pd.DataFrame(rows)


def fit_tilted(pitch_deg) -> tuple[float, float]:
    """The tilted range (deg) from walks' median pitches (module docstring: the rule)."""
    p = np.asarray(pitch_deg, dtype=float)
    tilted = p[p > FLAT_MAX_DEG]
    if tilted.size == 0:
        raise ValueError("no tilted walk (median pitch above 12 deg) to fit the range on")
    return float(np.floor(tilted.min() - MARGIN_DEG)), float(max(PRIOR_TILTED_DEG, tilted.max() + MARGIN_DEG))


def _covered(p: float, tilted: tuple[float, float]) -> bool:
    return FLAT_DEG[0] <= p <= FLAT_DEG[1] or tilted[0] <= p <= tilted[1]


def leave_one_user_out(walks: pd.DataFrame) -> pd.DataFrame:
    """The range fitted without each user, and that user's walks inside the simulated poses; last row: every user."""
    rows = []
    for user in [*dict.fromkeys(walks["user"]), "all (in sample)"]:
        held = walks if user == "all (in sample)" else walks[walks["user"] == user]
        tune = walks if user == "all (in sample)" else walks[walks["user"] != user]
        lo, hi = fit_tilted(tune["pitch_deg"])
        inside = [_covered(p, (lo, hi)) for p in held["pitch_deg"]]
        before = [_covered(p, BEFORE_TILTED_DEG) for p in held["pitch_deg"]]
        rows.append(
            {
                "held_out": user,
                "tilted_lo_deg": lo,
                "tilted_hi_deg": hi,
                "walks": len(held),
                "pitch_min_deg": float(held["pitch_deg"].min()),
                "pitch_max_deg": float(held["pitch_deg"].max()),
                "walks_covered": f"{sum(inside)}/{len(held)}",
                "covered_by_30_50": f"{sum(before)}/{len(held)}",
            }
        )
    return pd.DataFrame(rows)


def tilted_range(deg: tuple[float, float]):
    """A context in which the simulator draws tilted hand-held pitches from ``deg`` (min, max) instead of its default."""
    return subject_setting("HAND_TILTED_PITCH_DEG", (float(deg[0]), float(deg[1])))


def heldout_models(shared_data: str | Path, loo: pd.DataFrame) -> pd.DataFrame:
    """Each Oxford user's ``InHand`` walks read by demo-acc trained before, held out and in sample (module docstring)."""
    import tempfile

    from experiments.scripts.domain_report import add_scores, score

    recordings = _user_recordings(Path(shared_data))
    all_row = loo[loo["held_out"] == "all (in sample)"].iloc[0]
    fixed = {"before (30-50 deg)": BEFORE_TILTED_DEG, "in sample": (all_row["tilted_lo_deg"], all_row["tilted_hi_deg"])}
    rows: list[dict] = []
    pooled: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as tmp:
        models = {k: train_without_cv("demo-acc.toml", Path(tmp) / f"m{i}", tilted_range(v)) for i, (k, v) in enumerate(fixed.items())}
        fold_models: dict[tuple[float, float], object] = {}
        for _, r in loo[loo["held_out"] != "all (in sample)"].iterrows():
            user = r["held_out"]
            if user.startswith("ifsm-"):
                continue  # flat-held: the tilted range does not reach them
            rng = (r["tilted_lo_deg"], r["tilted_hi_deg"])
            if rng not in fold_models:  # folds that fit the same range share one model
                print(f"held out {user} ...", file=sys.stderr, flush=True)
                fold_models[rng] = train_without_cv("demo-acc.toml", Path(tmp) / f"fold{len(fold_models)}", tilted_range(rng))
            ranges = {**fixed, "held out": rng}
            for name in (*fixed, "held out"):
                model = fold_models[rng] if name == "held out" else models[name]
                tot: dict = {}
                for rec in recordings[user]:
                    tot = add_scores(tot, score(model, rec))
                rows.append({"user": user, "model": name, "tilted range (deg)": "{:.0f}-{:.0f}".format(*ranges[name]), **tot})
                pooled[name] = add_scores(pooled.get(name, {}), tot)
    for name, tot in pooled.items():
        rng = "per fold" if name == "held out" else "{:.0f}-{:.0f}".format(*fixed[name])
        rows.append({"user": "Oxford InHand (pooled)", "model": name, "tilted range (deg)": rng, **tot})
    out = pd.DataFrame(rows)
    n = out["windows"]
    pct = {"walk %": out["walk_all"], "flagged %": out["ood"], "silently wrong %": out["silent"]}
    return out.assign(**{k: 100.0 * v / n for k, v in pct.items()})[["user", "model", "tilted range (deg)", "windows", *pct]]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.hand_pose", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data", help="the shared data folder (default ../shared/data)")
    ap.add_argument("--out", help="also write the markdown tables here")
    ap.add_argument(
        "--models",
        action="store_true",
        help="also train the accelerometer-only demo model per fold and score the held-out user's walks (about 1 min more)",
    )
    args = ap.parse_args(argv)
    if not (Path(args.data) / "oxford-step-counter").is_dir():
        print(f"hand_pose: error: no oxford-step-counter in {args.data}; pass --data with the shared data folder", file=sys.stderr)
        return 2
    t0 = time.perf_counter()
    walks = real_pitch(args.data)
    loo = leave_one_user_out(walks)
    sections = [
        "### Real hand-held walks: the phone's holding angle (median over the walk's 2 s chunks)\n\n" + _markdown(walks),
        "### Tilted pitch range fitted without each user, and that user's walks covered\n\n" + _markdown(loo),
    ]
    if args.models:
        sections.append("### Oxford InHand walks read by the accelerometer-only demo model\n\n" + _markdown(heldout_models(args.data, loo)))
    return emit_tables(sections, Path(args.out) if args.out else None, t0)


if __name__ == "__main__":
    sys.exit(main())
