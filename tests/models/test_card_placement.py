"""The model card states the foot-placement rule, and that it is not applied to a model trained on a foot."""

from __future__ import annotations

import copy

from gaitml.models import model_card, read_model_json
from gaitml.models._placement import FOOT_REASON
from tests.conftest import ROOT


def test_card_states_the_foot_placement_rule():
    _, info = read_model_json(ROOT / "models" / "demo")
    card = model_card(info)
    assert "Foot-placement rule: a window holding a rest between fast swings" in card
    assert f"'{FOOT_REASON}'" in card
    foot = copy.deepcopy(info)
    foot["domain"]["positions"] = {**foot["domain"]["positions"], "foot-left": 100}
    assert "Foot-placement rule: not applied" in model_card(foot)
    bare = {k: v for k, v in info.items() if k != "domain"}
    assert "Foot-placement rule" not in model_card(bare)  # no domain record: nothing is checked
