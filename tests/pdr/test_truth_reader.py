"""One reader of the truth behind ``gaitml pdr --truth`` (scoring) and the step-length calibration (fitting).

:func:`gaitml.io.truth.truth_source` makes the one choice (a tyrex motion capture, the truth a recording carries, a
file); :func:`~gaitml.io.truth.recording_truth` gives the scoring view (landmarks or a dense path, a tyrex capture
smoothed to follow the walker) and :func:`~gaitml.io.truth.dense_truth` the fitting view (dense arrays, a tyrex capture
with NaN where the markers were lost). Both views of one truth hold the same positions.
"""

from __future__ import annotations

import argparse

import numpy as np
import pandas as pd
import pytest

from gaitml.commands.pdr import _load_truth
from gaitml.errors import InputError
from gaitml.io.truth import dense_truth, recording_truth, truth_source
from gaitml.pdr.calibrate import truth_track
from gaitml.simulate import sample_subjects
from gaitml.simulate.dataset import simulate_recording
from tests.conftest import shared


@pytest.fixture(scope="module")
def walk():
    """A simulated walk with its reference trajectory."""
    return simulate_recording(sample_subjects(1, 5)[0], route="straight", duration_s=30.0, modes=("walk",), seed=3)


def _both(rec, spec):
    """The command's truth (scoring view) and the calibration's (fitting view) of ``spec``."""
    return _load_truth(argparse.Namespace(truth=spec), rec), truth_track(rec, spec)


def test_self_is_the_reference_trajectory_in_both_views(walk):
    assert truth_source(walk, "self") == ("self", None)
    scored, (t, xy, name) = _both(walk, "self")
    traj = walk.reference["trajectory"]
    assert scored.kind == "dense" and name == scored.source == "reference trajectory"
    np.testing.assert_array_equal(t, scored.table["t_s"].to_numpy())
    np.testing.assert_array_equal(xy, traj[["x_m", "y_m"]].to_numpy(float))
    np.testing.assert_array_equal(xy, scored.table[["x_m", "y_m"]].to_numpy())


def test_a_truth_file_is_read_once_for_both_views_and_landmarks_only_score(walk, tmp_path):
    traj = walk.reference["trajectory"]
    dense = tmp_path / "path.csv"
    traj[["t", "x_m", "y_m"]].to_csv(dense, index=False)
    assert truth_source(walk, str(dense)) == ("file", str(dense))
    scored, (t, xy, name) = _both(walk, str(dense))
    assert name == scored.source == "path.csv"
    np.testing.assert_array_equal(xy, scored.table[["x_m", "y_m"]].to_numpy())
    np.testing.assert_array_equal(t, scored.table["t_s"].to_numpy())
    sparse = tmp_path / "landmarks.csv"
    traj.iloc[::250][["t", "x_m", "y_m"]].to_csv(sparse, index=False)
    assert recording_truth(walk, str(sparse)).kind == "landmarks"  # scored
    with pytest.raises(InputError, match="sparse landmarks.*true step lengths need a dense path"):
        dense_truth(walk, str(sparse))  # not fitted


def test_a_recording_with_landmarks_and_a_trajectory_is_scored_on_the_landmarks_and_fitted_on_the_trajectory(walk):
    traj = walk.reference["trajectory"]
    pick = traj.iloc[::250]
    landmarks = pd.DataFrame(
        {
            "t_s": pick["t"].to_numpy(float),
            "lat_deg": 48.0 + pick["y_m"].to_numpy(float) / 111_000.0,
            "lon_deg": 2.0 + pick["x_m"].to_numpy(float) / 74_000.0,
            "floor": 0.0,
        }
    )
    both = walk.replace(reference={**walk.reference, "landmarks": landmarks}, check_units=False)
    assert recording_truth(both, "self").kind == "landmarks"  # scored on the landmarks
    t, xy, name = dense_truth(both, "self")  # fitted on the dense trajectory (it refused the landmarks before)
    assert name == "reference trajectory"
    np.testing.assert_array_equal(xy, traj[["x_m", "y_m"]].to_numpy(float))
    assert len(t) == len(traj)


def test_no_truth_is_refused_with_each_views_message(walk):
    bare = walk.replace(reference={}, check_units=False)
    with pytest.raises(InputError, match="carries no landmarks .POSI lines. and no reference trajectory; pass --truth FILE"):
        recording_truth(bare, "self")
    with pytest.raises(InputError, match="carries no truth trajectory .* pass --truth FILE, a dense t,x_m,y_m CSV"):
        truth_track(bare, "self")


def test_a_tyrex_motion_capture_is_the_same_track_in_both_views():
    from gaitml.io import read_recording
    from gaitml.io.truth import tyrex_truth

    folder = shared("tyrex-attitude", "android", "Jakob_Nexus5_NoDist_Texting")
    rec = read_recording(folder)
    assert truth_source(rec, "self") == ("tyrex", None)
    capture = folder.parent.parent / "qualisys" / f"{folder.name}.csv.gz"
    assert truth_source(rec, str(capture)) == ("tyrex", str(capture))
    scored, (t, xy, name) = _both(rec, "self")
    assert name == scored.source == f"tyrex:{folder.name}" and scored.kind == "dense"
    ok = np.isfinite(xy).all(axis=1)
    assert ok.mean() > 0.95 and len(t) == len(scored.table)  # the scoring view fills the lost frames and smooths
    raw = tyrex_truth(rec)  # unsmoothed: the lost frames left out
    np.testing.assert_array_equal(raw.table[["x_m", "y_m"]].to_numpy(), xy[ok])
    np.testing.assert_array_equal(raw.table["t_s"].to_numpy(), t[ok])
    t2, xy2, _ = truth_track(rec, str(capture))
    np.testing.assert_array_equal(t2, t)
    pd.testing.assert_frame_equal(pd.DataFrame(xy2), pd.DataFrame(xy))
