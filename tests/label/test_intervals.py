"""Intervals files (CSV and Audacity label tracks) and their checks."""

from __future__ import annotations

import pandas as pd
import pytest

from gaitml.errors import InputError
from gaitml.labels import check_intervals, read_intervals


def test_csv_intervals(tmp_path):
    f = tmp_path / "iv.csv"
    f.write_text("start_s,end_s,label\n10.5,20,run\n0,10.5,walk\n\n")
    df = read_intervals(f)
    assert df[["start_s", "end_s", "label"]].values.tolist() == [[10.5, 20.0, "run"], [0.0, 10.5, "walk"]]
    assert df["line"].tolist() == [2, 3] and df.attrs["kind"] == "CSV"
    s = check_intervals(df, duration_s=30.0, sampling_rate_hz=50.0)
    assert s["label"].tolist() == ["walk", "run"]  # sorted, touching is fine


def test_audacity_label_track(tmp_path):
    f = tmp_path / "labels.txt"
    f.write_text("1.250000\t8.500000\twalk\n\\\t0.000000\t22050.000000\n8.500000\t15.000000\tside left\n")
    df = read_intervals(f)
    assert df.attrs["kind"] == "Audacity label track"
    assert df[["start_s", "end_s", "label"]].values.tolist() == [[1.25, 8.5, "walk"], [8.5, 15.0, "side left"]]
    assert df["line"].tolist() == [1, 3]


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ("3.0\t3.0\twalk\n", "point label at 3 s.*mark a region"),
        ("5\t3\twalk\n", "ends .* before it starts"),
        ("1\t3\t\n", "has no label"),
        ("start,end,label\n0,1,walk\n", "lacks the columns"),
        ("start_s,end_s,label\n0,abc,walk\n", "line 2: end_s 'abc' is not a number"),
        ("start_s,end_s,label\n", "no intervals"),
        ("   \n", "is empty"),
        ("1\t2\twalk\nnonsense\n", "line 2 is not an Audacity label"),
    ],
)
def test_bad_intervals_files(tmp_path, text, match):
    f = tmp_path / "iv.txt"
    f.write_text(text)
    with pytest.raises(InputError, match=match) as exc:
        read_intervals(f)
    assert "\n" not in str(exc.value)


@pytest.mark.parametrize(
    ("rows", "match"),
    [
        ([(0, 10, "walk"), (9.5, 20, "run")], "intervals overlap: 'walk' 0-10 s .* and 'run' 9.5-20 s"),
        ([(0, 10, "walk"), (10, 31, "run")], "ends at 31 s, after the recording ends"),
        ([(-1, 10, "walk")], "before the recording"),
    ],
)
def test_overlap_and_range_errors(rows, match):
    df = pd.DataFrame(rows, columns=["start_s", "end_s", "label"])
    with pytest.raises(InputError, match=match):
        check_intervals(df, duration_s=30.0, sampling_rate_hz=50.0)


def test_end_one_sample_past_the_last_is_allowed():
    df = pd.DataFrame([(0, 30.02, "walk")], columns=["start_s", "end_s", "label"])
    assert len(check_intervals(df, duration_s=30.0, sampling_rate_hz=50.0)) == 1
