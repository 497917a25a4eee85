"""Public API of gaitml.simulate: shapes, metadata, labels, ground-truth keys, errors."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from gaitml.consts import MOTION_MODES
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.simulate import (
    STAND,
    Subject,
    mode_schedule,
    sample_subjects,
    simulate_dataset,
    simulate_route,
)
from gaitml.simulate.subject import HAND_TILTED_PITCH_DEG


@pytest.fixture(scope="module")
def dataset():
    return simulate_dataset(n_subjects=3, duration_s=60.0, seed=3)


def _segments(labels):
    change = np.flatnonzero(labels[1:] != labels[:-1]) + 1
    bounds = np.concatenate([[0], change, [len(labels)]])
    return [(labels[a], b - a) for a, b in zip(bounds[:-1], bounds[1:], strict=True)]


def test_dataset_shapes_and_meta(dataset):
    assert len(dataset) == 3
    for i, rec in enumerate(dataset):
        assert isinstance(rec, Recording)
        assert rec.sampling_rate_hz == 50.0
        assert rec.n_samples == 3000
        assert rec.gyr.shape == (3000, 3)
        assert rec.meta["subject"] == f"S{i + 1:02d}"
        assert rec.meta["id"] == rec.meta["session"] == f"S{i + 1:02d}-R1"
        assert rec.meta["pose"] == "flat"
        assert 1.5 < rec.meta["walk_cadence_hz"] < 2.2
        steps = rec.reference["steps"]
        assert list(steps.columns[:5]) == ["t_s", "mode", "step_length_m", "heading_rad", "foot"]
        assert np.array_equal(rec.reference["steps_t_s"], steps["t_s"].to_numpy())
        assert rec.reference["n_steps_true"] == len(steps)
        assert np.all(np.diff(steps["t_s"]) > 0)
        assert steps["t_s"].iloc[-1] < rec.duration_s
        traj = rec.reference["trajectory"]
        assert list(traj.columns) == ["t", "x_m", "y_m", "heading_rad"]
        assert len(traj) == rec.n_samples
        assert set(steps["foot"]) <= {"left", "right"}
        assert np.all(np.abs(steps["heading_rad"]) <= np.pi + 1e-6)


def test_labels_are_modes_with_transitions_and_long_segments(dataset):
    for rec in dataset:
        labs = set(rec.labels)
        assert labs <= set(MOTION_MODES)
        assert len(labs) >= 3  # 60 s hold 3-7 segments of 8-20 s
        segs = _segments(rec.labels)
        inner = segs[1:-1]
        assert all(n / rec.sampling_rate_hz >= 7.5 for _, n in inner), inner


def test_default_dataset_has_all_five_modes():
    recs = simulate_dataset(n_subjects=2, duration_s=120.0, seed=0)
    for rec in recs:
        assert set(rec.labels) == set(MOTION_MODES)
        # every step lies in a sample labelled with its mode (up to the blended transition step)
        steps = rec.reference["steps"]
        idx = np.clip(np.round(steps["t_s"].to_numpy() * rec.sampling_rate_hz).astype(int) - 1, 0, rec.n_samples - 1)
        assert np.mean(rec.labels[idx] == steps["mode"].to_numpy()) > 0.97


def test_label_step_mode_agreement_in_every_step_interval(dataset):
    rec = dataset[0]
    steps = rec.reference["steps"]
    t = rec.t_s
    for row in steps.itertuples():
        inside = (t > row.t_start_s + 0.05) & (t < row.t_s - 0.05)
        assert set(rec.labels[inside]) <= {row.mode}


def test_pauses_are_labelled_stand_and_still():
    rec = simulate_dataset(1, 120.0, ("walk", "run"), seed=5, pauses=True)[0]
    assert STAND in set(rec.labels)
    still = rec.labels == STAND
    mag = np.linalg.norm(rec.acc[still], axis=1)
    assert abs(mag.mean() - 9.81) < 0.1 and mag.std() < 0.2
    steps_t = rec.reference["steps_t_s"]
    t_still = rec.t_s[still]
    assert not np.any(np.isin(np.round(steps_t * 50).astype(int), np.round(t_still * 50).astype(int)))


def test_modes_subset_and_rates():
    rec = simulate_dataset(1, 30.0, ["walk", "backward"], sampling_rate_hz=200.0, seed=1)[0]
    assert set(rec.labels) <= {"walk", "backward"}
    assert rec.n_samples == 6000 and rec.sampling_rate_hz == 200.0


def test_subjects_are_reproducible_and_prefix_stable():
    a = sample_subjects(3, seed=4)
    b = sample_subjects(5, seed=4)
    assert a == b[:3]
    assert sample_subjects(3, seed=5) != a
    rng = np.random.default_rng(0)
    s = Subject.random(rng, subject="S09", pose="tilted")
    lo, hi = np.radians(HAND_TILTED_PITCH_DEG)
    assert s.subject == "S09" and s.pose == "tilted" and lo <= s.pitch_rad <= hi


def test_route_recordings():
    rect = simulate_route("rectangle", seed=2)
    arc = simulate_route("arc", seed=2)
    assert rect.meta["route"] == "rectangle" and abs(rect.meta["route_length_m"] - 262.0) < 1e-6
    assert abs(arc.meta["route_length_m"] - 400.0) < 1e-6
    for rec, length in ((rect, 262.0), (arc, 400.0)):
        steps = rec.reference["steps"]
        assert abs(steps["step_length_m"].sum() - length) < 0.5
        assert len(set(steps["mode"])) >= 3  # mixed modes along the route
        end = rec.reference["trajectory"].iloc[-1]
        assert np.hypot(end.x_m, end.y_m) < 0.02 * length  # closed loop: back near the start
    rnd = simulate_route("random", seed=1, duration_s=40.0)
    assert rnd.n_samples == 2000


def test_mode_schedule_rounds():
    rng = np.random.default_rng(0)
    sch = mode_schedule(rng, MOTION_MODES, 300.0)
    assert isinstance(sch, pd.DataFrame)
    assert sch["t_start_s"].iloc[0] == 0.0 and sch["t_end_s"].iloc[-1] >= 300.0
    d = sch["t_end_s"] - sch["t_start_s"]
    assert d.between(8.0, 20.0).all()
    assert set(sch["mode"].iloc[:5]) == set(MOTION_MODES)
    assert (sch["mode"].to_numpy()[1:] != sch["mode"].to_numpy()[:-1]).all()


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"modes": ["walk", "jump"]}, "unknown motion mode"),
        ({"modes": []}, "no motion modes"),
        ({"sampling_rate_hz": 5.0}, "sampling_rate_hz"),
        ({"duration_s": 1.0}, "duration_s"),
        ({"route": "moon"}, "unknown route"),
        ({"pose": "pocket"}, "pose"),
        ({"n_subjects": 0}, "number of subjects"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"n_subjects": 1, "duration_s": 10.0}
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        simulate_dataset(**args)


def test_bad_subject():
    with pytest.raises(InputError, match="walk_cadence_hz"):
        Subject(walk_cadence_hz=9.0)
    with pytest.raises(InputError, match="pose"):
        Subject(pose="ear")


def test_sessions_of_one_subject_differ_a_little():
    recs = simulate_dataset(2, 20.0, seed=1, n_sessions=3)
    assert [r.name for r in recs] == ["S01-R1", "S01-R2", "S01-R3", "S02-R1", "S02-R2", "S02-R3"]
    cad = [r.meta["walk_cadence_hz"] for r in recs]
    assert cad[0] == pytest.approx(sample_subjects(2, seed=1)[0].walk_cadence_hz, abs=1e-6)
    assert len(set(cad)) == 6
    assert all(abs(c / cad[0] - 1) < 0.15 for c in cad[:3])
    assert {r.meta["subject"] for r in recs[:3]} == {"S01"}
