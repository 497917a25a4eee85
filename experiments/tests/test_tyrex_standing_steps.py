"""The standing rule of tyrex_standing_steps on synthetic motion capture, its counting, and one real recording."""

from __future__ import annotations

import numpy as np
import pytest

from experiments.scripts import tyrex_standing_steps as ss
from experiments.tests.conftest import shared
from experiments.tests.mocap_fakes import circle_walk, held_out_phone


def test_a_stop_in_a_walk_is_one_stretch_trimmed_inside_the_stop():
    """Walk, stand 20-35 s, walk: one stretch, inside the stop by at least the trim at each end."""
    t, pos, rot, _ = circle_walk(seconds=60.0, standing=(20.0, 35.0))
    st = ss.standing_stretches(t, pos, rot, "FrontPocket")
    assert len(st) == 1
    a, b = st[0]
    assert a >= 20.0 + ss.TRIM_S - 1e-9 and b <= 35.0 - ss.TRIM_S + 1e-9
    assert b - a > 15.0 - 2 * ss.TRIM_S - 3.0  # the 0.5 Hz body track blurs each end by well under 1.5 s


def test_walking_throughout_has_no_stretch_and_a_short_stop_is_not_one():
    t, pos, rot, _ = circle_walk(seconds=40.0)
    assert ss.standing_stretches(t, pos, rot, "FrontPocket") == []
    t, pos, rot, _ = circle_walk(seconds=40.0, standing=(20.0, 21.5))  # 1.5 s stop < MIN_RUN_S
    assert ss.standing_stretches(t, pos, rot, "FrontPocket") == []


def test_turning_on_the_spot_with_the_phone_held_out_is_standing_only_with_the_lever_arm():
    """1 rad/s at 0.4 m: the phone sweeps 0.4 m/s, the person stands. AR (0.4 m arm) finds it; with no arm it is not."""
    t, pos, rot = held_out_phone(seconds=30.0, turn_rads=1.0, lever_m=0.4)
    st = ss.standing_stretches(t, pos, rot, "AR")
    assert len(st) == 1 and ss.minutes(st) * 60 > 20.0
    assert ss.standing_stretches(t, pos, rot, "Phoning") == []


def test_bobbing_in_the_step_band_is_not_standing():
    """Turning on the spot with 2 cm steps: the corrected point stays, but the bounce says steps."""
    t, pos, rot = held_out_phone(seconds=30.0, turn_rads=1.0, lever_m=0.4, bounce_cm=2.0)
    assert ss.standing_stretches(t, pos, rot, "AR") == []


def test_a_long_lost_frame_gap_breaks_a_stretch_a_short_one_does_not():
    t, pos, rot = held_out_phone(seconds=30.0, turn_rads=0.0, lever_m=0.4)
    for gap_s, n in ((1.0, 2), (0.1, 1)):
        p = pos.copy()
        p[(t >= 15.0) & (t < 15.0 + gap_s)] = np.nan
        assert len(ss.standing_stretches(t, p, rot, "AR")) == n


def test_runs_clip_inside_minutes():
    assert ss.runs(np.array([0, 1, 1, 0, 1], dtype=bool)) == [(1, 3), (4, 5)]
    assert ss.runs(np.zeros(3, dtype=bool)) == []
    assert ss.clip([(0.0, 10.0), (20.0, 30.0)], [(5.0, 25.0)]) == [(5.0, 10.0), (20.0, 25.0)]
    assert ss.inside(np.array([1.0, 5.0, 12.0]), [(0.0, 5.0), (10.0, 11.0)]).tolist() == [True, True, False]
    assert ss.minutes([(0.0, 30.0), (40.0, 70.0)]) == pytest.approx(1.0)


def test_count_rows_and_step_kinds_count_what_lies_inside():
    """Two standing stretches of 30 s; steps at known times; a chain that runs in from outside is an edge."""
    t = np.arange(0.0, 100.0, 0.1)
    walk = {"name": "r", "motion": "AR", "person": "P", "ref": {"t_s": np.array([5.0, 15.0]), "steps_per_event": 1}}
    st = [(10.0, 40.0), (60.0, 90.0)]
    stretches = {"r": {ss.MAX_SPEED_MS: st, "t": t, "bounce_cm": np.where(t < 50, 0.2, 0.8)}}
    steps = np.array([8.5, 9.5, 10.5, 11.5, 50.0, 70.0, 70.5, 71.0])  # 2 in a chain from outside, 3 wholly inside
    runs_ = {"d": {"r": {"t": steps, "confidence": np.full(len(steps), 0.6), "confident": np.zeros(len(steps), dtype=bool)}}}
    df = ss.count_rows([walk], stretches, runs_)
    row = df.iloc[0]
    assert row["minutes"] == pytest.approx(1.0) and row["steps"] == 5 and row["conf>=0.5"] == 5 and row["confident"] == 0
    assert row["mocap_steps"] == 1
    k = ss.step_kinds([walk], stretches, runs_).iloc[0]
    assert (k["steps"], k["edge"], k["inside"], k["bounce<0.5"], k["bounce 0.5-1"]) == (5, 2, 3, 2, 3)


def test_bad_data_folder_is_one_error(tmp_path, capsys):
    assert ss.main(["--data", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--data" in err
    assert list(tmp_path.iterdir()) == []


def test_a_real_stop_while_texting_is_found_inside_the_phone_segments():
    """Jakob stops while texting (report figure): the rule finds standing there, every stretch inside a phone segment,
    and the motion-capture step reference has no step inside."""
    from experiments.scripts.tyrex_steps import read_tyrex_walk

    folder = shared("tyrex-attitude", "ios", "Jakob_iPhone4S_NoDist_Texting")
    w = read_tyrex_walk(folder)
    tab = ss.stretch_table([w])["Jakob_iPhone4S_NoDist_Texting"]
    st = tab[ss.MAX_SPEED_MS]
    assert ss.minutes(st) * 60 >= 3.0
    spans = ss.segment_spans(w)
    assert all(any(c <= a and b <= d for c, d in spans) for a, b in st)
    assert not ss.inside(w["ref"]["t_s"], st).any()
    # the variant's looser speed only adds standing time
    assert ss.minutes(tab[ss.VARIANT_SPEED_MS]) >= ss.minutes(st)
