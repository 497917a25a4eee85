"""The pseudo-std detector's interval rules (gaitml.zupt): merge a spike inside a stance, drop a dip inside a swing."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.zupt import PseudoStdZuptDetector, clean_stances, mask_runs, merge_short_gaps

FS = 100.0


def _foot(stance_s=0.5, swing_s=0.6, n_strides=6, *, spike_in_stance=False, reversal_in_swing=False, seed=0) -> tuple[Recording, list]:
    """Stances (still foot) and swings (one sagittal rotation); optional defects.

    ``spike_in_stance``: a 30 ms gyro spike (4 rad/s, as at a heel strike) in the middle of every stance.
    ``reversal_in_swing``: the swing rotation changes sign in mid-swing, so the gyro
    magnitude passes through zero there (as on stairs).
    Returns the recording and the true stance intervals (samples).
    """
    rng = np.random.default_rng(seed)
    parts, stances, t0 = [], [], 0
    n_st, n_sw = int(stance_s * FS), int(swing_s * FS)
    for _ in range(n_strides):
        st = np.zeros(n_st)
        if spike_in_stance:
            st[n_st // 2 - 1 : n_st // 2 + 2] = 4.0
        u = np.linspace(0, 1, n_sw, endpoint=False)
        sw = 5.0 * np.sin(np.pi * u)
        if reversal_in_swing:
            sw = 5.0 * np.sin(2 * np.pi * u)  # + then -, through zero at mid-swing
        stances.append((t0, t0 + n_st))
        parts += [st, sw]
        t0 += n_st + n_sw
    w = np.concatenate(parts + [np.zeros(n_st)])
    stances.append((t0, t0 + n_st))
    gyr = np.column_stack([0.05 * w, w, 0.02 * w]) + rng.normal(0, 0.005, (len(w), 3))
    acc = np.column_stack([3.0 * np.abs(w), np.zeros_like(w), np.full_like(w, GRAVITY_MS2)]) + rng.normal(0, 0.02, (len(w), 3))
    return Recording(acc=acc, gyr=gyr, sampling_rate_hz=FS, meta={"id": "foot"}, check_units=False), stances


def _n_intervals_per_stance(det, stances):
    s, e = mask_runs(det.per_sample_zupts_)
    return [int(np.sum((s < b) & (e > a))) for a, b in stances]


def test_spike_inside_a_stance_is_merged():
    rec, stances = _foot(spike_in_stance=True)
    raw = PseudoStdZuptDetector(merge_gap_s=0, min_interval_s=0).detect(rec)
    assert max(_n_intervals_per_stance(raw, stances)) == 2  # the paper's per-sample rule splits every stance
    det = PseudoStdZuptDetector().detect(rec)
    assert _n_intervals_per_stance(det, stances) == [1] * len(stances)
    assert len(det.zupts_) == len(stances)


def test_real_swing_is_kept_and_a_swing_dip_dropped():
    rec, stances = _foot(reversal_in_swing=True)
    raw = PseudoStdZuptDetector(merge_gap_s=0, min_interval_s=0).detect(rec)
    assert len(raw.zupts_) > len(stances)  # the mid-swing reversal dips below the threshold
    det = PseudoStdZuptDetector().detect(rec)
    assert len(det.zupts_) == len(stances)  # dips dropped, swings never merged over
    assert _n_intervals_per_stance(det, stances) == [1] * len(stances)
    # every swing stays a gap: no interval spans two stances
    s, e = mask_runs(det.per_sample_zupts_)
    for (_a0, b0), (a1, _b1) in zip(stances[:-1], stances[1:], strict=True):
        assert not np.any((s < b0) & (e > a1))


def test_short_stances_of_a_fast_gait_survive():
    # 0.2 s foot-flat between 0.35 s swings (a jog): longer than one window, kept
    rec, stances = _foot(stance_s=0.2, swing_s=0.35, n_strides=8)
    det = PseudoStdZuptDetector().detect(rec)
    assert _n_intervals_per_stance(det, stances) == [1] * len(stances)


def test_rule_lengths_default_to_one_window_and_validate():
    rec, _ = _foot()
    det = PseudoStdZuptDetector().detect(rec)
    assert det.merge_gap_samples_ == det.min_interval_samples_ == 11  # 2 s + 1 at s = 5 (100 Hz)
    det = PseudoStdZuptDetector(merge_gap_s=0.2, min_interval_s=0.05).detect(rec)
    assert (det.merge_gap_samples_, det.min_interval_samples_) == (20, 5)
    with pytest.raises(InputError, match="min_interval_s"):
        PseudoStdZuptDetector(min_interval_s=-0.1).detect(rec)
    with pytest.raises(InputError, match="merge_gap_s"):
        PseudoStdZuptDetector(merge_gap_s="x").detect(rec)


def test_merge_short_gaps_and_clean_stances_known_answer():
    m = np.zeros(40, bool)
    m[0:3] = m[5:12] = m[14:15] = m[30:38] = True
    # gaps: 3-5 (2), 12-14 (2), 15-30 (15); edges 38-40 stay
    assert np.flatnonzero(merge_short_gaps(m, 2) != m).tolist() == [3, 4, 12, 13]
    assert merge_short_gaps(m, 0).tolist() == m.tolist()
    out = clean_stances(m, merge_gap_samples=2, min_interval_samples=5)
    s, e = mask_runs(out)
    assert list(zip(s.tolist(), e.tolist(), strict=True)) == [(0, 15), (30, 38)]
    # dropping alone would lose the two short pieces of the first stance
    s, e = mask_runs(clean_stances(m, merge_gap_samples=0, min_interval_samples=5))
    assert list(zip(s.tolist(), e.tolist(), strict=True)) == [(5, 12), (30, 38)]


def _clean_stances_loop(mask, gap, shortest):
    """Plain reference: walk the samples, fill bounded gaps of <= gap, then drop runs < shortest."""
    m = list(bool(x) for x in mask)
    n = len(m)
    i = 0
    seen_true = False
    while i < n:
        if m[i]:
            seen_true = True
            i += 1
            continue
        j = i
        while j < n and not m[j]:
            j += 1
        if seen_true and j < n and j - i <= gap:
            for k in range(i, j):
                m[k] = True
        i = j
    out = [False] * n
    i = 0
    while i < n:
        if not m[i]:
            i += 1
            continue
        j = i
        while j < n and m[j]:
            j += 1
        if j - i >= shortest:
            out[i:j] = [True] * (j - i)
        i = j
    return np.array(out, dtype=bool)


@pytest.mark.parametrize("seed", range(5))
def test_clean_stances_equals_a_plain_loop(seed):
    rng = np.random.default_rng(seed)
    # runs of random lengths, alternating
    lengths = rng.integers(1, 25, 60)
    m = np.repeat(np.arange(60) % 2 == (seed % 2), lengths)
    for gap, shortest in [(0, 0), (5, 0), (0, 7), (5, 7), (11, 11)]:
        np.testing.assert_array_equal(
            clean_stances(m, merge_gap_samples=gap, min_interval_samples=shortest), _clean_stances_loop(m, gap, shortest)
        )
