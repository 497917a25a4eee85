"""Fit the back pocket's pelvis share and in-pocket roll to the real back-pocket walks, each user held out.

The simulated back pocket (:mod:`gaitml.simulate.positions`) turned with the thigh (60 % of its
sagittal rotation): its acceleration carried much of its power at the stride frequency (the
gravity direction swinging once per stride). The real Oxford back-pocket phones follow the
pelvis more: their acceleration's power sits at the step frequency (section "Back pocket:
pelvis and roll" of ``experiments/reports/simulator-positions.md``). Two fields of
:class:`~gaitml.simulate.positions.Placement` model it, drawn per subject uniformly over
:data:`gaitml.simulate.positions.BACK_POCKET_RANGE`:

- ``pelvis_share``: the buttock's rotation is ``(1 - share)`` times the thigh's plus ``share``
  times the pelvis's (belt-like: transverse rotation and obliquity once per stride, anterior
  tilt once per step);
- ``pocket_roll_deg``: an extra in-plane turn of the phone in the pocket, added to
  ``tilt_z_deg`` (+-15 deg).

This script fits both ranges to real signals only (never to a classifier's score), in the way of
:mod:`experiments.scripts.carry_vigour`:

- **Real walks**: every Oxford ``BackPocket`` walk (hard floor, 50 Hz, first to last foot-switch
  step; three users, two walks each); the ``FrontPocket`` walks are measured beside them to show
  that what separates the simulated back pocket from the real one is specific to it.
- **Statistics fitted** (:func:`back_pocket_statistics`): ``step_stride_db``, the acceleration's
  power at the step frequency over its power at the stride frequency (dB; Welch, 8 s segments,
  power summed over the three axes, so it does not depend on how the phone sits; bands of
  +-0.15 cadence around the cadence and half of it) for ``pelvis_share``; and ``screen_roll_deg``,
  the angle of the walk's mean gravity in the phone's screen plane from its long axis
  (``atan2(|g_x|, |g_y|)``), for ``pocket_roll_deg``.
- **Simulated population**: ``N_SIM`` subjects (seed ``SIM_SEED``) walking 60 s on the straight
  route, each simulated at every share of ``SHARE_GRID`` (:func:`share_curves`) and then, with the
  share drawn from its fitted range, at every roll of ``ROLL_GRID`` (:func:`roll_curves`; the
  pelvis share, the roll and the pelvis's amplitudes are drawn last, so every other field of a
  placement stays the same along a grid).
- **Fit** (:func:`fit_back_pocket`): :func:`experiments.scripts.hand_gain.fit_range` on a linear
  scale: the share range whose population's 5 % and 95 % ``step_stride_db`` are closest to the
  smallest and largest real value; the roll range ``(-r, r)`` whose population's 5-95 %
  ``screen_roll_deg`` is closest to the real span. Rounded to 0.05 (share) and 1 deg (roll).
- **Held out** (:func:`leave_one_user_out`): per user, both ranges fitted on the other two users'
  walks; ``N_CHECK`` new subjects (seed ``CHECK_SEED``) drawn from them; the user's walks checked
  against their 5-95 % range plus a tolerance (:data:`CHECK_STATS`) on the fitted statistics and
  on unfitted ones (``|acc|`` std, the largest and smallest variance share). The in-sample row
  fits and checks on all three users; the row ``before`` checks every user against the
  simulator without either field (share 0, no extra roll).

The in-sample fit is recorded as :data:`gaitml.simulate.positions.BACK_POCKET_FIT` (share 1, roll
+-13 deg) and is **not shipped**: it matches the two statistics it was fitted on but lowers the
back pocket's realism verdict on the others (partial -> no match: steps too alike, bounce too
dominant), so the shipped :data:`~gaitml.simulate.positions.BACK_POCKET_RANGE` stays the
thigh-driven model (share 0, no extra roll). :func:`back_pocket_ranges` patches the fit in.

With ``--models`` (:func:`heldout_models`) the accelerometer-only all-positions model
(``experiments/positions-acc.toml`` without its cross-validation) is trained without the two
fields, with each user's fold ranges and with the in-sample ranges, and the real Oxford walks are
scored by it (windows read as walk / silently wrong). These scores are looked at after the fit;
they do not choose it.

Run from the repository root (about 1 min on 2 cores; 6-12 min more with ``--models``, by load)::

    python -m experiments.scripts.back_pocket --data ../shared/data [--models] [--out report.md]
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
import scipy.signal

from experiments.scripts.domain_report import emit_tables
from experiments.scripts.hand_gain import _covered, fit_range, train_without_cv
from experiments.scripts.realism import _markdown, oxford_walks, position_statistics

__all__ = [
    "SHARE_GRID",
    "ROLL_GRID",
    "N_SIM",
    "SIM_SEED",
    "N_CHECK",
    "CHECK_SEED",
    "CHECK_STATS",
    "back_pocket_statistics",
    "back_pocket_ranges",
    "real_pocket_walks",
    "share_curves",
    "roll_curves",
    "fit_back_pocket",
    "check_population",
    "leave_one_user_out",
    "heldout_models",
    "main",
]

POSITION = "back-pocket"
#: Pelvis shares and extra roll half-widths (deg) at which every subject of the fitting population is simulated.
SHARE_GRID = np.round(np.linspace(0.0, 1.0, 11), 4)
ROLL_GRID = np.arange(0.0, 31.0, 5.0)
#: Candidate range ends (share: 0-1 by 0.05; roll: 0-30 deg by 1).
_SHARE_ENDS = np.round(np.linspace(0.0, 1.0, 21), 4)
_ROLL_ENDS = np.arange(0.0, 31.0, 1.0)
#: Subjects of the fitting population and their seed; subjects that check a fitted range.
N_SIM, SIM_SEED = 16, 11
N_CHECK, CHECK_SEED = 16, 12
#: Walking time per simulated subject (s).
SIM_DURATION_S = 60.0
#: Statistics checked on a held-out user, with the tolerance added to the simulated 5-95 % range.
CHECK_STATS = {"step_stride_db": 1.0, "screen_roll_deg": 2.0, "mag_std_ms2": 0.3, "var_share_1": 0.03, "var_share_3": 0.03}
#: Half-width of the step and stride bands, as a fraction of the cadence.
_BAND = 0.15


def back_pocket_statistics(recording) -> dict[str, float]:
    """:func:`~experiments.scripts.realism.position_statistics` plus ``step_stride_db`` and ``screen_roll_deg``
    (module docstring), from the first to the last true step."""
    out = position_statistics(recording)
    st = np.asarray(recording.reference["steps_t_s"], dtype=float)
    fs = recording.sampling_rate_hz
    acc = recording.acc[int(np.ceil(st[0] * fs)) : int(np.floor(st[-1] * fs))]
    cad = out["cadence_hz"]
    f, p = scipy.signal.welch(acc - acc.mean(axis=0), fs=fs, nperseg=min(len(acc), int(8 * fs)), axis=0)
    total = p.sum(axis=1)  # the sum over the axes: the same however the phone sits

    def band(fc: float) -> float:
        return float(total[np.abs(f - fc) <= _BAND * cad].sum())

    g = acc.mean(axis=0)
    out["step_stride_db"] = 10.0 * np.log10(band(cad) / band(cad / 2.0))
    out["screen_roll_deg"] = float(np.degrees(np.arctan2(abs(g[0]), abs(g[1]))))
    return out


@contextlib.contextmanager
def back_pocket_ranges(share: tuple[float, float] | None = None, roll: tuple[float, float] | None = None):
    """Temporarily draw the back pocket's ``pelvis_share`` / ``pocket_roll_deg`` from these ranges (patches
    :data:`~gaitml.simulate.positions.BACK_POCKET_RANGE`; None keeps the shipped range)."""
    from gaitml.simulate import positions as pos_mod

    saved = dict(pos_mod.BACK_POCKET_RANGE)
    if share is not None:
        pos_mod.BACK_POCKET_RANGE["pelvis_share"] = (float(share[0]), float(share[1]))
    if roll is not None:
        pos_mod.BACK_POCKET_RANGE["pocket_roll_deg"] = (float(roll[0]), float(roll[1]))
    try:
        yield
    finally:
        pos_mod.BACK_POCKET_RANGE.clear()
        pos_mod.BACK_POCKET_RANGE.update(saved)


@functools.lru_cache(maxsize=2)
def _real_pocket_walks(root: str) -> tuple:
    names = {"BackPocket": "back-pocket", "FrontPocket": "front-pocket"}
    rows = []
    for rec in oxford_walks(root):
        pos = names.get(rec.meta.get("position"))
        if pos is not None:
            rows.append({"position": pos, "user": rec.meta["user"], "walk": rec.meta.get("id", ""), **back_pocket_statistics(rec)})
    return tuple(rows)


def real_pocket_walks(shared_data: str | Path) -> pd.DataFrame:
    """One row per real Oxford back- and front-pocket walk: ``position``, ``user``, ``walk`` and the statistics."""
    return pd.DataFrame(list(_real_pocket_walks(str(Path(shared_data).resolve()))))


def _simulate(n: int, seed: int, position: str = POSITION) -> pd.DataFrame:
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(n, SIM_DURATION_S, ("walk",), seed=seed, positions=(position,))
    return pd.DataFrame([back_pocket_statistics(r) for r in recs])


def share_curves(*, n: int = N_SIM, seed: int = SIM_SEED, grid=SHARE_GRID) -> np.ndarray:
    """``step_stride_db`` of ``n`` simulated subjects (rows) at each pelvis share of ``grid`` (columns)."""
    out = np.empty((n, len(grid)))
    for j, s in enumerate(grid):
        with back_pocket_ranges(share=(s, s)):
            out[:, j] = _simulate(n, seed)["step_stride_db"].to_numpy()
    return out


def roll_curves(share: tuple[float, float], *, n: int = N_SIM, seed: int = SIM_SEED, grid=ROLL_GRID) -> np.ndarray:
    """``screen_roll_deg`` of ``n`` simulated subjects (rows) with the extra roll drawn from ``(-r, r)`` for
    each ``r`` of ``grid`` (columns; a subject's roll is ``r`` times its own fixed draw in -1..1)."""
    out = np.empty((n, len(grid)))
    for j, r in enumerate(grid):
        with back_pocket_ranges(share=share, roll=(-r, r)):
            out[:, j] = _simulate(n, seed)["screen_roll_deg"].to_numpy()
    return out


def _fit_roll(real: np.ndarray, curves: np.ndarray) -> float:
    """The half-width ``r`` (deg, of ``_ROLL_ENDS``) whose population's 5-95 % ``screen_roll_deg`` is closest
    to the real span (squared error; each subject's roll interpolated linearly in ``r``)."""
    target = np.array([np.min(real), np.max(real)])
    errs = []
    for r in _ROLL_ENDS:
        pop = np.array([np.interp(r, ROLL_GRID, c) for c in curves])
        errs.append(float(np.sum((np.percentile(pop, [5, 95]) - target) ** 2)))
    return float(_ROLL_ENDS[int(np.argmin(errs))])


def fit_back_pocket(walks: pd.DataFrame, curves_share: np.ndarray, roll_cache: dict | None = None) -> dict[str, tuple[float, float]]:
    """The ranges (``pelvis_share``, ``pocket_roll_deg``) fitted to the back-pocket ``walks`` (module docstring)."""
    share = fit_range(
        walks["step_stride_db"].to_numpy(), curves_share, grid=SHARE_GRID, lo_grid=_SHARE_ENDS, hi_grid=_SHARE_ENDS, log=False
    )
    roll_cache = {} if roll_cache is None else roll_cache
    if share not in roll_cache:
        roll_cache[share] = roll_curves(share)
    r = _fit_roll(walks["screen_roll_deg"].to_numpy(), roll_cache[share])
    return {"pelvis_share": share, "pocket_roll_deg": (-r, r)}


def check_population(share, roll, *, n: int = N_CHECK, seed: int = CHECK_SEED) -> pd.DataFrame:
    """Statistics of ``n`` new simulated back-pocket walkers with the share and roll drawn from these ranges."""
    with back_pocket_ranges(share=share, roll=roll):
        return _simulate(n, seed)


def leave_one_user_out(walks: pd.DataFrame, curves_share: np.ndarray) -> pd.DataFrame:
    """Per held-out user: both ranges fitted on the other users, and the user's walks covered.

    ``before``: every user against the simulator without the two fields; ``all (in sample)``:
    fitted on and checked against every user.
    """
    bp = walks[walks["position"] == POSITION]
    rows, cache = [], {}
    for user in ["before", *bp["user"].unique(), None]:
        test = bp if user in (None, "before") else bp[bp["user"] == user]
        if user == "before":
            fit = {"pelvis_share": (0.0, 0.0), "pocket_roll_deg": (0.0, 0.0)}
        else:
            fit = fit_back_pocket(bp if user is None else bp[bp["user"] != user], curves_share, cache)
        sim = check_population(fit["pelvis_share"], fit["pocket_roll_deg"])
        cov = _covered(test, sim, CHECK_STATS)
        rows.append(
            {
                "held_out": {None: "all (in sample)"}.get(user, user),
                "walks": len(test),
                "real_db": "{:.1f}-{:.1f}".format(test["step_stride_db"].min(), test["step_stride_db"].max()),
                "share_lo": fit["pelvis_share"][0],
                "share_hi": fit["pelvis_share"][1],
                "sim_db_5_95": "{:.1f}-{:.1f}".format(*np.percentile(sim["step_stride_db"], [5, 95])),
                "real_roll": "{:.1f}-{:.1f}".format(test["screen_roll_deg"].min(), test["screen_roll_deg"].max()),
                "roll_hi": fit["pocket_roll_deg"][1],
                "sim_roll_5_95": "{:.1f}-{:.1f}".format(*np.percentile(sim["screen_roll_deg"], [5, 95])),
                **{f"covered_{k}": v for k, v in cov.items()},
            }
        )
    return pd.DataFrame(rows)


#: Oxford positions scored by ``--models``.
SCORED_OXFORD = ("BackPocket", "FrontPocket", "Purse", "InHand", "SwingingArm")


def heldout_models(shared_data: str | Path, loo: pd.DataFrame) -> pd.DataFrame:
    """The real Oxford walks read by ``positions-acc`` trained before the two fields, per held-out fold and in sample.

    ``before``: share 0 and no extra roll; ``held out``: the back pocket's ranges fitted without the
    user (``loo``'s rows); ``in sample``: fitted on every user. Scores as
    :mod:`experiments.scripts.domain_report` (windows read as walk, flagged, silently wrong), per
    Oxford position and user, then the users pooled.
    """
    import tempfile

    from experiments.scripts.domain_report import _add, score
    from gaitml.io import read_dataset

    recs: dict[tuple[str, str], list] = {}
    for r in read_dataset(Path(shared_data) / "oxford-step-counter" / "optimisation"):
        if r.meta.get("position") in SCORED_OXFORD:
            recs.setdefault((r.meta["position"], r.meta["user"]), []).append(r)
    users = sorted({u for _, u in recs})

    def ranges(label: str) -> tuple:
        row = loo[loo["held_out"] == label].iloc[0]
        return (row["share_lo"], row["share_hi"]), (-row["roll_hi"], row["roll_hi"])

    def train(out: Path, share, roll):
        return train_without_cv("positions-acc.toml", out, back_pocket_ranges(share=share, roll=roll))

    rows: list[dict] = []
    with tempfile.TemporaryDirectory() as tmp:
        models = {
            "before": train(Path(tmp) / "before", (0.0, 0.0), (0.0, 0.0)),
            "in sample": train(Path(tmp) / "in", *ranges("all (in sample)")),
        }
        for user in users:
            print(f"held out {user} ...", file=sys.stderr, flush=True)
            models["held out"] = train(Path(tmp) / f"fold-{user}", *ranges(user))
            for position in SCORED_OXFORD:
                for name in ("before", "held out", "in sample"):
                    tot: dict = {}
                    for rec in recs.get((position, user), []):
                        tot = _add(tot, score(models[name], rec))
                    if tot:
                        rows.append({"oxford": position, "user": user, "model": name, **tot})
    out = pd.DataFrame(rows)
    num = ["windows", "ood", "walk_all", "silent"]
    pooled = out.groupby(["oxford", "model"], sort=False)[num].sum().reset_index().assign(user="pooled")
    out = pd.concat([out, pooled], ignore_index=True)
    n = out["windows"]
    pct = {"walk %": out["walk_all"], "flagged %": out["ood"], "silently wrong %": out["silent"]}
    out = out.assign(**{k: 100.0 * v / n for k, v in pct.items()})[["oxford", "user", "model", "windows", *pct]]
    order = {p: i for i, p in enumerate(SCORED_OXFORD)}
    return out.sort_values(["oxford", "user"], key=lambda c: c.map(order) if c.name == "oxford" else c, kind="stable").reset_index(
        drop=True
    )


_SHOWN = ["step_stride_db", "screen_roll_deg", "mag_std_ms2", "var_share_1", "var_share_3", "f_ax1_per_cadence", "f_ax3_per_cadence"]


def _per_user(df: pd.DataFrame, by: list[str]) -> pd.DataFrame:
    tab = df.groupby(by, sort=False)[_SHOWN].agg(["min", "max"])
    tab.columns = [f"{a}_{b}" for a, b in tab.columns]
    return tab.reset_index()


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.back_pocket", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data", help="the shared data folder (default ../shared/data)")
    ap.add_argument("--out", help="also write the markdown tables here")
    ap.add_argument(
        "--models",
        action="store_true",
        help="also train the accelerometer-only all-positions model per held-out user and score the real walks (6-12 min more)",
    )
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    walks = real_pocket_walks(args.data)
    if walks.empty:
        print(f"back_pocket: no Oxford walks under {args.data}; pass --data ../shared/data", file=sys.stderr)
        return 2
    curves = share_curves()
    loo = leave_one_user_out(walks, curves)
    fitted = loo[loo["held_out"] == "all (in sample)"].iloc[0]
    sims = []
    for label, share, roll in (
        ("before (share 0, no extra roll)", (0.0, 0.0), (0.0, 0.0)),
        ("fitted (in sample)", (fitted["share_lo"], fitted["share_hi"]), (-fitted["roll_hi"], fitted["roll_hi"])),
    ):
        sims.append(check_population(share, roll).assign(position="back-pocket", user=f"simulated, {label}"))
    sims.append(_simulate(N_CHECK, CHECK_SEED, "front-pocket").assign(position="front-pocket", user="simulated"))
    sections = [
        "### Real pocket walks per user and simulated populations (range over the walks / subjects)\n\n"
        + _markdown(_per_user(pd.concat([walks, *sims], ignore_index=True), ["position", "user"])),
        "### Back-pocket ranges fitted without each user, and that user's walks covered\n\n" + _markdown(loo),
    ]
    if args.models:
        tab = heldout_models(args.data, loo)
        sections.append("### Real Oxford walks read by the all-positions accelerometer model (positions-acc)\n\n" + _markdown(tab))
    return emit_tables(sections, Path(args.out) if args.out else None, t0)


if __name__ == "__main__":
    sys.exit(main())
