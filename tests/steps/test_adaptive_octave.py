"""adaptive's per-bout octave (stage 5a, opt-in): a bout read at two |acc| peaks per step is counted one step per step."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.recording import Recording
from gaitml.signal import bandpass
from gaitml.steps import get_detector
from gaitml.steps.adaptive import bout_octave, swing_projection

#: the opt-in setting of stage 5a with the short-bout exemption
ON = {"octave_swing_min_correlation": 0.5, "max_short_bout_interval_cv": 0.2}


def _slow_short_walk(seed: int, n_steps: int, swing_noise_rads: float = 0.5, step_s: float = 1.0, fs: float = 100.0, gyro: bool = True):
    """A short slow walk between two still stretches whose |acc| has two peaks per step (heel strike, push-off at 45 %
    of the step, nearly as high), the phone turning once per stride under rotation noise (a hand-held phone jiggled),
    so that the 5 s windows do not all see the swing's phase."""
    rng = np.random.default_rng(seed)
    pad = 10.0
    n = int((2 * pad + n_steps * step_s) * fs)
    t = np.arange(n) / fs
    steps = pad + step_s / 2 + np.arange(n_steps) * step_s + rng.normal(0, 0.02, n_steps)
    mag = np.zeros(n)
    for ts in steps:
        mag += 1.5 * np.exp(-0.5 * ((t - ts) / 0.05) ** 2) + 1.35 * np.exp(-0.5 * ((t - ts - 0.45 * step_s) / 0.05) ** 2)
    walking = (t >= pad) & (t <= pad + n_steps * step_s)
    jiggle = bandpass(rng.normal(0, 1, n), 0.3, 4.0, fs, order=2)
    swing = np.where(walking, 0.8 * np.sin(np.pi * (t - pad) / step_s), 0.0) + swing_noise_rads * jiggle / jiggle.std()
    acc = np.column_stack([np.zeros(n), np.zeros(n), 9.81 + mag]) + rng.normal(0, 0.05, (n, 3))
    gyr = np.column_stack([swing, np.zeros(n), np.zeros(n)]) + rng.normal(0, 0.02, (n, 3))
    rec = Recording.from_arrays(acc, fs, gyr=gyr) if gyro else Recording.from_arrays(acc, fs)
    return rec, n_steps


@pytest.mark.parametrize(("seed", "n_steps"), [(0, 8), (1, 8), (1, 20), (2, 20)])
def test_a_short_slow_walk_with_two_acc_peaks_per_step_is_counted_one_step_per_step(seed, n_steps):
    rec, n_true = _slow_short_walk(seed, n_steps)
    on = get_detector("adaptive", **ON).detect(rec)
    off = get_detector("adaptive").detect(rec)
    assert on.steps_.attrs["octave"]["half_steps"] >= 1  # the swing pooled over the bout decided it
    assert abs(len(on.steps_) - n_true) <= 1
    assert abs(len(on.steps_) - n_true) <= abs(len(off.steps_) - n_true)


def test_the_octave_stage_is_off_by_default_and_without_a_gyroscope():
    rec, _ = _slow_short_walk(0, 8)
    assert get_detector("adaptive").detect(rec).steps_.attrs["octave"] == {"half_steps": 0, "steps": 0, "undecided": 0}
    rec, _ = _slow_short_walk(0, 8, gyro=False)
    with pytest.warns(UserWarning, match="octave stage .* did not run: the recording has no gyroscope"):
        on = get_detector("adaptive", **ON).detect(rec)
    off = get_detector("adaptive").detect(rec)
    assert np.array_equal(on.steps_["t_peak_s"].to_numpy(), off.steps_["t_peak_s"].to_numpy())
    assert on.steps_.attrs["octave"] == {"half_steps": 0, "steps": 0, "undecided": 0}


def _bout(step_samples: float, peaks_per_step: int, fs: float = 25.0, swing_rads: float = 0.8, seconds: float = 12.0):
    """Peaks ``peaks_per_step`` per step of ``step_samples`` and a gyroscope turning once per two steps (or still)."""
    n = int(seconds * fs)
    pk = np.arange(int(fs), n - int(fs), step_samples / peaks_per_step).astype(np.int64)
    t = np.arange(n)
    g = np.column_stack([swing_rads * np.sin(np.pi * t / step_samples), np.zeros(n), np.zeros(n)])
    return pk, np.zeros(len(pk), dtype=np.int64), g


def test_bout_octave_reads_two_peaks_per_swing_step_as_half_steps_and_one_as_steps():
    fs = 25.0
    L = int(5 * fs)
    for per_step, expected in ((2, 2), (1, 1)):
        pk, bout, g = _bout(25.0, per_step)
        octave, step = bout_octave(pk, bout, g, 1, fs, L, swing_min_correlation=0.5)
        assert octave.tolist() == [expected]
        assert step[0] == pytest.approx(25.0, rel=0.1)  # the swing's step, half its stride period


def test_bout_octave_leaves_a_bout_without_a_regular_swing_undecided():
    fs = 25.0
    pk, bout, g = _bout(25.0, 2, swing_rads=0.0)
    assert bout_octave(pk, bout, g, 1, fs, int(5 * fs), swing_min_correlation=0.5)[0].tolist() == [0]  # still phone
    rng = np.random.default_rng(0)
    noise = np.column_stack([bandpass(rng.normal(0, 1, len(g)), 0.3, 4.0, fs, order=2), np.zeros(len(g)), np.zeros(len(g))])
    assert swing_projection(noise, len(g), 1, 1)[1][0] > 0.2  # it turns, irregularly
    assert bout_octave(pk, bout, noise, 1, fs, int(5 * fs), swing_min_correlation=0.5)[0].tolist() == [0]
    # off: nothing decided
    assert bout_octave(pk, bout, g, 1, fs, int(5 * fs), swing_min_correlation=0.0)[0].tolist() == [0]


def test_the_octave_stage_asked_for_with_the_gyroscope_off_says_it_did_not_run():
    """As the swing stage (2c) does: an opt-in stage that cannot run is said, not silently skipped."""
    rec, _ = _slow_short_walk(0, 8)
    with pytest.warns(UserWarning, match="octave stage .* did not run: use_gyroscope is False"):
        det = get_detector("adaptive", use_gyroscope=False, **ON).detect(rec)
    assert det.steps_.attrs["octave"] == {"half_steps": 0, "steps": 0, "undecided": 0}


def test_a_chunked_run_counts_the_octave_decisions_of_the_whole_file(tmp_path):
    """long_steps kept the last chunk's ``attrs['octave']`` (one bout of two here); each bout counts once."""
    from gaitml.chunked_run import long_steps
    from gaitml.io import read_recording, write_gaitml_csv

    a, _ = _slow_short_walk(0, 20)
    b, _ = _slow_short_walk(2, 20)
    p = tmp_path / "two.csv"
    write_gaitml_csv(Recording.from_arrays(np.vstack([a.acc, b.acc]), 100.0, gyr=np.vstack([a.gyr, b.gyr])), p)
    whole = get_detector("adaptive", **ON).detect(read_recording(p)).steps_
    assert whole.attrs["octave"]["half_steps"] == 2  # each 40 s walk is a bout read at two peaks per step
    for chunk_s, margin_s in ((40.0, 10.0), (20.0, 10.0)):
        chunked = long_steps(p, "adaptive", chunk_s=chunk_s, margin_s=margin_s, progress=False, detector_params=ON)
        assert chunked.attrs["octave"] == whole.attrs["octave"]
