"""experiments.scripts.step_bouts: where adaptive's count errors sit on the Oxford recordings, with and without its bout rules."""

from __future__ import annotations

import pytest

from experiments.scripts.step_bouts import RULES_OFF, edge_table, main
from experiments.tests.conftest import shared
from gaitml.errors import InputError
from gaitml.io import read_recording
from gaitml.steps import get_detector


def test_edge_table_on_two_neck_pouch_walks():
    root = shared("oxford-step-counter", "optimisation", "data")
    recs = [read_recording(root / n) for n in ("Pixel_Jamie_Hard_NeckPouch_1", "Samsung_Carmelo_Hard_Armband_2")]
    per_rec, per_pos = edge_table(recs, ["NeckPouch"])
    assert per_rec["recording"].tolist() == ["Pixel_Jamie_Hard_NeckPouch_1"]
    # cells: "detected (error): pre / post / inside"; measured 260 (+12): 5 / 4 / +3 without the rules, 255 with them
    off, on = (int(per_rec[c].item().split()[0]) for c in ("adaptive, no bout rules", "adaptive"))
    assert off == len(get_detector("adaptive", **RULES_OFF).detect(recs[0]).steps_)
    assert on < off and abs(on - 248) < abs(off - 248)
    row = per_pos.iloc[0]
    assert row["adaptive: false"] < row["adaptive, no bout rules: false"]
    assert row["adaptive: missed"] == row["adaptive, no bout rules: missed"]


def test_no_matching_recording_is_an_input_error():
    with pytest.raises(InputError, match="no Oxford recording matched"):
        edge_table([], ["NeckPouch"])


def test_main_needs_the_data(tmp_path):
    with pytest.raises(InputError, match="--data"):
        main(["--data", str(tmp_path)])
