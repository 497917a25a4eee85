"""Fit the simulator's hand gain range to real hand-held walks, and hold each user out.

A hand-held phone does not feel the whole vertical bounce of the trunk: the
elbow and wrist are compliant and damp it, and how much depends on the person
and the grip. :attr:`gaitml.simulate.subject.Subject.hand_gain` is that
fraction (walking, side and backward steps), drawn per simulated subject
log-uniformly over :data:`gaitml.simulate.subject.HAND_GAIN_RANGE`. This
script fits the range to real signals only (never to a classifier's score):

- **Real walks** (:func:`real_hand_walks`): the two IFSM flat-held walkers
  (``ifsm-flat-phone``, users ``ifsm-1``, ``ifsm-2``; walking span from the
  first to the last step peak of :func:`~experiments.scripts.realism.count_peaks`
  with the realism settings, which find exactly the published 284 and 319
  steps) and every Oxford ``InHand`` walk (users Jamie, Carmelo, Dario; both
  floor surfaces; resampled to 50 Hz; span from the first to the last
  foot-switch step). Five users.
- **Statistic fitted**: the standard deviation of ``|acc|`` over the walking
  span (``mag_std_ms2`` of :func:`~experiments.scripts.realism.position_statistics`):
  the intensity of the walk as the phone feels it.
- **Simulated population** (:func:`gain_curves`): ``N_SIM`` subjects drawn
  by :func:`~gaitml.simulate.subject.sample_subjects` (seed ``SIM_SEED``,
  poses as drawn), walking 60 s on the straight route at 50 Hz, each
  simulated at every gain of ``GAIN_GRID``; ``mag_std`` is interpolated in
  the gain per subject (it grows monotonically with it).
- **Fit** (:func:`fit_range`): the range ``(lo, hi)`` (log grid) whose
  population, each subject at the gain of its quantile ``(i + 0.5) / N`` of
  the log-uniform range, has its 5 % and 95 % quantiles of ``mag_std``
  closest to the smallest and largest ``mag_std`` of the real walks
  (squared error in m/s^2). Rounded to 0.05.
- **Held out** (:func:`leave_one_user_out`): for each of the five users, the
  range is fitted on the other four; then ``N_CHECK`` new subjects (seed
  ``CHECK_SEED``) are simulated with gains drawn from that range, and each
  of the held-out user's walks is checked against the simulated 5-95 % range
  (plus the floor of :func:`~experiments.scripts.realism.position_table`: 0.3
  m/s^2 for magnitudes, 0.05 for correlations) on four statistics: ``mag_std``,
  ``mag_p5``, ``mag_p95`` (intensity) and ``r_step`` (step regularity, not
  fitted). The in-sample row does the same with the range fitted on all five.

Run from the repository root (about 40 s on 2 cores; about 2 min with ``--models``)::

    python -m experiments.scripts.hand_gain --data ../shared/data [--models] [--out report.md]
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import functools
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.domain_report import emit_tables
from experiments.scripts.realism import MIN_PEAK_DISTANCE_S, PEAK_ABOVE_G_MS2, REAL_FILES, _markdown, count_peaks, position_statistics

__all__ = [
    "GAIN_GRID",
    "N_SIM",
    "SIM_SEED",
    "N_CHECK",
    "CHECK_SEED",
    "CHECK_STATS",
    "real_hand_recordings",
    "real_hand_walks",
    "subject_setting",
    "gain_curves",
    "fit_range",
    "check_population",
    "leave_one_user_out",
    "main",
]

#: Gains at which every subject of the fitting population is simulated.
GAIN_GRID = np.round(np.geomspace(0.2, 1.6, 13), 4)
#: Subjects of the fitting population and their seed.
N_SIM, SIM_SEED = 24, 11
#: Subjects simulated to check a fitted range (other seed: not the fitting population).
N_CHECK, CHECK_SEED = 24, 12
#: Walking time per simulated subject (s).
SIM_DURATION_S = 60.0
#: Statistics checked on the held-out user, with the tolerance added to the simulated range.
CHECK_STATS = {"mag_std_ms2": 0.3, "mag_p5_ms2": 0.3, "mag_p95_ms2": 0.3, "r_step": 0.05}
#: Candidate range ends (log grid) and the rounding of the fitted ends.
#: (inside GAIN_GRID: outside it the interpolated curves would be flat)
_LO_GRID = np.geomspace(GAIN_GRID[0], 1.0, 81)
_HI_GRID = np.geomspace(0.5, GAIN_GRID[-1], 61)
ROUND_TO = 0.05


def real_hand_recordings(shared_data: str | Path):
    """Every real hand-held walk as ``(user, walk, surface, recording, step times in s)``.

    The two IFSM flat-held walks (users ``ifsm-1``, ``ifsm-2``; steps: the realism settings'
    peaks) and every Oxford ``InHand`` walk (resampled to 50 Hz; steps: its foot switches).
    """
    from gaitml.io import read_recording
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder

    root = Path(shared_data)
    for i, f in enumerate(REAL_FILES, start=1):
        rec = read_recording(root / f)
        peaks = count_peaks(rec, height_above_g_ms2=PEAK_ABOVE_G_MS2, min_distance_s=MIN_PEAK_DISTANCE_S)
        yield f"ifsm-{i}", Path(f).stem, "Hard", rec, peaks / rec.sampling_rate_hz
    for d in list_oxford_folders(root / "oxford-step-counter"):
        rec = read_oxford_folder(d, sampling_rate_hz=50.0)
        if rec.meta.get("position") != "InHand":
            continue
        yield rec.meta["user"], Path(d).name, rec.meta.get("surface"), rec, np.asarray(rec.reference["steps_t_s"], dtype=float)


@functools.lru_cache(maxsize=2)
def _real_hand_walks(root: str) -> tuple:
    return tuple(
        {"user": user, "walk": walk, "surface": surface, **position_statistics(rec, steps)}
        for user, walk, surface, rec, steps in real_hand_recordings(root)
    )


def real_hand_walks(shared_data: str | Path) -> pd.DataFrame:
    """One row per real hand-held walk: ``user``, ``walk``, ``surface`` and the position statistics."""
    return pd.DataFrame(list(_real_hand_walks(str(Path(shared_data).resolve()))))


def _simulate(subjects) -> list[dict]:
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(len(subjects), SIM_DURATION_S, ("walk",), seed=0, subjects=subjects)
    return [position_statistics(r) for r in recs]


def gain_curves(*, n: int = N_SIM, seed: int = SIM_SEED, grid=GAIN_GRID) -> np.ndarray:
    """``mag_std`` (m/s^2) of ``n`` simulated subjects (rows) walking at each gain of ``grid`` (columns)."""
    from gaitml.simulate.subject import sample_subjects

    base = sample_subjects(n, seed)
    out = np.empty((n, len(grid)))
    for j, g in enumerate(grid):
        stats = _simulate([dataclasses.replace(s, hand_gain=float(g)) for s in base])
        out[:, j] = [s["mag_std_ms2"] for s in stats]
    return out


def _population_std(curves: np.ndarray, lo: float, hi: float, grid=GAIN_GRID, *, log: bool = True) -> np.ndarray:
    q = (np.arange(len(curves)) + 0.5) / len(curves)
    # subject i at quantile q_i; the subjects' order is random, so the quantiles are spread over them
    f = np.log if log else np.asarray
    values = f(lo) + q * (f(hi) - f(lo))
    lg = f(np.asarray(grid, dtype=float))
    return np.array([np.interp(v, lg, c) for v, c in zip(values, curves, strict=True)])


def fit_range(
    real_std: np.ndarray, curves: np.ndarray, *, grid=GAIN_GRID, lo_grid=None, hi_grid=None, log: bool = True
) -> tuple[float, float]:
    """The gain range whose population's 5-95 % ``mag_std`` spans ``real_std`` (module docstring).

    ``curves`` holds each subject's ``mag_std`` at the gains of ``grid``; ``lo_grid`` and
    ``hi_grid`` are the candidate range ends (default: the hand gain's, inside ``GAIN_GRID``).
    ``log=False`` fits a uniform (not log-uniform) range, interpolated linearly in the setting:
    any per-subject statistic and setting work the same way (``experiments.scripts.back_pocket``).
    """
    lo_grid = _LO_GRID if lo_grid is None else np.asarray(lo_grid, dtype=float)
    hi_grid = _HI_GRID if hi_grid is None else np.asarray(hi_grid, dtype=float)
    target = np.array([np.min(real_std), np.max(real_std)])
    best, arg = np.inf, (1.0, 1.0)
    for lo in lo_grid:
        for hi in hi_grid[hi_grid >= lo]:
            q = np.percentile(_population_std(curves, lo, hi, grid, log=log), [5, 95])
            err = float(np.sum((q - target) ** 2))
            if err < best:
                best, arg = err, (lo, hi)
    return tuple(round(float(np.round(v / ROUND_TO) * ROUND_TO), 2) for v in arg)


def check_population(lo: float, hi: float, *, n: int = N_CHECK, seed: int = CHECK_SEED) -> pd.DataFrame:
    """Statistics of ``n`` new simulated walkers with gains drawn log-uniformly from ``(lo, hi)``."""
    from gaitml.simulate.subject import sample_subjects

    rng = np.random.default_rng(seed)
    subs = [dataclasses.replace(s, hand_gain=float(np.exp(rng.uniform(np.log(lo), np.log(hi))))) for s in sample_subjects(n, seed)]
    return pd.DataFrame(_simulate(subs))


def covered(walks: pd.DataFrame, sim: pd.DataFrame, stats: dict[str, float] | None = None) -> dict[str, float]:
    """Per statistic of ``stats`` (default :data:`CHECK_STATS`, with its tolerance): the fraction of
    ``walks`` inside the simulated 5-95 % range widened by the tolerance."""
    out = {}
    for k, tol in (CHECK_STATS if stats is None else stats).items():
        a, b = np.percentile(sim[k], [5, 95])
        out[k] = float(np.mean((walks[k] >= a - tol) & (walks[k] <= b + tol)))
    return out


def leave_one_user_out(walks: pd.DataFrame, curves: np.ndarray) -> pd.DataFrame:
    """Per held-out user: the range fitted on the others and the fraction of the user's walks covered.

    The last row (``user = "all (in sample)"``) is the range fitted on every user, checked on them all.
    """
    rows = []
    for user in [*walks["user"].unique(), None]:
        tune = walks if user is None else walks[walks["user"] != user]
        test = walks if user is None else walks[walks["user"] == user]
        lo, hi = fit_range(tune["mag_std_ms2"].to_numpy(), curves)
        sim = check_population(lo, hi)
        cov = covered(test, sim)
        rows.append(
            {
                "held_out": "all (in sample)" if user is None else user,
                "walks": len(test),
                "real_std_min": float(test["mag_std_ms2"].min()),
                "real_std_max": float(test["mag_std_ms2"].max()),
                "gain_lo": lo,
                "gain_hi": hi,
                "sim_std_5": float(np.percentile(sim["mag_std_ms2"], 5)),
                "sim_std_95": float(np.percentile(sim["mag_std_ms2"], 95)),
                **{f"covered_{k}": v for k, v in cov.items()},
            }
        )
    return pd.DataFrame(rows)


def _user_recordings(shared_data: Path) -> dict[str, list]:
    """Every real hand-held user's recordings, as the domain report scores them (whole walks, read once)."""
    from gaitml.io import read_dataset, read_recording

    out = {f"ifsm-{i}": [read_recording(shared_data / f)] for i, f in enumerate(REAL_FILES, start=1)}
    for r in read_dataset(shared_data / "oxford-step-counter" / "optimisation"):
        if r.meta.get("position") == "InHand":
            out.setdefault(r.meta["user"], []).append(r)
    return out


def _clear_caches(runner) -> None:
    """Forget the runner's in-memory recordings and window tables (keyed by the config, not the simulator)."""
    runner._DATA_CACHE.clear()
    runner._DS_CACHE.clear()


def train_without_cv(config: str, out: Path, patch):
    """``experiments/<config>`` (without its cross-validation) trained inside the context ``patch``
    (a simulator setting patched for the fold), the runner's caches cleared around it."""
    from gaitml.models import load_model
    from gaitml.pipeline import runner
    from gaitml.pipeline.config import load_config

    root = Path(__file__).resolve().parents[2]
    cfg = load_config(root / "experiments" / config)
    cfg = cfg.with_values({"train.cross_validate": False, "name": f"{cfg.name}-fold"})
    with patch:
        _clear_caches(runner)  # the simulated data depend on the patched setting: never reuse another fold's
        try:
            runner.train_config(cfg, out_dir=out, progress=False)
        finally:
            _clear_caches(runner)
    return load_model(out)


@contextlib.contextmanager
def subject_setting(name: str, value):
    """Temporarily set the module constant ``name`` of :mod:`gaitml.simulate.subject` (a simulator range a fold patches)."""
    import gaitml.simulate.subject as subject_mod

    saved = getattr(subject_mod, name)
    setattr(subject_mod, name, value)
    try:
        yield
    finally:
        setattr(subject_mod, name, saved)


def _hand_gain_range(gain_range: tuple[float, float]):
    return subject_setting("HAND_GAIN_RANGE", tuple(gain_range))


def _train_acc_model(out: Path, gain_range: tuple[float, float]):
    """``experiments/demo-acc.toml`` (without CV) on a simulator whose hand gain range is ``gain_range``."""
    return train_without_cv("demo-acc.toml", out, _hand_gain_range(gain_range))


def heldout_models(shared_data: str | Path, loo: pd.DataFrame) -> pd.DataFrame:
    """Each held-out user's walks read by the accelerometer-only demo model trained three ways.

    ``before``: the simulator without the hand gain (every gain 1, the population of the shipped
    models before it); ``held out``: the range fitted without the user (``loo``'s row); ``in
    sample``: the range fitted on every user. Scores as in
    :mod:`experiments.scripts.domain_report`: windows read as walk, flagged out of domain, and
    silently wrong (neither walk nor flagged), over the user's whole walks.
    """
    import tempfile

    from experiments.scripts.domain_report import add_scores, score

    recordings = _user_recordings(Path(shared_data))
    all_row = loo[loo["held_out"] == "all (in sample)"].iloc[0]
    rows: list[dict] = []
    pooled: dict[str, dict] = {}
    with tempfile.TemporaryDirectory() as tmp:
        fixed = {"before": (1.0, 1.0), "in sample": (all_row["gain_lo"], all_row["gain_hi"])}
        models = {k: _train_acc_model(Path(tmp) / k.replace(" ", "-"), v) for k, v in fixed.items()}
        for _, r in loo[loo["held_out"] != "all (in sample)"].iterrows():
            user = r["held_out"]
            print(f"held out {user} ...", file=sys.stderr, flush=True)
            models["held out"] = _train_acc_model(Path(tmp) / f"fold-{user}", (r["gain_lo"], r["gain_hi"]))
            ranges = {**fixed, "held out": (r["gain_lo"], r["gain_hi"])}
            for name in ("before", "held out", "in sample"):
                tot: dict = {}
                for rec in recordings[user]:
                    tot = add_scores(tot, score(models[name], rec))
                rows.append({"user": user, "model": name, "gain range": "{:.2f}-{:.2f}".format(*ranges[name]), **tot})
                if not user.startswith("ifsm-"):
                    pooled[name] = add_scores(pooled.get(name, {}), tot)
    for name, tot in pooled.items():
        rows.append(
            {
                "user": "Oxford InHand (pooled)",
                "model": name,
                "gain range": "per fold" if name == "held out" else "{:.2f}-{:.2f}".format(*fixed[name]),
                **tot,
            }
        )
    out = pd.DataFrame(rows)
    n = out["windows"]
    pct = {"walk %": out["walk_all"], "flagged %": out["ood"], "silently wrong %": out["silent"]}
    return out.assign(**{k: 100.0 * v / n for k, v in pct.items()})[["user", "model", "gain range", "windows", *pct]]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.hand_gain", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data", help="the shared data folder (default ../shared/data)")
    ap.add_argument("--out", help="also write the markdown tables here")
    ap.add_argument(
        "--models",
        action="store_true",
        help="also train the accelerometer-only demo model per fold and score the held-out user's walks (about 2 min more)",
    )
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    walks = real_hand_walks(args.data)
    curves = gain_curves()
    loo = leave_one_user_out(walks, curves)
    per_user = walks.groupby("user")[["mag_std_ms2", "mag_p5_ms2", "mag_p95_ms2", "r_step", "cadence_hz"]].agg(["min", "max"])
    per_user.columns = [f"{a}_{b}" for a, b in per_user.columns]
    per_user.insert(0, "walks", walks.groupby("user").size())
    sections = [
        "### Real hand-held walks per user (range over the user's walks)\n\n" + _markdown(per_user.reset_index()),
        "### Hand gain range fitted without each user, and that user's walks covered\n\n" + _markdown(loo),
    ]
    if args.models:
        tab = heldout_models(args.data, loo)
        sections.append("### Held-out user's walks read by the accelerometer-only demo model\n\n" + _markdown(tab))
    return emit_tables(sections, Path(args.out) if args.out else None, t0)


if __name__ == "__main__":
    sys.exit(main())
