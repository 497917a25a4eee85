"""The still gate's step veto on a step-window model (``predict_step_windows``): a calm walker's steps read still by the
|acc| statistic keep their mode when the detector finds steps in them."""

from __future__ import annotations

import numpy as np

from gaitml.models import load_model
from gaitml.models._predict import STILL_STEP_VETO_DEFAULT
from tests.models.test_still_step_veto import calm_walker


def test_a_step_window_model_applies_the_veto(step_model_dir):
    from gaitml.models import predict_step_windows

    model = load_model(step_model_dir / "model")
    rec = calm_walker(40.0)
    gate_only = predict_step_windows(model, rec, still_step_veto=0)
    assert gate_only["still"].mean() > 0.5  # the statistic reads the calm walker's steps still
    # the veto at one step keeps them
    one = predict_step_windows(model, rec, still_step_veto=1)
    assert one["still"].mean() < 0.2 and one["still_vetoed"].sum() >= 0.5 * gate_only["still"].sum()
    # the default (two): the step windows read still that hold two of the default detector's peaks, and only those;
    # IFSM's steps of a calm walker span about two of adaptive's, so it keeps many of them (not "seldom")
    default = predict_step_windows(model, rec)
    assert default.attrs["still_gate"]["step_veto_min_steps"] == STILL_STEP_VETO_DEFAULT
    if STILL_STEP_VETO_DEFAULT is not None:
        expected = gate_only["still"].to_numpy(bool) & (default["window_steps"].to_numpy(float) >= STILL_STEP_VETO_DEFAULT)
        np.testing.assert_array_equal(default["still_vetoed"].to_numpy(bool), expected)
        assert default["still_vetoed"].sum() > 0.3 * gate_only["still"].sum()
