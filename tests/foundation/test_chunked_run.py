"""Chunked (bounded-memory) runs equal whole-recording runs."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.chunked_run import long_features, long_steps, long_zupts
from gaitml.cli import main
from gaitml.io import read_recording, write_gaitml_csv
from gaitml.simulate import simulate_dataset


@pytest.fixture(scope="module")
def long_file(tmp_path_factory):
    rec = simulate_dataset(1, 240.0, sampling_rate_hz=50.0, seed=3)[0]
    p = tmp_path_factory.mktemp("long") / "long.csv"
    write_gaitml_csv(rec, p)
    return p


def test_long_steps_match_whole(long_file):
    from gaitml.steps import detect_steps

    whole = detect_steps(read_recording(long_file), detector="single-peak")
    chunked = long_steps(long_file, "single-peak", chunk_s=30.0, margin_s=5.0, progress=False)
    assert len(chunked) == len(whole)
    np.testing.assert_array_equal(chunked["peak"].to_numpy(), whole["peak"].to_numpy())


def test_long_zupts_match_whole(long_file):
    from gaitml.zupt import detect_zupts

    whole = detect_zupts(read_recording(long_file), detector="magnitude", return_detector=True).per_sample_zupts_
    mask, table, fs = long_zupts(long_file, "magnitude", chunk_s=20.0, margin_s=3.0, progress=False)
    np.testing.assert_array_equal(mask, whole)
    assert fs == 50.0


def test_long_features_match_whole(long_file):
    from gaitml.features import extract_features, make_windows

    rec = read_recording(long_file)
    wins = make_windows(rec, 1.5, 0.5, min_label_fraction=0.0)
    whole = extract_features(rec, wins)
    chunked = long_features(long_file, chunk_s=20.0, progress=False)
    assert len(chunked) == len(whole)
    np.testing.assert_array_equal(chunked["start"].to_numpy(), wins["start"].to_numpy())
    np.testing.assert_allclose(chunked[whole.columns].to_numpy(), whole.to_numpy(), rtol=0, atol=1e-9)


def test_steps_cli_switches_to_chunks(long_file, monkeypatch, capsys, tmp_path):
    import gaitml.io.chunked as ch

    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 1000)
    out = tmp_path / "steps.csv"
    assert main(["steps", str(long_file), "--json", "--out", str(out)]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d["chunked"] and d["n_steps"] > 300 and out.exists()


def test_features_cli_long_equals_short(long_file, monkeypatch, tmp_path):
    import pandas as pd

    import gaitml.io.chunked as ch

    short = tmp_path / "short.csv"
    assert main(["features", str(long_file), "--out", str(short)]) == 0
    monkeypatch.setattr(ch, "LARGE_INPUT_SAMPLES", 1000)
    long = tmp_path / "long.csv"
    assert main(["features", str(long_file), "--out", str(long)]) == 0
    a, b = pd.read_csv(short), pd.read_csv(long)
    assert list(a.columns) == list(b.columns) and len(a) == len(b)
    num = a.select_dtypes("number").columns
    np.testing.assert_allclose(b[num].to_numpy(), a[num].to_numpy(), rtol=1e-9, atol=1e-9)


def test_long_predict_matches_whole(long_file):
    from gaitml.chunked_run import long_predict
    from gaitml.models import load_model, predict_recording
    from tests.conftest import ROOT

    model = load_model(ROOT / "models" / "demo")
    whole = predict_recording(model, read_recording(long_file), correction=True)
    chunked = long_predict(model, long_file, chunk_s=20.0, progress=False)
    assert len(chunked) == len(whole)
    np.testing.assert_array_equal(chunked["start"].to_numpy(), whole["start"].to_numpy())
    np.testing.assert_array_equal(chunked["mode"].to_numpy(), whole["mode"].to_numpy())
    np.testing.assert_array_equal(chunked["mode_raw"].to_numpy(), whole["mode_raw"].to_numpy())
