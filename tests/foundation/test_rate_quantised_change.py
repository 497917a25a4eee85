"""The file's rate is the rate most of its time runs at, and a rate change keeps its own rate, on exact,
millisecond-floored, millisecond-rounded and jittered clocks.

A clock in whole milliseconds with a real rate change used to be misjudged: 20 s at 400 Hz then 40 s at
200 Hz was judged at 267.5 Hz (no part of the file runs at it), and 400 Hz then 100 Hz gave the change a
rate of 111 Hz (the 10 ms intervals, over three times the file's median, were left out as gaps).
"""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import gaitml.io.chunked as ch
from gaitml.io import read_recording
from gaitml.recording.timestamps import judge_rate, judge_timestamps


def _parts(*parts: tuple[float, float]) -> np.ndarray:
    """Timestamps of consecutive ``(rate_hz, duration_s)`` parts, each part's end excluded."""
    out, t0 = [], 0.0
    for fs, dur in parts:
        out.append(t0 + np.arange(round(dur * fs)) / fs)
        t0 += dur
    return np.concatenate(out)


def _clock(t: np.ndarray, clock: str) -> np.ndarray:
    if clock == "floor":
        return np.floor(t * 1000) / 1000
    if clock == "round":
        return np.round(t * 1000) / 1000
    if clock == "jitter":
        return t + np.random.default_rng(3).normal(0.0, 2e-4, len(t))
    return t


def _assert_judged(judged: dict, main_hz: float, change: list[float]) -> None:
    """The rate within 1 % of the main rate; one change, its edges within 0.1 s and its rate within 2 %."""
    assert judged["rate_hz"] == pytest.approx(main_hz, rel=0.01), judged
    assert len(judged["rate_changes"]) == 1, judged["rate_changes"]
    start, end, hz = judged["rate_changes"][0]
    assert start == pytest.approx(change[0], abs=0.1) and end == pytest.approx(change[1], abs=0.1), judged["rate_changes"]
    assert hz == pytest.approx(change[2], rel=0.02), judged["rate_changes"]


@pytest.mark.parametrize(
    ("parts", "clock", "main_hz", "change"),
    [
        # the two cases left by the last fix, on a clock in whole ms: the faster part, a third of the file or more,
        # sets the rate (every part keeps its signal), the slower one is the change
        (((400, 20), (200, 40)), "floor", 400.0, [20.0, 59.995, 200.0]),
        (((400, 30), (100, 30)), "floor", 400.0, [30.0, 59.99, 100.0]),
        # the same on the other clocks
        (((400, 20), (200, 40)), "exact", 400.0, [20.0, 59.995, 200.0]),
        (((400, 30), (100, 30)), "jitter", 400.0, [30.0, 59.99, 100.0]),
        # a few of the synthetic grid (experiments/scripts/judge_rate_check.py)
        (((50, 30), (200, 30)), "exact", 200.0, [0.0, 30.0, 50.0]),
        (((400, 20), (50, 40)), "floor", 400.0, [20.0, 59.98, 50.0]),
        (((100, 30), (400, 90)), "round", 400.0, [0.0, 30.0, 100.0]),
        (((200, 20), (100, 40)), "jitter", 200.0, [20.0, 59.99, 100.0]),
        # a faster burst under FAST_PART_MIN_SHARE of the file does not set its rate
        (((400, 5), (50, 55)), "floor", 50.0, [0.0, 5.0, 400.0]),
        (((50, 5), (200, 55)), "round", 200.0, [0.0, 5.0, 50.0]),
        (((150, 20), (50, 40)), "floor", 150.0, [20.0, 59.98, 50.0]),
        (((60, 40), (150, 20)), "round", 150.0, [0.0, 40.0, 60.0]),
        # a 10 s island at 4x the rate (an eighth of the file), and a 20 s one at a quarter of it
        (((100, 20), (400, 10), (100, 50)), "floor", 100.0, [20.0, 30.0, 400.0]),
        (((400, 20), (100, 20), (400, 40)), "floor", 400.0, [20.0, 40.0, 100.0]),
        # a long slow part keeps the fast part's signal (the time-majority rule resampled the file to 10 Hz)
        (((100, 40), (10, 60)), "exact", 100.0, [40.0, 99.9, 10.0]),
    ],
)
def test_main_rate_and_change_on_quantised_and_jittered_clocks(parts, clock, main_hz, change):
    _assert_judged(judge_rate(_clock(_parts(*parts), clock)), main_hz, change)


def test_jitter_does_not_bias_the_main_rate_when_two_rates_are_mixed():
    # 1 / median interval over the whole file was 98.1 Hz here: the 20 ms intervals pull the median up
    judged = judge_rate(_clock(_parts((100, 30), (50, 30)), "jitter"))
    _assert_judged(judged, 100.0, [30.0, 59.98, 50.0])
    assert judged["rate_hz"] == pytest.approx(100.0, rel=0.002)


@pytest.mark.parametrize("clock", ["exact", "floor", "round", "jitter"])
@pytest.mark.parametrize("fs", [50, 60, 100, 150, 200, 300, 400])
def test_one_rate_throughout_has_no_change(fs, clock):
    # in whole ms, 60 Hz is 16, 17, 17 ms and 150 Hz 6, 7, 7 ms: the median interval gives 58.8 and 142.9 Hz
    judged = judge_rate(_clock(np.arange(60 * fs) / fs, clock))
    assert judged["rate_hz"] == pytest.approx(fs, rel=0.005)
    assert judged["rate_changes"] == []


def test_a_quantised_clock_says_so_in_the_rule():
    # 300 Hz in whole ms: 3, 3, 4 ms, whose median gives 333 Hz; then 100 Hz from 40 s
    plan = judge_timestamps(_clock(_parts((300, 40), (100, 20)), "floor"))
    assert plan["fs"] == pytest.approx(300.0, rel=0.001)
    assert "quantised to 0.001 s" in plan["meta"]["rate_rule"]
    assert len(plan["warnings"]) == 1 and "Hz from 40 to 59.989 s against 300 Hz" in plan["warnings"][0], plan["warnings"]
    assert plan["meta"]["rate_changes"][0][2] == pytest.approx(100.0, rel=0.001)


def test_ms_clock_with_a_rate_change_read_whole_and_scanned(tmp_path):
    t = _clock(_parts((400, 20), (200, 40)), "floor")
    acc = np.column_stack([0.3 * np.sin(2 * np.pi * t), 0.2 * np.cos(2 * np.pi * t), 9.81 + 2.0 * np.sin(4 * np.pi * t)])
    df = pd.DataFrame(np.column_stack([t, acc]), columns=["t", "acc_x", "acc_y", "acc_z"])
    p = tmp_path / "ms.csv"
    df.to_csv(p, index=False, float_format="%.6f")
    whole = read_recording(p)
    scan = ch.scan_gaitml_csv(p, rows_per_read=1000)
    assert whole.meta["rate_changes"] == scan.meta["rate_changes"]
    assert whole.sampling_rate_hz == scan.sampling_rate_hz == pytest.approx(400.0, rel=0.01)
    start, end, hz = whole.meta["rate_changes"][0]
    assert start == pytest.approx(20.0, abs=0.1) and end == pytest.approx(60.0, abs=0.1) and hz == pytest.approx(200.0, rel=0.02)


@pytest.mark.parametrize("n_gaps", [1, 5])
def test_gaps_in_a_fast_file_are_no_rate_change(n_gaps):
    # a stretch of 1000 intervals at 2 kHz lasts 0.5 s: gaps of 0.3-0.8 s take most of its time, yet are gaps
    t = np.arange(60 * 2000) / 2000
    for k in range(n_gaps):
        t[60_000 + 100 * k :] += 0.8 if n_gaps == 1 else 0.3
    judged = judge_rate(t)
    assert judged["rate_hz"] == pytest.approx(2000.0, rel=1e-6)
    assert judged["rate_changes"] == []


@pytest.mark.parametrize("fs", [60, 100])
@pytest.mark.parametrize("clock", ["exact", "floor", "round"])
def test_dropped_samples_do_not_lower_the_rate(fs, clock):
    # 3 % of single samples missing: twice the interval there; the clock's rate is still the rate
    t = np.arange(120 * fs) / fs
    t = _clock(t[np.random.default_rng(fs).random(len(t)) >= 0.03], clock)
    judged = judge_rate(t)
    assert judged["rate_hz"] == pytest.approx(fs, rel=0.01)
    assert judged["rate_changes"] == []
