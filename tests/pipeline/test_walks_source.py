"""[data.walks]: real walking with true step times added to a folder config as walk windows."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import ConfigError
from gaitml.pipeline.runner import WALK_MAX_STEP_GAP_S, WALK_STEP_PAD_S, step_walking_labels
from gaitml.recording import Recording


def _rec(steps_t_s, duration_s=60.0, fs=50.0):
    acc = np.tile([0.0, 0.0, 9.81], (int(duration_s * fs), 1))
    return Recording(acc, sampling_rate_hz=fs, reference={"steps_t_s": np.asarray(steps_t_s, float)})


def test_walk_only_inside_the_stretches_of_steps():
    # steps every 0.55 s over 5-20 s and 35-50 s; standing between and at both ends
    steps = np.r_[np.arange(5.0, 20.0, 0.55), np.arange(35.0, 50.0, 0.55)]
    rec = _rec(steps)
    lab = step_walking_labels(rec)
    t = rec.t_s
    walk = lab == "walk"
    assert set(np.unique(lab.astype(str))) == {"walk", "unlabelled"}
    inside = ((t >= 5.0) & (t <= steps[steps < 20.0][-1])) | ((t >= 35.0) & (t <= steps[-1]))
    assert walk[inside].all()
    assert 35.0 - 20.0 > WALK_MAX_STEP_GAP_S
    pad = WALK_STEP_PAD_S + 0.05
    outside = (t < 5.0 - pad) | ((t > steps[steps < 20.0][-1] + pad) & (t < 35.0 - pad)) | (t > steps[-1] + pad)
    assert not walk[outside].any()


def test_no_steps_no_walk():
    assert not (step_walking_labels(_rec([])) == "walk").any()
    assert not (step_walking_labels(_rec([12.0])) == "walk").any()


def test_walks_config_checks(tmp_path):
    from gaitml.pipeline.config import load_config

    (tmp_path / "data").mkdir()
    p = tmp_path / "c.toml"
    p.write_text('name = "w"\n[data]\nsource = "folder"\npath = "data"\n[data.walks]\npath = "nowhere"\n')
    with pytest.raises(ConfigError, match="data.walks.path"):
        load_config(p)
    p.write_text('name = "w"\n[data]\nsource = "folder"\npath = "data"\n[data.walks]\npath = "data"\nweight = 0\n')
    with pytest.raises(ConfigError, match="weight"):
        load_config(p)
    p.write_text('name = "w"\n[data]\nsource = "simulated"\n[data.walks]\npath = "data"\n')
    with pytest.raises(ConfigError, match="data.walks.path"):
        load_config(p)
    p.write_text('name = "w"\n[data]\nsource = "folder"\npath = "data"\n[data.walks]\npath = "data"\nweight = 3\n')
    assert load_config(p)["data"]["walks"]["weight"] == 3
