"""The per-step diagnosis helpers of tyrex_steps_texting, on made-up steps (no data needed)."""

import numpy as np

from experiments.scripts.tyrex_steps_octave import match_steps
from experiments.scripts.tyrex_steps_texting import chance_hits, match_flags, near, phase_in_step, step_rms, window_class


def test_match_flags_counts_as_match_steps():
    rng = np.random.default_rng(0)
    ref = np.cumsum(rng.uniform(0.5, 1.1, 80))
    t = np.sort(np.concatenate([ref[::2] + rng.normal(0, 0.05, 40), rng.uniform(0, ref[-1], 30)]))
    hit, matched = match_flags(t, ref)
    h, e, m = match_steps(t, ref)
    assert hit.sum() == matched.sum() == h
    assert (~matched).sum() == e and (~hit).sum() == m


def test_near_is_not_one_to_one():
    ref = np.array([1.0, 1.3])
    assert near(ref, np.array([1.15])).all()
    assert match_flags(np.array([1.15]), ref)[0].sum() == 1


def test_window_class_reads_the_octave():
    assert window_class(0.5, 0.8, 1.0) == "half"
    assert window_class(1.0, 0.8, 1.0) == "match"
    assert window_class(2.0, 0.8, 1.0) == "stride"
    assert window_class(1.0, 0.1, 1.0) == "low periodicity"


def test_phase_in_step():
    ref = np.array([0.0, 1.0, 3.0])
    assert phase_in_step(ref, 0.5) == 0.5
    assert phase_in_step(ref, 2.0) == 0.5
    assert np.isnan(phase_in_step(ref, -1.0)) and np.isnan(phase_in_step(ref, 4.0))


def test_chance_is_below_aligned_for_a_tight_window():
    rng = np.random.default_rng(1)
    ref = np.cumsum(rng.uniform(0.9, 1.1, 100))
    t = ref + 0.02
    aligned = match_flags(t, ref, 0.15)[0].sum()
    chance = chance_hits(t, ref, (ref[0], ref[-1]), tol=0.15)
    assert aligned == len(ref)
    assert chance < 0.6 * len(ref)


def test_step_rms_reads_the_quieter_side():
    fs = 100.0
    y = np.concatenate([np.full(200, 0.1), np.full(200, 1.0)]) * np.tile([1.0, -1.0], 200)
    assert abs(step_rms([(0.0, fs, y)], 2.0, 1.0) - 0.1) < 1e-9
    assert np.isnan(step_rms([(0.0, fs, y)], 0.5, 1.0))


def test_bad_keywords_are_refused_before_any_data_is_read(tmp_path, capsys):
    from experiments.scripts.tyrex_steps_texting import main

    assert main(["--data", str(tmp_path), "--set", "no_such_keyword=1"]) == 2
    assert "no_such_keyword" in capsys.readouterr().err
    assert main(["--data", str(tmp_path), "--min-rms", "-1"]) == 2
    assert main(["--data", str(tmp_path), "--set", "min_rms_ms2"]) == 2
    # a valid keyword with no data: the data error, one line
    assert main(["--data", str(tmp_path), "--set", "min_rms_ms2=0.15"]) == 2
    assert "tyrex-attitude" in capsys.readouterr().err
