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

The in-sample fit (share 1, roll
+-13 deg) is **not shipped**: it matches the two statistics it was fitted on but lowers the
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

from experiments.scripts.carry_vigour import score_oxford_models
from experiments.scripts.domain_report import emit_tables
from experiments.scripts.hand_gain import covered, fit_range
from experiments.scripts.realism import _markdown, oxford_walks, position_statistics

__all__ = [
    "BACK_POCKET_FIT",
    "STANCE_GATE_FIT",
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
#: The pelvis-share and in-pocket roll fit on every Oxford back-pocket user (``--pelvis-roll``; not
#: shipped: ``experiments/reports/simulator-positions.md``, "Back pocket: pelvis and roll"). Moved here
#: from gaitml.simulate.positions (issue 26): the library ships ranges, the lab records its fits.
BACK_POCKET_FIT = {"pelvis_share": (1.0, 1.0), "pocket_roll_deg": (-13.0, 13.0)}
#: The joint fit of the one-sided step on every Oxford back-pocket user (shipped as
#: gaitml.simulate.positions STANCE_GATE_RANGE, the share of BACK_POCKET_RANGE and the back pocket's
#: VIGOUR_RANGE; report section "Back pocket: the one-sided step").
STANCE_GATE_FIT = {"pelvis_share": (0.8, 1.0), "stance_gate": (1.0, 1.0), "vigour": (1.2, 1.75)}
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


def oxford_feet(folder: str | Path) -> np.ndarray:
    """The foot (``"right"`` / ``"left"``) of every foot-switch step of an Oxford folder, in the order of
    its ``reference['steps_t_s']`` (the reader sorts the 0 -> 1 transitions of both switches the same way)."""
    s = pd.read_csv(Path(folder) / "stepcounter.csv", header=None).to_numpy(float)
    t, feet = [], []
    for col, name in ((1, "right"), (2, "left")):
        idx = np.flatnonzero((s[1:, col] == 1) & (s[:-1, col] == 0)) + 1
        t.append(s[idx, 0])
        feet += [name] * len(idx)
    return np.array(feet)[np.argsort(np.concatenate(t), kind="stable")]


#: Components of :func:`step_shape_statistics`: vertical (along the walk's mean gravity), the two
#: horizontal principal axes (most and least variance) and ``|acc|``.
_COMPONENTS = ("vert", "h1", "h2", "mag")
#: Multiples of the cadence at which :func:`step_shape_statistics` measures the power (0.5 = stride).
_HARMONICS = (0.5, 1.0, 1.5, 2.0)
#: Points per step of the mean step templates.
_TEMPLATE_N = 50


def _components(acc: np.ndarray) -> dict[str, np.ndarray]:
    g = acc.mean(axis=0)
    up = g / np.linalg.norm(g)
    h = acc - np.outer(acc @ up, up)
    h = h - h.mean(axis=0)
    axes = np.linalg.svd(h, full_matrices=False)[2]
    return {"vert": acc @ up, "h1": h @ axes[0], "h2": h @ axes[1], "mag": np.linalg.norm(acc, axis=1)}


def step_templates(x: np.ndarray, t: np.ndarray, steps_t_s: np.ndarray, feet: np.ndarray, n: int = _TEMPLATE_N):
    """Mean step cycles of ``x`` (sampled at ``t``): ``(right, left)``, each (n,), the right step from a
    right heel strike to the next left one, the left step from there to the next right one, averaged
    over every stride right-left-right whose steps last 0.35-0.8 s."""
    right, left = [], []
    for i in range(len(steps_t_s) - 2):
        if tuple(feet[i : i + 3]) != ("right", "left", "right"):
            continue
        a, b, c = steps_t_s[i : i + 3]
        if not (0.35 < b - a < 0.8 and 0.35 < c - b < 0.8):
            continue
        right.append(np.interp(np.linspace(a, b, n, endpoint=False), t, x))
        left.append(np.interp(np.linspace(b, c, n, endpoint=False), t, x))
    if not right:
        return np.full(n, np.nan), np.full(n, np.nan)
    return np.mean(right, axis=0), np.mean(left, axis=0)


def step_shape_statistics(recording, feet: np.ndarray | None = None) -> dict[str, float]:
    """How the carrying leg's step differs from the other's, from the first to the last true step.

    Per component (:data:`_COMPONENTS`: the acceleration along the walk's mean gravity, its two
    horizontal principal axes, ``|acc|``): ``{c}_p{h}``, the share of the component's 0.3-6 Hz power
    within +-0.15 cadence of ``h`` x cadence (``h`` of :data:`_HARMONICS`; the odd multiples of half the
    cadence, 0.5 and 1.5, are the part of the signal that differs between alternate steps);
    ``{c}_step_ratio``, the standard deviation of the quieter mean step cycle over the louder one's
    (:func:`step_templates`; 1: both feet's steps alike, 0: the phone feels one step only). ``feet``:
    the foot of each true step (default: the simulated ``reference['steps']['foot']``).
    """
    st = np.asarray(recording.reference["steps_t_s"], dtype=float)
    if feet is None:
        feet = recording.reference["steps"]["foot"].to_numpy()[: len(st)]
    fs = recording.sampling_rate_hz
    i0, i1 = int(np.ceil(st[0] * fs)), int(np.floor(st[-1] * fs))
    t = np.arange(i0, i1) / fs
    cad = (len(st) - 1) / (st[-1] - st[0])
    out: dict[str, float] = {}
    for name, x in _components(recording.acc[i0:i1]).items():
        x = x - x.mean()
        f, p = scipy.signal.welch(x, fs=fs, nperseg=min(len(x), int(8 * fs)))
        total = p[(f > 0.3) & (f < 6.0)].sum()
        for h in _HARMONICS:
            out[f"{name}_p{h:g}"] = float(p[np.abs(f - h * cad) <= _BAND * cad].sum() / total)
        sd = sorted(float(np.std(m)) for m in step_templates(x, t, st, np.asarray(feet)))
        out[f"{name}_step_ratio"] = sd[0] / sd[1] if sd[1] > 0 else float("nan")
    return out


@contextlib.contextmanager
def back_pocket_ranges(
    share: tuple[float, float] | None = None,
    roll: tuple[float, float] | None = None,
    gate: tuple[float, float] | None = None,
    vigour: tuple[float, float] | None = None,
):
    """Temporarily draw the back pocket's ``pelvis_share`` / ``pocket_roll_deg`` / ``stance_gate`` / ``vigour``
    from these ranges (patches :data:`~gaitml.simulate.positions.BACK_POCKET_RANGE`,
    :data:`~gaitml.simulate.positions.STANCE_GATE_RANGE` and the back pocket's
    :data:`~gaitml.simulate.positions.VIGOUR_RANGE`; None keeps the shipped range)."""
    from gaitml.simulate import positions as pos_mod

    saved, saved_gate, saved_vigour = dict(pos_mod.BACK_POCKET_RANGE), pos_mod.STANCE_GATE_RANGE, pos_mod.VIGOUR_RANGE[POSITION]
    if share is not None:
        pos_mod.BACK_POCKET_RANGE["pelvis_share"] = (float(share[0]), float(share[1]))
    if roll is not None:
        pos_mod.BACK_POCKET_RANGE["pocket_roll_deg"] = (float(roll[0]), float(roll[1]))
    if gate is not None:
        pos_mod.STANCE_GATE_RANGE = (float(gate[0]), float(gate[1]))
    if vigour is not None:
        pos_mod.VIGOUR_RANGE[POSITION] = (float(vigour[0]), float(vigour[1]))
    try:
        yield
    finally:
        pos_mod.BACK_POCKET_RANGE.clear()
        pos_mod.BACK_POCKET_RANGE.update(saved)
        pos_mod.STANCE_GATE_RANGE = saved_gate
        pos_mod.VIGOUR_RANGE[POSITION] = saved_vigour


@functools.lru_cache(maxsize=2)
def _real_pocket_walks(root: str) -> tuple:
    names = {"BackPocket": "back-pocket", "FrontPocket": "front-pocket"}
    rows = []
    for rec in oxford_walks(root):
        pos = names.get(rec.meta.get("position"))
        if pos is not None:
            shape = step_shape_statistics(rec, oxford_feet(rec.meta["source"]))
            rows.append({"position": pos, "user": rec.meta["user"], "walk": rec.meta.get("id", ""), **back_pocket_statistics(rec), **shape})
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
        with back_pocket_ranges(share=(s, s), gate=(0.0, 0.0), vigour=VIGOUR_BEFORE):
            out[:, j] = _simulate(n, seed)["step_stride_db"].to_numpy()
    return out


def roll_curves(share: tuple[float, float], *, n: int = N_SIM, seed: int = SIM_SEED, grid=ROLL_GRID) -> np.ndarray:
    """``screen_roll_deg`` of ``n`` simulated subjects (rows) with the extra roll drawn from ``(-r, r)`` for
    each ``r`` of ``grid`` (columns; a subject's roll is ``r`` times its own fixed draw in -1..1)."""
    out = np.empty((n, len(grid)))
    for j, r in enumerate(grid):
        with back_pocket_ranges(share=share, roll=(-r, r), gate=(0.0, 0.0), vigour=VIGOUR_BEFORE):
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
    with back_pocket_ranges(share=share, roll=roll, gate=(0.0, 0.0), vigour=VIGOUR_BEFORE):
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
        cov = covered(test, sim, CHECK_STATS)
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


# ---------------------------------------------------------------- the one-sided step (stance gate)
#: The back pocket's vigour range before the gate (fitted on the thigh-driven back pocket). The share and
#: the gate are fitted on it (one pass: share and gate, then the vigour refitted on them; a second pass
#: moves the share's lower end from 0.8 to 0.9), and the pelvis-and-roll fit (:func:`fit_back_pocket`) and
#: the ``before`` rows use it with gate 0, so they reproduce what they measured before the gate shipped.
VIGOUR_BEFORE = (0.9, 1.45)
#: Pelvis shares and stance gates at which every subject of the joint fitting population is simulated.
JOINT_SHARE_GRID = np.round(np.linspace(0.0, 1.0, 5), 4)
GATE_GRID = np.round(np.linspace(0.0, 1.0, 6), 4)
#: Candidate range ends of the joint fit (0-1 by 0.1).
_JOINT_ENDS = np.round(np.linspace(0.0, 1.0, 11), 4)
#: Statistics of the joint fit, each error measured in units of its tolerance.
JOINT_STATS = {"step_stride_db": 1.0, "r_step": 0.05}
#: Statistics checked on a held-out user after the joint fit (tolerance added to the simulated 5-95 % range).
JOINT_CHECK_STATS = {
    "step_stride_db": 1.0,
    "r_step": 0.05,
    "mag_std_ms2": 0.3,
    "mag_p5_ms2": 0.3,
    "mag_p95_ms2": 0.3,
    "var_share_1": 0.03,
    "r_stride": 0.05,
    "mag_step_ratio": 0.05,
    "mag_p1.5": 0.03,
}


def _simulate_shape(n: int, seed: int) -> pd.DataFrame:
    from gaitml.simulate import simulate_dataset

    recs = simulate_dataset(n, SIM_DURATION_S, ("walk",), seed=seed, positions=(POSITION,))
    return pd.DataFrame([{**back_pocket_statistics(r), **step_shape_statistics(r)} for r in recs])


def joint_curves(*, n: int = N_SIM, seed: int = SIM_SEED) -> dict[str, np.ndarray]:
    """Per statistic of :data:`JOINT_STATS`: its value for ``n`` simulated subjects at every pelvis share of
    :data:`JOINT_SHARE_GRID` and stance gate of :data:`GATE_GRID`, shape (n, shares, gates)."""
    out = {k: np.empty((n, len(JOINT_SHARE_GRID), len(GATE_GRID))) for k in JOINT_STATS}
    for i, s in enumerate(JOINT_SHARE_GRID):
        for j, g in enumerate(GATE_GRID):
            with back_pocket_ranges(share=(s, s), gate=(g, g), vigour=VIGOUR_BEFORE):
                sim = _simulate(n, seed)
            for k in JOINT_STATS:
                out[k][:, i, j] = sim[k].to_numpy()
    return out


def _bilinear(c: np.ndarray, s: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Each subject's statistic (``c``: n x shares x gates) at its own share ``s`` and gate ``g`` (n,)."""
    xs, xg = JOINT_SHARE_GRID, GATE_GRID
    i = np.clip(np.searchsorted(xs, s, side="right") - 1, 0, len(xs) - 2)
    j = np.clip(np.searchsorted(xg, g, side="right") - 1, 0, len(xg) - 2)
    u = (s - xs[i]) / (xs[i + 1] - xs[i])
    v = (g - xg[j]) / (xg[j + 1] - xg[j])
    r = np.arange(len(c))
    return (1 - u) * (1 - v) * c[r, i, j] + u * (1 - v) * c[r, i + 1, j] + (1 - u) * v * c[r, i, j + 1] + u * v * c[r, i + 1, j + 1]


def fit_joint(walks: pd.DataFrame, curves: dict[str, np.ndarray]) -> dict[str, tuple[float, float]]:
    """The ranges of ``pelvis_share`` and ``stance_gate`` fitted jointly to the back-pocket ``walks``.

    As :func:`experiments.scripts.hand_gain.fit_range`, in two settings at once: subject ``i`` of the
    population sits at quantile ``(i + 0.5) / n`` of the share range and at a fixed shuffled quantile of
    the gate range (the two are drawn independently); the ranges (ends on a 0.1 grid) whose population's
    5 % and 95 % quantiles of each statistic of :data:`JOINT_STATS` are closest to the smallest and the
    largest real value win (squared error, each statistic in units of its tolerance).
    """
    n = len(next(iter(curves.values())))
    q = (np.arange(n) + 0.5) / n
    qg = q[np.random.default_rng(0).permutation(n)]
    targets = {k: np.array([walks[k].min(), walks[k].max()]) for k in JOINT_STATS}
    best, arg = np.inf, None
    ends = [(a, b) for a in _JOINT_ENDS for b in _JOINT_ENDS if b >= a]
    for slo, shi in ends:
        s = slo + q * (shi - slo)
        for glo, ghi in ends:
            g = glo + qg * (ghi - glo)
            err = 0.0
            for k, tol in JOINT_STATS.items():
                pq = np.percentile(_bilinear(curves[k], s, g), [5, 95])
                err += float(np.sum(((pq - targets[k]) / tol) ** 2))
            if err < best - 1e-12:
                best, arg = err, ((slo, shi), (glo, ghi))
    return {"pelvis_share": tuple(float(v) for v in arg[0]), "stance_gate": tuple(float(v) for v in arg[1])}


def fit_vigour(
    walks: pd.DataFrame, share: tuple[float, float], gate: tuple[float, float], cache: dict | None = None
) -> tuple[float, float]:
    """The back pocket's vigour range refitted (as ``python -m experiments.scripts.carry_vigour``: the walking
    ``|acc|`` standard deviation of ``walks``) on the simulator with these share and gate ranges: the gate
    takes part of the trunk's acceleration away, so the intensity's range moves with it."""
    from experiments.scripts.carry_vigour import END_GRID, VIGOUR_GRID, vigour_curves

    cache = {} if cache is None else cache
    key = (tuple(share), tuple(gate))
    if key not in cache:
        with back_pocket_ranges(share=share, gate=gate):
            cache[key] = vigour_curves(POSITION)
    return fit_range(walks["mag_std_ms2"].to_numpy(), cache[key], grid=VIGOUR_GRID, lo_grid=END_GRID, hi_grid=END_GRID)


def joint_ranges(fit: dict[str, tuple[float, float]]):
    """The context drawing the back pocket's share, gate and vigour from ``fit`` (keys ``pelvis_share``,
    ``stance_gate``, ``vigour``)."""
    return back_pocket_ranges(share=fit["pelvis_share"], gate=fit["stance_gate"], vigour=fit["vigour"])


def leave_one_user_out_joint(walks: pd.DataFrame, curves: dict[str, np.ndarray]) -> pd.DataFrame:
    """Per held-out user: the share and gate ranges fitted jointly on the other users (:func:`fit_joint`),
    then the vigour refitted on them (:func:`fit_vigour`), and the user's walks covered by ``N_CHECK`` new
    subjects (seed ``CHECK_SEED``) on :data:`JOINT_CHECK_STATS`; ``before``: the shipped back pocket
    (share 0, no gate, the shipped vigour); ``all (in sample)``: fitted on and checked against every user."""
    bp = walks[walks["position"] == POSITION]
    rows, cache = [], {}
    for user in ["before", *bp["user"].unique(), None]:
        test = bp if user in (None, "before") else bp[bp["user"] == user]
        if user == "before":
            fit = {"pelvis_share": (0.0, 0.0), "stance_gate": (0.0, 0.0), "vigour": VIGOUR_BEFORE}
        else:
            tune = bp if user is None else bp[bp["user"] != user]
            fit = fit_joint(tune, curves)
            fit["vigour"] = fit_vigour(tune, fit["pelvis_share"], fit["stance_gate"], cache)
        with joint_ranges(fit):
            sim = _simulate_shape(N_CHECK, CHECK_SEED)
        cov = covered(test, sim, JOINT_CHECK_STATS)
        rows.append(
            {
                "held_out": {None: "all (in sample)"}.get(user, user),
                "walks": len(test),
                "share_lo": fit["pelvis_share"][0],
                "share_hi": fit["pelvis_share"][1],
                "gate_lo": fit["stance_gate"][0],
                "gate_hi": fit["stance_gate"][1],
                "vigour_lo": fit["vigour"][0],
                "vigour_hi": fit["vigour"][1],
                "real_db": "{:.1f}-{:.1f}".format(test["step_stride_db"].min(), test["step_stride_db"].max()),
                "sim_db_5_95": "{:.1f}-{:.1f}".format(*np.percentile(sim["step_stride_db"], [5, 95])),
                "real_r_step": "{:.2f}-{:.2f}".format(test["r_step"].min(), test["r_step"].max()),
                "sim_r_step_5_95": "{:.2f}-{:.2f}".format(*np.percentile(sim["r_step"], [5, 95])),
                **{f"covered_{k}": v for k, v in cov.items()},
            }
        )
    return pd.DataFrame(rows)


#: Oxford positions scored by ``--models``.
SCORED_OXFORD = ("BackPocket", "FrontPocket", "Purse", "InHand", "SwingingArm")


def heldout_models(shared_data: str | Path, loo: pd.DataFrame) -> pd.DataFrame:
    """The real Oxford walks read by ``positions-acc`` trained before the fit, per held-out fold and in sample.

    ``before``: share 0, no extra roll, no gate (the shipped back pocket); ``held out``: the back
    pocket's ranges fitted without the user (``loo``'s rows: :func:`leave_one_user_out`, or
    :func:`leave_one_user_out_joint` with the gate and the vigour); ``in sample``: fitted on every user. Scores as
    :mod:`experiments.scripts.domain_report` (windows read as walk, flagged, silently wrong), per
    Oxford position and user, then the users pooled (:func:`experiments.scripts.carry_vigour.score_oxford_models`).
    """

    def ranges(label: str):
        if label == "before":
            return back_pocket_ranges(share=(0.0, 0.0), roll=(0.0, 0.0), gate=(0.0, 0.0), vigour=VIGOUR_BEFORE)
        row = loo[loo["held_out"] == label].iloc[0]
        if "gate_lo" in loo:  # the joint fit (leave_one_user_out_joint): share, gate and vigour
            fit = {
                k: (row[f"{c}_lo"], row[f"{c}_hi"]) for k, c in (("pelvis_share", "share"), ("stance_gate", "gate"), ("vigour", "vigour"))
            }
            return joint_ranges(fit)
        return back_pocket_ranges(share=(row["share_lo"], row["share_hi"]), roll=(-row["roll_hi"], row["roll_hi"]))

    return score_oxford_models(shared_data, SCORED_OXFORD, ranges)


#: Step-shape statistics shown per user (the one-sided step).
_SHAPE_SHOWN = [
    "r_step",
    "r_stride",
    "mag_step_ratio",
    "vert_step_ratio",
    "h1_step_ratio",
    "mag_p0.5",
    "mag_p1",
    "mag_p1.5",
    "mag_p2",
    "vert_p1.5",
    "h2_p1.5",
    "mag_p5_ms2",
    "mag_p95_ms2",
    "var_share_1",
]
_SHOWN = ["step_stride_db", "screen_roll_deg", "mag_std_ms2", "var_share_1", "var_share_3", "f_ax1_per_cadence", "f_ax3_per_cadence"]


def _per_user(df: pd.DataFrame, by: list[str], shown: list[str] = _SHOWN) -> pd.DataFrame:
    tab = df.groupby(by, sort=False)[shown].agg(["min", "max"])
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
    ap.add_argument(
        "--pelvis-roll",
        action="store_true",
        help="the earlier fit instead: pelvis share and in-pocket roll without the gate (back_pocket.BACK_POCKET_FIT; --models scores it)",
    )
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    walks = real_pocket_walks(args.data)
    if walks.empty:
        print(f"back_pocket: no Oxford walks under {args.data}; pass --data ../shared/data", file=sys.stderr)
        return 2
    if not args.pelvis_roll:
        return _main_joint(args, walks, t0)
    curves = share_curves()
    loo = leave_one_user_out(walks, curves)
    fitted = loo[loo["held_out"] == "all (in sample)"].iloc[0]
    sims = []
    for label, share, roll in (
        ("thigh (share 0, no extra roll, no gate)", (0.0, 0.0), (0.0, 0.0)),
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


def _main_joint(args, walks: pd.DataFrame, t0: float) -> int:
    """The one-sided step: real step shapes per user, the joint fit of share and gate (each user held out),
    the simulated populations before and with the in-sample fit, and with ``--models`` the real walks read."""
    loo = leave_one_user_out_joint(walks, joint_curves())
    row = loo[loo["held_out"] == "all (in sample)"].iloc[0]
    fit = {k: (row[f"{c}_lo"], row[f"{c}_hi"]) for k, c in (("pelvis_share", "share"), ("stance_gate", "gate"), ("vigour", "vigour"))}
    before = {"pelvis_share": (0.0, 0.0), "stance_gate": (0.0, 0.0), "vigour": VIGOUR_BEFORE}
    sims = []
    for label, ranges in (("thigh (share 0, no gate)", before), ("fitted (in sample)", fit)):
        with joint_ranges(ranges):
            sims.append(_simulate_shape(N_CHECK, CHECK_SEED).assign(position=POSITION, user=f"simulated, {label}"))
    from gaitml.simulate import simulate_dataset

    simulate_front = simulate_dataset(N_CHECK, SIM_DURATION_S, ("walk",), seed=CHECK_SEED, positions=("front-pocket",))
    front = pd.DataFrame([{**back_pocket_statistics(r), **step_shape_statistics(r)} for r in simulate_front])
    sims.append(front.assign(position="front-pocket", user="simulated"))
    both = pd.concat([walks, *sims], ignore_index=True)
    sections = [
        "### Step shape of the real pocket walks per user and of the simulated populations (range over walks / subjects)\n\n"
        + _markdown(_per_user(both, ["position", "user"], _SHAPE_SHOWN)),
        "### Step and stride power, roll and axes (as the pelvis-and-roll fit)\n\n" + _markdown(_per_user(both, ["position", "user"])),
        "### Share, gate and vigour fitted without each user, and that user's walks covered\n\n" + _markdown(loo),
    ]
    if args.models:
        tab = heldout_models(args.data, loo)
        sections.append("### Real Oxford walks read by the all-positions accelerometer model (positions-acc)\n\n" + _markdown(tab))
    return emit_tables(sections, Path(args.out) if args.out else None, t0)


if __name__ == "__main__":
    sys.exit(main())
