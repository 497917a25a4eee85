"""The accelerometer range a model reads every phone through (``[features] acc_range_ms2``).

A phone's accelerometer saturates at its measurement range: many phones stop at
+-2 g per axis (about 19.6 m/s^2; e.g. the Nexus 5 and the iPhone 4S of the tyrex
recordings), others read to 8 g or 16 g. Paper 003's features (sec. 3.2: per-axis
maxima, variances, quartiles, kurtosis, the magnitude's statistics) change with the
range whenever the signal goes beyond the narrower one: a vigorous run, a jolt. A
model trained on phones that clip reads a wider-range phone's running as something
it has never seen, although the walker's motion is the same.

A model with a range (``acc_range_ms2`` in ``model.json``) therefore reads every
phone through the narrowest accelerometer range in its training data: each axis is
clipped to ``[-acc_range_ms2, +acc_range_ms2]`` before the features, in training (real
and simulated recordings alike, after any augmentation, because the training phones'
own sensors did so), in cross-validation and in every prediction path (whole,
chunked, streaming, step windows, the PDR's mode evidence, the portable export). A
phone with a wider range is then not out of domain merely for reading beyond it. The
value is a sensor fact (the training phones' range), not a setting fitted to a score.

Read through the range: the classifier's features and the whole domain record
(:mod:`gaitml.models.domain`: feature distance, gravity direction, orientation
dynamics), which is fitted on the training windows as the model read them, so that
check and record compare like with like. Read raw: the fixed physics rules that were
not learnt from the training data: the foot-placement rule
(:mod:`gaitml.models._placement`, whose accelerometer test needs peaks of 2.5 g, above
a 2 g range), the still gate and the side-direction flag
(:mod:`gaitml.models._predict`).

Clipping acts on each sample alone, so a window's clipped features still depend on
its own samples only (chunked and streamed rows equal the whole-file rows).
"""

from __future__ import annotations

import numpy as np

from gaitml.consts import GRAVITY_MS2
from gaitml.errors import InputError

__all__ = ["check_acc_range", "clip_acc", "acc_range_tally", "WIDER_RANGE_RATIO"]

#: A recording whose largest |axis| exceeds the model's range by this factor reads wider than
#: the model's training phones (a phone that clips at 2 g reads up to about 2.2 g, 21.7 m/s^2 in
#: the tyrex runs: its own clipping, not a wider range); ``gaitml predict`` says so in one line.
WIDER_RANGE_RATIO = 1.25


def check_acc_range(value) -> float | None:
    """``value`` as a range in m/s^2, or None for no range (None or 0).

    Raises
    ------
    InputError
        Not a finite number, or a range under 1 g (no phone has one: a phone lying still would saturate).
    """
    if value is None:
        return None
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = float("nan")
    if v == 0:
        return None
    if not np.isfinite(v) or v < GRAVITY_MS2:
        raise InputError(
            f"accelerometer range {value!r} m/s^2 is not a finite number >= {GRAVITY_MS2} (1 g); give the training phones' "
            "range per axis (e.g. 19.6 for +-2 g) or 0 for none."
        )
    return v


def clip_acc(acc, range_ms2: float | None) -> np.ndarray:
    """``acc`` (n, 3) in m/s^2 as an accelerometer of range +-``range_ms2`` per axis reads it (None: unchanged)."""
    a = np.asarray(acc, dtype=float)
    r = check_acc_range(range_ms2)
    return a if r is None else np.clip(a, -r, r)


def acc_range_tally(acc, range_ms2: float | None) -> dict | None:
    """What reading ``acc`` through the range changes: None without a range, else a dict.

    ``range_ms2``; ``n_samples``; ``n_samples_clipped`` (samples with at least one axis
    beyond the range); ``max_abs_axis_ms2`` (the largest |axis| of the input, 0 when empty);
    ``wider`` (the input reads more than :data:`WIDER_RANGE_RATIO` x the range: a sensor with a
    wider range than the model's training phones).
    """
    r = check_acc_range(range_ms2)
    if r is None:
        return None
    a = np.abs(np.asarray(acc, dtype=float))
    peak = a.max(axis=1) if len(a) else np.zeros(0)
    top = float(peak.max()) if len(peak) else 0.0
    return {
        "range_ms2": r,
        "n_samples": int(len(a)),
        "n_samples_clipped": int(np.count_nonzero(peak > r)),
        "max_abs_axis_ms2": top,
        "wider": bool(top > WIDER_RANGE_RATIO * r),
    }
