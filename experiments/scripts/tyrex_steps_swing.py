"""Adaptive's swing rules on the tyrex recordings: leave-one-person-out choice and the rule not adopted (issue 30).

Two candidate rules for ``adaptive``'s walking-count errors on the trunk motions
(``experiments/reports/tyrex-steps.md``, "where adaptive's walking misses are"):

- **weak |acc|** (in ``gaitml``, off by default: stage 2c, :func:`gaitml.steps.adaptive.gyro_swing_cadence`): where
  |acc|'s periodicity is below the 0.3 floor and the phone's swing is regular (its stride period ``P`` correlates at
  least ``gyro_swing_min_periodicity`` and is in anti-phase at ``P / 2``, at most ``-gyro_swing_half_correlation``),
  the step period is ``P / 2`` and the periodicity the swing's; optionally |acc| must still correlate at ``P / 2``
  (``gyro_swing_acc_correlation``) and a bout with such steps must reach ``gyro_swing_min_bout_steps``. A setting is
  *admissible* when adaptive gives no more steps per minute than with the rule off on the simulated gestures and desk
  handling (``gaitml.simulate.nongait``, the nongait study's selection seeds 0-39). For each person left out, every
  admissible setting (and the rule off) is scored on the other two people (mean over the seven scored motions of the
  mean count accuracy against the motion-capture count of :mod:`experiments.scripts.tyrex_steps`), the best is
  chosen and the left-out person scored with it; then the same with every setting allowed.
- **half a step** (``--octave``; measured, not in ``gaitml``): where the swing is regular, |acc|'s period that the
  half-period rule halved from a stride is doubled back when its double lies nearer the swing's step ``P / 2``
  (the two |acc| peaks of a slow step, heel strike and push-off, read as two steps). Optionally (``context``) the
  windows within three of a regular one follow the median of their regular neighbours, so a bout keeps one octave.

    python -m experiments.scripts.tyrex_steps_swing [--data ../shared/data] [--cache DIR]  # LOPO of the weak-|acc| rule, ~5 min
    python -m experiments.scripts.tyrex_steps_swing [--data ../shared/data] --octave       # the half-step rule on top, per person
    python -m experiments.scripts.tyrex_steps_swing --nongait-heldout [--cache DIR]       # held-out non-gait seeds, stage off / on
    python -m experiments.scripts.tyrex_steps_swing --no-gyroscope [--data ../shared/data] # Oxford and IFSM, stage off / on
"""

from __future__ import annotations

import argparse
import itertools
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED, _counts, _load, _score

#: the four settings of the weak-|acc| rule: gyro_swing_min_periodicity, gyro_swing_half_correlation,
#: gyro_swing_acc_correlation, gyro_swing_min_bout_steps (0: the ordinary min_bout_steps)
GRID = {
    "gyro_swing_min_periodicity": (0.2, 0.3, 0.5),
    "gyro_swing_half_correlation": (0.0, 0.3),
    "gyro_swing_acc_correlation": (-1.0, 0.0, 0.1, 0.2),
    "gyro_swing_min_bout_steps": (0, 10),
}
OFF = (0.0,)
#: the opt-in setting documented in gaitml (gyro_swing_min_periodicity=0.3, the rest at their defaults)
OPT_IN = (0.3, 0.0, -1.0, 0)
#: simulated non-gait recordings (gaitml.simulate.nongait) that decide which settings are admissible: the nongait
#: study's selection seeds; its held-out seeds 100-119 are not used here
NONGAIT_SEEDS = tuple(range(40))


def _settings() -> list[tuple]:
    return [OFF, *itertools.product(*GRID.values())]


def _params(k: tuple) -> dict:
    return {"gyro_swing_min_periodicity": 0.0} if k == OFF else dict(zip(GRID, k, strict=True))


def _grid(items: list[dict]) -> dict[tuple, pd.DataFrame]:
    grid = {}
    for k in _settings():
        grid[k] = _counts(items, **_params(k))
        print(f"tyrex {_name(k)}: {_score(grid[k]):.4f}", file=sys.stderr)
    return grid


def nongait_rates(cache: str | None = None, seeds=NONGAIT_SEEDS, settings=None) -> dict[tuple, dict[str, float]]:
    """Mean steps per minute of adaptive on the simulated gestures and desk handling (``seeds``), per setting.

    Also ``<kind>_max``: the most steps per minute on one recording.
    """
    import pickle

    from gaitml.simulate.nongait import simulate_nongait
    from gaitml.steps import get_detector

    recs = None
    path = Path(cache) / f"nongait_recs_{seeds[0]}_{seeds[-1]}.pkl" if cache else None
    if path is not None and path.exists():
        recs = pickle.loads(path.read_bytes())
    if recs is None:
        recs = {(kind, s): simulate_nongait(kind, duration_s=120, seed=s) for kind in ("gestures", "desk") for s in seeds}
        if path is not None:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_bytes(pickle.dumps(recs))
    out = {}
    for k in settings or _settings():
        rate = {}
        for kind in ("gestures", "desk"):
            per = [
                len(get_detector("adaptive", **_params(k)).detect(recs[(kind, s)]).steps_) / (recs[(kind, s)].duration_s / 60)
                for s in seeds
            ]
            rate[kind] = float(np.mean(per))
            rate[f"{kind}_max"] = float(np.max(per))
        out[k] = rate
        print(f"nongait {_name(k)}: {rate}", file=sys.stderr)
    return out


def _name(k: tuple) -> str:
    return "off" if k == OFF else ", ".join(f"{v:g}" for v in k)


def lopo_markdown(grid: dict[tuple, pd.DataFrame], admissible: set) -> str:
    """Per person left out: the admissible setting chosen on the other two, training and held-out score, held-out per motion (rule off)."""
    off = grid[OFF]
    cols = ["left out", "chosen", "training score", "held-out score", "held-out, rule off", *SCORED]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for held in PEOPLE:
        train = {k: _score(v[v["person"] != held]) for k, v in grid.items() if k in admissible}
        best = max(train, key=train.get)
        te = grid[best][grid[best]["person"] == held]
        te0 = off[off["person"] == held]
        per, per0 = te.groupby("motion")["acc"].mean(), te0.groupby("motion")["acc"].mean()
        cells = [held, _name(best), f"{train[best]:.4f}", f"{_score(te):.4f}", f"{_score(te0):.4f}"]
        cells += [f"{per[m]:.3f} ({per0[m]:.3f})" for m in SCORED]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def insample_markdown(grid: dict[tuple, pd.DataFrame], rates: dict[tuple, dict[str, float]], admissible: set) -> str:
    """Every setting on all three people, best first, per motion, with its non-gait rates."""
    allp = {k: _score(v) for k, v in grid.items()}
    out = ["| setting | admissible | gestures /min | desk /min | score | " + " | ".join(SCORED) + " |", "|" + "---|" * (5 + len(SCORED))]
    for k in sorted(allp, key=allp.get, reverse=True):
        per = grid[k].groupby("motion")["acc"].mean()
        r = rates[k]
        cells = [_name(k), "yes" if k in admissible else "no", f"{r['gestures']:.3f}", f"{r['desk']:.3f}", f"{allp[k]:.4f}"]
        out.append("| " + " | ".join(cells) + " | " + " | ".join(f"{per[m]:.3f}" for m in SCORED) + " |")
    return "\n".join(out)


def per_person_markdown(runs: dict[str, pd.DataFrame]) -> str:
    """Mean count accuracy per motion and person for each named run."""
    out = ["| run | person | " + " | ".join(SCORED) + " | score |", "|" + "---|" * (3 + len(SCORED))]
    for name, df in runs.items():
        for person in (*PEOPLE, "all"):
            d = df if person == "all" else df[df["person"] == person]
            per = d.groupby("motion")["acc"].mean()
            out.append(f"| {name} | {person} | " + " | ".join(f"{per[m]:.3f}" for m in SCORED) + f" | {_score(d):.4f} |")
    return "\n".join(out)


def octave_rule(context: bool):
    """A gyro_swing_cadence that also doubles a halved |acc| period toward the swing's step (the rule not adopted)."""
    from gaitml.steps import adaptive as A

    base = A.gyro_swing_cadence

    def patched(cadence, projection, sampling_rate_hz, acc_windows=None, **kw):
        fs = float(sampling_rate_hz)
        T = np.asarray(cadence["period_s"], dtype=float) * fs
        n = len(T)
        proj, rms = projection
        P, corr, half = A.swing_stride(proj[:n], fs, min_step_hz=kw["min_step_hz"], max_step_hz=kw["max_step_hz"])
        regular = (rms[:n] >= kw["min_rms_rads"]) & (np.nan_to_num(corr) >= kw["swing_min_periodicity"])
        regular &= np.nan_to_num(half, nan=1.0) <= -kw["swing_half_correlation"]
        step = np.where(regular, P / 2.0, np.nan)
        if context:
            reg = np.flatnonzero(regular)
            for i in np.flatnonzero(~regular):
                nb = reg[np.abs(reg - i) <= A.SLOW_STEP_CONTEXT]
                if len(nb):
                    step[i] = np.median(step[nb])
        halved = np.asarray(cadence["stride"], dtype=bool) & ~np.asarray(cadence["inferred"], dtype=bool)
        periodic = np.asarray(cadence["periodicity"], dtype=float) >= kw["min_periodicity"]
        nearer = np.abs(np.log(2.0 * T / step)) < np.abs(np.log(T / step))
        double = np.isfinite(step) & halved & periodic & nearer & (2.0 * T <= fs / kw["min_step_hz"])
        c = dict(cadence)
        c["period_s"] = np.where(double, 2.0 * T, T) / fs
        c["stride"] = np.asarray(cadence["stride"], dtype=bool) & ~double
        return base(c, projection, sampling_rate_hz, acc_windows, **kw)

    return base, patched


def no_gyroscope_check(data: str | Path) -> str:
    """adaptive at its defaults and with the swing stage on over the Oxford and IFSM recordings (no gyroscope): the same steps?"""
    from gaitml.io.ifsm import read_ifsm_xlsx
    from gaitml.io.oxford import list_oxford_folders, read_oxford_folder
    from gaitml.steps import get_detector

    root = Path(data)
    recs = []
    for f in list_oxford_folders(root / "oxford-step-counter"):
        r = read_oxford_folder(f)
        recs.extend(r if isinstance(r, list) else [r])
    recs += [read_ifsm_xlsx(f) for f in sorted((root / "ifsm-flat-phone").rglob("*.xlsx"))]
    same = n_def = n_on = 0
    for r in recs:
        a = get_detector("adaptive").detect(r).steps_["t_peak_s"].to_numpy()
        b = get_detector("adaptive", gyro_swing_min_periodicity=0.3).detect(r).steps_["t_peak_s"].to_numpy()
        same += int(np.array_equal(a, b))
        n_def, n_on = n_def + len(a), n_on + len(b)
    n_gyr = sum(r.has_gyr for r in recs)
    return f"{len(recs)} Oxford and IFSM recordings, {n_gyr} with a gyroscope; identical step times {same}/{len(recs)}; steps {n_def} (defaults) vs {n_on} (stage on)"


def main(argv: list[str] | None = None) -> int:
    """Print the leave-one-person-out choice (or, with ``--octave``, the half-step rule per person)."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_swing", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--octave", action="store_true", help="measure the half-step rule (not adopted) on top of the defaults")
    ap.add_argument("--cache", default=None, help="folder for the simulated non-gait recordings (a rerun is cheaper)")
    ap.add_argument("--no-gyroscope", action="store_true", help="the Oxford and IFSM recordings (no gyroscope) with the stage off and on")
    ap.add_argument(
        "--nongait-heldout",
        action="store_true",
        help="the rule off and at its opt-in setting on the held-out non-gait seeds 100-119 (no tyrex)",
    )
    a = ap.parse_args(argv)
    if not (Path(a.data) / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    if a.no_gyroscope:
        print(no_gyroscope_check(a.data))
        return 0
    if a.nongait_heldout:
        seeds = tuple(range(100, 120))
        rates = nongait_rates(a.cache, seeds, [OFF, OPT_IN])
        print(f"Simulated non-gait, held-out seeds {seeds[0]}-{seeds[-1]}, adaptive steps per minute (mean / worst recording)\n")
        print("| setting | gestures | desk |\n|---|---|---|")
        for k, r in rates.items():
            print(f"| {_name(k)} | {r['gestures']:.3f} / {r['gestures_max']:.1f} | {r['desk']:.3f} / {r['desk_max']:.1f} |")
        return 0
    items = _load(a.data)
    if a.octave:
        from gaitml.steps import adaptive as A

        on = {"gyro_swing_min_periodicity": 0.3}
        runs = {"default (swing rules off)": _counts(items), "weak-|acc| rule at 0.3": _counts(items, **on)}
        base = A.gyro_swing_cadence
        try:
            for context in (False, True):
                A.gyro_swing_cadence = octave_rule(context)[1]
                runs[f"weak-|acc| + half-step rule{' with context' if context else ''}"] = _counts(items, **on)
        finally:
            A.gyro_swing_cadence = base
        print(per_person_markdown(runs))
        return 0
    rates = nongait_rates(a.cache)
    today = rates[OFF]
    admissible = {k for k, r in rates.items() if all(r[kind] <= today[kind] + 1e-9 for kind in ("gestures", "desk"))}
    grid = _grid(items)
    print(f"Admissible: no more steps per minute than the rule off on the simulated non-gait seeds {NONGAIT_SEEDS[0]}-{NONGAIT_SEEDS[-1]}")
    print(f"(gestures {today['gestures']:.3f}, desk {today['desk']:.3f}); {len(admissible)} of {len(rates)} settings.\n")
    print("Leave-one-person-out: the admissible setting chosen on the other two people, scored on the person left out")
    print("(setting = " + ", ".join(GRID) + ")\n")
    print(lopo_markdown(grid, admissible))
    print("\nThe same, every setting allowed (the simulated non-gait not weighed):\n")
    print(lopo_markdown(grid, set(grid)))
    print("\nEvery setting on all three people (in sample), best first:\n")
    print(insample_markdown(grid, rates, admissible))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
