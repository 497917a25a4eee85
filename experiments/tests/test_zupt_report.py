"""The tables of experiments/scripts/zupt_report.py: held-out protocol, label-free counts, the gaitmap step count."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts.zupt_report import (
    TRIALS,
    heldout_fit_table,
    ic_stride_counts,
    running_table,
    swing_bracketed_counts,
    synthetic_running_foot,
    trial_table,
)
from experiments.tests.conftest import shared
from gaitml.recording import Recording
from tests.synthetic import synthetic_foot_walk


def _mask(n, runs):
    m = np.zeros(n, bool)
    for a, b in runs:
        m[a:b] = True
    return m


def test_swing_bracketed_counts_known_answer():
    rec = synthetic_foot_walk(600, 100.0)  # swings peak at phase 0.7 of each 1 s stride: 70, 170, ...
    # one interval between peaks 1-2, two between 2-3, none between 3-4, one between 4-5
    m = _mask(600, [(100, 140), (200, 220), (225, 240), (400, 440)])
    r = swing_bracketed_counts(rec, m)
    assert r["n_stances"] == 5  # 6 swing peaks
    assert (r["n_spurious"], r["n_missed"]) == (1, 2)  # 2-3 split; 3-4 and 5-6 empty
    assert r["spurious_per_stance"] == pytest.approx(1 / 5)


def test_ic_stride_counts_known_answer():
    rec = synthetic_foot_walk(600, 100.0)
    rec = Recording(
        acc=rec.acc, gyr=rec.gyr, sampling_rate_hz=100.0, meta={"id": "x"}, check_units=False,
        reference={"strides": pd.DataFrame({"start": [0, 100, 200], "end": [100, 200, 300]})},
    )  # fmt: skip
    # midpoints 20 (stride 0), 120 and 180 (stride 1: one spurious), none in stride 2
    r = ic_stride_counts(rec, _mask(600, [(10, 30), (110, 130), (170, 190), (290, 330)]))
    assert (r["n_stances"], r["n_spurious"], r["n_missed"]) == (3, 1, 1)  # 290-330: midpoint 310 is past stride 2
    r = ic_stride_counts(rec, _mask(600, [(10, 30)]))
    assert (r["n_spurious"], r["n_missed"], r["stance_hit_rate"]) == (0, 2, pytest.approx(1 / 3))


def test_synthetic_running_foot_sanity():
    rec, flats = synthetic_running_foot(n_strides=10, seed=1)
    assert len(flats) == 10 and rec.duration_s == pytest.approx(7.0, rel=0.1)
    g = np.linalg.norm(rec.gyr, axis=1)
    for a, b in flats:
        assert g[a:b].max() < np.radians(5)  # the foot is still
    rows = running_table(seeds=(0,), foot_flats_s=(0.15,))
    after = next(r for r in rows if "after" in r["variant"])
    before = next(r for r in rows if "before" in r["variant"])
    assert after["stance_hit_rate"] == 1.0 and after["spurious_per_stance"] == 0.0
    assert before["spurious_per_stance"] > 0.5  # the swing reversal dips under the threshold


@pytest.mark.realdata
def test_heldout_protocol_on_gaitmap():
    folder = shared("gaitmap-example", "imu_sample.csv.gz").parent
    rows = heldout_fit_table(folder)
    lofo = [r for r in rows if r["protocol"] == "leave-one-foot-out"]
    assert {r["detector"] for r in lofo} == {"pseudo-std", "magnitude", "shoe"}
    for r in lofo:
        foot = r["test"].split()[-1]
        assert r["in_sample_fit_on"] == foot and r["held_out_fit_on"] != foot
        assert r["in_sample_threshold"] != r["held_out_threshold"]  # fitted on different feet
    ps = {r["test"]: r for r in lofo if r["detector"] == "pseudo-std"}
    for r in ps.values():  # measured: 1.000 both ways; spurious 0.034 (left) and 0.000 (right) both ways
        assert r["held_out_min_vel_hit_rate"] == 1.0 and r["held_out_spurious_per_stance"] <= 0.05
    loto = [r for r in rows if r["protocol"].startswith("leave-one-trial-out")]
    assert len(loto) == 3 * (len(TRIALS) - 2) and all(r["held_out_fit_on"] == "walk" for r in loto)


@pytest.mark.realdata
def test_trial_table_before_after():
    folder = shared("gaitmap-example", "imu_sample.csv.gz").parent
    rows = {(r["trial"], r["foot"], r["variant"].split()[0]): r for r in trial_table(folder)}
    walk_l = rows[("walk", "left", "before")], rows[("walk", "left", "after")]
    assert walk_l[0]["spurious_per_stance"] == pytest.approx(2 / 29) and walk_l[1]["spurious_per_stance"] == pytest.approx(1 / 29)
    assert walk_l[1]["min_vel_hit_rate"] == 1.0
    stairs = [k for k in rows if k[0].startswith("healthy_stair")]
    before = sum(rows[k]["n_spurious"] for k in stairs if k[2] == "before")
    after = sum(rows[k]["n_spurious"] for k in stairs if k[2] == "after")
    assert after == 0 < before  # the rules remove every spurious stair interval the detector finds without them


@pytest.mark.realdata
def test_zupt_magnitude_step_count_within_one_of_strides():
    from experiments.scripts.zupt_report import step_count_table

    rows = step_count_table(shared("gaitmap-example", "imu_sample.csv.gz"))
    for row in rows:
        assert abs(row["n_steps_in_span"] - row["n_strides"]) <= 1, row
