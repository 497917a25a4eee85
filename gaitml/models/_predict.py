"""Per-window motion modes of a recording with a saved model."""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.recording import Recording

__all__ = ["predict_recording", "model_inputs"]


def _windows_for(recording: Recording, length_s: float, overlap: float) -> pd.DataFrame:
    """All complete windows of the recording (labels not needed, none dropped)."""
    from gaitml.features import make_windows

    w = make_windows(recording, length_s, overlap, min_label_fraction=0.0).reset_index(drop=True)
    return w


def model_inputs(model, recording: Recording, windows: pd.DataFrame) -> np.ndarray:
    """The model's input for ``windows`` of ``recording`` (features in saved order, or raw)."""
    from gaitml.models._dataset import raw_windows

    if model.input_kind == "raw":
        length = int(round(model.length_s * model.sampling_rate_hz))
        return raw_windows(recording, windows["start"].to_numpy(), length, model.raw_channels)
    from gaitml.features import extract_features

    feats = extract_features(recording, windows, subset=model.feature_set)
    names = model.feature_names
    missing = [n for n in names if n not in feats.columns]
    if missing:
        raise InputError(f"the feature table lacks {missing[:3]} that the model needs; the feature set changed, retrain the model.")
    return feats[names].to_numpy(dtype=float)


def predict_recording(model, recording: Recording, correction: bool = True) -> pd.DataFrame:
    """Predict the motion mode of every window of ``recording``.

    Applies the model's saved window length, overlap and sampling rate
    (resampling the recording when its rate differs), then the model, then -
    unless ``correction=False`` - the adjacent-window correction of paper 003
    sec. 3.4 over the windows in time order.

    Parameters
    ----------
    model : TrainedModel (from :func:`gaitml.models.load_model`)
    recording : Recording
    correction : bool, default True

    Returns
    -------
    DataFrame
        One row per window: ``start``, ``end`` (samples at the model's rate),
        ``t_start_s``, ``t_end_s``, ``mode_raw`` (model output), ``mode`` (after
        the correction, or equal to ``mode_raw``), plus ``label`` and
        ``label_fraction`` when the recording has labels. ``attrs`` holds
        ``sampling_rate_hz``, ``resampled_from_hz`` (or None) and ``correction``.

    Raises
    ------
    InputError
        The recording is shorter than one window, or lacks a gyroscope the
        feature set needs.
    """
    from gaitml.models._dataset import resample_recording
    from gaitml.postprocess import adjacent_window_correction

    fs0 = recording.sampling_rate_hz
    rec = resample_recording(recording, model.sampling_rate_hz)
    length = int(round(model.length_s * model.sampling_rate_hz))
    rec.require_samples(length, f"one {model.length_s} s window of the model")
    if "gyro" in model.feature_set:
        rec.require_gyr(
            f"the model's feature set {model.feature_set!r}", "a model trained on feature set 'all52' (e.g. experiments/paper-svm.toml)"
        )
    w = _windows_for(rec, model.length_s, model.overlap)
    X = model_inputs(model, rec, w)
    pred = np.asarray(model.estimator.predict(X)).astype(str)
    out = w[["start", "end", "t_start_s", "t_end_s"]].copy()
    out["mode_raw"] = pred
    out["mode"] = np.asarray(adjacent_window_correction(pred)).astype(str) if correction else pred
    for c in ("label", "label_fraction"):
        if c in w.columns:
            out[c] = w[c].to_numpy()
    out.attrs.update(
        sampling_rate_hz=model.sampling_rate_hz, resampled_from_hz=None if rec is recording else fs0, correction=bool(correction)
    )
    return out
