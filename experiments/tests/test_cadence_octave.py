"""The cadence-octave diagnosis (experiments/scripts/cadence_octave.py): it tells doubled steps from a doubled report."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

from experiments.scripts import cadence_octave as co
from gaitml.recording import Recording

FS = 50.0


def _rec(n):
    return Recording(acc=np.tile([0.0, 0.0, 9.81], (n, 1)), sampling_rate_hz=FS, meta={"id": "x", "t0_original_s": 10.0}, check_units=False)


def _cap(t_s, per=1):
    t_s = np.asarray(t_s, dtype=float)
    return {"t_s": t_s + 10.0, "steps_per_event": per, "t_first_s": 10.0, "t_last_s": 10.0 + 60.0}


def _steps(t_s, cadence_hz):
    pk = np.rint(np.asarray(t_s) * FS).astype(np.int64)
    return pd.DataFrame({"start": pk, "peak": pk, "end": pk, "cadence_hz": np.full(len(pk), float(cadence_hz))})


def test_doubled_steps_are_spaced_doubled_and_a_doubled_report_is_not():
    rec = _rec(int(61 * FS))
    cap = _cap(np.arange(1.0, 59.0, 1.0))  # the capture: one step a second
    # the detector's octave error: two steps per capture step, each reporting 2 steps/s
    doubled = co.step_rows(rec, _steps(np.arange(1.0, 59.0, 0.5), 2.0), cap)
    # a reporting defect: steps where the capture has them, each reporting 2 steps/s
    report = co.step_rows(rec, _steps(np.arange(1.0, 59.0, 1.0), 2.0), cap)
    mid = slice(10, -10)  # away from the ends, where the capture's local window is cut
    assert doubled["spacing_hz"].iloc[mid].to_numpy() == pytest.approx(2.0)
    assert doubled["mocap_hz"].iloc[mid].to_numpy() == pytest.approx(1.0)
    assert report["spacing_hz"].iloc[mid].to_numpy() == pytest.approx(1.0)
    v = co.verdict_table(pd.concat([doubled.assign(motion="a", person="p"), report.assign(motion="b", person="p")]))
    a, b = v.set_index("motion").loc["a"], v.set_index("motion").loc["b"]
    assert a["cadence_hz doubled"] == len(doubled) and a["spaced doubled"] >= 0.9 * len(doubled) and a["spaced like capture"] == 0
    assert b["cadence_hz doubled"] == len(report) and b["spaced like capture"] >= 0.9 * len(report) and b["spaced doubled"] == 0
    assert "spaced like the capture" in co.step_verdict(report)


def test_a_gap_between_bouts_is_no_step_interval_and_steps_outside_the_capture_span_are_left_out():
    rec = _rec(int(80 * FS))
    cap = _cap(np.arange(1.0, 59.0, 1.0))
    t = np.concatenate([np.arange(1.0, 20.0, 1.0), np.arange(30.0, 50.0, 1.0), [65.0, 66.0]])  # a 10 s gap; two steps past the span
    r = co.step_rows(rec, _steps(t, 1.0), cap)
    assert len(r) == len(t) - 2
    assert r["spacing_hz"].to_numpy() == pytest.approx(1.0)  # the 10 s gap does not enter either neighbour's spacing
    assert co.step_rows(rec, _steps([], 1.0), cap).empty
