"""gaitml.segment.segment (steps / strides / zupt as one segment table) and `gaitml segment`."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from gaitml.cli import main
from gaitml.consts import DEFAULT_STEP_DETECTOR
from gaitml.errors import InputError
from gaitml.io import read_recording
from gaitml.segment import BY, SEGMENT_COLUMNS, resolve_detector, segment
from gaitml.steps import SinglePeakStepDetector, detect_steps
from gaitml.zupt import PseudoStdZuptDetector, detect_zupts, segment_strides
from tests.conftest import shared
from tests.synthetic import synthetic_foot_walk

WALK = "data/samples/S01-walk.csv"


@pytest.fixture(scope="module")
def phone():
    return read_recording(WALK)


@pytest.fixture(scope="module")
def foot():
    return synthetic_foot_walk(1200, 100.0)  # 12 strides of 1 s, stance 40 %


def _check_table(t: pd.DataFrame, fs: float):
    assert tuple(t.columns[: len(SEGMENT_COLUMNS)]) == SEGMENT_COLUMNS
    assert t["index"].tolist() == list(range(len(t)))
    np.testing.assert_allclose(t["start_s"], t["start"] / fs)
    np.testing.assert_allclose(t["end_s"], t["end"] / fs)
    np.testing.assert_allclose(t["duration_s"], (t["end"] - t["start"]) / fs)
    assert (t["duration_s"] > 0).all()
    assert t.attrs["sampling_rate_hz"] == fs


def test_by_steps_is_the_step_table(phone):
    t = segment(phone, by="steps", detector="adfsm")
    steps = detect_steps(phone, "adfsm")
    _check_table(t, phone.sampling_rate_hz)
    assert len(t) == len(steps) == 37
    assert t["start"].tolist() == steps["start"].tolist() and t["end"].tolist() == steps["end"].tolist()
    np.testing.assert_allclose(t["event_s"], steps[steps.attrs["event"]])
    assert t["confidence"].isna().all()  # adfsm has no confidence
    assert (t["kind"] == "step").all() and t.attrs["by"] == "steps" and t.attrs["detector"] == "adfsm"
    assert segment(phone).attrs["detector"] == DEFAULT_STEP_DETECTOR  # the default


def test_step_confidence_is_passed_through(phone):
    class WithConfidence(SinglePeakStepDetector):
        def detect(self, recording):
            super().detect(recording)
            self.steps_["confidence"] = np.linspace(0.2, 0.9, len(self.steps_))
            return self

    t = segment(phone, by="steps", detector=WithConfidence())
    np.testing.assert_allclose(t["confidence"], np.linspace(0.2, 0.9, len(t)))


def test_by_strides_and_zupt_on_a_foot(foot):
    det = PseudoStdZuptDetector()
    z = segment(foot, by="zupt", detector=det)
    st = segment(foot, by="strides")
    _check_table(z, 100.0)
    _check_table(st, 100.0)
    zupts = detect_zupts(foot, "pseudo-std")
    assert z["start"].tolist() == zupts["start"].tolist() and (z["kind"] == "stance").all()
    ref = segment_strides(zupts, 100.0)
    assert st["start"].tolist() == ref["start"].tolist() and st["end"].tolist() == ref["end"].tolist()
    assert len(st) == len(z) - 1 >= 11
    np.testing.assert_allclose(st["duration_s"].iloc[1:-1], 1.0, atol=0.03)  # one stride per second (first and last touch the edges)
    assert (st["start_s"] < st["stance_end_s"]).all() and (st["stance_end_s"] < st["swing_end_s"]).all()
    assert (st["swing_end_s"] < st["end_s"]).all()
    assert st["confidence"].isna().all()
    assert len(segment(foot, by="strides", max_stride_s=0.5)) == 0


@pytest.mark.parametrize(
    ("by", "detector", "match"),
    [
        (
            "steps",
            "pseudo-std",
            r"unknown step detector 'pseudo-std' for --by steps \('pseudo-std' is a zero-velocity detector\); choose one of single-peak",
        ),
        ("strides", "ifsm", r"unknown zero-velocity detector 'ifsm' .*is a step detector.*choose one of pseudo-std"),
        ("zupt", "nope", r"unknown zero-velocity detector 'nope' for --by zupt; choose one of pseudo-std, magnitude"),
        ("walk", None, r"unknown segmentation 'walk'; choose by one of steps, strides, zupt"),
        ("steps", PseudoStdZuptDetector(), r"needs a step detector"),
        ("zupt", SinglePeakStepDetector(), r"needs a zero-velocity detector"),
    ],
)
def test_bad_by_or_detector(by, detector, match):
    with pytest.raises(InputError, match=match):
        resolve_detector(by, detector)


def test_bad_inputs(phone, foot):
    with pytest.raises(InputError, match="max_stride_s applies to by='strides' only"):
        segment(foot, by="zupt", max_stride_s=2.0)
    with pytest.raises(InputError, match="needs a gaitml Recording"):
        segment(np.zeros((10, 3)), by="steps")
    no_gyr = read_recording(WALK)
    no_gyr = type(no_gyr)(acc=no_gyr.acc, sampling_rate_hz=no_gyr.sampling_rate_hz, meta={"id": "acc-only"})
    with pytest.raises(InputError, match="gyroscope"):
        segment(no_gyr, by="strides")


@pytest.mark.parametrize("by", BY)
def test_cli_writes_the_table_and_one_json_object(by, tmp_path, capsys):
    out = tmp_path / "seg.csv"
    inp = WALK
    assert main(["segment", inp, "--by", by, "--out", str(out), "--json"]) == 0
    cap = capsys.readouterr()
    lines = [ln for ln in cap.out.splitlines() if ln.strip()]
    assert len(lines) == 1
    obj = json.loads(lines[0])
    table = pd.read_csv(out)
    assert tuple(table.columns[: len(SEGMENT_COLUMNS)]) == SEGMENT_COLUMNS
    assert obj["by"] == by and obj["n_segments"] == len(table) == len(obj["segments"])
    assert obj["detector"] == (DEFAULT_STEP_DETECTOR if by == "steps" else "pseudo-std")
    if len(table):
        assert obj["segments"][0]["start_s"] == pytest.approx(table["start_s"].iloc[0])
        conf = table["confidence"].iloc[0]
        assert obj["segments"][0]["confidence"] == (None if pd.isna(conf) else pytest.approx(conf))  # NaN -> null: valid JSON


def test_cli_summary_line(tmp_path, capsys):
    out = tmp_path / "seg.csv"
    assert main(["segment", WALK, "--by", "steps", "--detector", "ifsm", "--out", str(out)]) == 0
    cap = capsys.readouterr()
    n = len(detect_steps(read_recording(WALK), "ifsm"))
    assert f"{n} steps (ifsm)" in cap.out and len(pd.read_csv(out)) == n


@pytest.mark.parametrize(
    ("argv", "match"),
    [
        (["--by", "steps", "--detector", "shoe"], "unknown step detector 'shoe'"),
        (["--by", "strides", "--detector", "adaptive"], "unknown zero-velocity detector 'adaptive'"),
        (["--by", "stance"], "invalid choice: 'stance'"),
    ],
)
def test_cli_bad_detector_is_exit_2_one_line_no_file(argv, match, tmp_path, capsys):
    out = tmp_path / "seg.csv"
    assert main(["segment", WALK, *argv, "--out", str(out), "--json"]) == 2
    cap = capsys.readouterr()
    assert cap.out == ""
    lines = cap.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("gaitml: error: ") and match in lines[0] and "; " in lines[0]
    assert not list(tmp_path.iterdir())


def test_cli_needs_out(capsys):
    assert main(["segment", WALK]) == 2
    assert "--out" in capsys.readouterr().err


@pytest.mark.realdata
def test_gaitmap_strides_match_the_motion_capture_strides():
    rec = read_recording(shared("gaitmap-example", "imu_sample.csv.gz"), sensor="left")
    ev = rec.reference["stride_events"]
    st = segment(rec, by="strides")
    inside = st[(st["start"] >= ev["start"].min() - 100) & (st["end"] <= ev["end"].max() + 100)]
    # 28 motion-capture strides (min_vel to min_vel) + the turn rest that splits the long turn stride in two
    assert len(inside) == len(ev) + 1
    d = np.abs(inside["start"].to_numpy()[None, :] - ev["start"].to_numpy()[:, None]).min(axis=1) / rec.sampling_rate_hz
    assert np.mean(d <= 0.15) == 1.0  # every reference stride start has a segment start within 0.15 s
