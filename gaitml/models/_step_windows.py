"""Step-window data sets and predictions: the models' side of :mod:`gaitml.features.step_windows`.

A model trained on step windows (config ``windows.by = "steps"`` or ``"strides"``)
records ``window.by`` and ``window.detector`` in ``model.json``; predicting with it
detects the steps (strides) of a recording with that detector and gives one row per
step. Models saved before step windows existed have no ``window.by`` and read as
``"time"``.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.models._dataset import (
    WindowDataset,
    check_dataset_inputs,
    drop_unkept_labels,
    raw_windows,
    resample_recording,
)
from gaitml.recording import Recording

__all__ = ["build_step_window_dataset", "predict_step_windows", "step_model_inputs", "window_by", "window_detector", "is_step_model"]


def window_by(model) -> str:
    """``window.by`` of a trained model (``'time'`` for models saved before step windows)."""
    return str((model.info.get("window") or {}).get("by", "time"))


def window_detector(model) -> str:
    """``window.detector`` of a step-window model ('' for time windows)."""
    return str((model.info.get("window") or {}).get("detector", "") or "")


def is_step_model(model) -> bool:
    """True when the model classifies step (or stride) windows."""
    return window_by(model) != "time"


def _raw_signal(recording: Recording, channels: Sequence[str]) -> np.ndarray:
    """The raw channels of the whole recording, shape (n, len(channels))."""
    return raw_windows(recording, np.array([0]), recording.n_samples, channels)[0]


def build_step_window_dataset(
    recordings: Sequence[Recording],
    *,
    groups: Sequence[str],
    by: str,
    detector: str | None,
    min_label_fraction: float = 0.5,
    feature_set: str = "all52",
    keep_labels: Sequence[str] | None = None,
    need_features: bool = True,
    need_raw: bool = False,
) -> WindowDataset:
    """One window per detected step (stride) of every labelled recording, with features and/or raw spans.

    As :func:`gaitml.models.build_window_dataset` for time windows; the windows come
    from :func:`gaitml.features.make_step_windows`. ``length_s`` of the result is the
    median span length (s) and ``overlap`` 0; the windows table has the extra columns
    ``step`` and ``t_event_s``. Raw spans are resampled to
    :data:`gaitml.features.step_windows.RAW_SPAN_SAMPLES` samples.
    """
    from gaitml.features.step_windows import RAW_SPAN_SAMPLES, check_window_by, extract_step_features, make_step_windows, step_raw_windows

    det = check_window_by(by, detector)
    if by == "time":
        raise InputError("build_step_window_dataset needs by 'steps' or 'strides'; use build_window_dataset for time windows.")
    fs, channels = check_dataset_inputs(recordings, groups, feature_set, need_raw)
    tables, feats, raws, names, skipped = [], [], [], [], []
    n_total = n_frac = n_lab = 0
    dropped: dict[str, int] = {}
    keep = None if not keep_labels else {str(x) for x in keep_labels}
    for i, (rec, grp) in enumerate(zip(recordings, groups, strict=True)):
        if rec.labels is None:
            raise InputError(f"recording {rec.name!r} has no labels; give per-sample labels or a label column in the manifest/meta.")
        names.append(rec.name)
        w = make_step_windows(rec, by, det, min_label_fraction=min_label_fraction)
        n_total += int(w.attrs["n_total"])
        n_frac += int(w.attrs["n_dropped"])
        if w.attrs["n_total"] == 0:
            skipped.append(rec.name)  # no step detected: nothing to classify
            continue
        if keep is not None:
            w, n_bad = drop_unkept_labels(w, keep, dropped)
            n_lab += n_bad
        if len(w) == 0:
            continue
        if need_features:
            feats.append(extract_step_features(rec, w, subset=feature_set).reset_index(drop=True))
        if need_raw:
            raws.append(step_raw_windows(_raw_signal(rec, channels), w, RAW_SPAN_SAMPLES[by]))
        tables.append(w.assign(recording=i, group=str(grp)))
    if not tables:
        raise InputError(
            f"no step windows left ({n_total} {by} detected with {det}, {n_frac} below min_label_fraction, {n_lab} with other labels); "
            "check that the recordings hold walking, try another detector, a lower min_label_fraction or other labels."
        )
    windows = pd.concat(tables, ignore_index=True)
    cols = ["recording", "group", "step", "start", "end", "t_start_s", "t_end_s", "t_event_s", "label", "label_fraction"]
    windows = windows[[c for c in cols if c in windows.columns]]
    windows["label"] = windows["label"].astype(str)
    return WindowDataset(
        windows=windows,
        features=pd.concat(feats, ignore_index=True) if need_features else None,
        raw=np.concatenate(raws, axis=0) if need_raw else None,
        recording_names=names,
        sampling_rate_hz=fs,
        length_s=float(np.median((windows["end"] - windows["start"]).to_numpy()) / fs),
        overlap=0.0,
        feature_set=feature_set,
        raw_channels=tuple(channels),
        n_total=n_total,
        n_dropped_fraction=n_frac,
        n_dropped_label=n_lab,
        dropped_labels=dropped,
        skipped_recordings=skipped,
    )


def step_model_inputs(model, recording: Recording, windows: pd.DataFrame) -> np.ndarray:
    """The model's input for step ``windows`` of ``recording`` (features in saved order, or resampled raw spans)."""
    from gaitml.features.step_windows import RAW_SPAN_SAMPLES, extract_step_features, step_raw_windows

    if model.input_kind == "raw":
        length = int((model.info.get("window") or {}).get("raw_length_samples") or RAW_SPAN_SAMPLES[window_by(model)])
        return step_raw_windows(_raw_signal(recording, model.raw_channels), windows, length)
    feats = extract_step_features(recording, windows, subset=model.feature_set)
    return feats[model.feature_names].to_numpy(dtype=float)


def step_domain_columns(model, recording: Recording, windows: pd.DataFrame, X: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The out-of-domain check of every step window (as :func:`gaitml.models._predict.domain_columns` for time windows).

    The domain of a step-window model is fitted on its step windows' own features and
    the mean gravity direction of each step's samples; ``X`` (the model's feature
    matrix of these windows) is reused when the domain is on the model's features.
    """
    from gaitml.models._predict import checked_domain_columns, recording_dynamics, unchecked_domain_columns

    dom = getattr(model, "domain", None)
    if dom is None or len(windows) == 0:
        return unchecked_domain_columns(dom, len(windows))
    from gaitml.features.step_windows import extract_step_features
    from gaitml.models._predict import domain_view
    from gaitml.models.domain import span_gravity

    recording, clipped = domain_view(dom, recording)  # a record with its own accelerometer range reads the recording through it
    if clipped:
        X = None
    if X is None or model.input_kind != "features" or dom.feature_set != model.feature_set:
        X = extract_step_features(recording, windows, subset=dom.feature_set).to_numpy(dtype=float)
    gravity = (
        span_gravity(recording.acc, windows["start"].to_numpy(np.int64), windows["end"].to_numpy(np.int64)) if dom.gravity_check else None
    )
    starts, ends = windows["start"].to_numpy(np.int64), windows["end"].to_numpy(np.int64)
    order = np.argsort(starts, kind="stable")  # the span median (and its grid of computed windows) needs time order
    dyn = recording_dynamics(dom, recording, starts[order], ends[order])
    if dyn is None or np.all(order == np.arange(len(order))):
        return checked_domain_columns(dom, X, gravity, dyn)
    cols = checked_domain_columns(dom, X[order], None if gravity is None else gravity[order], dyn)
    back = np.empty_like(order)
    back[order] = np.arange(len(order))
    return {k: v[back] for k, v in cols.items()}


def predict_step_windows(
    model,
    recording: Recording,
    correction: bool = True,
    *,
    spans: pd.DataFrame | None = None,
    run_min_cadence_hz: float | None = None,
    still_step_veto: int | None = None,
) -> pd.DataFrame:
    """Motion mode of every detected step (stride) of ``recording`` with a step-window model.

    Resamples the recording to the model's rate, finds the steps with the model's
    detector (or takes ``spans``, sample spans at the model's rate from
    :func:`gaitml.features.step_windows.spans_from_steps`), classifies each step on
    its own samples and - unless ``correction=False`` - applies the adjacent-window
    correction of paper 003 sec. 3.4 over the steps in time order, then the finishing rules of
    :func:`gaitml.models._predict.finish_predictions` (still gate, run-cadence rule with
    ``run_min_cadence_hz``: None for :data:`gaitml.models._predict.RUN_CADENCE_DEFAULT_HZ`, 0 off; side direction).
    The still gate's step veto (``still_step_veto``: None for :data:`gaitml.models._predict.STILL_STEP_VETO_DEFAULT`,
    0 off) counts the veto's steps (:func:`gaitml.models._predict.veto_steps`) inside each step window as in a time
    window. How often a window holds
    :data:`~gaitml.models._predict.STILL_STEP_VETO_MIN_STEPS` of them depends on the window detector's spans, not on
    time: ``adaptive``'s own step windows (a half period either side of each peak) hold their own peak and so seldom a
    second, while ``ifsm``'s steps of a calm walker span about two of ``adaptive``'s, and the veto keeps more than half
    of the step windows the statistic reads still (experiments/reports/still-gate.md, "Second review of the step veto").

    Returns
    -------
    DataFrame
        One row per step: ``step``, ``start``, ``end`` (samples at the model's
        rate), ``t_start_s``, ``t_end_s``, ``t_event_s``, ``mode_raw``, ``mode``, plus
        ``label`` and ``label_fraction`` when the recording has labels. ``attrs``:
        ``sampling_rate_hz``, ``resampled_from_hz``, ``correction``, ``by``,
        ``detector``, ``n_short`` (spans too short to classify), ``acc_range``
        (:func:`gaitml.models._predict.model_view`: None without an accelerometer range).
    """
    from gaitml.features.step_windows import make_step_windows
    from gaitml.models._predict import finish_predictions, model_view, predicted_modes

    by, det = window_by(model), window_detector(model)
    if by == "time":
        raise InputError("predict_step_windows needs a step-window model (window.by steps or strides); use predict_recording.")
    rec = resample_recording(recording, model.sampling_rate_hz)
    if "gyro" in model.feature_set:
        rec.require_gyr(
            f"the model's feature set {model.feature_set!r}", "a model trained on feature set 'all52' (e.g. experiments/paper-svm.toml)"
        )
    # a model with an accelerometer range reads the recording through it (gaitml.features._range): steps, features
    # and the domain check, as in training; the fixed physics rules in finish_predictions read the recording itself
    seen, tally = model_view(model, rec)
    w = make_step_windows(seen, by, det, min_label_fraction=0.0, spans=spans)
    cols = ["step", "start", "end", "t_start_s", "t_end_s", "t_event_s"]
    out = w[cols].copy()
    if len(w):
        X = step_model_inputs(model, seen, w)
        out["mode_raw"], out["mode"] = predicted_modes(model, X, correction)
    else:
        X = None
        out["mode_raw"] = pd.Series(dtype=str)
        out["mode"] = pd.Series(dtype=str)
    domain = step_domain_columns(model, seen, w, X if model.input_kind == "features" else None)
    return finish_predictions(
        out,
        w,
        domain,
        model,
        recording,
        rec,
        correction,
        X=X,
        run_min_cadence_hz=run_min_cadence_hz,
        still_step_veto=still_step_veto,
        by=by,
        detector=det,
        n_short=int(w.attrs.get("n_short", 0)),
        acc_range=tally,
    )
