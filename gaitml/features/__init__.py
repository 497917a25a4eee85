"""Windowing and the 52 time-domain features of paper 003 sec. 3.2 (DESIGN sec. 2, 4).

- :func:`make_windows`: windows by length/overlap in s, majority labels, dropping weak ones;
- :func:`make_step_windows` / :func:`extract_step_features`: one window per detected step
  or stride, features on its own samples (:mod:`gaitml.features.step_windows`);
- :func:`extract_features` / :func:`features_from_arrays`: vectorised feature matrix;
- :class:`StreamingFeatureExtractor`: the same rows from samples pushed as they arrive;
- :data:`CATALOGUE`, :data:`FEATURE_SETS`, :func:`feature_names`: the catalogue and subsets;
- :func:`forward_vectors` (:mod:`gaitml.features._forward`): the opt-in, time-odd forward-vector
  group W1..W3 of the ``all52+fwd`` / ``all52+gyro+fwd`` sets (forward against backward walking);
- :data:`FEATURE_FRAMES`, :func:`gravity_frame_rotations`: the phone frame (paper 003) or a
  per-window gravity-aligned frame that makes the features independent of the phone's orientation;
- :func:`clip_acc`, :func:`acc_range_tally`: the accelerometer range a model reads every phone through
  (:mod:`gaitml.features._range`).
"""

from gaitml.features._catalogue import (
    CATALOGUE,
    FEATURE_SETS,
    FORWARD_CATALOGUE,
    FORWARD_FACE_CATALOGUE,
    GYRO_CATALOGUE,
    PAPER34_NUMBERS,
    FeatureSpec,
    catalogue_markdown,
    feature_names,
    feature_specs,
    resolve_subset,
    uses_forward,
    uses_forward_face,
    uses_gyro,
)
from gaitml.features._extract import extract_features, features_from_arrays
from gaitml.features._forward import FORWARD_BAND_HZ, forward_vectors
from gaitml.features._frame import FEATURE_FRAMES, check_frame, gravity_frame_rotations
from gaitml.features._range import WIDER_RANGE_RATIO, acc_range_tally, check_acc_range, clip_acc
from gaitml.features._streaming import StreamingFeatureExtractor
from gaitml.features._windows import make_windows
from gaitml.features.step_windows import WINDOW_BY, extract_step_features, make_step_windows

__all__ = [
    "CATALOGUE",
    "FEATURE_FRAMES",
    "FEATURE_SETS",
    "FORWARD_BAND_HZ",
    "FORWARD_CATALOGUE",
    "FORWARD_FACE_CATALOGUE",
    "GYRO_CATALOGUE",
    "PAPER34_NUMBERS",
    "FeatureSpec",
    "StreamingFeatureExtractor",
    "WIDER_RANGE_RATIO",
    "WINDOW_BY",
    "acc_range_tally",
    "catalogue_markdown",
    "check_acc_range",
    "check_frame",
    "clip_acc",
    "extract_features",
    "extract_step_features",
    "feature_names",
    "feature_specs",
    "features_from_arrays",
    "forward_vectors",
    "gravity_frame_rotations",
    "make_step_windows",
    "make_windows",
    "resolve_subset",
    "uses_forward",
    "uses_forward_face",
    "uses_gyro",
]
