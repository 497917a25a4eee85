"""The still gate's step veto on a step-window model (``predict_step_windows``): a calm walker's steps read still by the
|acc| statistic keep their mode when the detector finds steps in them."""

from __future__ import annotations

from gaitml.models import load_model
from gaitml.models._predict import STILL_STEP_VETO_DEFAULT
from tests.models.test_still_step_veto import calm_walker


def test_a_step_window_model_applies_the_veto(step_model_dir):
    from gaitml.models import predict_step_windows

    model = load_model(step_model_dir / "model")
    rec = calm_walker(40.0)
    gate_only = predict_step_windows(model, rec, still_step_veto=0)
    assert gate_only["still"].mean() > 0.5  # the statistic reads the calm walker's steps still
    # a step window spans about one step: the veto at one step keeps them, the default (two) seldom fires there
    one = predict_step_windows(model, rec, still_step_veto=1)
    assert one["still"].mean() < 0.2 and one["still_vetoed"].sum() >= 0.5 * gate_only["still"].sum()
    assert predict_step_windows(model, rec).attrs["still_gate"]["step_veto_min_steps"] == STILL_STEP_VETO_DEFAULT
