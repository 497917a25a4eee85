"""The Oxford walking labels of experiments.scripts.oxford_walk: walk inside stretches of true steps only."""

from __future__ import annotations

import numpy as np

from experiments.scripts.oxford_walk import MAX_STEP_GAP_S, STEP_PAD_S, walking_labels
from gaitml.recording import Recording


def _rec(steps_t_s, duration_s=60.0, fs=50.0):
    acc = np.tile([0.0, 0.0, 9.81], (int(duration_s * fs), 1))
    return Recording(acc, sampling_rate_hz=fs, reference={"steps_t_s": np.asarray(steps_t_s, float)})


def test_walk_only_inside_the_stretches_of_steps():
    # steps every 0.55 s over 5-20 s and 35-50 s, standing between and at both ends
    steps = np.r_[np.arange(5.0, 20.0, 0.55), np.arange(35.0, 50.0, 0.55)]
    rec = _rec(steps)
    lab = walking_labels(rec)
    t = rec.t_s
    walk = lab == "walk"
    assert set(np.unique(lab.astype(str))) == {"walk", "unlabelled"}
    # every sample between two steps of a stretch is walk
    inside = ((t >= 5.0) & (t <= steps[steps < 20.0][-1])) | ((t >= 35.0) & (t <= steps[-1]))
    assert walk[inside].all()
    # the pause (longer than MAX_STEP_GAP_S) and the ends, beyond the padding, are not
    assert 30.0 - 20.0 > MAX_STEP_GAP_S
    outside = (t < 5.0 - STEP_PAD_S - 0.05) | ((t > 20.0 + STEP_PAD_S) & (t < 35.0 - STEP_PAD_S - 0.05)) | (t > 50.0 + STEP_PAD_S)
    assert not walk[outside].any()


def test_no_steps_no_walk():
    assert not (walking_labels(_rec([])) == "walk").any()
    assert not (walking_labels(_rec([12.0])) == "walk").any()
