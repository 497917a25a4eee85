"""Config keys of step-synchronous windows and folder data: windows.by / windows.detector, data.manifest, [data.labelling]."""

from __future__ import annotations

import pytest

from gaitml.errors import ConfigError
from gaitml.pipeline import parse_config


def _cfg(**sections):
    raw = {"name": "x", "data": {"simulated": {"subjects": 2, "duration_s": 20.0}}}
    for k, v in sections.items():
        raw[k] = v
    return parse_config(raw)


def test_defaults_keep_time_windows():
    w = _cfg()["windows"]
    assert w["by"] == "time" and w["detector"] == ""


@pytest.mark.parametrize(
    "windows, match",
    [
        ({"by": "step"}, r"windows.by = 'step' is not allowed; allowed: 'time', 'steps', 'strides'"),
        ({"by": "steps", "detector": "pseudo-std"}, r"windows.detector = 'pseudo-std'.*not a step detector.*single-peak"),
        ({"by": "strides", "detector": "ifsm"}, r"windows.detector = 'ifsm'.*not a zero-velocity detector.*pseudo-std"),
        ({"by": "steps", "detector": "nonsense"}, r"not a step detector"),
        ({"by": 3}, r"windows.by = 3 has the wrong type"),
    ],
)
def test_bad_window_settings_are_one_line_config_errors(windows, match):
    with pytest.raises(ConfigError, match=match) as e:
        _cfg(windows=windows)
    assert "\n" not in str(e.value)


def test_detectors_from_the_right_registry_are_accepted():
    assert _cfg(windows={"by": "steps", "detector": "ifsm"})["windows"]["detector"] == "ifsm"
    assert _cfg(windows={"by": "strides", "detector": "shoe"})["windows"]["detector"] == "shoe"
    assert _cfg(windows={"by": "time", "detector": "ifsm"})["windows"]["by"] == "time"  # ignored by time windows


def test_a_sweep_over_windows_by_is_checked():
    cfg = _cfg(windows={"detector": "adfsm"}, sweep={"windows.by": ["time", "steps"]})
    assert cfg.sweep == {"windows.by": ["time", "steps"]}
    with pytest.raises(ConfigError, match="not a zero-velocity detector"):
        _cfg(windows={"detector": "adfsm"}, sweep={"windows.by": ["time", "strides"]})


def test_labelling_keys(tmp_path):
    base = {"name": "x", "data": {"source": "folder", "path": str(tmp_path)}}
    cfg = parse_config(base)
    assert cfg["data"]["labelling"] == {"snap": "steps", "detector": "", "max_snap_s": 0.5, "rule": "change", "moving_speed_ms": 0.0}
    assert "rule" not in cfg.resolved()["data"]["labelling"]  # written only when set: older configs resolve as before
    nearest = parse_config({**base, "data": {**base["data"], "labelling": {"rule": "nearest"}}})
    assert nearest.resolved()["data"]["labelling"]["rule"] == "nearest"
    with pytest.raises(ConfigError, match=r"data.labelling.rule = 'closest' is not allowed; allowed: 'change', 'nearest'"):
        parse_config({**base, "data": {**base["data"], "labelling": {"rule": "closest"}}})
    assert cfg["data"]["manifest"] == ""
    with pytest.raises(ConfigError, match=r"data.labelling.snap = 'step' is not allowed; allowed: 'steps', 'strides', 'none'"):
        parse_config({**base, "data": {**base["data"], "labelling": {"snap": "step"}}})
    with pytest.raises(ConfigError, match=r"data.labelling.detector = 'single-peak' is not a zero-velocity detector"):
        parse_config({**base, "data": {**base["data"], "labelling": {"snap": "strides", "detector": "single-peak"}}})
    with pytest.raises(ConfigError, match=r"data.manifest = 'recordings.csv' is not a file in .*; write the manifest") as e:
        parse_config({**base, "data": {**base["data"], "manifest": "recordings.csv"}})
    assert "\n" not in str(e.value)


def test_step_windows_refuse_the_gravity_frame():
    """Step windows compute their features in the phone frame only: the gravity frame is refused, not ignored."""
    with pytest.raises(ConfigError, match=r"windows.by = 'steps' computes the features in the phone frame only.*features.frame = 'phone'"):
        _cfg(windows={"by": "steps", "detector": "ifsm"}, features={"frame": "gravity"})
    with pytest.raises(ConfigError, match=r"phone frame only"):
        _cfg(windows={"detector": "ifsm"}, features={"frame": "gravity"}, sweep={"windows.by": ["time", "steps"]})
    assert _cfg(windows={"by": "time"}, features={"frame": "gravity"})["features"]["frame"] == "gravity"
