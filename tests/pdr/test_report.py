"""End to end on the simulator: multi-state PDR on the 262 m rectangle beats forward-only (paper 003 sec. 4.3)."""

import pytest

from gaitml.experiments.pdr_routes import VARIANTS, evaluate_route, route_table


@pytest.mark.slow
def test_rectangle_multi_state_within_paper_bound_and_far_better_than_forward_only():
    pick = dict(VARIANTS)
    variants = [(k, pick[k]) for k in ("multi / true modes / hde", "forward-only / hde", "multi / true modes / hde / true lengths")]
    rows = evaluate_route("rectangle", 1, variants=variants)
    err = {r["variant"]: r["end_error_pct"] for r in rows}
    assert rows[0]["n_steps"] == rows[0]["n_steps_true"]
    assert 250 < rows[0]["distance_true_m"] < 275
    assert err["multi / true modes / hde"] < 1.6
    assert err["multi / true modes / hde / true lengths"] < 1.6
    assert err["forward-only / hde"] > 2 * err["multi / true modes / hde"]
    tab = route_table(rows)
    assert ("rectangle", "mean") in tab.columns
