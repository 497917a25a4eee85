"""Adaptive's noise floor (stage 4, ``min_rms_ms2``) chosen leave-one-person-out on the tyrex recordings (issue 30).

The texstep diagnosis (``experiments/reports/tyrex-steps.md``, "texstep helper") found 125 of the 545 Texting steps
adaptive misses removed by the noise floor alone (the band-passed |acc| RMS one step period either side of a peak must
reach ``MIN_RMS_MS2`` = 0.2 m/s^2), calm hand-held steps at 0.13-0.26 m/s^2. The rule fixed before measuring (same
section): grid :data:`GRID` (0.2 today, 0.15, 0.1: three and two times the noisiest phone accelerometer's noise);
*admissible* = no more raw and no more confident steps/min than today on the simulated non-gait selection seeds 0-39
(gestures and desk); per person left out, the admissible setting best on the other two
(:func:`experiments.scripts.tyrex_steps_lopo._score`; today wins ties) scored on the third. Adopted only if N1-N7 hold:

- N1 pooled held-out score above today's; N2 no left-out person below today's by more than
  :data:`~experiments.scripts.tyrex_steps_joint.MAX_PERSON_LOSS`;
- N3 no walking motion's pooled held-out mean count accuracy below today's by more than :data:`MAX_WALK_LOSS`, both
  running motions >= 0.95, every motion >= AD-FSM's;
- N4-N6 for the setting that would ship: held-out non-gait seeds 100-119 raw and confident steps/min not above today's;
  the simulated slow walkers' held-out seeds not below today's; Oxford and IFSM mean count accuracy not below today's;
- N7 is ``python -m benchmarks.steps`` (run apart).

Detector runs are cached per setting in ``--cache`` (pickles keyed by the setting: empty the folder after any change
to ``gaitml``).

    python -m experiments.scripts.tyrex_steps_floor --data ../shared/data --cache /tmp/floor      # ~2 min, seconds cached
    python -m experiments.scripts.tyrex_steps_floor --data ../shared/data --cache /tmp/floor --check F0.1   # N4-N6 alone
    python -m experiments.scripts.tyrex_steps_floor --data ../shared/data --cache /tmp/floor --round 2     # round 2
    python -m experiments.scripts.tyrex_steps_floor --data ../shared/data --cache /tmp/perio --round 3     # round 3 (perio)

Round 3 (perio helper, same report): the periodicity floor's gyroscope relief, ``rhythm_min_periodicity`` 0.2 / 0.15
(rule P1-P7: N1-N7 with Oxford / IFSM also unchanged file by file, :data:`GYRO_ONLY`).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import pandas as pd

from experiments.scripts.tyrex_steps_bouts import KINDS, admissible_set, no_gyroscope, nongait_rates, slow_walkers
from experiments.scripts.tyrex_steps_joint import (
    HELDOUT_SEEDS,
    RUNNING,
    SELECTION_SEEDS,
    STEP_MOTIONS,
    _cached,
    f1,
    frame,
    nongait_recordings,
    per_motion,
    step_times,
)
from experiments.scripts.tyrex_steps_joint import lopo as joint_lopo
from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED, _load, _score

OFF = "off"
#: the grids fixed before measuring (report, texstep section). Round 1: the floor itself at today's 0.2 m/s^2 and 0.15 /
#: 0.1 (three / two times the noisiest phone accelerometer's 0.05 m/s^2 RMS in the gait band). Round 2: the floor
#: scaled with the square of the step frequency below 1.2 steps/s, down to 0.15 / 0.1 (``min_rms_slow_ms2``,
#: :func:`gaitml.steps.adaptive.slow_step_noise_floor`). Everything else at the defaults
ROUNDS: dict[int, dict[str, dict]] = {
    1: {OFF: {}, "F0.15": {"min_rms_ms2": 0.15}, "F0.1": {"min_rms_ms2": 0.1}},
    2: {OFF: {}, "S0.15": {"min_rms_slow_ms2": 0.15}, "S0.1": {"min_rms_slow_ms2": 0.1}},
    #: round 3 (perio helper): the periodicity floor's gyroscope relief down to 0.2 / 0.15 (``rhythm_min_periodicity``,
    #: :func:`gaitml.steps.adaptive.rhythm_windows`; off at its default 0), ``rhythm_step_tolerance`` 0.25
    3: {OFF: {}, "P0.2": {"rhythm_min_periodicity": 0.2}, "P0.15": {"rhythm_min_periodicity": 0.15}},
}
#: settings that cannot change a recording without a gyroscope: their Oxford / IFSM check (N6 / P6) also needs no file
#: changed
GYRO_ONLY = frozenset({"P0.2", "P0.15"})
GRID: dict[str, dict] = {k: v for grid in ROUNDS.values() for k, v in grid.items()}
#: N3: the most a walking motion's pooled held-out count accuracy may fall below today's
MAX_WALK_LOSS = 0.002
WALKING = tuple(m for m in SCORED if m not in RUNNING)


def choose(grid: dict[str, pd.DataFrame], allowed: set[str], people=None) -> str:
    """The allowed setting with the best score on ``people`` (all if None); today wins ties, then grid order."""

    def s(k):
        d = grid[k] if people is None else grid[k][grid[k]["person"].isin(people)]
        return _score(d)

    return max((k for k in GRID if k in allowed and k in grid), key=s)


def lopo(grid: dict[str, pd.DataFrame], allowed: set[str], adfsm: pd.DataFrame | None = None) -> tuple[str, dict[str, bool], list[str]]:
    """Per person left out: the allowed setting chosen on the other two, its held-out figures (cells: chosen
    (today)), and N1-N3 (:func:`experiments.scripts.tyrex_steps_joint.lopo` with this grid's choice, names and N3:
    no walking motion more than ``MAX_WALK_LOSS`` below today, running at its floor)."""
    return joint_lopo(
        grid,
        allowed,
        adfsm,
        off_key=OFF,
        chooser=choose,
        label=str,
        rule="N",
        off_label="today",
        max_loss=MAX_WALK_LOSS,
        loss_motions=WALKING,
    )


def insample(grid: dict[str, pd.DataFrame], rates: dict[str, dict[str, float]], allowed: set[str]) -> str:
    """Every setting on all three people, with its non-gait rates on the selection seeds."""
    cols = ["setting", "admissible", "gestures /min (confident)", "desk /min (confident)", "score", *SCORED, "F1 Texting", "F1 Phoning"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for k in grid:
        per, r = per_motion(grid[k]), rates[k]
        cells = [k, "yes" if k in allowed else "no"]
        cells += [f"{r[kind]:.3f} ({r[kind + '_confident']:.3f})" for kind in KINDS]
        cells += [f"{_score(grid[k]):.4f}", *(f"{per[m]:.3f}" for m in SCORED), *(f"{f1(grid[k], m):.3f}" for m in STEP_MOTIONS)]
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def per_person(grid: dict[str, pd.DataFrame]) -> str:
    """Count accuracy per motion and person, and per-step hits / extras / misses on Texting, every setting (in sample)."""
    cols = ["setting", "person", *SCORED, "score", "Texting hits / extras / misses"]
    out = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for k, df in grid.items():
        for person in PEOPLE:
            d = df[df["person"] == person]
            per = per_motion(d)
            t = d[d["motion"] == "Texting"]
            hem = f"{int(t['hits'].sum())} / {int(t['extras'].sum())} / {int(t['misses'].sum())}"
            out.append("| " + " | ".join([k, person, *(f"{per[m]:.3f}" for m in SCORED), f"{_score(d):.4f}", hem]) + " |")
    return "\n".join(out)


def heldout_checks(key: str, data: str | Path, cache: Path | None) -> tuple[list[str], dict[str, bool]]:
    """N4-N6 for setting ``key`` against today: held-out non-gait seeds, slow walkers' held-out seeds, Oxford and IFSM."""
    import numpy as np

    ho = nongait_recordings(HELDOUT_SEEDS, cache)
    h0 = _cached(cache, "nongait_heldout_off", lambda: nongait_rates(ho, HELDOUT_SEEDS, **GRID[OFF]))
    h1 = _cached(cache, f"nongait_heldout_{key}", lambda: nongait_rates(ho, HELDOUT_SEEDS, **GRID[key]))
    s0, s1 = slow_walkers(OFF, cache, GRID[OFF]), slow_walkers(key, cache, GRID[key])
    ox = no_gyroscope(data, key, GRID[key], GRID[OFF])
    checks = {
        "N4": all(h1[c] <= h0[c] + 1e-9 for kind in KINDS for c in (kind, f"{kind}_confident")),
        "N5": all(np.mean(s1[p]) >= np.mean(s0[p]) - 1e-12 for p in s0),
        "N6": ox["setting"] >= ox["off"] - 1e-12 and (key not in GYRO_ONLY or ox["changed"] == 0),
    }
    lines = [f"Held-out checks for {key} (today -> it):"]
    for kind in KINDS:
        lines.append(
            f"- non-gait {kind}, seeds 100-119: raw {h0[kind]:.3f} (worst {h0[kind + '_max']:.1f}) -> {h1[kind]:.3f} "
            f"(worst {h1[kind + '_max']:.1f}) steps/min; confident {h0[kind + '_confident']:.3f} -> {h1[kind + '_confident']:.3f}"
        )
    for p in s0:
        lines.append(
            f"- slow walkers {p}, seeds 100-119: {np.mean(s0[p]):.3f} (worst {np.min(s0[p]):.3f}) -> {np.mean(s1[p]):.3f} (worst {np.min(s1[p]):.3f})"
        )
    lines.append(
        f"- Oxford and IFSM: {ox['files']} files ({ox['counted']} with a true count), mean count accuracy {ox['off']:.5f} -> "
        f"{ox['setting']:.5f}; files whose step times change: {ox['changed']}"
    )
    return lines, checks


def main(argv: list[str] | None = None) -> int:
    """Print admissibility, the leave-one-person-out choice with N1-N3, in sample, and N4-N6 for the setting that would ship."""
    ap = argparse.ArgumentParser(prog="python -m experiments.scripts.tyrex_steps_floor", description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data")
    ap.add_argument("--cache", default=None, help="folder for the per-setting detector runs and simulated recordings (pickles)")
    ap.add_argument("--check", default=None, help=f"only N4-N6 for one setting, one of {', '.join(k for k in GRID if k != OFF)}")
    ap.add_argument("--round", type=int, choices=tuple(ROUNDS), default=1, help="the grid of round 1, 2 or 3 (report)")
    a = ap.parse_args(argv)
    if a.check is not None and (a.check not in GRID or a.check == OFF):
        print(f"error: --check must be one of {', '.join(k for k in GRID if k != OFF)}, got {a.check!r}", file=sys.stderr)
        return 2
    if not (Path(a.data) / "tyrex-attitude").is_dir():
        print(f"error: no tyrex-attitude folder under {a.data}; pass --data pointing at the shared data folder", file=sys.stderr)
        return 2
    cache = Path(a.cache) if a.cache else None
    if a.check is not None:
        lines, checks = heldout_checks(a.check, a.data, cache)
        print("\n".join(lines))
        print("\nChecks: " + ", ".join(f"{c} {'pass' if v else 'FAIL'}" for c, v in checks.items()))
        return 0
    ng = nongait_recordings(SELECTION_SEEDS, cache)
    keys = list(ROUNDS[a.round])
    rates = {k: _cached(cache, f"nongait_sel_{k}", lambda k=k: nongait_rates(ng, SELECTION_SEEDS, **GRID[k])) for k in keys}
    allowed = admissible_set(rates)
    items = _load(a.data)
    grid = {}
    for k in keys:
        grid[k] = frame(items, _cached(cache, f"tyrex_{k}", lambda k=k: step_times(items, **GRID[k])))
        r = rates[k]
        print(
            f"{k}: {_score(grid[k]):.4f}, gestures {r['gestures']:.3f} ({r['gestures_confident']:.3f}), desk {r['desk']:.3f}",
            file=sys.stderr,
        )
    adfsm = frame(items, _cached(cache, "tyrex_adfsm", lambda: step_times(items, "adfsm")))
    r0 = rates[OFF]
    print(
        f"Admissible: no more raw and confident steps/min than today on the simulated non-gait seeds 0-39 (gestures "
        f"{r0['gestures']:.3f} ({r0['gestures_confident']:.3f}), desk {r0['desk']:.3f} ({r0['desk_confident']:.3f})): "
        f"{', '.join(k for k in keys if k in allowed)}.\n"
    )
    print("Leave-one-person-out, admissible settings only (cells: held out with the chosen setting (today)):\n")
    table, checks, _ = lopo(grid, allowed, adfsm)
    print(table)
    ship = choose(grid, allowed)
    print(f"\nSetting that would ship (admissible, best on all three people): {ship} ({_score(grid[ship]):.4f})")
    print("\nThe same with every setting allowed (non-gait not weighed; for the record):\n")
    print(lopo(grid, set(grid), adfsm)[0])
    print("\nIn sample (all three people):\n")
    print(insample(grid, rates, allowed))
    print("\nPer person, in sample:\n")
    print(per_person(grid))
    if ship != OFF:
        lines, more = heldout_checks(ship, a.data, cache)
        checks.update(more)
        print("\n".join(["", *lines]))
    print("\nAdoption checks: " + ", ".join(f"{c} {'pass' if v else 'FAIL'}" for c, v in checks.items()))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
