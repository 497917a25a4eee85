"""Sampling rates: training copies at lower rates (data.augment.rates) and the rate check of predict."""

from __future__ import annotations

import json

import numpy as np
import pytest

from gaitml.cli import main
from gaitml.errors import ConfigError
from gaitml.models import load_model, predict_recording, rate_reason, resample_recording
from gaitml.pipeline.augment import rate_copies
from gaitml.pipeline.config import parse_config
from gaitml.pipeline.runner import prepare_data
from gaitml.simulate import simulate_dataset

CONFIG = """
name = "rates-small"
seed = 4
[data]
source = "simulated"
[data.simulated]
subjects = 3
duration_s = 40.0
[features]
set = "all52+gyro"
[train]
cross_validate = false
"""


def _sim_config(**augment):
    raw = {"name": "r", "seed": 2, "data": {"source": "simulated", "simulated": {"subjects": 2, "duration_s": 20.0}}}
    if augment:
        raw["data"]["augment"] = augment
    return parse_config(raw)


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    """Two small simulated models: trained at 50 Hz only, and with copies at 20 Hz (data.augment.rates)."""
    d = tmp_path_factory.mktemp("rates")
    (d / "plain.toml").write_text(CONFIG)
    (d / "rates.toml").write_text(CONFIG + "[data.augment]\nrates = [20]\n")
    for name in ("plain", "rates"):
        assert main(["train", str(d / f"{name}.toml"), "--out", str(d / name)]) == 0
    return d


@pytest.fixture(scope="module")
def walk():
    """A held-out simulated recording (another seed) at 50 Hz, and the files of it recorded at 50, 20 and 12 Hz."""
    return list(simulate_dataset(n_subjects=1, duration_s=30.0, seed=91))[0]


def _files(tmp_path, rec, rates=(50.0, 20.0, 12.0)):
    from gaitml.io import write_gaitml_csv

    out = {}
    for f in rates:
        p = tmp_path / f"walk{f:g}.csv"
        write_gaitml_csv(resample_recording(rec, f), p)
        out[f] = p
    return out


# ---- config


def test_rates_are_validated_and_written_only_when_set():
    cfg = _sim_config(rates=[20, 25.0])
    assert cfg["data"]["augment"]["rates"] == [20.0, 25.0]
    assert "augment" not in _sim_config().resolved()["data"]  # the default writes nothing: older configs resolve as before
    assert cfg.resolved()["data"]["augment"]["rates"] == [20.0, 25.0]
    for bad, msg in (
        (["20"], "must list sampling rates in Hz"),
        ([True], "must list sampling rates in Hz"),
        ([0.5], "not a sampling rate"),
        ([20, 20.0], "lists a rate twice"),
        ([50.0], "not below the model's rate data.resample_hz = 50 Hz"),
        ([80], "not below the model's rate"),
    ):
        with pytest.raises(ConfigError, match=msg):
            _sim_config(rates=bad)
    with pytest.raises(ConfigError, match="data.augment.rates"):
        _sim_config(rates=20)


# ---- the copies


def test_a_rate_copy_is_the_recording_down_and_back_up_through_predicts_resampling(walk):
    (c,) = rate_copies([walk], [20.0])
    ref = resample_recording(resample_recording(walk, 20.0), walk.sampling_rate_hz)
    n = c.n_samples
    assert abs(n - walk.n_samples) <= 2 and c.sampling_rate_hz == walk.sampling_rate_hz
    np.testing.assert_array_equal(c.acc, ref.acc[:n])
    np.testing.assert_array_equal(c.gyr, ref.gyr[:n])
    np.testing.assert_array_equal(c.labels, np.asarray(walk.labels, dtype=object)[:n])  # the truth, sample for sample
    assert c.meta["augmented"] == "recorded at 20 Hz" and c.meta["augment_rate_hz"] == 20.0 and c.meta["resampled_from_hz"] == 20.0
    assert walk.meta.get("augmented") is None

    # the copy lost what a 20 Hz phone cannot record: the power above its 10 Hz Nyquist rate (only the linear
    # interpolation's kinks are left there) is a small fraction of the original's
    def high(x):
        p = np.abs(np.fft.rfft(x - x.mean())) ** 2
        return p[np.fft.rfftfreq(len(x), 1 / walk.sampling_rate_hz) > 10.5].sum() / p.sum()

    assert high(c.acc[:, 2]) < 0.25 * high(walk.acc[:n, 2])
    with pytest.raises(Exception, match="below the recording's 50 Hz"):
        rate_copies([walk], [60.0])


def test_every_training_recording_gets_its_copies_in_its_own_group():
    plain = prepare_data(_sim_config(), use_cache=False)
    data = prepare_data(_sim_config(rates=[20, 25]), use_cache=False)
    n = len(plain.recordings)
    assert len(data.recordings) == 3 * n
    assert sorted(data.groups) == sorted(plain.groups * 3)
    copies = data.recordings[n:]
    assert sorted(r.meta["augment_rate_hz"] for r in copies) == [20.0] * n + [25.0] * n
    assert any(f"augmented: {2 * n} copies" in s for s in data.notes)


def test_the_copies_never_enter_the_domain_record_but_its_rate(models):
    from tests.pipeline.test_augment import assert_same_domain

    plain, rates = load_model(models / "plain"), load_model(models / "rates")
    assert_same_domain(rates.domain, plain.domain)
    assert np.isclose(rates.domain.distance_threshold, plain.domain.distance_threshold, rtol=1e-9)
    assert plain.domain.min_rate_hz == 50.0 and rates.domain.min_rate_hz == 20.0
    # twice the windows: every recording once more at 20 Hz
    assert rates.info["training_data"]["n_windows"] == 2 * plain.info["training_data"]["n_windows"]
    card = (models / "rates" / "MODEL.md").read_text()
    assert "Sampling rates: trained on recordings carrying 20 Hz and above" in card and "below 18 Hz" in card


def test_the_rate_record_is_saved_and_loaded(models):
    info = json.loads((models / "rates" / "model.json").read_text())
    assert info["domain"]["min_rate_hz"] == 20.0
    assert json.loads((models / "plain" / "model.json").read_text())["domain"]["min_rate_hz"] == 50.0


# ---- the check


def test_a_recording_below_the_training_rates_is_flagged_in_every_window(models, walk):
    plain, rates = load_model(models / "plain"), load_model(models / "rates")
    low = resample_recording(walk, 20.0)
    p = predict_recording(plain, low)
    assert (p["in_domain"] == False).all()  # noqa: E712 (object column)
    assert set(p["out_of_domain_reason"]) == {"rate: recorded at 20 Hz, below the 50 Hz the model was trained at"}
    assert p.attrs["rate_check"] == {"recorded_hz": 20.0, "trained_min_hz": 50.0, "tolerance": 0.9, "below": True}
    # the model trained with 20 Hz copies answers it; 46 Hz (a nominal 50 Hz phone running slow) is within the tolerance
    q = predict_recording(rates, low)
    assert not any(str(r).startswith("rate:") for r in q["out_of_domain_reason"]) and q.attrs["rate_check"]["below"] is False
    assert rate_reason(plain, 46.0) == "" and rate_reason(plain, 44.0).startswith("rate: recorded at 44 Hz")
    assert rate_reason(rates, 17.0) == "rate: recorded at 17 Hz, below the 20 Hz the model was trained at"
    # the windows the features check alone flags are still flagged at the model's own rate (the rate adds, never removes)
    native = predict_recording(plain, walk)
    assert native.attrs["rate_check"]["below"] is False
    assert not any(str(r).startswith("rate:") for r in native["out_of_domain_reason"])


def test_a_recording_brought_up_to_a_higher_rate_is_judged_at_the_rate_it_was_made_at(models, walk, tmp_path, capsys):
    """Up-sampling adds no signal: a 12 Hz walk resampled to 50 Hz by a caller, or read with --sampling-rate-hz 50, is still 12 Hz."""
    m = load_model(models / "rates")
    up = resample_recording(resample_recording(walk, 12.0), 50.0)
    assert up.sampling_rate_hz == 50.0 and up.meta["resampled_from_hz"] == 12.0
    p = predict_recording(m, up)
    assert (p["in_domain"] == False).all() and p.attrs["rate_check"]["recorded_hz"] == 12.0  # noqa: E712
    files = _files(tmp_path, walk, (12.0,))
    assert main(["predict", str(models / "rates"), str(files[12.0]), "--sampling-rate-hz", "50", "--json"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert d["out_of_domain_fraction"] == 1.0 and d["rate_check"]["below"] is True
    assert len([ln for ln in cap.err.splitlines() if "rate:" in ln]) == 1


def test_the_windows_of_a_slower_stretch_are_flagged_and_the_rest_answered(models, walk):
    """A file whose reader found a stretch at another rate (meta rate_changes) has that stretch's windows out of domain."""
    m = load_model(models / "rates")
    rec = walk.replace(meta={**walk.meta, "rate_changes": [[10.0, 20.0, 10.0]]}, check_units=False)
    p = predict_recording(m, rec)
    inside = (p["t_end_s"] > 10.0) & (p["t_start_s"] < 20.0)
    reason = "rate: recorded at 10 Hz, below the 20 Hz the model was trained at"
    assert inside.any() and (~inside).any()
    assert (p.loc[inside, "out_of_domain_reason"] == reason).all() and (p.loc[inside, "in_domain"] == False).all()  # noqa: E712
    assert not p.loc[~inside, "out_of_domain_reason"].astype(str).str.startswith("rate:").any()
    assert p.attrs["rate_check"]["below"] is False


def test_cli_predict_says_it_in_the_table_the_json_and_one_stderr_line(models, walk, tmp_path, capsys):
    files = _files(tmp_path, walk)
    out_csv = tmp_path / "t.csv"
    assert main(["predict", str(models / "rates"), str(files[12.0]), "--json", "--out", str(out_csv)]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    reason = "rate: recorded at 12 Hz, below the 20 Hz the model was trained at"
    assert d["out_of_domain_fraction"] == 1.0 and d["out_of_domain_reasons"] == {reason: len(d["windows"])}
    assert all(w["in_domain"] is False and w["out_of_domain_reason"] == reason for w in d["windows"])
    assert d["rate_check"] == {"recorded_hz": 12.0, "trained_min_hz": 20.0, "tolerance": 0.9, "below": True}
    lines = [ln for ln in cap.err.splitlines() if "rate:" in ln]
    assert len(lines) == 1 and lines[0].startswith("gaitml: warning:") and reason in lines[0]
    import pandas as pd

    t = pd.read_csv(out_csv)
    assert (t["out_of_domain_reason"] == reason).all()
    # at 20 Hz the same model says nothing about the rate
    assert main(["predict", str(models / "rates"), str(files[20.0]), "--json"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    assert "rate:" not in cap.err and not any(k.startswith("rate:") for k in d["out_of_domain_reasons"])
    assert d["rate_check"]["below"] is False


def test_chunked_predict_flags_as_the_whole_file_does(models, walk, tmp_path, monkeypatch):
    from gaitml.chunked_run import long_predict

    files = _files(tmp_path, walk, (12.0,))
    m = load_model(models / "rates")
    whole = predict_recording(m, resample_recording(walk, 12.0))
    chunked = long_predict(m, files[12.0], chunk_s=10.0, progress=False)
    assert len(chunked) == len(whole) and (chunked["in_domain"] == False).all()  # noqa: E712
    assert set(chunked["out_of_domain_reason"]) == set(whole["out_of_domain_reason"]) and chunked.attrs["rate_check"]["below"]


def test_streaming_extractor_keeps_the_rate_check(models):
    from gaitml.features import StreamingFeatureExtractor

    m = load_model(models / "rates")
    assert StreamingFeatureExtractor.for_model(m, recorded_hz=12.0).rate_reason_.startswith("rate: recorded at 12 Hz")
    assert StreamingFeatureExtractor.for_model(m, recorded_hz=20.0).rate_reason_ == ""
    assert StreamingFeatureExtractor.for_model(m).rate_reason_ is None


def test_pdr_with_a_model_gives_each_step_the_rate_reason(models, walk, tmp_path, capsys):
    files = _files(tmp_path, walk, (12.0,))
    assert main(["pdr", str(files[12.0]), "--model", str(models / "rates"), "--json"]) == 0
    cap = capsys.readouterr()
    d = json.loads(cap.out)
    steps = d["trajectory"][1:]  # the first row is the start
    assert steps and all(s["in_domain"] is False and s["out_of_domain_reason"].startswith("rate: recorded at 12 Hz") for s in steps)
    assert d["out_of_domain_steps"] == len(steps)
    assert len([ln for ln in cap.err.splitlines() if "rate:" in ln]) == 1


def test_a_model_saved_before_the_rate_record_still_predicts_without_a_rate_check(models, walk, tmp_path):
    """A model.json whose domain has no min_rate_hz (saved before): predict works, the rate is not checked, the card says so."""
    import shutil

    from gaitml.models import model_card
    from gaitml.models._persist import settings_sha256

    old = tmp_path / "old"
    shutil.copytree(models / "plain", old)
    info = json.loads((old / "model.json").read_text())
    del info["domain"]["min_rate_hz"]
    info["settings_sha256"] = settings_sha256(info)
    (old / "model.json").write_text(json.dumps(info))
    m = load_model(old)
    assert m.domain is not None and m.domain.min_rate_hz is None and rate_reason(m, 5.0) is None
    p = predict_recording(m, resample_recording(walk, 12.0))
    assert p.attrs["rate_check"] is None and not any(str(r).startswith("rate:") for r in p["out_of_domain_reason"])
    assert p["in_domain"].map(lambda v: v is True or v is np.True_).any()
    assert "Sampling rates: not recorded" in model_card(info)
