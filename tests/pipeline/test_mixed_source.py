"""A folder of real recordings labelled by its motion capture's walking speed, plus simulated subjects (issue 27)."""

from __future__ import annotations

import numpy as np
import pytest

from gaitml.errors import ConfigError
from gaitml.evaluation.trajectory import moving_samples
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import prepare_data
from tests.io_apps.test_tyrex import android_folder, qualisys_csv

MODES = ["walk", "run", "side_left", "side_right", "backward"]


def _tyrex_root(tmp_path, *, truth=True):
    """One Android recording (30 s) whose capture stands 10 s (capture clock), then walks at 1 m/s."""
    android_folder(tmp_path, "Alice_Nexus5_NoDist_Texting", dt_s=-1.5)
    if truth:
        t = np.arange(0, 28, 1 / 60)
        x_mm = 1000 * np.clip(t - 10, 0, None)
        pos = np.column_stack([x_mm, np.zeros_like(t), np.full_like(t, 1200.0)])
        qualisys_csv(tmp_path, "Alice_Nexus5_NoDist_Texting", t, pos, np.tile(np.eye(3), (len(t), 1, 1)))
    return tmp_path


def _config(root, **data):
    raw = {
        "name": "mixed",
        "seed": 3,
        "data": {
            "source": "folder",
            "path": str(root),
            "label": "mode",
            "labels": MODES,
            "labelling": {"moving_speed_ms": 0.3},
            "add_simulated": True,
            "simulated": {"subjects": 2, "duration_s": 20.0, "positions": ["hand-flat", "front-pocket"]},
            **data,
        },
        "features": {"set": "all52+gyro"},
    }
    return parse_config(raw, base_dir=root)


def test_moving_samples_known_answer():
    tt = np.arange(0, 30, 1 / 60)
    xy = np.column_stack([np.clip(tt - 10, 0, 10), np.zeros_like(tt)])  # still 10 s, 1 m/s for 10 s, still 10 s
    q = np.array([-1.0, 5.0, 15.0, 25.0, 31.0])
    assert list(moving_samples(q, tt, xy)) == [-1, 0, 1, 0, -1]
    assert list(moving_samples(q, tt, xy, min_speed_ms=1.5)) == [-1, 0, 0, 0, -1]


def test_folder_labelled_by_the_walkers_speed_plus_simulated_subjects(tmp_path):
    data = prepare_data(_config(_tyrex_root(tmp_path)), use_cache=False)
    real = [r for r in data.recordings if r.meta.get("format") == "tyrex"]
    assert len(real) == 1 and len(data.recordings) == 1 + 2 * 2
    rec = real[0]
    # capture clock = phone clock - 1.5 s: standing until phone time 11.5 s, walking after
    t_phone = rec.t_s + rec.meta["t0_original_s"]
    lab = rec.labels.astype(str)
    assert set(lab[(t_phone > 3) & (t_phone < 10)]) == {"still"}
    assert set(lab[(t_phone > 14) & (t_phone < 28)]) == {"walk"}
    assert set(lab[t_phone > 29.6]) <= {"unlabelled"}
    assert "Alice" in data.groups and len(set(data.groups)) == 3
    assert any("motion capture" in n for n in data.notes) and any("added to the folder" in n for n in data.notes)
    sim_positions = sorted(r.meta["position"] for r in data.recordings if r is not rec)
    assert sim_positions == ["front-pocket", "front-pocket", "hand-flat", "hand-flat"]


def test_recordings_without_a_capture_are_left_out_or_refused(tmp_path):
    root = _tyrex_root(tmp_path / "a")
    android_folder(root, "Bob_Nexus5_NoDist_Swinging_old")  # the extra take: no motion capture
    data = prepare_data(_config(root), use_cache=False)
    assert [r.meta["subject"] for r in data.recordings if r.meta.get("format") == "tyrex"] == ["Alice"]
    assert any("1 without a motion capture left out" in n for n in data.notes)
    with pytest.raises(ConfigError, match="no recording has a motion capture"):
        prepare_data(_config(_tyrex_root(tmp_path / "b", truth=False)), use_cache=False)


@pytest.mark.parametrize(
    ("data", "pattern"),
    [
        ({"add_simulated": True}, r"data.add_simulated applies to data.source = 'folder'"),
        ({"labelling": {"moving_speed_ms": 0.3}}, r"data.labelling.moving_speed_ms applies to data.source = 'folder'"),
        ({"labelling": {"moving_speed_ms": -1.0}}, r"data.labelling.moving_speed_ms.*must be >= 0"),
    ],
)
def test_mixed_source_keys_need_a_folder(data, pattern):
    with pytest.raises(ConfigError, match=pattern):
        parse_config({"name": "x", "data": {"source": "simulated", **data}})


def test_a_recording_shorter_than_a_window_is_left_out_and_counted(tmp_path):
    """E.g. a 9-sample stretch between two sensor gaps of a tyrex recording (read as segments): it gives no window."""
    import pandas as pd

    from gaitml.pipeline.runner import _load_recordings

    for name, dur_s in (("long", 10.0), ("short", 0.2)):
        t = np.arange(0, dur_s, 0.01)
        pd.DataFrame({"t": t, "acc_x": 0.1 * np.sin(t), "acc_y": 0.0, "acc_z": 9.81, "label": "walk"}).to_csv(
            tmp_path / f"{name}.csv", index=False
        )
    cfg = parse_config({"name": "x", "data": {"source": "folder", "path": str(tmp_path)}}, base_dir=tmp_path)
    recs, notes = _load_recordings(cfg)
    assert len(recs) == 1 and recs[0].duration_s > 9
    assert any("1 recording(s) shorter than one 1.5 s window left out: short" in n for n in notes)


def test_the_new_keys_are_written_to_the_resolved_config_only_when_set(tmp_path):
    """A config that does not use them resolves as before (the shipped models' training_config stays equal)."""
    plain = parse_config({"name": "x"}).resolved()
    assert "add_simulated" not in plain["data"] and "moving_speed_ms" not in plain["data"]["labelling"]
    used = _config(_tyrex_root(tmp_path)).resolved()
    assert used["data"]["add_simulated"] is True and used["data"]["labelling"]["moving_speed_ms"] == 0.3
