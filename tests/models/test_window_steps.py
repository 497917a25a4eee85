"""The ``window_steps`` column and the still line on stderr.

``window_steps`` holds, in each window the gate's statistic reads still, the count of the veto's steps the veto
decided on, NaN in every other window and whenever the veto is off: a whole file and its chunks give the same column
(a chunk without a still-read window used to leave NaN where a whole-file run counted every window). ``gaitml
predict`` prints the still line whenever a window is flagged either way: still, or kept in its mode by the veto
(``still_vetoed``), as the other flags' lines.
"""

from __future__ import annotations

import argparse
import json

import numpy as np
import pandas as pd
import pytest

import gaitml.models._predict as P
from gaitml.models import load_model, predict_recording, resample_recording
from gaitml.recording import Recording
from tests.conftest import ROOT
from tests.models.test_still_step_veto import FS, calm_walker


@pytest.fixture(scope="module")
def demo():
    return load_model(ROOT / "models" / "demo")


def calm_then_brisk() -> Recording:
    """30 s standing, 60 s of a calm walker the statistic reads still, 30 s standing, then 240 s of brisk walking that
    no window of reads still (so the chunks over it have no still-read window)."""
    calm = calm_walker(60.0, stand_s=30.0, seed=4)
    brisk = calm_walker(240.0, amp=2.0, seed=5)
    return Recording(acc=np.vstack([calm.acc, brisk.acc]), gyr=np.vstack([calm.gyr, brisk.gyr]), sampling_rate_hz=FS)


def _nan_where_not_read_still(table) -> None:
    read_still = table["still"].to_numpy(bool) | table["still_vetoed"].to_numpy(bool)
    steps = table["window_steps"].to_numpy(float)
    np.testing.assert_array_equal(np.isnan(steps), ~read_still)
    kept = table["still_vetoed"].to_numpy(bool)
    assert (steps[kept] >= P.STILL_STEP_VETO_MIN_STEPS).all() and (steps[table["still"].to_numpy(bool)] < P.STILL_STEP_VETO_MIN_STEPS).all()


@pytest.mark.parametrize("rate", [50.0, 20.0])
def test_window_steps_is_the_same_whole_and_chunked(demo, tmp_path, rate):
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv

    rec = calm_then_brisk()
    path = tmp_path / "walk.csv"
    write_gaitml_csv(rec if rate == FS else resample_recording(rec, rate), path)
    whole = predict_recording(demo, read_recording(path))
    chunked = long_predict(demo, path, chunk_s=45.0, progress=False)
    assert whole["still_vetoed"].sum() > 10 and whole["still"].sum() > 10
    for col in ("still", "still_vetoed", "mode", "window_steps"):
        np.testing.assert_array_equal(whole[col].to_numpy(), chunked[col].to_numpy(), err_msg=col)
    _nan_where_not_read_still(whole)
    _nan_where_not_read_still(chunked)


def test_window_steps_is_nan_with_the_veto_off_and_without_a_gyroscope_too(demo):
    rec = calm_walker(60.0, stand_s=20.0, seed=6)
    assert np.isnan(predict_recording(demo, rec, still_step_veto=0)["window_steps"].to_numpy(float)).all()
    acc_only = Recording(acc=rec.acc, sampling_rate_hz=FS)  # the run-cadence rule's steps are the veto's: not counted twice
    table = predict_recording(load_model(ROOT / "models" / "demo-acc"), acc_only)
    assert table["still"].any() or table["still_vetoed"].any()
    _nan_where_not_read_still(table)


def _report(demo, table, capsys):
    from gaitml.commands.predict import _report

    args = argparse.Namespace(out=None, json=True, no_correction=False)
    assert _report(args, demo, table, "windows", {"window_s": demo.length_s, "overlap": demo.overlap}) == 0
    cap = capsys.readouterr()
    return json.loads(cap.out), [line for line in cap.err.splitlines() if "still" in line]


def test_a_line_names_the_vetoed_windows_when_none_is_still(demo, capsys):
    table = predict_recording(demo, calm_walker(60.0, stand_s=20.0, seed=7))
    assert table["still"].any() and table["still_vetoed"].any()
    out, lines = _report(demo, table, capsys)
    assert len(lines) == 1 and f"{out['still_vetoed_count']} more" in lines[0]
    # every window the statistic reads still kept by the veto: still one line, naming them and saying none is still
    kept = table.copy()
    kept["still_vetoed"] = kept["still"].to_numpy(bool) | kept["still_vetoed"].to_numpy(bool)
    kept["still"] = False
    out, lines = _report(demo, kept, capsys)
    n = int(kept["still_vetoed"].sum())
    assert out["still_vetoed_count"] == n and out["still_fraction"] == 0.0
    assert len(lines) == 1 and lines[0].startswith(f"gaitml: warning: {n} of {len(kept)} windows") and "still_vetoed" in lines[0]
    assert "none is reported as 'still'" in lines[0] and "2 or more detected steps" in lines[0]
    # no window flagged either way: no line
    none = kept.assign(still_vetoed=False)
    assert _report(demo, none, capsys)[1] == []


@pytest.mark.parametrize("held_whole", [False, True])
def test_a_resampled_file_runs_the_vetos_finder_only_in_chunks_with_a_still_read_window(demo, tmp_path, monkeypatch, held_whole):
    """A file recorded at 20 Hz (its gate comes after the chunks): the statistic of every window is read from the file
    as recorded first, so a chunk of brisk walking, where no window reads still, does not look for the veto's steps;
    the table is the one the finder in every chunk gives, and the whole file's. ``held_whole``: the file handed over
    read whole (a format other than gaitml-csv), else read again chunk by chunk at its own rate."""
    import gaitml.chunked_run as C
    from gaitml.chunked_run import long_predict
    from gaitml.io import read_recording, write_gaitml_csv

    path = tmp_path / "walk20.csv"
    write_gaitml_csv(resample_recording(calm_then_brisk(), 20.0), path)
    kw = {"recording": read_recording(path)} if held_whole else {}
    calls = []
    real = P.veto_steps
    monkeypatch.setattr(P, "veto_steps", lambda rec: calls.append(rec.n_samples) or real(rec))
    lean = long_predict(demo, path, chunk_s=45.0, progress=False, **kw)
    n_lean = len(calls)
    with monkeypatch.context() as m:
        m.setattr(C, "_chunk_reads_still", lambda read_still, k: True)  # the finder in every chunk
        every = long_predict(demo, path, chunk_s=45.0, progress=False, **kw)
    n_chunks = len(calls) - n_lean
    pd.testing.assert_frame_equal(lean, every)
    whole = predict_recording(demo, read_recording(path))
    for col in ("still", "still_vetoed", "mode", "window_steps"):
        np.testing.assert_array_equal(whole[col].to_numpy(), lean[col].to_numpy(), err_msg=col)
    # the calm walk and its standing fill the first 120 s; the chunks of the 240 s of brisk walking after need no steps
    read_still_s = lean.loc[lean["still"] | lean["still_vetoed"], "t_end_s"].max()
    assert read_still_s < 130.0 and 1 <= n_lean <= int(np.ceil(read_still_s / 45.0)) + 1 < n_chunks
