"""Data-only model folders (gaitml.models._persist, _export, _card): no unpickling, conversion, JSON/ONNX export, model card.

The JSON test re-implements prediction from the exported JSON alone in plain numpy
(only the feature extraction, which the JSON specifies, comes from gaitml.features).
"""

from __future__ import annotations

import json
import pickle
import shutil
from pathlib import Path

import numpy as np
import pytest

from gaitml.errors import ModelError
from gaitml.models import (
    build_window_dataset,
    convert_model,
    export_json,
    load_model,
    make_model,
    model_card,
    predict_recording,
    read_model_json,
    resample_recording,
    save_model,
    torch_available,
)
from gaitml.models._legacy import load_legacy_model
from gaitml.models._persist import settings_sha256, sha256_file
from tests.conftest import ROOT, shared
from tests.models.synth import synth_recording, synth_set

LEGACY = Path(__file__).parent / "data" / "legacy-demo"
DEMO = ROOT / "models" / "demo"
needs_torch = pytest.mark.skipif(not torch_available(), reason="torch extra not installed")


def _route():
    from gaitml.simulate import simulate_route

    return simulate_route("rectangle", seed=3)


def _gaitmap_real():
    from gaitml.io import read_recording

    return read_recording(shared("gaitmap-example", "imu_sample.csv.gz"), sensor="left")


# ------------------------------------------------------------------ old pickle models
def test_old_pickle_model_is_refused_with_the_convert_command(tmp_path, capsys):
    from gaitml.cli import main

    with pytest.raises(ModelError, match=r"gaitml model convert .*legacy-demo .*legacy-demo-v2") as exc:
        load_model(LEGACY)
    assert "\n" not in str(exc.value)
    assert main(["model", "card", str(LEGACY)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "gaitml model convert" in err


def test_convert_keeps_predictions_and_weights(tmp_path):
    # the legacy pickle is the demo model as first shipped (format 1); models/demo has since been
    # retrained in the data-only format (simulator with hand gain), so the conversion is checked
    # against the pickle itself
    old = load_legacy_model(LEGACY)
    new = convert_model(LEGACY, tmp_path / "demo")
    assert sorted(p.name for p in (tmp_path / "demo").iterdir()) == ["MODEL.md", "arrays.npz", "model.json"]
    assert new.info["converted_from"]["sha256"] == old.info["sha256"]
    assert new.info["created_utc"] == old.info["created_utc"]
    rec = _route()
    before = predict_recording(old, rec)
    after = predict_recording(new, rec)
    np.testing.assert_array_equal(after["mode_raw"].to_numpy(), before["mode_raw"].to_numpy())
    np.testing.assert_array_equal(after["mode"].to_numpy(), before["mode"].to_numpy())
    for name in ("coef_", "intercept_", "mean_", "scale_", "pairs_", "classes_"):
        np.testing.assert_array_equal(getattr(new.estimator, name), getattr(old.estimator, name))


@pytest.mark.realdata
def test_converted_demo_predicts_like_the_pickle_on_a_real_recording(tmp_path):
    rec = _gaitmap_real()
    before = predict_recording(load_legacy_model(LEGACY), rec)
    after = predict_recording(convert_model(LEGACY, tmp_path / "demo"), rec)
    np.testing.assert_array_equal(after["mode"].to_numpy(), before["mode"].to_numpy())
    np.testing.assert_array_equal(after["mode_raw"].to_numpy(), before["mode_raw"].to_numpy())


def test_convert_refuses_bad_input(tmp_path):
    with pytest.raises(ModelError, match="give another folder"):
        convert_model(LEGACY, LEGACY)
    with pytest.raises(ModelError, match="not an old"):
        convert_model(DEMO, tmp_path / "x")
    bad = tmp_path / "bad"
    shutil.copytree(LEGACY, bad)
    b = bytearray((bad / "model.joblib").read_bytes())
    b[len(b) // 2] ^= 0xFF
    (bad / "model.joblib").write_bytes(bytes(b))
    with pytest.raises(ModelError, match="refusing to unpickle"):
        convert_model(bad, tmp_path / "y")
    assert not (tmp_path / "y").exists()


# ------------------------------------------------------------------ torch kinds
@needs_torch
@pytest.mark.parametrize("kind", ["mlp", "cnn1d"])
def test_torch_model_roundtrip_is_weights_only(tmp_path, kind):
    recs = synth_set(3, seconds_per_mode=8.0)
    ds = build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5, need_raw=True)
    est = make_model(kind, {"epochs": 2})
    X = ds.inputs(est.input_kind)
    est.fit(X, ds.y)
    info = _info(ds, kind, est.input_kind)
    save_model(tmp_path / "m", est, info)
    saved = json.loads((tmp_path / "m" / "model.json").read_text())
    assert set(saved["files"]) == {"arrays.npz", "weights.pt"}
    m = load_model(tmp_path / "m")
    np.testing.assert_array_equal(m.estimator.predict_proba(X), est.predict_proba(X))
    np.testing.assert_array_equal(m.estimator.predict(X), est.predict(X))


def _info(ds, kind="linear-ovo-svm", input_kind="features", fset="all52"):
    from gaitml.features import feature_names

    return {
        "model_kind": kind,
        "input_kind": input_kind,
        "feature_set": fset,
        "feature_names": list(feature_names(fset)) if input_kind == "features" else [],
        "raw_channels": list(ds.raw_channels) if input_kind == "raw" else [],
        "window": {"length_s": 1.5, "overlap": 0.5, "min_label_fraction": 0.5},
        "sampling_rate_hz": 50.0,
        "labels": sorted(set(ds.y)),
        "postprocess": {"adjacent_correction": True},
    }


# ------------------------------------------------------------------ JSON export in plain numpy
def _forward_from_json(spec: dict, acc: np.ndarray, starts: np.ndarray, length: int) -> np.ndarray:
    """W1..W6 of every window, step by step as spec["features"]["conventions"]["forward_vector"]["rule"] states them:
    columns acc_x/y/z__fwd then acc_x/y/z__fwdface."""
    rule = spec["features"]["conventions"]["forward_vector"]
    lo, hi = rule["band_hz"]
    fs, n = float(spec["sampling_rate_hz"]), length
    t = np.arange(n)
    freq = np.arange(n // 2 + 1) * fs / n  # coefficient k of the real DFT is at k fs / N
    out = np.zeros((len(starts), 6))
    for r, s in enumerate(starts):
        w = acc[s : s + n]
        g = w.mean(axis=0)
        up = g / np.linalg.norm(g) if np.linalg.norm(g) > 1e-6 else np.array([0.0, 0.0, 1.0])
        d = np.column_stack([w[:, c] - np.polyval(np.polyfit(t, w[:, c], 1), t) for c in range(3)])
        spec_c = np.fft.rfft(d, axis=0)
        spec_c[(freq < lo) | (freq > hi)] = 0.0
        bp = np.fft.irfft(spec_c, n=n, axis=0)
        v = bp @ up
        h = bp - np.outer(v, up)
        dv = (v[(t + 1) % n] - v[(t - 1) % n]) * fs / 2
        F = (h * dv[:, None]).mean(axis=0)
        den = np.sqrt(np.mean(np.sum(h * h, axis=1)) * np.mean(dv * dv))
        out[r, :3] = F / den if den > 1e-12 else 0.0
        out[r, 3:] = out[r, :3] * max(0.0, up[2])
    return out


def _numpy_predict_from_json(
    spec: dict, acc: np.ndarray, gyr: np.ndarray | None, cadence_hz: np.ndarray | None = None, step_peaks: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Prediction from the exported JSON alone (features from gaitml.features, as the JSON specifies).

    ``cadence_hz``: each window's local step cadence (from a step detector: not in the JSON) for the
    run-cadence rule; None leaves the rule out. ``step_peaks``: the peaks (samples at the JSON's
    ``sampling_rate_hz``) of a step detector run over the whole recording (not in the JSON) for the still
    gate's step veto, counted per window as the JSON's rule states; None leaves the veto out."""
    from gaitml.features import features_from_arrays

    length, hop = spec["window"]["length_samples"], spec["window"]["hop_samples"]
    starts = np.arange(0, len(acc) - length + 1, hop)
    names = [f["name"] for f in spec["features"]["features"]]
    X = features_from_arrays(acc, gyr, fs=spec["sampling_rate_hz"], starts=starts, length=length, subset=spec["features"]["set"])
    assert X.shape[1] == len(names)
    fwd = [i for i, f in enumerate(spec["features"]["features"]) if f["stat"] in ("fwd", "fwdface")]
    if fwd:  # the forward vector from the JSON's own words, not gaitml's code
        own = _forward_from_json(spec, acc, starts, length)
        cols = [
            ("xyz".index(f["channel"][-1]) + (3 if f["stat"] == "fwdface" else 0)) for f in (spec["features"]["features"][i] for i in fwd)
        ]
        # the words give gaitml's numbers (not only its answers: a flat phone's face-up weight is 1 whatever its form)
        np.testing.assert_allclose(own[:, cols], X[:, fwd], rtol=0, atol=1e-9)
        X[:, fwd] = own[:, cols]
    clf = spec["classifier"]
    coef, intercept = np.array(clf["coef"]), np.array(clf["intercept"])
    pairs, labels = clf["pairs"], spec["labels"]
    d = X @ coef.T + intercept
    votes = np.zeros((len(X), len(labels)))
    conf = np.zeros((len(X), len(labels)))
    for k, (i, j) in enumerate(pairs):
        votes[:, i] += d[:, k] > 0
        votes[:, j] += d[:, k] <= 0
        conf[:, i] += d[:, k]
        conf[:, j] -= d[:, k]
    raw = [labels[c] for c in np.argmax(votes + conf / (3 * (np.abs(conf) + 1)), axis=1)]
    out = list(raw)
    for k in range(1, len(raw) - 1):  # the correction rule as written in spec["postprocess"]["rule"]
        w1 = out[k - 2] if k >= 2 else None
        w2, w3, w4 = out[k - 1], raw[k], raw[k + 1]
        if w1 is not None and w2 != w3 and w2 != w4 and w3 != w4 and w1 == w2:
            out[k] = w2
        elif w2 == w4 and w2 != w3:
            out[k] = w2
    still = spec["postprocess"]["still"]  # the still gate as the JSON states it
    mag = np.linalg.norm(acc, axis=1)
    if still["statistic"] == "std_lp":  # each window's axes low-passed over its own samples, then the std of |acc|
        import scipy.signal

        sos = scipy.signal.butter(still["lowpass_order"], still["lowpass_hz"], fs=spec["sampling_rate_hz"], output="sos")
        pad = min(3 * (2 * len(sos) + 1), length - 1)
        value = np.array(
            [np.linalg.norm(scipy.signal.sosfiltfilt(sos, acc[s : s + length], axis=0, padlen=pad), axis=1).std() for s in starts]
        )
    else:
        stat = {"std": np.std, "range": np.ptp}[still["statistic"]]
        value = np.array([stat(mag[s : s + length]) for s in starts])
    veto = still["step_veto"]  # the step veto as the JSON states it
    kept = np.zeros(len(value), dtype=bool)
    if step_peaks is not None:  # "at least min_steps steps whose peak lies inside the window (start <= peak < end)"
        peaks = np.asarray(step_peaks, dtype=np.int64)
        kept = np.array([np.sum((peaks >= s) & (peaks < s + length)) >= veto["min_steps"] for s in starts], dtype=bool)
    out = [still["mode"] if v < still["threshold_ms2"] and not k else m for m, v, k in zip(out, value, kept, strict=True)]
    run = spec["postprocess"]["run_cadence"]  # the run-cadence rule as the JSON states it
    if cadence_hz is not None:
        scores = votes + conf / (3 * (np.abs(conf) + 1))
        scores[:, labels.index(run["mode"])] = -np.inf
        for k, c in enumerate(cadence_hz):
            if out[k] == run["mode"] and run["stride_cadence_hz"] <= c < run["min_cadence_hz"]:
                out[k] = raw[k] if raw[k] != run["mode"] else labels[int(np.argmax(scores[k]))]
    side = spec["postprocess"]["side_direction"]  # the side-direction flag as the JSON states it
    g = np.array([acc[s : s + length].mean(axis=0) for s in starts])
    cos_z = g[:, 2] / np.linalg.norm(g, axis=1)
    unsure = np.isin(out, side["modes"]) & (cos_z < np.cos(np.radians(side["face_up_max_deg"])))
    return np.array(raw), np.array(out), unsure


def _still_unsure_from_json(
    spec: dict, gyr: np.ndarray | None, starts: np.ndarray, length: int, labels, projections: list | None = None
) -> np.ndarray:
    """The ``still_unsure`` mark from the JSON's words alone (``postprocess.still.unsure``): numpy and scipy's filter,
    no gaitml code. ``labels``: the reader's own labels after the still gate and its veto. ``projections``: a list the
    projection x of each still window is appended to (to compare numbers, not only marks)."""
    import scipy.signal

    u = spec["postprocess"]["still"]["unsure"]
    marked = np.zeros(len(starts), dtype=bool)
    if not u["in_force"] or gyr is None:
        return marked
    fs = float(spec["sampling_rate_hz"])
    n = len(gyr)
    q = max(1, int(np.floor(fs / u["decimate_to_hz"])))
    L = int(round(u["window_s"] * fs / q))
    S = L * q
    if n < S:
        return marked
    f = fs / q
    pad = int(round(u["pad_s"] * fs))
    sos = scipy.signal.butter(2, [u["band_hz"][0], min(u["band_hz"][1], 0.45 * fs)], btype="bandpass", fs=fs, output="sos")
    lo_step, hi_step = u["step_hz"]
    lags = np.arange(max(int(np.floor(2 * f / hi_step)) - 1, 1), min(int(np.ceil(2 * f / lo_step)) + 1, L - 3) + 1)

    def r(x, k):  # the normalised autocorrelation at integer lag k
        a, b = x[: L - k], x[k:]
        den = np.sqrt(np.sum(a * a) * np.sum(b * b))
        return float(np.sum(a * b) / den) if den > 0 else 0.0

    for w in np.flatnonzero(np.asarray(labels) == spec["postprocess"]["still"]["mode"]):
        a = min(max((2 * int(starts[w]) + length - S) // 2, 0), n - S)
        lo, hi = max(a - pad, 0), min(a + S + pad, n)
        piece = scipy.signal.sosfiltfilt(sos, gyr[lo:hi] - gyr[lo:hi].mean(axis=0), axis=0)
        five = piece[a - lo : a - lo + S : q]
        five = five - five.mean(axis=0)
        x = five @ np.linalg.eigh(five.T @ five)[1][:, -1]
        if projections is not None:
            projections.append(x)
        if np.sqrt(np.mean(x**2)) < u["min_rms_rads"] or len(lags) < 3:
            continue
        rk = np.array([r(x, int(k)) for k in lags])
        peaks = [i for i in range(1, len(lags) - 1) if rk[i] >= rk[i - 1] and rk[i] > rk[i + 1]]
        if not peaks:
            continue
        best = max(rk[i] for i in peaks)
        near = [i for i in peaks if rk[i] >= u["octave_tolerance"] * best]
        if not near:
            continue
        P = float(lags[near[0]])
        k0 = int(np.floor(P / 2))
        half = (1 - (P / 2 - k0)) * r(x, k0) + (P / 2 - k0) * r(x, k0 + 1)
        marked[w] = rk[near[0]] >= u["min_periodicity"] and half <= u["max_half_correlation"] and f / hi_step <= P / 2 <= f / lo_step
    return marked


def _check_json_equals_predict(model, rec, tmp_path):
    from gaitml.cli import main
    from gaitml.models._predict import recording_steps

    out = tmp_path / "model.export.json"
    assert main(["model", "export", str(model.path), "--format", "json", "--out", str(out)]) == 0
    spec = json.loads(out.read_text())
    rec = resample_recording(rec, spec["sampling_rate_hz"])  # the JSON's "resampling" step (a no-op at the model's rate)
    run = spec["postprocess"]["run_cadence"]
    for on in (run["in_force"], not run["in_force"]):  # predict's default first, then the run-cadence rule the other way
        table = predict_recording(
            model, rec, **({} if on == run["in_force"] else {"run_min_cadence_hz": run["min_cadence_hz"] if on else 0})
        )
        cadence = table["step_cadence_hz"].to_numpy() if on else None  # the cadence is a step detector's, not in the JSON
        # so are the steps of the still gate's veto: gaitml's detector (the JSON names it, with its swing stage's
        # setting where the recording has a gyroscope) over the whole recording
        veto = spec["postprocess"]["still"]["step_veto"]
        peaks = recording_steps(rec, veto["swing_periodicity"] if rec.has_gyr else 0.0)["peak"].to_numpy() if veto["in_force"] else None
        raw, corrected, unsure = _numpy_predict_from_json(spec, rec.acc, rec.gyr, cadence, peaks)
        assert len(raw) == len(table) > 20
        np.testing.assert_array_equal(raw, table["mode_raw"].to_numpy())
        np.testing.assert_array_equal(corrected, table["mode"].to_numpy())
        np.testing.assert_array_equal(unsure, table["side_direction_unsure"].to_numpy(bool))
        starts = np.arange(0, len(rec.acc) - spec["window"]["length_samples"] + 1, spec["window"]["hop_samples"])
        still_unsure = _still_unsure_from_json(spec, rec.gyr, starts, spec["window"]["length_samples"], corrected)
        np.testing.assert_array_equal(still_unsure, table["still_unsure"].to_numpy(bool))
    return spec


def test_json_export_in_plain_numpy_equals_predict_on_the_demo_route(tmp_path):
    spec = _check_json_equals_predict(load_model(DEMO), _route(), tmp_path)
    f = spec["features"]["features"]
    assert len(f) == 107 and f[0]["code"] == "F1" and f[51]["paper_number"] == 52 and f[52]["code"] == "G1" and f[52]["paper_number"] == 1
    assert [x["code"] for x in f[104:]] == ["W4", "W5", "W6"]  # the face-up-weighted forward vector (features/catalogue.md)
    assert spec["features"]["set"] in spec["features"]["channels"]["gyr_x, gyr_y, gyr_z"]  # the gyroscope's sets name the model's
    assert spec["window"]["length_samples"] == 75 and spec["window"]["hop_samples"] == 38
    for key in ("rule", "tie_rule"):
        assert spec["classifier"]["voting"][key]
    assert "sec. 3.4" in spec["postprocess"]["source"]
    # the standardised form in the export is the same decision
    clf = spec["classifier"]
    x = np.array(clf["scaler"]["mean"]) + np.array(clf["scaler"]["scale"])
    z = (x - np.array(clf["scaler"]["mean"])) / np.array(clf["scaler"]["scale"])
    np.testing.assert_allclose(
        np.array(clf["coef_standardised"]) @ z + np.array(clf["intercept_standardised"]),
        np.array(clf["coef"]) @ x + np.array(clf["intercept"]),
        rtol=1e-9,
        atol=1e-9,
    )


@pytest.mark.realdata
def test_json_export_in_plain_numpy_equals_predict_on_real_recordings(tmp_path):
    from gaitml.io import read_recording
    from gaitml.models import LinearOVOSVM

    # the shipped gyro model on a real IMU recording (204.8 Hz, resampled to 50 Hz)
    _check_json_equals_predict(load_model(DEMO), _gaitmap_real(), tmp_path)
    # an accelerometer-only model on the real IFSM phone recording at its own 50 Hz
    recs = synth_set(3, seconds_per_mode=10.0)
    ds = build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5)
    save_model(tmp_path / "acc", LinearOVOSVM().fit(ds.inputs("features"), ds.y), _info(ds))
    rec = read_recording(shared("ifsm-flat-phone", "acceleration_flat_holding_1.xlsx"))
    assert rec.sampling_rate_hz == 50.0
    _check_json_equals_predict(load_model(tmp_path / "acc"), rec, tmp_path)


def test_json_export_in_plain_numpy_applies_the_step_veto(tmp_path):
    """A calm walker whose |acc| the still gate's statistic reads still between two standing stretches: the plain reader
    applies the step veto from the JSON's words (the detector's peaks counted per window) and equals predict, and the
    veto is what keeps those windows in their mode (the reader without it answers them still)."""
    from tests.models.test_still_step_veto import calm_walker

    model, rec = load_model(DEMO), calm_walker(40.0, stand_s=15.0)
    table = predict_recording(model, rec)
    vetoed = table["still_vetoed"].to_numpy(bool)
    assert vetoed.sum() > 30 and table["still"].sum() > 10  # the veto and the gate both answer here
    spec = _check_json_equals_predict(model, rec, tmp_path)
    _raw, without, _unsure = _numpy_predict_from_json(spec, rec.acc, rec.gyr)
    assert (without[vetoed] == spec["postprocess"]["still"]["mode"]).all()


def test_json_export_states_the_vetos_swing_stage_as_predict_runs_it(tmp_path):
    """A weak ear walk whose phone turns once per stride (the veto's swing-stage steps are not adaptive's defaults'
    there): the export states the swing setting predict runs (``swing_periodicity``), and the plain reader that runs the
    detector with it equals predict, while the defaults' steps answer windows differently."""
    import gaitml.models._predict as P
    from gaitml.models._predict import recording_steps
    from gaitml.recording import Recording
    from tests.models.test_still_veto_swing import ear_walk

    model = load_model(DEMO)
    parts = [ear_walk(seed, seconds=60.0, stand_s=20.0)[0] for seed in range(2)]
    rec = Recording(acc=np.vstack([r.acc for r in parts]), gyr=np.vstack([r.gyr for r in parts]), sampling_rate_hz=50.0)
    spec = _check_json_equals_predict(model, rec, tmp_path)
    veto = spec["postprocess"]["still"]["step_veto"]
    assert veto["swing_periodicity"] == P.STILL_STEP_SWING_PERIODICITY > 0 and "swing stage" in veto["rule"]
    table = predict_recording(model, rec)
    _raw, with_defaults, _unsure = _numpy_predict_from_json(
        spec, rec.acc, rec.gyr, table["step_cadence_hz"].to_numpy(), recording_steps(rec)["peak"].to_numpy()
    )
    assert (with_defaults != table["mode"].to_numpy()).sum() >= 10  # the stated setting matters on this walk


def test_json_export_refuses_torch_kinds(tmp_path):
    class Fake:
        kind = "mlp"

    with pytest.raises(ModelError, match="--format onnx"):
        export_json(Fake())


# ------------------------------------------------------------------ ONNX
def _ort():
    return pytest.importorskip("onnxruntime", reason="optional extra gaitml[onnx] (onnx, onnxruntime) not installed")


def test_onnx_export_equals_predict(tmp_path):
    ort = _ort()
    from gaitml.cli import main
    from gaitml.models import model_inputs
    from gaitml.models._predict import _windows_for

    out = tmp_path / "demo.onnx"
    assert main(["model", "export", str(DEMO), "--format", "onnx", "--out", str(out)]) == 0
    sess = ort.InferenceSession(str(out), providers=["CPUExecutionProvider"])
    model = load_model(DEMO)
    recs = [_route()]
    try:
        recs.append(resample_recording(_gaitmap_real(), 50.0))
    except pytest.skip.Exception:
        pass
    for rec in recs:
        X = model_inputs(model, rec, _windows_for(rec, model.length_s, model.overlap))
        label, _, scores = sess.run(None, {"features": X})
        table = predict_recording(model, rec, correction=False)
        np.testing.assert_array_equal(np.asarray(label).astype(str), table["mode_raw"].to_numpy())
    meta = {p.key: p.value for p in __import__("onnx").load(str(out)).metadata_props}
    assert json.loads(meta["gaitml"])["features"]["features"][0]["code"] == "F1"


@needs_torch
@pytest.mark.parametrize("kind", ["mlp", "cnn1d"])
def test_onnx_export_of_torch_models_equals_predict(tmp_path, kind):
    ort = _ort()
    pytest.importorskip("onnxscript", reason="torch.onnx.export needs onnxscript (extra gaitml[onnx])")
    from gaitml.models import export_onnx

    recs = synth_set(3, seconds_per_mode=8.0)
    ds = build_window_dataset(recs, groups=[r.meta["subject"] for r in recs], length_s=1.5, overlap=0.5, need_raw=True)
    est = make_model(kind, {"epochs": 3})
    X = ds.inputs(est.input_kind)
    est.fit(X, ds.y)
    save_model(tmp_path / "m", est, _info(ds, kind, est.input_kind))
    model = load_model(tmp_path / "m")
    export_onnx(model, tmp_path / "m.onnx")
    sess = ort.InferenceSession(str(tmp_path / "m.onnx"), providers=["CPUExecutionProvider"])
    (proba,) = sess.run(None, {"features": np.asarray(X, dtype=np.float64)})
    np.testing.assert_allclose(proba, model.estimator.predict_proba(X), rtol=1e-4, atol=1e-5)
    np.testing.assert_array_equal(model.estimator.classes_[np.argmax(proba, axis=1)], model.estimator.predict(X))


# ------------------------------------------------------------------ model card
def test_shipped_models_have_an_up_to_date_card():
    for folder in sorted(p for p in (ROOT / "models").iterdir() if (p / "model.json").is_file()):
        _, info = read_model_json(folder)
        assert (folder / "MODEL.md").read_text(encoding="utf-8") == model_card(info), f"regenerate {folder}/MODEL.md"


def test_model_card_command(tmp_path, capsys):
    from gaitml.cli import main

    assert main(["model", "card", str(DEMO)]) == 0
    text = capsys.readouterr().out
    for part in (
        "# Model card: demo",
        "## Training data",
        "## Cross-validation",
        "| walk |",
        "## Domain it is valid for",
        "## Known failure cases",
        "## Versions",
        "all52+gyro",
        "1.5 s",
    ):
        assert part in text
    assert main(["model", "card", str(DEMO), "--out", str(tmp_path / "card.md")]) == 0
    assert (tmp_path / "card.md").read_text() == text


# ------------------------------------------------------------------ security
class _Payload:
    """Unpickling this writes ``marker`` (what an attacker's model file would do)."""

    def __init__(self, marker: Path):
        self.marker = str(marker)

    def __reduce__(self):
        return (exec, (f"open({self.marker!r}, 'w').write('unpickled')",))


def _rehash(folder: Path) -> None:
    """Recompute every hash in model.json so that the tampering is not caught by a hash."""
    info = json.loads((folder / "model.json").read_text())
    if "files" in info:
        info["files"] = {name: sha256_file(folder / name) for name in info["files"]}
    if "sha256" in info:
        info["sha256"] = sha256_file(folder / "model.joblib")
    info["settings_sha256"] = settings_sha256(info)
    (folder / "model.json").write_text(json.dumps(info))


def _npz_with_pickled_member(path: Path, marker: Path) -> None:
    import io
    import zipfile

    buf = io.BytesIO()
    np.save(buf, np.array([_Payload(marker)], dtype=object), allow_pickle=True)
    with zipfile.ZipFile(path, "w") as z:
        z.writestr("coef_.npy", buf.getvalue())


def _attacks(tmp_path: Path, marker: Path):
    """(name, model folder) pairs, each with a crafted pickle where a model file is expected."""
    payload = pickle.dumps(_Payload(marker))
    out = []
    # 1. an old-format folder: model.joblib is the payload, model.json (format 1) rehashed
    d = tmp_path / "legacy"
    shutil.copytree(LEGACY, d)
    (d / "model.joblib").write_bytes(payload)
    _rehash(d)
    out.append(("model.joblib, format 1", d))
    # 2. a current folder with format_version edited to 1 and the payload as model.joblib
    d = tmp_path / "downgraded"
    shutil.copytree(DEMO, d)
    (d / "model.joblib").write_bytes(payload)
    info = json.loads((d / "model.json").read_text())
    info.update(format_version=1, sha256="")
    (d / "model.json").write_text(json.dumps(info))
    _rehash(d)
    out.append(("model.joblib, format edited to 1", d))
    # 3. arrays.npz replaced by the raw pickle
    d = tmp_path / "npz-pickle"
    shutil.copytree(DEMO, d)
    (d / "arrays.npz").write_bytes(payload)
    _rehash(d)
    out.append(("arrays.npz = pickle", d))
    # 4. arrays.npz a real zip whose .npy member is a pickled object array
    d = tmp_path / "npz-object"
    shutil.copytree(DEMO, d)
    _npz_with_pickled_member(d / "arrays.npz", marker)
    _rehash(d)
    out.append(("arrays.npz with an object-array member", d))
    if torch_available():
        import torch

        recs = synth_set(2, seconds_per_mode=6.0)
        ds = build_window_dataset(recs, groups=["a", "b"], length_s=1.5, overlap=0.5)
        est = make_model("mlp", {"epochs": 1}).fit(ds.inputs("features"), ds.y)
        # 5. weights.pt as a torch zip archive whose data.pkl is the payload
        d = tmp_path / "torch-zip"
        save_model(d, est, _info(ds, "mlp"))
        torch.save(_Payload(marker), d / "weights.pt")
        _rehash(d)
        out.append(("weights.pt = torch.save(payload)", d))
        # 6. weights.pt as a raw pickle
        d = tmp_path / "torch-raw"
        save_model(d, est, _info(ds, "mlp"))
        (d / "weights.pt").write_bytes(payload)
        _rehash(d)
        out.append(("weights.pt = pickle", d))
    return out


def test_crafted_pickles_are_never_executed(tmp_path, capsys):
    from gaitml.cli import main
    from gaitml.io import write_gaitml_csv

    marker = tmp_path / "MARKER"
    # the payload works: unpickling it does write the marker (so the test below can fail)
    pickle.loads(pickle.dumps(_Payload(tmp_path / "proof")))
    assert (tmp_path / "proof").read_text() == "unpickled"

    rec = synth_recording(0, seconds_per_mode=6.0, gyr=True)
    csv = write_gaitml_csv(rec, tmp_path / "rec.csv")
    attacks = _attacks(tmp_path, marker)
    assert len(attacks) >= 4
    for name, folder in attacks:
        for argv in (
            ["predict", str(folder), str(csv)],
            ["pdr", str(csv), "--model", str(folder)],
            ["model", "card", str(folder)],
            ["model", "export", str(folder), "--format", "json", "--out", str(tmp_path / "x.json")],
        ):
            code = main(argv)
            err = capsys.readouterr().err
            assert not marker.exists(), f"{name}: {' '.join(argv[:2])} executed the pickle"
            if argv[0] != "model" or argv[1] != "card" or "format" in name or "joblib" in name:
                assert code == 2, f"{name}: {argv[:2]} should refuse the model: {err}"
        with pytest.raises(ModelError):
            load_model(folder)
        assert not marker.exists()
    # a pickle lying beside a valid data-only model is ignored: the model loads, the file is never opened
    d = tmp_path / "beside"
    shutil.copytree(DEMO, d)
    (d / "model.joblib").write_bytes(pickle.dumps(_Payload(marker)))
    assert main(["predict", str(d), str(csv)]) == 0
    assert main(["model", "card", str(d)]) == 0
    assert not marker.exists()


def test_evaluate_and_train_never_open_a_crafted_model_folder(tmp_path, capsys):
    """evaluate and train read data, never a model: a crafted model folder as their output is replaced unread."""
    from gaitml.cli import main
    from tests.models.synth import write_synth_folder

    marker = tmp_path / "MARKER"
    write_synth_folder(tmp_path / "data", n_subjects=3, seconds_per_mode=6.0)
    cfg = tmp_path / "c.toml"
    cfg.write_text('name = "safe"\n[data]\nsource = "folder"\npath = "data"\n[cv]\nn_jobs = 1\n')
    for cmd in ("evaluate", "train"):
        name, folder = next((n, f) for n, f in _attacks(tmp_path / cmd, marker) if n == "arrays.npz = pickle")
        assert main([cmd, str(cfg), "--out", str(folder)]) == 0, capsys.readouterr().err
        assert not marker.exists(), f"{cmd} executed the pickle of a crafted model folder ({name})"
    assert load_model(tmp_path / "train" / "npz-pickle").labels  # train replaced it with a real model


@pytest.mark.parametrize("seed", [0, 1])
def test_json_export_in_plain_numpy_marks_still_unsure_as_predict_does(tmp_path, monkeypatch, seed):
    """A calm phone-at-ear walk between two standing stretches (the still gate reads much of the walk still, the phone
    turns once per stride): the plain reader marks ``still_unsure`` from the export's words alone (its numbers and its
    rule) in exactly the windows predict marks, and computes the same projections."""
    from gaitml.models import stride_rhythm
    from tests.models.test_still_unsure import rhythm_projections
    from tests.models.test_still_veto_swing import ear_walk

    model = load_model(DEMO)
    rec, _ = ear_walk(seed, seconds=40.0, stand_s=20.0)
    table = predict_recording(model, rec)
    marked, still = table["still_unsure"].to_numpy(bool), table["still"].to_numpy(bool)
    assert marked.sum() >= 15 and (still & ~marked).sum() >= 15  # both answers occur
    spec = _check_json_equals_predict(model, rec, tmp_path)  # compares the reader's still_unsure with predict's
    # the words give gaitml's numbers, not only its answers (a window moved by a sample keeps its mark here): gaitml's
    # projection of each still window, the input of adaptive.swing_stride in stride_rhythm
    seen = rhythm_projections(monkeypatch)
    np.testing.assert_array_equal(stride_rhythm(rec, table[still]), marked[still])
    mine: list = []
    length = spec["window"]["length_samples"]
    _still_unsure_from_json(spec, rec.gyr, table["start"].to_numpy(), length, table["mode"].to_numpy(), mine)
    assert len(seen) == 1 and len(mine) == len(seen[0]) == int(still.sum())
    for x, p in zip(mine, seen[0], strict=True):  # an eigenvector's sign is arbitrary
        np.testing.assert_allclose(x * np.sign(x @ p), p, rtol=0, atol=1e-9)


@pytest.mark.parametrize("fs", [12.5, 25.0, 100.0, 204.8])
def test_the_exports_still_unsure_words_hold_at_other_model_rates(fs):
    """The rule is written for any ``sampling_rate_hz`` (the decimation q = floor(fs / decimate_to_hz): 1 at 12.5 and
    25 Hz, 4 and 8 at 100 and 204.8 Hz): the plain reader of the demo export's words, given another rate, marks what
    ``stride_rhythm`` marks on a gyroscope that turns with a stride rhythm (cadence 0.8 -> 2 steps/s) between two calm
    stretches, every window read as still."""
    import pandas as pd

    from gaitml.models import stride_rhythm
    from gaitml.models._export import input_spec
    from gaitml.recording import Recording
    from gaitml.signal import window_params

    spec = json.loads(json.dumps(input_spec(load_model(DEMO))))
    spec["sampling_rate_hz"] = fs
    rng = np.random.default_rng(int(fs))
    n = int(120 * fs)
    t = np.arange(n) / fs
    phase = np.cumsum(np.pi * (0.8 + 1.2 * t / t[-1])) / fs
    amp = np.where((t > 30) & (t < 90), 0.35, 0.05)
    gyr = np.column_stack([amp * np.sin(phase), 0.3 * amp * np.cos(phase), np.zeros(n)]) + rng.normal(0, 0.1, (n, 3))
    length, hop = window_params(1.5, 0.5, fs)
    starts = np.arange(0, n - length + 1, hop)
    marked = stride_rhythm(
        Recording(acc=np.tile([0.0, 0.0, 9.81], (n, 1)), gyr=gyr, sampling_rate_hz=fs),
        pd.DataFrame({"start": starts, "end": starts + length}),
    )
    assert 0.3 < marked.mean() < 0.7  # measured 74-77 of 149-159 windows: the walk marked, the calm stretches not
    np.testing.assert_array_equal(_still_unsure_from_json(spec, gyr, starts, length, np.full(len(starts), "still")), marked)
