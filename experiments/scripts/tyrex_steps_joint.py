"""Adaptive's opt-in stages 2c and 5a chosen together, leave-one-person-out on the tyrex recordings (issue 30).

The fourth helper found two errors of opposite sign in ``adaptive``'s walking counts (misses where |acc| is weakly
periodic, extras where a slow step's two |acc| peaks are read as two steps) and that they "must be fixed together"
(``experiments/reports/tyrex-steps.md``). Stage 2c (``gyro_swing_*``, :func:`gaitml.steps.adaptive.gyro_swing_cadence`)
addresses the first, stage 5a (``octave_swing_min_correlation``, ``max_short_bout_interval_cv``,
:func:`gaitml.steps.adaptive.bout_octave`) the second; each was measured alone. Here they are chosen jointly over
:data:`SWING_2C` x :data:`OCTAVE_5A` under the adoption rule fixed before measuring (the report's "joint helper"
section):

- *admissible*: on the simulated non-gait selection seeds 0-39 no more steps per minute than all-off (gestures and
  desk, as :mod:`experiments.scripts.tyrex_steps_swing`);
- per person left out, the admissible setting with the best score on the other two (mean over the seven scored
  motions of the mean count accuracy, :func:`experiments.scripts.tyrex_steps_lopo._score`) is scored on the third;
- J1 pooled held-out score above all-off's; J2 no left-out person below all-off by more than :data:`MAX_PERSON_LOSS`;
  J3 no motion's pooled held-out figure below all-off by more than :data:`MAX_MOTION_LOSS`, running >=
  :data:`RUNNING_FLOOR`, every motion >= AD-FSM; then for the setting that would ship (the admissible setting best on
  all three people): J4 held-out non-gait seeds 100-119 not above all-off, J5 the slow walkers' held-out seeds not
  below all-off, J6 Oxford and IFSM step times identical (J7, throughput, is ``python -m benchmarks.steps``).

Per-step hits / extras / misses and F1 (:func:`experiments.scripts.tyrex_steps_octave.match_steps`) are printed
beside the count for the motions whose reference counts steps (Texting, Phoning); they are not part of the rule.
Every detector run is cached per setting (pickles in ``--cache``, keyed by the setting only: empty the folder after
any change to ``gaitml``), so a rerun only recomputes the tables.

    python -m experiments.scripts.tyrex_steps_joint [--data ../shared/data] [--cache /tmp/joint]       # ~2 min, 20 s cached
    python -m experiments.scripts.tyrex_steps_joint --check 0.3,0,-1,0/0.7,0 [--cache /tmp/joint]    # J4-J6 for one setting
    python -m experiments.scripts.tyrex_steps_joint --misses 0.3,0,-1,0/off                          # why steps are missed
"""

from __future__ import annotations

import argparse
import itertools
import pickle
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED, _load, _score
from experiments.scripts.tyrex_steps_octave import match_steps

#: stage 2c's settings (gyro_swing_min_periodicity, gyro_swing_half_correlation, gyro_swing_acc_correlation,
#: gyro_swing_min_bout_steps): off, the documented opt-in, and the three admissible settings the steps3 folds chose
#: (tyrex-steps.md, "fifth helper")
SWING_2C: dict[str, tuple] = {
    "off": (),
    "0.3,0,-1,0": (0.3, 0.0, -1.0, 0),
    "0.5,0.3,-1,10": (0.5, 0.3, -1.0, 10),
    "0.3,0,0.1,10": (0.3, 0.0, 0.1, 10),
    "0.2,0.3,0,10": (0.2, 0.3, 0.0, 10),
}
SWING_KEYS = ("gyro_swing_min_periodicity", "gyro_swing_half_correlation", "gyro_swing_acc_correlation", "gyro_swing_min_bout_steps")
#: stage 5a's settings (octave_swing_min_correlation, max_short_bout_interval_cv): off and four around the octave
#: helper's fold choice (0.5, 0) and its documented example (0.5, 0.2) (tyrex-steps.md, "octave helper")
OCTAVE_5A: dict[str, tuple] = {"off": (), "0.5,0": (0.5, 0.0), "0.5,0.2": (0.5, 0.2), "0.7,0": (0.7, 0.0), "0.7,0.2": (0.7, 0.2)}
OCTAVE_KEYS = ("octave_swing_min_correlation", "max_short_bout_interval_cv")
OFF = ("off", "off")
#: J2: the most a left-out person's held-out score may fall below all-off's
MAX_PERSON_LOSS = 0.005
#: J3: the most a motion's pooled held-out count accuracy may fall below all-off's
MAX_MOTION_LOSS = 0.01
#: J3: the floor of both running motions (the issue's running target)
RUNNING_FLOOR = 0.95
RUNNING = ("RunningHand", "RunningPocket")
#: the motions whose reference counts one event per step (per-step F1 is read there)
STEP_MOTIONS = ("Texting", "Phoning")
SELECTION_SEEDS = tuple(range(40))
HELDOUT_SEEDS = tuple(range(100, 120))


def settings() -> list[tuple[str, str]]:
    """Every joint setting of the grid: (stage 2c name, stage 5a name), all-off first."""
    return list(itertools.product(SWING_2C, OCTAVE_5A))


def params(k: tuple[str, str]) -> dict:
    """``adaptive``'s keyword arguments for joint setting ``k``."""
    p = dict(zip(SWING_KEYS, SWING_2C[k[0]], strict=False))
    p.update(zip(OCTAVE_KEYS, OCTAVE_5A[k[1]], strict=False))
    return p


def name(k: tuple[str, str]) -> str:
    """Readable name of a joint setting."""
    return f"2c {k[0]} / 5a {k[1]}"


def _cached(cache: Path | None, key: str, make):
    path = cache / f"{key}.pkl" if cache is not None else None
    if path is not None and path.exists():
        return pickle.loads(path.read_bytes())
    value = make()
    if path is not None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_bytes(pickle.dumps(value))
    return value


def step_times(items: list[dict], detector: str = "adaptive", **kw) -> list[np.ndarray]:
    """Per recording, the detector's step times on the motion-capture clock inside the reference's span."""
    from gaitml.steps import get_detector

    out = []
    for it in items:
        tt = []
        for r in it["recs"]:
            st = get_detector(detector, **kw).detect(r).steps_
            t = float(r.meta.get("t0_original_s", 0.0)) + st["t_peak_s"].to_numpy()
            tt.append(t[(t >= it["ref"]["t_first_s"]) & (t <= it["ref"]["t_last_s"])])
        out.append(np.sort(np.concatenate(tt)) if tt else np.zeros(0))
    return out


def frame(items: list[dict], times: list[np.ndarray]) -> pd.DataFrame:
    """Count accuracy per recording (as ``tyrex_steps_lopo._counts``) and, where the reference counts steps, the
    per-step hits / extras / misses."""
    rows = []
    for it, t in zip(items, times, strict=True):
        n_ref = it["ref"]["n_steps"]
        row = {"recording": it["name"], "motion": it["motion"], "person": it["person"], "n": len(t)}
        row["acc"] = 1 - abs(len(t) - n_ref) / max(n_ref, 1)
        h = e = m = np.nan
        if it["ref"]["steps_per_event"] == 1:
            h, e, m = match_steps(t, np.asarray(it["ref"]["t_s"]))
        rows.append({**row, "hits": h, "extras": e, "misses": m})
    return pd.DataFrame(rows)


def f1(df: pd.DataFrame, motion: str) -> float:
    """Per-step F1 over every recording of ``motion`` in ``df`` (hits, extras and misses summed first)."""
    d = df[df["motion"] == motion]
    h, e, m = d["hits"].sum(), d["extras"].sum(), d["misses"].sum()
    return float(2 * h / (2 * h + e + m)) if h + e + m > 0 else float("nan")


def per_motion(df: pd.DataFrame) -> pd.Series:
    """Mean count accuracy per motion."""
    return df.groupby("motion")["acc"].mean()


def admissible_set(rates: dict[tuple, dict[str, float]]) -> set:
    """The settings with no more steps per minute than all-off on gestures and on desk (all-off is always admissible)."""
    ref = rates[OFF]
    return {k for k, r in rates.items() if all(r[kind] <= ref[kind] + 1e-9 for kind in ("gestures", "desk"))}


def choose(grid: dict[tuple, pd.DataFrame], allowed: set, people=None) -> tuple:
    """The allowed setting with the best score on ``people`` (all if None); all-off wins ties."""

    def s(k):
        d = grid[k] if people is None else grid[k][grid[k]["person"].isin(people)]
        return _score(d)

    order = [OFF, *sorted(k for k in allowed if k != OFF)]
    return max((k for k in order if k in allowed), key=s)


def lopo(
    grid: dict,
    allowed: set,
    adfsm: pd.DataFrame | None = None,
    *,
    off_key=OFF,
    chooser=None,
    label=name,
    rule: str = "J",
    off_label: str = "all-off",
    max_loss: float = MAX_MOTION_LOSS,
    loss_motions: tuple[str, ...] | None = None,
) -> tuple[str, dict[str, bool], list]:
    """Per person left out: the allowed setting chosen on the other two, its held-out score per motion, and J1-J3.

    Another study's grid (``tyrex_steps_bouts``, ``tyrex_steps_floor``) passes its own off setting ``off_key``, its
    ``chooser`` (default :func:`choose`), the ``label`` of a setting in the table, the ``rule`` letter of its checks,
    ``off_label``, and the third check's bound: no motion of ``loss_motions`` (default every motion scored in the table) falls more
    than ``max_loss`` below off, and running stays at ``RUNNING_FLOOR``."""
    chooser = choose if chooser is None else chooser
    off = grid[off_key]
    cols = ["left out", "chosen", "training score", "held-out score", f"held-out, {off_label}", *SCORED, "F1 Texting", "F1 Phoning"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    held_rows, chosen, j2 = [], [], True
    for held in PEOPLE:
        train = [p for p in PEOPLE if p != held]
        best = chooser(grid, allowed, train)
        chosen.append(best)
        te, te0 = grid[best][grid[best]["person"] == held], off[off["person"] == held]
        held_rows.append(te)
        per, per0 = per_motion(te), per_motion(te0)
        j2 &= _score(te) >= _score(te0) - MAX_PERSON_LOSS - 1e-12
        tr = grid[best][grid[best]["person"].isin(train)]
        cells = [held, label(best), f"{_score(tr):.4f}", f"{_score(te):.4f}", f"{_score(te0):.4f}"]
        cells += [f"{per[m]:.3f} ({per0[m]:.3f})" for m in SCORED]
        cells += [f"{f1(te, m):.3f} ({f1(te0, m):.3f})" for m in STEP_MOTIONS]
        out.append("| " + " | ".join(cells) + " |")
    pooled = pd.concat(held_rows)
    pm, pm0 = per_motion(pooled), per_motion(off)
    j1 = _score(pooled) > _score(off) + 1e-12
    drop = pm - pm0 if loss_motions is None else pm[list(loss_motions)] - pm0[list(loss_motions)]
    j3 = bool((drop >= -max_loss - 1e-12).all()) and all(pm[m] >= RUNNING_FLOOR for m in RUNNING)
    if adfsm is not None:
        j3 &= bool((pm >= per_motion(adfsm) - 1e-12).all())
    cells = ["pooled held out", "", "", f"{_score(pooled):.4f}", f"{_score(off):.4f}"]
    cells += [f"{pm[m]:.3f} ({pm0[m]:.3f})" for m in SCORED]
    cells += [f"{f1(pooled, m):.3f} ({f1(off, m):.3f})" for m in STEP_MOTIONS]
    out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out), {f"{rule}1": j1, f"{rule}2": j2, f"{rule}3": j3}, chosen


def insample(grid: dict[tuple, pd.DataFrame], rates: dict[tuple, dict[str, float]], allowed: set) -> str:
    """Every setting on all three people, best first: admissibility, non-gait rates, score, per motion, F1."""
    cols = ["setting", "admissible", "gestures /min", "desk /min", "score", *SCORED, "F1 Texting", "F1 Phoning"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    allp = {k: _score(v) for k, v in grid.items()}
    for k in sorted(allp, key=allp.get, reverse=True):
        per, r = per_motion(grid[k]), rates[k]
        cells = [name(k), "yes" if k in allowed else "no", f"{r['gestures']:.3f}", f"{r['desk']:.3f}", f"{allp[k]:.4f}"]
        cells += [f"{per[m]:.3f}" for m in SCORED] + [f"{f1(grid[k], m):.3f}" for m in STEP_MOTIONS]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def per_person(runs: dict[str, pd.DataFrame]) -> str:
    """Mean count accuracy per motion and person, with per-step F1, for each named run (in sample)."""
    cols = ["run", "person", *SCORED, "score", "F1 Texting", "F1 Phoning"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for label, df in runs.items():
        for person in PEOPLE:
            d = df[df["person"] == person]
            per = per_motion(d)
            cells = [label, person, *(f"{per[m]:.3f}" for m in SCORED), f"{_score(d):.4f}"]
            cells += [f"{f1(d, m):.3f}" for m in STEP_MOTIONS]
            out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def per_step(runs: dict[str, pd.DataFrame]) -> str:
    """Per step-counting motion and person: hits, extras, misses, F1 and detected / reference count for each named run."""
    cols = ["motion", "person", "run", "hits", "extras", "misses", "F1", "detected / reference"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for motion in STEP_MOTIONS:
        for person in PEOPLE:
            for label, df in runs.items():
                d = df[(df["motion"] == motion) & (df["person"] == person)]
                h, e, m = (int(d[c].sum()) for c in ("hits", "extras", "misses"))
                cells = [motion, person, label, str(h), str(e), str(m), f"{f1(d, motion):.3f}", f"{(h + e) / max(h + m, 1):.2f}"]
                out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


#: stage 2c relaxed step by step, to tell why a window it refused was refused (``--misses``): any swing correlation
#: (its regularity test relaxed), then also a swing RMS down to 0.05 rad/s (its amplitude test relaxed too)
RELAXED_2C = {
    "irregular swing": {"gyro_swing_min_periodicity": 0.01},
    "weak swing": {"gyro_swing_min_periodicity": 0.01, "gyro_min_rms_rads": 0.05},
}
#: a reference step is covered by a detected step closer than this (s), as tyrex_steps_misses.COVER_S
COVER_S = 0.45


def _window_flags(rec, **kw) -> dict[str, np.ndarray]:
    """Adaptive's step times and its cadence windows' centres, period, periodicity and swing flag (clock of the
    reference: recording time + t0)."""
    from gaitml.steps import get_detector

    det = get_detector("adaptive", **kw).detect(rec)
    t0 = float(rec.meta.get("t0_original_s", 0.0))
    c = det.cadence_
    return {
        "steps": t0 + det.steps_["t_peak_s"].to_numpy(),
        "t": t0 + c["t_s"].to_numpy(),
        "period": c["period_s"].to_numpy(),
        "periodicity": c["periodicity"].to_numpy(),
        "swing": c["swing"].to_numpy(),
    }


def nearest_window(runs: list[dict], x: float) -> tuple[dict, int] | None:
    """The cadence window nearest the time ``x`` (s, the reference's clock) over ``runs`` (:func:`_window_flags`
    dicts, one per recording piece): ``(run, index)``, or None when no run has a window."""
    best = None
    for g in runs:
        if len(g["t"]):
            j = int(np.argmin(np.abs(g["t"] - x)))
            if best is None or abs(g["t"][j] - x) < abs(best[0]["t"][best[1]] - x):
                best = (g, j)
    return best


def uncovered(ref: np.ndarray, runs: list[dict]) -> np.ndarray:
    """Per reference step time in ``ref`` (s), True where no step of ``runs`` lies within :data:`COVER_S` (a missed step)."""
    steps = np.concatenate([g["steps"] for g in runs]) if runs else np.zeros(0)
    if not len(steps):
        return np.ones(len(ref), dtype=bool)
    return np.min(np.abs(ref[:, None] - steps[None, :]), axis=1) > COVER_S


#: adaptive's rules that drop steps after they are picked, each switched off in turn (``--misses``): the short-bout
#: rule alone, then every bout rule (tyrex_steps_misses.ABLATIONS "no_bout_rules"), then the gyroscope gait check; a
#: missed step found with one of them off was picked and then dropped by it
DROP_RULES_OFF = {
    "short-bout rule": {"short_bout_steps": 0},
    "other bout rules": {"short_bout_steps": 0, "min_bout_steps": 1, "edge_confidence_ratio": 0.0},
    "gait check": {"gait_check": False},
}
#: a cadence window whose step period is at least this multiple of the reference's local step interval read strides
STRIDE_RATIO = 1.5
#: the reference's local step interval: the median interval of its steps within this many seconds of the missed one
LOCAL_S = 2.5


def miss_causes(items: list[dict], k: tuple) -> pd.DataFrame:
    """Per step-counting recording at setting ``k``: its reference steps with no detected step within :data:`COVER_S`,
    by the state of the cadence window nearest them and the walker's speed.

    Where |acc| periodicity is >= 0.3 there or stage 2c set the window: the first rule of :data:`DROP_RULES_OFF`
    with which a step is found there (the step was picked and that rule dropped it), else ``stride period`` (the window's step period is at least :data:`STRIDE_RATIO` times
    the reference's local interval: one step per stride), else ``not picked``. Where stage 2c refused the window:
    ``irregular swing`` (it sets the window once its regularity test is relaxed, :data:`RELAXED_2C`), ``weak swing``
    (once its swing RMS floor is relaxed too), ``no swing`` (neither). ``slow``: the body moved slower than 0.3 m/s
    (tyrex_steps_misses.body_state).
    """
    from experiments.scripts.tyrex_steps_misses import SLOW_MS, body_state

    rows = []
    for it in items:
        if it["motion"] not in STEP_MOTIONS:
            continue
        ref = np.asarray(it["ref"]["t_s"])
        runs = {"base": params(k), **{c: {**params(k), **v} for c, v in DROP_RULES_OFF.items()}}
        runs.update({c: {**params(k), **v} for c, v in RELAXED_2C.items()})
        got = {c: [_window_flags(r, **p) for r in it["recs"]] for c, p in runs.items()}
        missed = uncovered(ref, got["base"])
        found = {c: ~uncovered(ref, got[c]) for c in DROP_RULES_OFF}
        t, speed, _ = body_state(it["truth"])
        for i in np.flatnonzero(missed):
            x = ref[i]
            near = nearest_window(got["base"], x)
            if near is None:
                cause = "no window"
            else:
                g, j = near
                if g["periodicity"][j] >= 0.3 or g["swing"][j]:
                    local = ref[np.abs(ref - x) <= LOCAL_S]
                    interval = float(np.median(np.diff(local))) if len(local) > 1 else np.nan
                    dropped = [c for c in DROP_RULES_OFF if found[c][i]]
                    if dropped:
                        cause = dropped[0]
                    elif np.isfinite(interval) and g["period"][j] >= STRIDE_RATIO * interval:
                        cause = "stride period"
                    else:
                        cause = "not picked"
                else:
                    cause = "no swing"
                    for c in RELAXED_2C:
                        w = nearest_window(got[c], x)
                        if w is not None and w[0]["swing"][w[1]]:
                            cause = c
                            break
            slow = bool(speed[int(np.clip(np.searchsorted(t, x), 0, len(t) - 1))] < SLOW_MS)
            rows.append({"recording": it["name"], "motion": it["motion"], "person": it["person"], "cause": cause, "slow": slow})
    return pd.DataFrame(rows, columns=["recording", "motion", "person", "cause", "slow"])


MISS_CAUSES = (*DROP_RULES_OFF, "stride period", "not picked", *RELAXED_2C, "no swing", "no window")


def miss_table(df: pd.DataFrame, items: list[dict]) -> str:
    """Missed reference steps per motion and person, by cause; cells: missed (of them slow)."""
    cols = ["motion", "person", "reference", "missed", *MISS_CAUSES]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for motion in STEP_MOTIONS:
        for person in PEOPLE:
            n_ref = sum(len(it["ref"]["t_s"]) for it in items if it["motion"] == motion and it["person"] == person)
            d = df[(df["motion"] == motion) & (df["person"] == person)]
            cells = [motion, person, str(n_ref), f"{len(d)} ({int(d['slow'].sum())})"]
            cells += [f"{int((d['cause'] == c).sum())} ({int((d['slow'] & (d['cause'] == c)).sum())})" for c in MISS_CAUSES]
            out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def nongait_recordings(seeds, cache: Path | None) -> dict:
    """The simulated gestures and desk recordings (120 s each) for ``seeds``."""
    from gaitml.simulate.nongait import simulate_nongait

    def make():
        return {(kind, s): simulate_nongait(kind, duration_s=120, seed=s) for kind in ("gestures", "desk") for s in seeds}

    return _cached(cache, f"nongait_recs_{seeds[0]}_{seeds[-1]}", make)


def nongait_rate(recs: dict, seeds, **kw) -> dict[str, float]:
    """Adaptive's mean (and worst) steps per minute on the gestures and desk recordings."""
    from gaitml.steps import get_detector

    out = {}
    for kind in ("gestures", "desk"):
        per = [len(get_detector("adaptive", **kw).detect(recs[(kind, s)]).steps_) / (recs[(kind, s)].duration_s / 60) for s in seeds]
        out[kind], out[f"{kind}_max"] = float(np.mean(per)), float(np.max(per))
    return out


def slow_walkers(k: tuple, cache: Path | None) -> dict[str, list[float]]:
    """Adaptive's count accuracy per position on the simulated slow walkers' held-out seeds, at setting ``k``."""
    from experiments.scripts.slow_walks import POSITIONS, count_accuracy, slow_recording
    from gaitml.steps import get_detector

    def make():
        out = {}
        for position in POSITIONS:
            acc = []
            for s in HELDOUT_SEEDS:
                rec = slow_recording(s, position)
                acc.append(count_accuracy(rec.reference["n_steps_true"], len(get_detector("adaptive", **params(k)).detect(rec).steps_)))
            out[position] = acc
        return out

    return _cached(cache, f"slow_{k[0]}_{k[1]}", make)


def no_gyroscope(data: str | Path, k: tuple) -> tuple[int, int, int]:
    """Oxford and IFSM (no gyroscope): files, files with identical step times all-off and at ``k``, files with a gyroscope."""
    from gaitml.io.ifsm import read_ifsm_xlsx
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder
    from gaitml.steps import get_detector

    root = Path(data)
    recs = []
    for f in list_oxford_folders(root / "oxford-step-counter"):
        r = read_oxford_folder(f)
        recs.extend(r if isinstance(r, list) else [r])
    recs += [read_ifsm_xlsx(f) for f in sorted((root / "ifsm-flat-phone").rglob("*.xlsx"))]
    same = 0
    for r in recs:
        a = get_detector("adaptive").detect(r).steps_["t_peak_s"].to_numpy()
        with warnings.catch_warnings():  # each file says its opt-in stages did not run (no gyroscope): the point here
            warnings.filterwarnings("ignore", message=".*did not run: the recording has no gyroscope", category=UserWarning)
            b = get_detector("adaptive", **params(k)).detect(r).steps_["t_peak_s"].to_numpy()
        same += int(np.array_equal(a, b))
    return len(recs), same, sum(bool(r.has_gyr) for r in recs)


def heldout_checks(k: tuple, data: str | Path, cache: Path | None) -> tuple[list[str], dict[str, bool]]:
    """J4-J6 for setting ``k`` against all-off: held-out non-gait seeds, slow walkers' held-out seeds, Oxford and IFSM."""
    ho = nongait_recordings(HELDOUT_SEEDS, cache)
    h0 = _cached(cache, "nongait_heldout_off_off", lambda: nongait_rate(ho, HELDOUT_SEEDS))
    h1 = _cached(cache, f"nongait_heldout_{k[0]}_{k[1]}", lambda: nongait_rate(ho, HELDOUT_SEEDS, **params(k)))
    s0, s1 = slow_walkers(OFF, cache), slow_walkers(k, cache)
    n, same, n_gyr = no_gyroscope(data, k)
    checks = {
        "J4": all(h1[kind] <= h0[kind] + 1e-9 for kind in ("gestures", "desk")),
        "J5": all(np.mean(s1[p]) >= np.mean(s0[p]) - 1e-12 for p in s0),
        "J6": same == n,
    }
    lines = [f"Held-out checks for {name(k)} (all-off -> it; mean (worst)):"]
    for kind in ("gestures", "desk"):
        lines.append(
            f"- non-gait {kind}, seeds 100-119: {h0[kind]:.3f} ({h0[kind + '_max']:.1f}) -> {h1[kind]:.3f} ({h1[kind + '_max']:.1f}) steps/min"
        )
    for p in s0:
        lines.append(
            f"- slow walkers {p}, seeds 100-119: {np.mean(s0[p]):.3f} ({np.min(s0[p]):.3f}) -> {np.mean(s1[p]):.3f} ({np.min(s1[p]):.3f})"
        )
    lines.append(f"- Oxford and IFSM: {n} files, {n_gyr} with a gyroscope, identical step times {same}/{n}")
    return lines, checks


def parse_setting(text: str) -> tuple[str, str]:
    """``"2C/5A"`` (names of :data:`SWING_2C` and :data:`OCTAVE_5A`, e.g. ``0.3,0,-1,0/0.7,0``) as a joint setting."""
    parts = text.split("/")
    if len(parts) != 2 or parts[0] not in SWING_2C or parts[1] not in OCTAVE_5A:
        raise ValueError(f"--check must be 2C/5A with 2C one of {', '.join(SWING_2C)} and 5A one of {', '.join(OCTAVE_5A)}, got {text!r}")
    return parts[0], parts[1]


def main(argv: list[str] | None = None) -> int:
    """Print admissibility, the leave-one-person-out choice with J1-J3, in sample, and J4-J6 for the setting that would ship."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_joint", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--cache", default=None, help="folder for the per-setting detector runs and simulated recordings (pickles)")
    ap.add_argument("--misses", default=None, help="why the reference steps are missed at one joint setting 2C/5A (Texting, Phoning)")
    ap.add_argument("--check", default=None, help="only J4-J6 for one joint setting 2C/5A, e.g. 0.3,0,-1,0/0.7,0")
    a = ap.parse_args(argv)
    check = misses = None
    if a.check or a.misses:
        try:
            check = parse_setting(a.check) if a.check else None
            misses = parse_setting(a.misses) if a.misses else None
        except ValueError as exc:
            print(f"error: {exc}", file=sys.stderr)
            return 2
    if not (Path(a.data) / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    cache = Path(a.cache) if a.cache else None
    if misses is not None:
        items = _load(a.data)
        print(
            f"Missed reference steps at {name(misses)}, by the cadence window nearest them; cells: missed (of them slower than 0.3 m/s)\n"
        )
        print(miss_table(miss_causes(items, misses), items))
        return 0
    if check is not None:
        lines, checks = heldout_checks(check, a.data, cache)
        print("\n".join(lines))
        print("\nChecks: " + ", ".join(f"{c} {'pass' if v else 'FAIL'}" for c, v in checks.items()))
        return 0
    ng = nongait_recordings(SELECTION_SEEDS, cache)
    rates = {k: _cached(cache, f"nongait_{k[0]}_{k[1]}", lambda k=k: nongait_rate(ng, SELECTION_SEEDS, **params(k))) for k in settings()}
    allowed = admissible_set(rates)
    items = _load(a.data)
    grid = {}
    for k in settings():
        grid[k] = frame(items, _cached(cache, f"tyrex_{k[0]}_{k[1]}", lambda k=k: step_times(items, **params(k))))
        print(f"{name(k)}: {_score(grid[k]):.4f}, gestures {rates[k]['gestures']:.3f}, desk {rates[k]['desk']:.3f}", file=sys.stderr)
    adfsm = frame(items, _cached(cache, "tyrex_adfsm", lambda: step_times(items, "adfsm")))
    r0 = rates[OFF]
    print(f"Admissible: no more steps/min than all-off on the simulated non-gait seeds 0-39 (gestures {r0['gestures']:.3f}, ")
    print(f"desk {r0['desk']:.3f}): {len(allowed)} of {len(rates)} settings.\n")
    print("Leave-one-person-out, admissible settings only (cells: held out with the chosen setting (all-off)):\n")
    table, checks, chosen = lopo(grid, allowed, adfsm)
    print(table)
    ship = choose(grid, allowed)
    print(f"\nSetting that would ship (admissible, best on all three people): {name(ship)} ({_score(grid[ship]):.4f})")
    print("\nThe same with every setting allowed (non-gait not weighed; for the record):\n")
    print(lopo(grid, set(grid), adfsm)[0])
    print("\nIn sample (all three people), best first:\n")
    print(insample(grid, rates, allowed))
    runs = {"all-off (today)": grid[OFF]}
    for k in dict.fromkeys([*chosen, ship]):
        runs[name(k)] = grid[k]
    runs["adfsm"] = adfsm
    print("\nPer person, in sample:\n")
    print(per_person(runs))
    steps = {"all-off": grid[OFF]}
    for k in (
        ("0.5,0.3,-1,10", "off"),
        ("off", "0.5,0"),
        *chosen,
        ship,
        ("0.3,0,-1,0", "off"),
        ("0.3,0,-1,0", "0.5,0"),
        ("0.3,0,-1,0", "0.7,0"),
    ):
        steps[name(k)] = grid[k]
    print("\nPer step (Texting and Phoning, in sample; a reference step is hit by the nearest unmatched detected step within 0.45 s):\n")
    print(per_step(steps))
    if ship != OFF:
        lines, more = heldout_checks(ship, a.data, cache)
        checks.update(more)
        print("\n".join(["", *lines]))
    print("\nAdoption checks: " + ", ".join(f"{c} {'pass' if v else 'FAIL'}" for c, v in checks.items()))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
