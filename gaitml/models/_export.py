"""Portable exports of a model: a self-describing JSON and ONNX.

JSON (:func:`export_json`, linear OVO SVM): everything a phone developer needs
to reproduce ``gaitml predict`` without gaitml: the sampling rate and window
rule, every feature with its paper number (paper 003 sec. 3.2) and formula, the
scaler, the pairwise weights and intercepts, the class pairs, the voting and
tie rule, and the adjacent-window correction (paper 003 sec. 3.4). Prediction
is a few dozen lines: compute the features, one dot product per class pair,
count votes, break ties, correct.

ONNX (:func:`export_onnx`, optional extra ``gaitml[onnx]``): the linear OVO SVM
is built node by node with the ``onnx`` package's helper API (scikit-learn
converters do not cover this custom one-vs-one model); the torch kinds go
through :func:`torch.onnx.export` with the standardisation in front and the
softmax behind. The feature extraction stays outside the graph and is specified
in the model's metadata (``metadata_props['gaitml']``: the JSON export without
the weights).

``format_version`` 2 states the still gate by its statistic (``postprocess.still``:
``statistic``, ``threshold_ms2``); version 1 named only ``range_ms2`` (max - min of |acc|),
which is null in version 2 unless the range rule is in force. A reader of version 1 must
not read a version 2 export.

``format_version`` 3 is written for a model with an accelerometer range (``acc_range_ms2``,
:mod:`gaitml.features._range`): its ``acc_range`` entry (``range_ms2``, ``rule``) says to clip
each accelerometer axis to +-``range_ms2`` before the features. A reader of version 2 must not
read a version 3 export (it would compute the features of a wide-range phone unclipped). Until
version 4, a model without a range was exported as version 2.

``format_version`` 4 is written for every model: it adds ``postprocess.run_cadence`` (a rule
``gaitml predict`` applies by default) and the still gate's ``statistic`` ``"std_lp"`` (the
standard deviation of |acc| after a low-pass, ``lowpass_hz``). A reader of versions 2 or 3 must not
read a version 4 export: it would leave out the run-cadence rule and misread the still gate. In
version 4 the ``acc_range`` entry is optional: present (and to be applied) exactly when the model has
an accelerometer range.

``format_version`` 5 adds the still gate's step veto (``postprocess.still.step_veto``: a window with at
least ``min_steps`` detected steps is not still), which ``gaitml predict`` applies by default. A reader of
version 4 must not read a version 5 export: it would answer ``still`` in a calm walker's windows that
predict keeps in their mode. The entry's ``swing_periodicity`` (added within version 5; absent: 0) is the swing stage
setting gaitml's own step finder runs for the veto on a recording with a gyroscope
(:data:`gaitml.models._predict.STILL_STEP_SWING_PERIODICITY`); the steps are the reader's own detector's in any case.
The still gate's ``unsure`` entry (added within version 5; absent: not in force) states the ``still_unsure`` mark
(:func:`gaitml.models._predict.still_unsure`): it changes no label, so a reader without it answers the same labels. Its
rule and numbers (``decimate_to_hz`` and ``octave_tolerance`` among them, added with the rule's exact words before any
release) are enough to compute the mark without gaitml.
"""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

from gaitml.errors import ModelError

__all__ = ["export_json", "export_onnx", "input_spec", "PORTABLE_FORMAT", "PORTABLE_FORMAT_VERSION", "PORTABLE_RANGE_FORMAT_VERSION"]

PORTABLE_FORMAT = "gaitml-portable-model"
#: Version of the portable layout (see the module docstring for what changed in 2, 3, 4 and 5).
PORTABLE_FORMAT_VERSION = 5
#: Version of the portable layout of a model with an accelerometer range (its ``acc_range`` entry, new in 3;
#: from version 4 on the same version as a model without one, the entry being optional).
PORTABLE_RANGE_FORMAT_VERSION = 5
ONNX_HINT = "install the optional extra: pip install 'gaitml[onnx]'"

_VOTING = {
    "rule": (
        "For each class pair k = (i, j): machine k votes for class i when d_k > 0, else for class j. "
        "score_c = votes_c + conf_c / (3 * (|conf_c| + 1)), where conf_c = sum of d_k over pairs with c first "
        "minus sum of d_k over pairs with c second. The predicted class is the one with the highest score."
    ),
    "tie_rule": (
        "Equal vote counts are broken by the squashed confidence conf_c / (3 (|conf_c| + 1)), which lies in (-1/3, 1/3) "
        "and so never overturns a vote difference (the rule of scikit-learn's OneVsOneClassifier); "
        "equal scores go to the class listed first in 'labels'."
    ),
}

_CORRECTION = {
    "source": "paper 003 sec. 3.4 (adjacent-window correction)",
    "rule": (
        "Process window labels in time order. For window k (1 <= k <= n-2) let W1 = corrected label of window k-2 "
        "(missing for k = 1), W2 = corrected label of window k-1, W3 = raw label of window k, W4 = raw label of window k+1. "
        "Rule 1: if W1 exists and W2 != W3 and W2 != W4 and W3 != W4 and W1 == W2, the corrected label of k is W2. "
        "Rule 2: otherwise, if W2 == W4 and W2 != W3, it is W2. Otherwise it is W3."
    ),
    "edges": "The first and the last window keep their raw labels.",
    "delay": "Causal with a one-window delay: the label of window k is final once window k+1 is classified.",
}


def _window_spec(info: dict) -> dict:
    win = info["window"]
    if win.get("by", "time") != "time":  # step-synchronous windows (gaitml.features.step_windows)
        from gaitml.features.step_windows import MAX_STEP_S, MIN_SPAN_SAMPLES

        unit = "step" if win["by"] == "steps" else "stride"
        rule = (
            "one window per detected step: from the sample after the previous step's peak up to and including the step's peak "
            f"(the first step reaches back as far as the second lasts), cut to its last {MAX_STEP_S:g} s"
            if unit == "step"
            else f"one window per stride, mid-stance to mid-stance of consecutive zero-velocity intervals, strides over {2 * MAX_STEP_S:g} s dropped"
        )
        return {
            "by": win["by"],
            "detector": win.get("detector"),
            "rule": f"{rule}; windows under {MIN_SPAN_SAMPLES} samples are not classified; a window's features depend on its own samples only "
            f"(variable length; raw-input models: each {unit} linearly resampled to {win.get('raw_length_samples')} samples).",
        }
    fs = float(info["sampling_rate_hz"])
    length_s, overlap = float(info["window"]["length_s"]), float(info["window"]["overlap"])
    length = int(round(length_s * fs))
    hop = max(1, int(round(length * (1 - overlap))))
    return {
        "length_s": length_s,
        "overlap": overlap,
        "length_samples": length,
        "hop_samples": hop,
        "rule": (
            f"length = round(length_s * sampling_rate_hz) = {length} samples; hop = max(1, round(length * (1 - overlap))) = {hop}; "
            "window w covers samples [w * hop, w * hop + length); only complete windows are formed; "
            "a window's features depend on its own samples only."
        ),
    }


def _feature_spec(info: dict) -> dict:
    from gaitml.features import feature_specs
    from gaitml.features._catalogue import MODE_BIN_WIDTH
    from gaitml.features._extract import DEGENERATE_REL, MAGNITUDE_OFFSET_MS2

    fset = info["feature_set"]
    specs = feature_specs(fset)
    names = list(info["feature_names"])
    if [s.name for s in specs] != names:
        raise ModelError(f"the model's feature names do not match feature set {fset!r} of this gaitml; retrain the model.")
    return {
        "set": fset,
        "source": "paper 003 (Deng et al. 2021) sec. 3.2 and Table 1; F<k> = paper feature number k, G<k> = F<k> on the gyroscope"
        + (
            "; W<k>: the forward vector, conventions.forward_vector (not in paper 003)"
            if any(s.stat.startswith("fwd") for s in specs)
            else ""
        ),
        "channels": {
            "acc_x, acc_y, acc_z": "accelerometer in the phone frame, m/s^2, gravity included",
            "acc_mag": (
                f"|acc| - {MAGNITUDE_OFFSET_MS2} m/s^2 (paper eq. 1), smoothed by a centred 3-sample moving average computed within "
                "each window (paper sec. 2.1, N = 3): sample i of the window is the mean of samples i-1, i, i+1; the first and last "
                "sample of the window average 2 samples (themselves and their one neighbour inside the window)"
            ),
            "gyr_x, gyr_y, gyr_z": f"gyroscope in the phone frame, rad/s (feature sets {', '.join(_gyro_sets())} only)",
            "gyr_mag": "|gyr| (no offset), smoothed like acc_mag",
        },
        "conventions": {
            "N": "number of samples in the window",
            "moments": "variance, skewness and kurtosis use population (1/N) moments; kurtosis is excess (m4 / m2^2 - 3)",
            "quantiles": "linear interpolation between order statistics: h = p (N - 1), Q = s[floor(h)] + (h - floor(h)) (s[floor(h)+1] - s[floor(h)]) (numpy default, type 7)",
            "mode_bin_width": {"acc": MODE_BIN_WIDTH["acc"], "gyr": MODE_BIN_WIDTH["gyr"]},
            "mode": "bin k = floor(a / w + 1/2) with w the bin width; the mode is w * (the bin with most samples); ties go to the smallest bin",
            "constant_window": f"a channel whose std <= {DEGENERATE_REL} * (1 + |mean|) is constant: its skewness, kurtosis and correlations are 0",
            "correlation": "zero-lag Pearson coefficient of two axes over the window, clipped to [-1, 1]",
            **({"forward_vector": _forward_spec()} if any(s.stat.startswith("fwd") for s in specs) else {}),
        },
        "features": [
            {
                "index": i,
                "name": s.name,
                "code": s.code,
                "paper_number": None if s.stat.startswith("fwd") else (s.number if s.sensor == "acc" else s.number - 52),
                "sensor": s.sensor,
                "channel": s.channel,
                "stat": s.stat,
                "description": s.description,
                "formula": s.formula,
            }
            for i, s in enumerate(specs)
        ],
    }


def _gyro_sets() -> list[str]:
    """The feature sets that read the gyroscope (G1..G52)."""
    from gaitml.features import FEATURE_SETS, uses_gyro

    return [k for k in FEATURE_SETS if uses_gyro(k)]


def _forward_spec() -> dict:
    """How the opt-in forward-vector columns W1..W3 (``+fwd`` feature sets) are computed (:mod:`gaitml.features._forward`)."""
    from gaitml.features import FORWARD_BAND_HZ

    lo, hi = FORWARD_BAND_HZ
    return {
        "source": "gaitml.features._forward (not in paper 003): the inverted pendulum's forward acceleration follows d/dt of the vertical one",
        "band_hz": [lo, hi],
        "rule": (
            "per window of N samples at fs Hz, acc in the phone frame: up = mean(acc) / |mean(acc)| (phone z if |mean| <= 1e-6); "
            "each axis minus its least-squares line over the window; its real DFT over the window with every coefficient of "
            f"frequency k fs / N outside [{lo:g}, {hi:g}] Hz set to 0, transformed back (N samples); v(t) = band-passed acc . up; "
            "h(t) = band-passed acc - v(t) up; v'(t) = (v(t+1) - v(t-1)) fs / 2 with indices modulo N; "
            "F = (1/N) sum_t h(t) v'(t); den = sqrt((1/N) sum_t |h(t)|^2 (1/N) sum_t v'(t)^2); "
            "acc_x__fwd, acc_y__fwd, acc_z__fwd = F / den along the phone's x, y, z (0 when den <= 1e-12; NaN when the "
            "window holds a NaN or infinite sample); "
            "acc_x__fwdface, acc_y__fwdface, acc_z__fwdface = the same times max(0, up_z)"
        ),
    }


def input_spec(model) -> dict:
    """The JSON export without the classifier's numbers (also the ONNX metadata)."""
    info = model.info
    out = {
        "format": PORTABLE_FORMAT,
        "format_version": PORTABLE_FORMAT_VERSION,
        "model_kind": info["model_kind"],
        "name": info.get("name"),
        "labels": [str(c) for c in model.estimator.classes_],
        "source_model": {
            "gaitml_version": (info.get("versions") or {}).get("gaitml"),
            "created_utc": info.get("created_utc"),
            "settings_sha256": info.get("settings_sha256"),
        },
        "sampling_rate_hz": float(info["sampling_rate_hz"]),
        "resampling": "input at another rate: low-pass at 0.45 x the new rate (4th-order Butterworth, zero phase) when down-sampling, then linear interpolation onto the new grid",
        "window": _window_spec(info),
        "postprocess": {
            "adjacent_correction": bool((info.get("postprocess") or {}).get("adjacent_correction", True)),
            **_CORRECTION,
            "still": _still_spec(),
            "side_direction": _side_direction_spec(),
            "run_cadence": _run_cadence_spec(),
        },
    }
    rng = getattr(model, "acc_range_ms2", None)
    if rng is not None:
        out["format_version"] = PORTABLE_RANGE_FORMAT_VERSION
        out["acc_range"] = _acc_range_spec(rng)
    if info["input_kind"] == "features":
        out["features"] = _feature_spec(info)
    else:
        out["raw_channels"] = list(info.get("raw_channels", []))
    return out


def _acc_range_spec(range_ms2: float) -> dict:
    """The accelerometer range (gaitml.features._range) as the JSON export states it."""
    return {
        "range_ms2": float(range_ms2),
        "rule": (
            "Before the features (after resampling to sampling_rate_hz): clip each accelerometer axis to [-range_ms2, +range_ms2] "
            "(x = min(max(x, -range_ms2), range_ms2)): the model reads every phone through the narrowest accelerometer range of its "
            "training phones. The still gate and the side-direction flag read the accelerometer unclipped."
        ),
    }


def _still_spec() -> dict:
    """The still gate (gaitml.models._predict.still_windows, default rule) as the JSON export states it."""
    from gaitml.models._predict import (
        STILL,
        STILL_LOWPASS_HZ,
        STILL_LOWPASS_ORDER,
        STILL_RANGE_MS2,
        STILL_RULE,
        STILL_STEP_VETO_MIN_STEPS,
        STILL_THRESHOLDS_MS2,
        still_step_veto_threshold,
    )

    what = {
        "std_lp": (
            f"the standard deviation of |acc| (population form: divided by the number of samples) over the window's span of time "
            f"in the samples as recorded (before any resampling), after a {STILL_LOWPASS_HZ:g} Hz low-pass of each axis over those "
            f"samples (order-{STILL_LOWPASS_ORDER} Butterworth in second-order sections run forwards and backwards with an odd "
            f"extension of 3 x (2 x sections + 1) samples at each end, at most the window's length - 1, as scipy's sosfiltfilt; "
            "none when the recording's Nyquist frequency is not above it)"
        ),
        "std": "the standard deviation of |acc| over its samples (population form: divided by the number of samples)",
        "range": "max - min of |acc| over its samples",
    }[STILL_RULE]
    return {
        "mode": STILL,
        "statistic": STILL_RULE,
        "threshold_ms2": STILL_THRESHOLDS_MS2[STILL_RULE],
        "lowpass_hz": STILL_LOWPASS_HZ if STILL_RULE == "std_lp" else None,
        "lowpass_order": STILL_LOWPASS_ORDER if STILL_RULE == "std_lp" else None,
        # the earlier gate's threshold on max - min (format_version 1 named only this): null unless that rule is in force
        "range_ms2": STILL_RANGE_MS2 if STILL_RULE == "range" else None,
        "rule": (
            "After the correction: a window whose |acc| (sqrt(acc_x^2 + acc_y^2 + acc_z^2), m/s^2"
            + (", at the model's rate" if STILL_RULE != "std_lp" else "")
            + f") has {what} below threshold_ms2 gets the label '{STILL}' (no gait in it: a phone lying still or a person standing; "
            "a walker's steps keep |acc| oscillating at the step rate, paper 003 sec. 2.2); the raw label is the classifier's. "
            "Unless step_veto says otherwise."
        ),
        "step_veto": _step_veto_spec(STILL_STEP_VETO_MIN_STEPS, still_step_veto_threshold(None)),
        "unsure": _still_unsure_spec(),
    }


def _still_unsure_spec() -> dict:
    """The ``still_unsure`` mark (gaitml.models._predict.still_unsure, STILL_UNSURE_DEFAULT) as the JSON export states it:
    in words a reader can compute it from (the plain-numpy reader in tests/models/test_persist.py does)."""
    from gaitml.models._predict import STILL_UNSURE_DEFAULT, STILL_UNSURE_PAD_S
    from gaitml.steps import adaptive as ad

    return {
        "in_force": bool(STILL_UNSURE_DEFAULT),
        "window_s": ad.WINDOW_S,
        "pad_s": STILL_UNSURE_PAD_S,
        "band_hz": list(ad.GYRO_BAND_HZ),
        "decimate_to_hz": ad.CADENCE_RATE_HZ,
        "min_rms_rads": ad.GYRO_MIN_RMS_RADS,
        "min_periodicity": ad.MIN_PERIODICITY,
        "octave_tolerance": ad.OCTAVE_TOLERANCE,
        "max_half_correlation": -ad.GYRO_SWING_HALF_CORRELATION,
        "step_hz": [ad.MIN_STEP_HZ, ad.MAX_STEP_HZ],
        "rule": (
            "Applied by gaitml predict by default when in_force is true, with a gyroscope only; the label stays. A window left "
            "with the label 'still' (after step_veto) is marked still_unsure when the phone turns with a stride rhythm around "
            "it. On the angular rate at sampling_rate_hz (fs, after resampling; n samples): q = max(1, floor(fs / "
            "decimate_to_hz)), L = round(window_s x fs / q), S = L x q samples (none is marked when n < S). The S samples "
            "[a, a + S) with a = floor((start + end - S) / 2) (start, end: the window's first and one-past-last sample), "
            "moved inside the recording (a clipped to 0 .. n - S). The piece [max(a - round(pad_s x fs), 0), min(a + S + "
            "round(pad_s x fs), n)), each axis minus its mean over the piece, band-passed to band_hz (the upper edge at most "
            "0.45 x fs; order-2 Butterworth in second-order sections run forwards and backwards, scipy's sosfiltfilt with its "
            "default odd extension); of it every q-th sample of [a, a + S) (L samples, at f = fs / q), each axis minus its "
            "mean over them, projected on the eigenvector of the largest eigenvalue of their 3 x 3 scatter matrix: x. Marked "
            "when all hold: the RMS of x is at least min_rms_rads; with r(k) = sum x[i] x[i + k] / sqrt(sum x[i]^2 x sum "
            "x[i + k]^2) over i = 0 .. L - 1 - k (0 when a sum is 0) and r at a fractional lag interpolated linearly between "
            "its two integer lags, the lags k from max(floor(2 f / step_hz[1]) - 1, 1) to min(ceil(2 f / step_hz[0]) + 1, "
            "L - 3) (none marked when fewer than 3), the peaks are the lags other than the first and the last with r(k) >= "
            "r(k - 1) and r(k) > r(k + 1); P is the shortest peak lag whose r reaches octave_tolerance x the highest peak's "
            "(none marked without a peak); r(P) >= min_periodicity; r(P / 2) <= max_half_correlation; and f / step_hz[1] <= "
            "P / 2 <= f / step_hz[0]. A reader without a gyroscope, or without this rule, marks nothing: the label is the same "
            "either way."
        ),
    }


def _step_veto_spec(min_steps: int, default: int | None) -> dict:
    """The still gate's step veto (gaitml.models._predict.STILL_STEP_VETO_MIN_STEPS) as the JSON export states it, with
    the swing stage its step finder runs (gaitml.models._predict.STILL_STEP_SWING_PERIODICITY)."""
    from gaitml.models._predict import STILL_STEP_SWING_PERIODICITY

    swing = float(STILL_STEP_SWING_PERIODICITY)
    return {
        "in_force": default is not None,
        "min_steps": min_steps if default is None else default,
        "swing_periodicity": swing,
        "rule": (
            "Applied by gaitml predict by default when in_force is true (else on request). A window whose |acc| statistic is "
            "below threshold_ms2 keeps its label (it is not still) when a step detector run over the whole recording finds at "
            "least min_steps steps whose peak lies inside the window (start <= peak < end, samples at sampling_rate_hz): a calm "
            "walker's phone at the ear varies |acc| as little as a standing hand, but its steps repeat. gaitml uses its adaptive "
            "detector with its gait check (gaitml.steps), at the model's rate"
            + (
                f", with its swing stage (gyro_swing_min_periodicity = swing_periodicity, {swing:g}) where the recording has a "
                "gyroscope: where |acc| repeats too weakly, the phone's regular turning once per stride sets the step period"
                if swing > 0
                else ""
            )
            + ". The steps are not in this file: a stream needs its own step detector; without one, leave the veto out."
        ),
    }


def _side_direction_spec() -> dict:
    """The side-direction flag (gaitml.models._predict.side_direction_unsure) as the JSON export states it."""
    from gaitml.models._predict import FACE_UP_MAX_DEG, SIDE_MODES

    return {
        "modes": list(SIDE_MODES),
        "face_up_max_deg": FACE_UP_MAX_DEG,
        "rule": (
            "After the still gate: a window whose label is one of 'modes' is marked side_direction_unsure when the unit mean "
            "of its acceleration samples (gravity in the phone frame) is more than face_up_max_deg from the phone's +z axis "
            "(mean_z / |mean| < cos(face_up_max_deg)): the phone is held upright (pocket, swinging hand, ear), where its "
            "placement flips left and right; the label stays."
        ),
    }


def _run_cadence_spec() -> dict:
    """The run-cadence rule (gaitml.models._predict.run_cadence_rule, default threshold) as the JSON export states it."""
    from gaitml.models._predict import RUN_CADENCE_REACH_S, RUN_MIN_CADENCE_HZ, RUN_MODE, RUN_STRIDE_CADENCE_HZ, run_cadence_threshold

    default = run_cadence_threshold(None)
    return {
        "in_force": default is not None,
        "mode": RUN_MODE,
        "min_cadence_hz": RUN_MIN_CADENCE_HZ if default is None else default,
        "stride_cadence_hz": RUN_STRIDE_CADENCE_HZ,
        "reach_s": RUN_CADENCE_REACH_S,
        "rule": (
            "Applied by gaitml predict by default when in_force is true (else on request). "
            "After the still gate: a window labelled 'mode' whose local step cadence c (steps/s: the largest cadence estimate "
            "among the steps whose peak lies in the window or within reach_s of it, from a step detector over the recording "
            "that gives each step a cadence; gaitml uses its adaptive detector, gaitml.steps, whose cadence_hz is the "
            "autocorrelation period of |acc| over 5 s windows, not the spacing of two steps) has stride_cadence_hz <= c < min_cadence_hz (a walking cadence: under the "
            "walk-to-run transition's 140 steps/min, and not half a running one) gets the label with the highest vote score "
            "other than 'mode' (voting.rule with 'mode' left out), or its raw label where the correction made it 'mode'. "
            "A window with no step near it keeps its label. The cadence is not in this file: a stream needs its own step "
            "detector; without one, leave the rule out."
        ),
    }


def export_json(model) -> dict:
    """Self-describing JSON of a linear OVO SVM model (see the module docstring).

    Parameters
    ----------
    model : TrainedModel
        From :func:`gaitml.models.load_model`.

    Returns
    -------
    dict
        JSON-ready: ``labels``, ``sampling_rate_hz``, ``window``, ``features``
        (every feature with its paper number and formula), ``classifier``
        (``coef``, ``intercept``, ``pairs``, ``scaler``, ``voting``),
        ``postprocess`` (the correction rule).

    Raises
    ------
    ModelError
        A torch model (use the ONNX export for those).
    """
    if model.kind != "linear-ovo-svm":
        raise ModelError(f"the JSON export covers the linear OVO SVM, not model kind {model.kind!r}; export it with --format onnx.")
    est = model.estimator
    out = input_spec(model)
    mean, scale = np.asarray(est.mean_, dtype=float), np.asarray(est.scale_, dtype=float)
    coef, intercept = np.asarray(est.coef_, dtype=float), np.asarray(est.intercept_, dtype=float)
    out["classifier"] = {
        "type": "linear SVM, one-vs-one (paper 003 sec. 3.1, 3.3)",
        "decision": (
            "d_k = sum_f coef[k][f] * x[f] + intercept[k] for every class pair k, with x the feature vector in the order of "
            "features.features (raw feature values: the standardisation is already folded into coef and intercept)"
        ),
        "pairs": np.asarray(est.pairs_, dtype=int).tolist(),
        "pairs_note": "pairs[k] = [i, j]: indices into labels; d_k > 0 is a vote for labels[i], otherwise for labels[j]",
        "coef": coef.tolist(),
        "intercept": intercept.tolist(),
        "scaler": {
            "mean": mean.tolist(),
            "scale": scale.tolist(),
            "note": (
                "the standardisation learned in training, z = (x - mean) / scale; the same decision is "
                "d_k = coef_standardised[k] . z + intercept_standardised[k] (equal to the folded form up to rounding)"
            ),
        },
        "coef_standardised": (coef * scale).tolist(),
        "intercept_standardised": (intercept + coef @ mean).tolist(),
        "voting": _VOTING,
    }
    return out


def _require_onnx():
    try:
        import onnx
    except ImportError as exc:
        raise ModelError(f"the ONNX export needs the onnx package, which is not installed; {ONNX_HINT}.") from exc
    return onnx


def _svm_graph(model):
    """ONNX graph of the linear OVO SVM: double features in; label, index and scores out."""
    onnx = _require_onnx()
    from onnx import TensorProto, helper, numpy_helper

    est = model.estimator
    n_classes, n_feat = len(est.classes_), int(est.n_features_in_)
    first, second = est.vote_matrices_
    inits = [
        numpy_helper.from_array(np.ascontiguousarray(est.coef_.T, dtype=np.float64), "coef_t"),
        numpy_helper.from_array(np.asarray(est.intercept_, dtype=np.float64), "intercept"),
        numpy_helper.from_array(np.asarray(first, dtype=np.float64), "first"),
        numpy_helper.from_array(np.asarray(second, dtype=np.float64), "second"),
        numpy_helper.from_array(np.asarray(first - second, dtype=np.float64), "first_minus_second"),
        numpy_helper.from_array(np.array(0.0), "zero"),
        numpy_helper.from_array(np.array(1.0), "one"),
        numpy_helper.from_array(np.array(3.0), "three"),
        helper.make_tensor("classes", TensorProto.STRING, [n_classes], [str(c).encode("utf-8") for c in est.classes_]),
    ]
    nodes = [
        helper.make_node("MatMul", ["features", "coef_t"], ["xw"]),
        helper.make_node("Add", ["xw", "intercept"], ["pairwise"]),
        helper.make_node("Greater", ["pairwise", "zero"], ["win_bool"]),
        helper.make_node("Cast", ["win_bool"], ["win"], to=TensorProto.DOUBLE),
        helper.make_node("Sub", ["one", "win"], ["lose"]),
        helper.make_node("MatMul", ["win", "first"], ["votes_first"]),
        helper.make_node("MatMul", ["lose", "second"], ["votes_second"]),
        helper.make_node("Add", ["votes_first", "votes_second"], ["votes"]),
        helper.make_node("MatMul", ["pairwise", "first_minus_second"], ["conf"]),
        helper.make_node("Abs", ["conf"], ["conf_abs"]),
        helper.make_node("Add", ["conf_abs", "one"], ["conf_abs1"]),
        helper.make_node("Mul", ["conf_abs1", "three"], ["den"]),
        helper.make_node("Div", ["conf", "den"], ["squashed"]),
        helper.make_node("Add", ["votes", "squashed"], ["scores"]),
        helper.make_node("ArgMax", ["scores"], ["index"], axis=1, keepdims=0),
        helper.make_node("Gather", ["classes", "index"], ["label"], axis=0),
    ]
    graph = helper.make_graph(
        nodes,
        "gaitml_linear_ovo_svm",
        [helper.make_tensor_value_info("features", TensorProto.DOUBLE, ["N", n_feat])],
        [
            helper.make_tensor_value_info("label", TensorProto.STRING, ["N"]),
            helper.make_tensor_value_info("index", TensorProto.INT64, ["N"]),
            helper.make_tensor_value_info("scores", TensorProto.DOUBLE, ["N", n_classes]),
        ],
        initializer=inits,
    )
    m = helper.make_model(graph, producer_name="gaitml", opset_imports=[helper.make_opsetid("", 17)])
    m.ir_version = 8  # readable by onnxruntime releases from 1.14 on
    onnx.checker.check_model(m)
    return m


def _torch_graph(model, path: Path):
    """Export a torch kind via torch.onnx.export (torch.export based; needs onnxscript).

    Double input, standardised in double as ``predict_proba`` does, then the float32
    network and the softmax.
    """
    _require_onnx()
    import onnx
    import torch

    est = model.estimator
    cnn = hasattr(est, "window_shape_")

    class _Wrapped(torch.nn.Module):
        def __init__(self):
            super().__init__()
            self.net = est.net_
            self.register_buffer("mean", torch.as_tensor(np.asarray(est.mean_, dtype=np.float64)))
            self.register_buffer("scale", torch.as_tensor(np.asarray(est.scale_, dtype=np.float64)))

        def forward(self, x):
            z = ((x - self.mean) / self.scale).to(torch.float32)
            if cnn:
                z = z.transpose(1, 2)
            return torch.softmax(self.net(z), dim=1)

    shape = (2, *est.window_shape_) if cnn else (2, int(est.n_features_in_))
    dummy = torch.zeros(shape, dtype=torch.float64)
    wrapped = _Wrapped().eval()
    try:
        torch.onnx.export(
            wrapped,
            (dummy,),
            str(path),
            input_names=["features"],
            output_names=["probabilities"],
            dynamic_shapes=({0: torch.export.Dim("N")},),
            dynamo=True,
        )
    except ImportError as exc:  # onnxscript missing
        raise ModelError(f"torch's ONNX exporter needs a package that is missing ({exc}); {ONNX_HINT}.") from exc
    return onnx.load(str(path))


def export_onnx(model, out: str | os.PathLike) -> Path:
    """Write an ONNX file of ``model`` with the feature specification in its metadata.

    Linear OVO SVM: input ``features`` (double, N x n_features, in the order of
    the metadata's feature list); outputs ``label`` (string), ``index`` (int64)
    and ``scores`` (votes + squashed confidences). Torch kinds: input
    ``features`` (double; the MLP's features or the CNN's raw windows
    N x samples x channels), output ``probabilities`` (float, columns in
    ``labels`` order). The adjacent-window correction is outside the graph
    (rule in the metadata).

    Raises
    ------
    ModelError
        onnx (or torch's exporter) is not installed.
    """
    from gaitml.io import atomic_path

    out = Path(out)
    spec = input_spec(model)
    with atomic_path(out) as tmp:
        if model.kind == "linear-ovo-svm":
            m = _svm_graph(model)
        else:
            m = _torch_graph(model, Path(tmp))
        import onnx

        for key, value in (("gaitml", json.dumps(spec)), ("labels", json.dumps(spec["labels"]))):
            entry = m.metadata_props.add()
            entry.key, entry.value = key, value
        onnx.save(m, str(tmp))
    return out
