"""The ``still_unsure`` mark on a step-window model (``predict_step_windows``): a step window the still gate reports
``still`` while the phone turns with a walker's stride rhythm around it is marked, as a time window is (the CHANGELOG's
"whole file, chunks and step-window models alike"); ``gaitml predict`` says it in the JSON and one stderr line."""

from __future__ import annotations

import json

import numpy as np

from gaitml.models import load_model, stride_rhythm
from tests.models.test_still_veto_swing import ear_walk


def test_a_step_window_model_marks_the_still_steps_of_a_calm_ear_walk(step_model_dir, tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv
    from gaitml.models import predict_step_windows

    model = load_model(step_model_dir / "model")
    rec, _ = ear_walk(0, seconds=60.0)
    table = predict_step_windows(model, rec)
    still, marked = table["still"].to_numpy(bool), table["still_unsure"].to_numpy(bool)
    assert still.sum() >= 5 and marked.sum() >= 0.5 * still.sum()  # measured 41 of 41 (54 steps)
    assert not (marked & ~still).any() and (table.loc[marked, "mode"] == "still").all()
    np.testing.assert_array_equal(marked[still], stride_rhythm(rec, table[still]))  # the rhythm of each still step
    path = tmp_path / "ear.csv"
    write_gaitml_csv(rec, path)
    assert main(["predict", str(step_model_dir / "model"), str(path), "--json"]) == 0
    cap = capsys.readouterr()
    doc = json.loads(cap.out)
    assert doc["still_unsure_count"] == sum(w["still_unsure"] for w in doc["windows"]) == int(marked.sum())
    lines = [ln for ln in cap.err.splitlines() if "still_unsure" in ln]
    assert len(lines) == 1 and lines[0].startswith("gaitml: warning:") and " steps reported 'still'" in lines[0]
