"""Fit the simulator's vigour range per carried position to real walks, and hold each user out.

The carried positions' parameters (:meth:`gaitml.simulate.positions.Placement.random`:
segment gains, impact, levers) were sized by hand on the Oxford users Jamie and Carmelo.
The third user, Dario, walks far more vigorously with the phone in a trouser pocket
(``|acc|`` standard deviation 5.5-6.7 m/s^2 against 2.7-5.0) than anything that population
produces, so a model trained on it reads his pocket walks as running or side steps
(``experiments/reports/model-domain.md``). :attr:`~gaitml.simulate.positions.Placement.vigour`
scales the trunk's acceleration and heel-strike impact at the carrying segment (walk, side
and backward steps; not running, whose flight phase is free fall whatever the vigour); it
is drawn per subject log-uniformly over
:data:`gaitml.simulate.positions.VIGOUR_RANGE`. This script fits that range to real signals
only (never to a classifier's score), per position, as
:mod:`experiments.scripts.hand_gain` fits the hand gain:

- **Real walks** (:func:`real_carried_walks`): every Oxford walk (hard floor, 50 Hz, span
  from the first to the last foot-switch step) in ``FrontPocket`` (-> ``front-pocket``),
  ``BackPocket`` (-> ``back-pocket``) and ``Purse`` (-> ``bag``): three users, two walks
  each. ``SwingingArm`` has one user (nobody to hold out) and the belt no real walking:
  they keep vigour 1.
- **Statistic fitted**: the walking ``|acc|`` standard deviation (``mag_std_ms2`` of
  :func:`~experiments.scripts.realism.position_statistics`).
- **Simulated population** (:func:`vigour_curves`): ``N_SIM`` subjects with their
  placements (seed ``SIM_SEED``), walking 60 s on the straight route at 50 Hz, each at
  every vigour of ``VIGOUR_GRID`` (the vigour is drawn last, so every other field of a
  placement stays the same along the grid).
- **Fit**: :func:`experiments.scripts.hand_gain.fit_range` on this grid: the range whose
  population has its 5 % and 95 % ``mag_std`` quantiles closest to the calmest and the most
  vigorous real walk, rounded to 0.05.
- **Held out** (:func:`leave_one_user_out`): per position and user, the range is fitted on
  the other two users' walks; ``N_CHECK`` new subjects (seed ``CHECK_SEED``) are simulated
  with vigours drawn from it, and the held-out user's walks are checked against their 5-95 %
  range (plus the floors of :data:`~experiments.scripts.hand_gain.CHECK_STATS`) on
  ``mag_std``, ``mag_p5``, ``mag_p95`` and ``r_step`` (step regularity, not fitted). The
  in-sample row fits and checks on all three users.

With ``--models`` (:func:`heldout_models`) the accelerometer-only all-positions model
(``experiments/positions-acc.toml`` without its cross-validation) is trained on the
simulator with every position's range fitted without each user in turn, and that user's
real Oxford walks are scored by it (windows read as walk, flagged out of domain, silently
wrong), next to the model trained without the vigour and the one with the in-sample ranges.

Run from the repository root (about 1.5 min on 2 cores; 3-8 min with ``--models``, by load)::

    python -m experiments.scripts.carry_vigour --data ../shared/data [--models] [--out report.md]
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import sys
import time
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.domain_report import emit_tables
from experiments.scripts.hand_gain import covered, fit_range, train_without_cv
from experiments.scripts.realism import OXFORD_POSITIONS, _markdown, oxford_walks, position_statistics

__all__ = [
    "VIGOUR_POSITIONS",
    "VIGOUR_GRID",
    "N_SIM",
    "SIM_SEED",
    "N_CHECK",
    "CHECK_SEED",
    "vigour_range",
    "vigour_ranges",
    "real_carried_walks",
    "vigour_curves",
    "check_population",
    "leave_one_user_out",
    "heldout_models",
    "score_oxford_models",
    "main",
]

#: Carried positions whose vigour is fitted (those with real walking of more than one user).
VIGOUR_POSITIONS = ("front-pocket", "back-pocket", "bag")
#: Vigours at which every subject of the fitting population is simulated.
VIGOUR_GRID = np.round(np.geomspace(0.6, 2.2, 13), 4)
#: Subjects of the fitting population and their seed; subjects that check a fitted range.
N_SIM, SIM_SEED = 16, 11
N_CHECK, CHECK_SEED = 16, 12
#: Walking time per simulated subject (s).
SIM_DURATION_S = 60.0
#: Candidate range ends (inside the grid, where the interpolated curves are not flat).
END_GRID = np.geomspace(VIGOUR_GRID[0], VIGOUR_GRID[-1], 81)


@contextlib.contextmanager
def vigour_ranges(ranges: dict[str, tuple[float, float]]):
    """Temporarily draw each position's vigour from its ``(lo, hi)`` in ``ranges`` (patches ``VIGOUR_RANGE``)."""
    from gaitml.simulate import positions as pos_mod

    saved = dict(pos_mod.VIGOUR_RANGE)
    pos_mod.VIGOUR_RANGE.update({p: (float(lo), float(hi)) for p, (lo, hi) in ranges.items()})
    try:
        yield
    finally:
        pos_mod.VIGOUR_RANGE.clear()
        pos_mod.VIGOUR_RANGE.update(saved)


def vigour_range(position: str, lo: float, hi: float):
    """Temporarily draw ``position``'s vigour from ``(lo, hi)`` (:func:`vigour_ranges` of one position)."""
    return vigour_ranges({position: (lo, hi)})


@functools.lru_cache(maxsize=2)
def _real_carried_walks(root: str) -> tuple:
    oxford = {v: k for k, v in OXFORD_POSITIONS.items() if k in VIGOUR_POSITIONS}
    rows = []
    for rec in oxford_walks(root):
        pos = oxford.get(rec.meta.get("position"))
        if pos is None:
            continue
        rows.append({"position": pos, "user": rec.meta["user"], "walk": rec.meta.get("id", ""), **position_statistics(rec)})
    return tuple(rows)


def real_carried_walks(shared_data: str | Path) -> pd.DataFrame:
    """One row per real walk in a fitted position: ``position``, ``user``, ``walk`` and the statistics."""
    return pd.DataFrame(list(_real_carried_walks(str(Path(shared_data).resolve()))))


def _simulate(position: str, n: int, seed: int) -> pd.DataFrame:
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(n, SIM_DURATION_S, ("walk",), seed=seed, positions=(position,))
    return pd.DataFrame([position_statistics(r) for r in recs])


def vigour_curves(position: str, *, n: int = N_SIM, seed: int = SIM_SEED, grid=VIGOUR_GRID) -> np.ndarray:
    """``mag_std`` (m/s^2) of ``n`` simulated subjects (rows) at each vigour of ``grid`` (columns)."""
    out = np.empty((n, len(grid)))
    for j, g in enumerate(grid):
        with vigour_range(position, g, g):
            out[:, j] = _simulate(position, n, seed)["mag_std_ms2"].to_numpy()
    return out


def check_population(position: str, lo: float, hi: float, *, n: int = N_CHECK, seed: int = CHECK_SEED) -> pd.DataFrame:
    """Statistics of ``n`` new simulated subjects with vigours drawn log-uniformly from ``(lo, hi)``."""
    with vigour_range(position, lo, hi):
        return _simulate(position, n, seed)


def leave_one_user_out(walks: pd.DataFrame, curves: dict[str, np.ndarray]) -> pd.DataFrame:
    """Per position and held-out user: the range fitted on the other users and the user's walks covered.

    The row with ``held_out = "all (in sample)"`` fits on every user and checks them all; the row
    ``"none (vigour 1)"`` checks every user against the population without the vigour (the
    placement ranges as sized on Jamie and Carmelo).
    """
    rows = []
    for position in VIGOUR_POSITIONS:
        pw = walks[walks["position"] == position]
        for user in ["none", *pw["user"].unique(), None]:
            test = pw if user in (None, "none") else pw[pw["user"] == user]
            if user == "none":
                lo = hi = 1.0
            else:
                tune = pw if user is None else pw[pw["user"] != user]
                lo, hi = fit_range(tune["mag_std_ms2"].to_numpy(), curves[position], grid=VIGOUR_GRID, lo_grid=END_GRID, hi_grid=END_GRID)
            sim = check_population(position, lo, hi)
            cov = covered(test, sim)
            label = {None: "all (in sample)", "none": "none (vigour 1)"}.get(user, user)
            rows.append(
                {
                    "position": position,
                    "held_out": label,
                    "walks": len(test),
                    "real_std_min": float(test["mag_std_ms2"].min()),
                    "real_std_max": float(test["mag_std_ms2"].max()),
                    "vigour_lo": lo,
                    "vigour_hi": hi,
                    "sim_std_5": float(np.percentile(sim["mag_std_ms2"], 5)),
                    "sim_std_95": float(np.percentile(sim["mag_std_ms2"], 95)),
                    **{f"covered_{k}": v for k, v in cov.items()},
                }
            )
    return pd.DataFrame(rows)


#: Oxford positions scored by ``--models`` (the fitted ones first, then the other trained ones).
SCORED_OXFORD = ("FrontPocket", "BackPocket", "Purse", "InHand", "SwingingArm")


def score_oxford_models(shared_data: str | Path, scored: tuple[str, ...], patch) -> pd.DataFrame:
    """The real Oxford walks in the ``scored`` positions read by ``positions-acc`` trained three ways.

    ``experiments/positions-acc.toml`` (without its cross-validation) is trained inside the context
    ``patch(label)`` for ``label`` ``"before"``, ``"all (in sample)"`` and, per user, the user's name
    (fitted without the user); each user's walks are read by the model of the three labels
    (``before``, ``in sample``, ``held out``). Scores as :mod:`experiments.scripts.domain_report`
    (windows read as walk, flagged out of domain, silently wrong, in %). One row per Oxford position
    (in ``scored`` order), user and model, then the users pooled.
    """
    import tempfile

    from experiments.scripts.domain_report import add_scores, score
    from gaitml.io import read_dataset

    recs: dict[tuple[str, str], list] = {}
    for r in read_dataset(Path(shared_data) / "oxford-step-counter" / "optimisation"):
        if r.meta.get("position") in scored:
            recs.setdefault((r.meta["position"], r.meta["user"]), []).append(r)
    users = sorted({u for _, u in recs})

    def train(out: Path, label: str):
        return train_without_cv("positions-acc.toml", out, patch(label))

    rows: list[dict] = []
    with tempfile.TemporaryDirectory() as tmp:
        models = {
            name: train(Path(tmp) / name.replace(" ", "-"), label)
            for name, label in (("before", "before"), ("in sample", "all (in sample)"))
        }
        for user in users:
            print(f"held out {user} ...", file=sys.stderr, flush=True)
            models["held out"] = train(Path(tmp) / f"fold-{user}", user)
            for position in scored:
                for name in ("before", "held out", "in sample"):
                    tot: dict = {}
                    for rec in recs.get((position, user), []):
                        tot = add_scores(tot, score(models[name], rec))
                    if tot:
                        rows.append({"oxford": position, "user": user, "model": name, **tot})
    out = pd.DataFrame(rows)
    num = ["windows", "ood", "walk_all", "silent"]
    pooled = out.groupby(["oxford", "model"], sort=False)[num].sum().reset_index().assign(user="pooled")
    out = pd.concat([out, pooled], ignore_index=True)
    n = out["windows"]
    pct = {"walk %": out["walk_all"], "flagged %": out["ood"], "silently wrong %": out["silent"]}
    out = out.assign(**{k: 100.0 * v / n for k, v in pct.items()})[["oxford", "user", "model", "windows", *pct]]
    order = {p: i for i, p in enumerate(scored)}
    return out.sort_values(["oxford", "user"], key=lambda c: c.map(order) if c.name == "oxford" else c, kind="stable").reset_index(
        drop=True
    )


def heldout_models(shared_data: str | Path, loo: pd.DataFrame) -> pd.DataFrame:
    """Each user's real Oxford walks read by ``positions-acc`` trained without the vigour, held out and in sample.

    ``before``: every vigour 1 (the placement ranges sized on Jamie and Carmelo); ``held out``:
    every fitted position's range fitted without the user (``loo``'s rows); ``in sample``:
    the ranges fitted on every user. Scores as :mod:`experiments.scripts.domain_report`
    (:func:`score_oxford_models`). One row per Oxford position, model and user, then the users pooled.
    """

    def fitted(label: str):
        """The simulator drawing every fitted position's vigour from the ``loo`` rows of ``label``."""
        if label == "before":
            return vigour_ranges(dict.fromkeys(VIGOUR_POSITIONS, (1.0, 1.0)))
        sel = loo[loo["held_out"] == label]
        return vigour_ranges({r["position"]: (r["vigour_lo"], r["vigour_hi"]) for _, r in sel.iterrows()})

    return score_oxford_models(shared_data, SCORED_OXFORD, fitted)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.carry_vigour", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data", help="the shared data folder (default ../shared/data)")
    ap.add_argument("--out", help="also write the markdown tables here")
    ap.add_argument(
        "--models",
        action="store_true",
        help="also train the accelerometer-only all-positions model per held-out user and score the user's real walks (2-7 min more)",
    )
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    walks = real_carried_walks(args.data)
    if walks.empty:
        print(f"carry_vigour: no Oxford walks under {args.data}; pass --data ../shared/data", file=sys.stderr)
        return 2
    curves = {p: vigour_curves(p) for p in VIGOUR_POSITIONS}
    loo = leave_one_user_out(walks, curves)
    per_user = walks.groupby(["position", "user"])[["mag_std_ms2", "mag_p5_ms2", "mag_p95_ms2", "r_step"]].agg(["min", "max"])
    per_user.columns = [f"{a}_{b}" for a, b in per_user.columns]
    per_user.insert(0, "walks", walks.groupby(["position", "user"]).size())
    sections = [
        "### Real carried walks per position and user (range over the user's walks)\n\n" + _markdown(per_user.reset_index()),
        "### Vigour range fitted without each user, and that user's walks covered\n\n" + _markdown(loo),
    ]
    if args.models:
        tab = heldout_models(args.data, loo)
        sections.append("### Real Oxford walks read by the all-positions accelerometer model (positions-acc)\n\n" + _markdown(tab))
    return emit_tables(sections, Path(args.out) if args.out else None, t0)


if __name__ == "__main__":
    sys.exit(main())
