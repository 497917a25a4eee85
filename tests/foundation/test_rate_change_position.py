"""A rate change mid-file is placed where the intervals change, on a file read whole and in chunks.

The rate is judged on stretches of 1000 intervals; a change used to be placed at the start of the first
stretch judged off (up to a stretch away from the truth: 37.4 s for a change at 30 s), and its two
interval levels were taken for a quantised clock (the file judged at 87.6 Hz, the mean of the stretches,
where 100 Hz is its main rate).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import gaitml.io.chunked as ch
from gaitml.cli import main
from gaitml.io import read_recording
from gaitml.recording.timestamps import judge_rate
from gaitml.simulate import simulate_dataset

COLUMNS = ["--columns", "t=time_ms,acc_x=ax,acc_y=ay,acc_z=az,gyr_x=gx,gyr_y=gy,gyr_z=gz", "--time-unit", "ms"]


def _steps(*parts):
    """Timestamps from ``(t_start_s, t_end_s, rate_hz)`` stretches, end excluded."""
    return np.concatenate([a + np.arange(round((b - a) * fs)) / fs for a, b, fs in parts])


@pytest.mark.parametrize(
    ("t", "main_hz", "truth"),
    [
        (_steps((0, 30, 100), (30, 60, 50)), 100.0, [30.0, 59.98, 50.0]),
        (_steps((0, 30, 50), (30, 90, 100)), 100.0, [0.0, 30.0, 50.0]),
        (_steps((0, 20, 100), (20, 40, 50), (40, 80, 100)), 100.0, [20.0, 40.0, 50.0]),
        # a clock in whole milliseconds: 400 Hz, then 200 Hz from 30 s
        (np.floor(_steps((0, 30, 400), (30, 60, 200)) * 1000) / 1000, 400.0, [30.0, 59.995, 200.0]),
    ],
    ids=["100-to-50", "50-to-100", "50-island", "quantised-400-to-200"],
)
def test_rate_change_is_placed_where_the_intervals_change(t, main_hz, truth):
    judged = judge_rate(t)
    assert judged["rate_hz"] == pytest.approx(main_hz, rel=0.01)
    assert len(judged["rate_changes"]) == 1
    start, end, hz = judged["rate_changes"][0]
    assert start == pytest.approx(truth[0], abs=0.021)  # within one interval of the slower rate
    assert end == pytest.approx(truth[1], abs=0.021)
    assert hz == pytest.approx(truth[2], rel=0.01)


def test_a_quantised_clock_is_still_read_at_its_mean_rate():
    t = np.floor(np.arange(40_000) / 400 * 1000) / 1000  # 400 Hz logged in whole ms: 2, 3, 2, 3 ms
    judged = judge_rate(t)
    assert judged["rate_hz"] == pytest.approx(400.0, rel=0.01)
    assert judged["rate_changes"] == []


@pytest.fixture(scope="module")
def rate_change_rec():
    """The file of tests/foundation/test_chunked_warnings.py: 30 s at 100 Hz, then 50 Hz to 60 s."""
    rec = simulate_dataset(1, 60.0, sampling_rate_hz=100.0, seed=5)[0]
    keep = np.r_[np.arange(3000), np.arange(3000, rec.n_samples, 2)]
    return rec, keep


def test_columns_csv_rate_change_at_30_s_read_whole_and_in_chunks(rate_change_rec, tmp_path, monkeypatch, capsys):
    rec, keep = rate_change_rec
    df = pd.DataFrame({"time_ms": 1000.0 * rec.t_s[keep]})
    for i, ax in enumerate("xyz"):
        df[f"a{ax}"] = rec.acc[keep, i]
    for i, ax in enumerate("xyz"):
        df[f"g{ax}"] = rec.gyr[keep, i]
    p = tmp_path / "logger.csv"
    df.to_csv(p, index=False)
    lines = []
    for chunked in (False, True):
        monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", -1 if chunked else 10**12)
        assert main(["zupt", str(p), *COLUMNS, "--json"]) == 0
        lines.append([w for w in capsys.readouterr().err.splitlines() if "rate changes mid-file" in w])
    assert lines[0] == lines[1] and len(lines[0]) == 1
    assert "50 Hz from 30 to 59.98 s against 100 Hz" in lines[0][0], lines[0][0]


def test_gaitml_csv_rate_change_at_30_s_read_whole_and_scanned(rate_change_rec, tmp_path):
    rec, keep = rate_change_rec
    df = pd.DataFrame(np.column_stack([rec.t_s[keep], rec.acc[keep], rec.gyr[keep]]))
    df.columns = ["t", "acc_x", "acc_y", "acc_z", "gyr_x", "gyr_y", "gyr_z"]
    p = tmp_path / "rec.csv"
    df.to_csv(p, index=False, float_format="%.6f")
    whole = read_recording(p)
    scan = ch.scan_gaitml_csv(p, rows_per_read=1000)
    assert whole.meta["rate_changes"] == scan.meta["rate_changes"]
    assert whole.sampling_rate_hz == scan.sampling_rate_hz == pytest.approx(100.0)
    start, end, hz = whole.meta["rate_changes"][0]
    assert start == pytest.approx(30.0, abs=0.021) and end == pytest.approx(59.98, abs=0.021) and hz == pytest.approx(50.0, rel=0.01)
