"""Motion-mode classifiers behind one scikit-learn interface, and model artifacts.

- ``linear-ovo-svm``: :class:`LinearOVOSVM`, standardised features, linear SVM,
  one-vs-one (paper 003 sec. 3.1, 3.3).
- ``mlp``, ``cnn1d``: small torch baselines (optional extra ``gaitml[torch]``).
- :func:`make_model` builds one by kind; :func:`save_model` / :func:`load_model`
  write and check the data-only artifact folder (DESIGN sec. 3; no pickle is
  loaded); :func:`convert_model` turns an old pickle model into one (trusted
  models only); :func:`model_card` writes its ``MODEL.md``; :func:`export_json` /
  :func:`export_onnx` give portable exports; :func:`predict_recording` gives
  per-window modes of a recording; :func:`predict_step_windows` per-step modes with a
  step-window model (``window.by`` steps/strides in model.json);
  :func:`window_placement_reason` the foot-placement rule of one window, for a stream;
  :func:`rate_reason` the rate check of a recording (made below the rates the model was trained at).
"""

from gaitml.models._card import model_card
from gaitml.models._dataset import WindowDataset, build_window_dataset, raw_window_channels, raw_windows, resample_recording
from gaitml.models._export import export_json, export_onnx
from gaitml.models._legacy import convert_model
from gaitml.models._persist import TrainedModel, library_versions, load_model, read_model_json, save_model, sha256_file
from gaitml.models._predict import (
    STILL_RULE,
    STILL_RULES,
    STILL_THRESHOLDS_MS2,
    describe_still_gate,
    model_inputs,
    predict_recording,
    rate_reason,
    still_windows,
    stride_rhythm,
    window_placement_reason,
)
from gaitml.models._registry import MODEL_KINDS, TORCH_KINDS, make_model, model_class, model_param_names
from gaitml.models._step_windows import build_step_window_dataset, is_step_model, predict_step_windows, window_by, window_detector
from gaitml.models._svm import LinearOVOSVM, ovo_vote
from gaitml.models._torch import TorchCNN1DClassifier, TorchMLPClassifier, require_torch, torch_available

__all__ = [
    "MODEL_KINDS",
    "STILL_RULE",
    "STILL_RULES",
    "STILL_THRESHOLDS_MS2",
    "TORCH_KINDS",
    "LinearOVOSVM",
    "TorchCNN1DClassifier",
    "TorchMLPClassifier",
    "TrainedModel",
    "WindowDataset",
    "build_step_window_dataset",
    "build_window_dataset",
    "convert_model",
    "describe_still_gate",
    "export_json",
    "export_onnx",
    "is_step_model",
    "library_versions",
    "load_model",
    "make_model",
    "model_class",
    "model_card",
    "model_inputs",
    "model_param_names",
    "ovo_vote",
    "predict_recording",
    "predict_step_windows",
    "rate_reason",
    "raw_window_channels",
    "raw_windows",
    "read_model_json",
    "require_torch",
    "resample_recording",
    "save_model",
    "sha256_file",
    "still_windows",
    "stride_rhythm",
    "torch_available",
    "window_by",
    "window_detector",
    "window_placement_reason",
]
