"""Lab tests of the noise-floor round's leave-one-person-out script (small, synthetic)."""

from __future__ import annotations

import pandas as pd

from experiments.scripts.tyrex_steps_floor import GRID, GYRO_ONLY, OFF, ROUNDS, admissible_set, choose, lopo
from experiments.scripts.tyrex_steps_lopo import PEOPLE, SCORED


def test_the_grids_are_the_ones_fixed_before_measuring():
    assert ROUNDS[1] == {OFF: {}, "F0.15": {"min_rms_ms2": 0.15}, "F0.1": {"min_rms_ms2": 0.1}}
    assert ROUNDS[2] == {OFF: {}, "S0.15": {"min_rms_slow_ms2": 0.15}, "S0.1": {"min_rms_slow_ms2": 0.1}}
    assert ROUNDS[3] == {OFF: {}, "P0.2": {"rhythm_min_periodicity": 0.2}, "P0.15": {"rhythm_min_periodicity": 0.15}}
    assert len(GRID) == 7  # today once, two settings per round
    # round 3's relief needs a gyroscope: its Oxford / IFSM check also needs no file changed (P6)
    assert GYRO_ONLY == {"P0.2", "P0.15"}


def _rates(g, d, gc=0.1, dc=0.5):
    return {"gestures": g, "desk": d, "gestures_confident": gc, "desk_confident": dc}


def test_admissible_needs_no_more_raw_and_no_more_confident_non_gait_steps():
    rates = {OFF: _rates(1.0, 3.0), "F0.15": _rates(1.0, 2.9), "F0.1": _rates(0.5, 2.0, dc=0.6)}
    assert admissible_set(rates) == {OFF, "F0.15"}


def _grid(change: dict[str, dict[str, float]], last_person_sign: float = -1.0) -> dict[str, pd.DataFrame]:
    """A frame per setting: every motion at 0.9 (running 0.96), plus ``change[setting][motion]`` for the first two
    people and ``last_person_sign`` times it for the third."""
    out = {}
    for k in [OFF, *change]:
        rows = []
        for i, p in enumerate(PEOPLE):
            for m in SCORED:
                g = change.get(k, {}).get(m, 0.0) * (1.0 if i < 2 else last_person_sign)
                acc = (0.96 if m.startswith("Running") else 0.9) + g
                rows.append({"recording": f"{p}{m}", "motion": m, "person": p, "n": 1, "acc": acc, "hits": 1, "extras": 0, "misses": 0})
        out[k] = pd.DataFrame(rows)
    return out


def test_choose_prefers_today_on_ties_and_never_an_inadmissible_setting():
    g = _grid({"F0.15": {}, "F0.1": {"Texting": 0.03}})
    assert choose(g, {OFF, "F0.15"}) == OFF
    assert choose(g, {OFF, "F0.1"}, people=PEOPLE[:2]) == "F0.1"
    assert choose(g, {OFF}, people=PEOPLE[:2]) == OFF


def test_lopo_passes_a_setting_better_for_everyone():
    g = _grid({"F0.15": {"Texting": 0.03}}, last_person_sign=1.0)
    _, checks, chosen = lopo(g, set(g))
    assert chosen == ["F0.15"] * 3
    assert all(checks.values())


def test_lopo_fails_n3_on_a_walking_motion_that_falls_more_than_the_tolerance():
    # the gain on Texting outweighs a loss of 0.004 on Swinging for everyone: N1 and N2 pass, N3 (0.002) does not
    g = _grid({"F0.15": {"Texting": 0.05, "Swinging": -0.004}}, last_person_sign=1.0)
    _, checks, _ = lopo(g, set(g))
    assert checks["N1"] and checks["N2"] and not checks["N3"]


def test_lopo_fails_n2_when_the_setting_chosen_on_two_costs_the_third():
    g = _grid({"F0.15": {"Texting": 0.05}})
    _, checks, chosen = lopo(g, set(g))
    assert chosen[-1] == "F0.15" and not checks["N2"]


def test_an_inadmissible_setting_leaves_today_everywhere():
    g = _grid({"F0.15": {"Texting": 0.05}}, last_person_sign=1.0)
    _, checks, chosen = lopo(g, {OFF})
    assert chosen == [OFF] * 3 and not checks["N1"]
