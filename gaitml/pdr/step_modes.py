"""Motion mode of every step from a window classifier, with refined mode boundaries.

Paper 003 classifies 1.5 s windows (sec. 3.3, corrected by the adjacent-window rule
of sec. 3.4) and moves every step by the mode of its window (sec. 4.1). A step is
about 0.5 s, so at every mode change the window that contains the first steps of the
new mode also contains the last steps of the old one: whichever mode the window gets,
one or two steps around each change move in the wrong direction. On the simulated
routes most of the per-step mode errors of the nearest-window assignment lie near a
true mode change (``experiments/reports/pdr-step-modes.md``).

:func:`refine_mode_boundaries` (ours, not in the papers) keeps the window
classifier's decision *which* modes occur and re-places *where* each change happens,
step by step:

1. **Transition artefacts.** A run of steps of mode C shorter than one model window
   between runs of two different modes A and B is a mixed window classified as a
   third mode (for example walk -> side step read as backward); its steps join the
   A/B boundary search. This is the step-level form of the paper's own assumption
   (at most one mode switch within one window, sec. 3.4).
2. **Change point.** Around each change from A to B (steps within ``search_s`` of
   it and not beyond the middle of either neighbouring run, so no run disappears),
   every step k gets the evidence
   ``g_k``: the classifier's A-versus-B margin on a short window starting at the
   step's peak plus the margin on a short window ending at the next step's peak (the
   step itself, seen from both sides). The boundary ``j`` maximises
   ``sum(g_k, k < j) - sum(g_k, k >= j)``: the steps before it are A, the rest B.
   For the linear one-vs-one SVM the margin is the decision value of the A/B
   machine; for models with ``predict_proba`` it is ``log p(A) - log p(B)``.

Short windows are half the model's window (0.75 s for the paper's 1.5 s: one to two
steps). The SVM was trained on full windows; its A/B machine is still informative on
half windows because the features are per-sample statistics (means, variances,
quantiles, correlations). Models on raw windows (``cnn1d``) need their own length, so
for them the short windows are full model windows.

:func:`gaitml.pdr.run_pdr` (``mode_boundaries='auto'``) refines only peak-timed steps
(single-peak, adaptive): the FSM detectors time a step by its end, where the nearest
window already does better than the refinement. The measured per-step mode accuracies
and end-point errors of the three assignments, seed by seed, with the commands that
reproduce them, are in ``experiments/reports/pdr-step-modes.md``.

3. **Short non-forward runs** (:func:`forward_short_runs`, :func:`gaitml.pdr.run_pdr`'s
   ``short_run_windows``). A run of side or backward steps between two forward runs (walk or run on both
   sides) means two mode switches; under the paper's assumption (at most one switch within one model
   window, sec. 3.4) they are at least one window apart, so the run holds at least the steps the walker
   makes in one window. A run with fewer steps than that (its step count times the recording's median
   step interval shorter than ``short_run_windows`` model windows) is read as the forward mode of the
   step before it. The interval is the walker's median, not the run's own span, because a run at a stop
   spans the standing between its steps. Measured on tyrex, where nobody steps sideways or backward, and on
   the simulator's routes: ``experiments/reports/tyrex-pdr.md``, section "Sideways and backward steps on tyrex".

A model trained on step windows (``window.by = "steps"``, :mod:`gaitml.features.step_windows`)
needs none of this: :func:`modes_from_step_model` classifies each PDR step on its own
samples, one prediction per step.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.consts import SHORT_RUN_DEFAULT as _SHORT_RUN_DEFAULT
from gaitml.errors import InputError
from gaitml.recording import Recording

__all__ = [
    "modes_from_step_model",
    "modes_from_windows",
    "window_values_at_steps",
    "pair_margin",
    "refine_mode_boundaries",
    "mode_runs",
    "next_step_times",
    "forward_short_runs",
    "MODE_ASSIGNMENTS",
    "NONFORWARD_MODES",
    "SHORT_RUN_DEFAULT",
    "SHORT_RUN_WINDOWS",
]

#: Ways to turn window predictions into per-step modes (``run_pdr(mode_boundaries=...)``):
#: ``nearest`` (window nearest the step time), ``middle`` (window nearest the middle
#: between the step time and the next one), ``refine`` (:func:`refine_mode_boundaries`
#: after ``nearest``), ``auto`` (``refine`` when the step times are peaks, else ``nearest``).
MODE_ASSIGNMENTS = ("auto", "refine", "nearest", "middle")
#: Modes that move the walker off the facing direction (paper 003 eq. 11's side steps and backward walking).
NONFORWARD_MODES = ("side_left", "side_right", "backward")
#: The short-run rule (:func:`forward_short_runs`): a side or backward run between forward steps must hold at
#: least the steps of this many model windows (paper 003 sec. 3.4: at most one mode switch within one window),
#: else its steps take the forward mode before it. Figures: ``experiments/reports/tyrex-pdr.md``, section
#: "Sideways and backward steps on tyrex".
SHORT_RUN_WINDOWS = 1.0
#: :func:`gaitml.pdr.run_pdr`'s default ``short_run_windows`` (``gaitml pdr --short-runs``; the value lives in
#: :data:`gaitml.consts.SHORT_RUN_DEFAULT`): 0, the rule off. Opt-in: with :data:`SHORT_RUN_WINDOWS` it failed
#: one of the three parts of its adoption rule, fixed before measuring (``experiments/reports/tyrex-pdr.md``,
#: section "Sideways and backward steps on tyrex", where the figures are).
SHORT_RUN_DEFAULT = _SHORT_RUN_DEFAULT


def modes_from_windows(windows: pd.DataFrame, step_t_s) -> np.ndarray:
    """Mode of the window containing each step time (nearest window centre).

    Parameters
    ----------
    windows : DataFrame with ``t_start_s``, ``t_end_s``, ``mode`` (model predictions).
    step_t_s : (m,) step times.

    Notes
    -----
    With overlapping windows a step lies in two; the window whose centre is nearest to
    the step time is used (it sees the step best). Steps before the first or after the
    last window take the nearest window. A detected step is gait: where its window was
    reported ``still`` (no gait in the window's |acc| by the still gate,
    :func:`gaitml.models.still_windows`) the step takes the model's own answer
    (``mode_raw``).
    """
    modes = window_values_at_steps(windows, step_t_s, "mode").astype(str)
    if len(modes) and "still" in windows and "mode_raw" in windows:
        from gaitml.models._predict import STILL

        raw = window_values_at_steps(windows, step_t_s, "mode_raw").astype(str)
        modes = np.where(modes == STILL, raw, modes)
    return modes


def window_values_at_steps(windows: pd.DataFrame, step_t_s, column: str) -> np.ndarray:
    """Value of ``column`` of the window nearest each step time (the rule of :func:`modes_from_windows`).

    Used for the per-step out-of-domain flag (``column='in_domain'``); an object array.
    """
    for c in ("t_start_s", "t_end_s", column):
        if c not in windows:
            raise InputError(f"the window table has no `{c}` column; pass gaitml.models.predict_recording output.")
    t = np.asarray(step_t_s, dtype=float)
    if len(windows) == 0:
        raise InputError("the model predicted no windows (recording shorter than one window); use --modes true or forward.")
    centre = 0.5 * (windows["t_start_s"].to_numpy(float) + windows["t_end_s"].to_numpy(float))
    order = np.argsort(centre)
    centre = centre[order]
    values = windows[column].to_numpy(dtype=object)[order]
    j = np.searchsorted(centre, t)
    lo = np.clip(j - 1, 0, len(centre) - 1)
    hi = np.clip(j, 0, len(centre) - 1)
    pick = np.where(np.abs(t - centre[lo]) <= np.abs(centre[hi] - t), lo, hi)
    return values[pick]


def next_step_times(step_t_s) -> np.ndarray:
    """The time of the step after each step (the last one gets its time plus the median interval).

    ``step_t_s`` has at least two increasing times.
    """
    t = np.asarray(step_t_s, dtype=float)
    return np.r_[t[1:], t[-1] + np.median(np.diff(t))]


def mode_runs(modes) -> list[tuple[int, int, str]]:
    """Runs of equal consecutive modes as ``(first, stop, mode)`` (``stop`` exclusive)."""
    m = np.asarray(modes).astype(str)
    if len(m) == 0:
        return []
    first = np.flatnonzero(np.r_[True, m[1:] != m[:-1]])
    stop = np.r_[first[1:], len(m)]
    return [(int(a), int(b), str(m[a])) for a, b in zip(first, stop, strict=True)]


def forward_short_runs(modes, step_t_s, window_s: float, min_windows: float = SHORT_RUN_WINDOWS) -> tuple[np.ndarray, int]:
    """Read side and backward runs too short to be a bout as the forward mode around them (module docstring, item 3).

    Parameters
    ----------
    modes : (m,) per-step modes.
    step_t_s : (m,) increasing step times (s); their median interval is the walker's step interval.
    window_s : the model's window length (s), paper 003's 1.5 s.
    min_windows : a run of :data:`NONFORWARD_MODES` steps whose previous and next steps are ``walk`` or ``run``
        is kept when its step count times the median step interval is at least ``min_windows * window_s``;
        0 keeps every run.

    Returns
    -------
    (modes, n_changed) : the new per-step modes (str) and how many steps changed.
    """
    m = np.asarray(modes).astype(str).reshape(-1).astype(object)
    t = np.asarray(step_t_s, dtype=float).reshape(-1)
    if len(t) != len(m):
        raise InputError(f"{len(t)} step times but {len(m)} modes; give one mode per step.")
    for name, v in (("window_s", window_s), ("min_windows", min_windows)):
        if not (np.isfinite(v) and v >= 0):
            raise InputError(f"{name} must be a finite number >= 0, got {v}.")
    if min_windows == 0 or len(t) < 3:
        return m.astype(str), 0
    interval = float(np.median(np.diff(t)))
    if not (np.isfinite(interval) and interval > 0):
        return m.astype(str), 0
    forward = ("walk", "run")
    out = m.copy()
    changed = 0
    for a, b, mode in mode_runs(m):
        if mode not in NONFORWARD_MODES or a == 0 or b == len(m) or m[a - 1] not in forward or m[b] not in forward:
            continue
        if (b - a) * interval < min_windows * window_s:
            out[a:b] = m[a - 1]
            changed += b - a
    return out.astype(str), changed


def pair_margin(estimator, X: np.ndarray, a: str, b: str) -> np.ndarray:
    """Evidence for class ``a`` against class ``b`` per row of ``X`` (positive favours ``a``).

    The decision value of the ``a``/``b`` machine of a one-vs-one linear SVM
    (:class:`gaitml.models.LinearOVOSVM`); ``log p(a) - log p(b)`` for estimators with
    ``predict_proba``; otherwise +1 / -1 / 0 for rows predicted ``a`` / ``b`` / other.
    """
    classes = [str(c) for c in estimator.classes_]
    if a not in classes or b not in classes:
        raise InputError(f"modes {a!r} and {b!r} must both be classes of the model {classes}.")
    ia, ib = classes.index(a), classes.index(b)
    pairs = getattr(estimator, "pairs_", None)
    if pairs is not None:
        d = estimator.pairwise_decision_function(X)
        for k, (i, j) in enumerate(np.asarray(pairs)):
            if (i, j) == (ia, ib):
                return d[:, k]
            if (i, j) == (ib, ia):
                return -d[:, k]
    if hasattr(estimator, "predict_proba"):
        p = np.clip(np.asarray(estimator.predict_proba(X), dtype=float), 1e-12, 1.0)
        return np.log(p[:, ia]) - np.log(p[:, ib])
    pred = np.asarray(estimator.predict(X)).astype(str)
    return (pred == a).astype(float) - (pred == b).astype(float)


def _merge_transition_artefacts(modes: np.ndarray, t: np.ndarray, max_blip_s: float) -> np.ndarray:
    """Give runs lasting less than ``max_blip_s`` between two different modes to the left mode.

    A run lasts from its first step time to the first step time after it. Merging
    repeats until no such run is left, so two adjacent artefacts (A, C, D, B) both go.
    """
    m = modes.copy()
    while True:
        runs = mode_runs(m)
        for q in range(1, len(runs) - 1):
            a0, a1, _ = runs[q]
            left, right = runs[q - 1][2], runs[q + 1][2]
            if left != right and t[a1] - t[a0] < max_blip_s:
                m[a0:a1] = left  # the boundary search re-places the change inside this stretch
                break
        else:
            return m


def refine_mode_boundaries(
    model,
    recording: Recording,
    step_t_s,
    modes,
    *,
    short_window_s: float | None = None,
    search_s: float | None = None,
    max_blip_s: float | None = None,
) -> np.ndarray:
    """Re-place every mode change of a per-step mode sequence at the most likely step.

    See the module docstring for the method (ours, not in the papers).

    Parameters
    ----------
    model : TrainedModel (:func:`gaitml.models.load_model`), the model that gave ``modes``.
    recording : Recording with the signals the model needs.
    step_t_s : (m,) step times in seconds, increasing: the step *peaks* (the evidence
        windows start at a step time and end at the next one). :func:`gaitml.pdr.run_pdr`
        refines only step tables whose event is ``t_peak_s``.
    modes : (m,) initial modes per step, e.g. :func:`modes_from_windows` of the corrected
        window predictions.
    short_window_s : float, optional
        Length of the evidence windows of feature models; default half the model's
        window. Raw-input models (``cnn1d``) always use their own window length.
    search_s : float, optional
        How far (s) from the initial change the boundary may move; default one model window.
    max_blip_s : float, optional
        Runs lasting less than this between two different modes are transition
        artefacts; default one model window.

    Returns
    -------
    ndarray of str, shape (m,)
    """
    from gaitml.models._dataset import raw_windows, resample_recording

    t = np.asarray(step_t_s, dtype=float).reshape(-1)
    m = np.asarray(modes).astype(str).reshape(-1).astype(object)
    if len(t) != len(m):
        raise InputError(f"{len(t)} step times but {len(m)} modes; give one mode per step.")
    if not np.all(np.isfinite(t)):
        raise InputError("step times must be finite; drop the steps without a time.")
    if len(t) > 1 and np.any(np.diff(t) < 0):
        raise InputError("step times must be increasing; sort the step table by time.")
    unknown = sorted(set(m) - {str(c) for c in model.estimator.classes_})
    if unknown:
        raise InputError(f"modes {unknown} are not classes of the model {list(model.labels)}; pass the model's own predictions.")
    raw = model.input_kind == "raw"
    if raw and short_window_s is not None:
        raise InputError(
            "short_window_s applies to feature models only; a raw-input model needs windows of its own length, drop the argument."
        )
    search_s = model.length_s if search_s is None else float(search_s)
    max_blip_s = model.length_s if max_blip_s is None else float(max_blip_s)
    for name, v in (("search_s", search_s), ("max_blip_s", max_blip_s)):
        if not (np.isfinite(v) and v >= 0):
            raise InputError(f"{name} must be a finite number of seconds >= 0, got {v}.")
    if len(t) < 2:
        return m.astype(str)
    rec = resample_recording(recording, model.sampling_rate_hz)
    from gaitml.models._predict import model_view

    rec = model_view(model, rec)[0]  # the model's evidence reads the accelerometer through its range, as predict does
    fs = rec.sampling_rate_hz
    n = rec.n_samples
    win_s = model.length_s if raw else (0.5 * model.length_s if short_window_s is None else float(short_window_s))
    length = int(round(win_s * fs))
    if length < 2:
        raise InputError(f"short_window_s = {win_s} s is shorter than 2 samples at {fs:g} Hz; use a longer window.")
    if length > n:
        raise InputError(f"the recording ({n / fs:g} s) is shorter than the evidence window ({win_s:g} s); use a longer recording.")

    t_next = next_step_times(t)
    m = _merge_transition_artefacts(m, np.r_[t, t_next[-1]], max_blip_s)  # a run lasts until the next step after it
    peak = np.round(t * fs).astype(np.int64)
    next_peak = np.round(t_next * fs).astype(np.int64)

    def inputs(starts: np.ndarray) -> np.ndarray:
        starts = np.clip(starts, 0, n - length)
        # only the stretch the windows cover: each boundary costs O(window), not O(recording)
        a, b = int(starts.min()), int(starts.max()) + length
        if raw:
            return raw_windows(rec.slice(a, b), starts - a, length, model.raw_channels, getattr(model, "frame", "phone"))
        from gaitml.features import features_from_arrays

        gyr = rec.gyr[a:b] if rec.gyr is not None else None
        return features_from_arrays(rec.acc[a:b], gyr, fs, starts - a, length, model.feature_set, getattr(model, "frame", "phone"))

    out = m.copy()
    runs = mode_runs(m)
    for q in range(1, len(runs)):
        left_first, _, mode_a = runs[q - 1]
        k, right_stop, mode_b = runs[q]
        # the boundary moves at most search_s, and at most (n - 1) // 2 steps into a
        # neighbouring run of n steps, so no run disappears
        lo = max(k - (k - left_first - 1) // 2, int(np.searchsorted(t, t[k] - search_s)))
        hi = min(k + (right_stop - k - 1) // 2, int(np.searchsorted(t, t[k] + search_s, side="right")))
        idx = np.arange(lo, hi)
        if len(idx) == 0:
            continue
        X = inputs(np.r_[peak[idx], next_peak[idx] - length])
        g = pair_margin(model.estimator, X, mode_a, mode_b)
        g = g[: len(idx)] + g[len(idx) :]
        cum = np.r_[0.0, np.cumsum(g)]
        score = cum - (cum[-1] - cum)  # A-evidence before the boundary minus A-evidence after it
        best = np.flatnonzero(score >= score.max() - 1e-12)
        j = lo + int(best[np.argmin(np.abs(lo + best - k))])  # ties: stay nearest the initial change
        out[lo:j] = mode_a
        out[j:hi] = mode_b
    return out.astype(str)


def modes_from_step_model(
    model, recording: Recording, steps: pd.DataFrame, *, with_reasons: bool = False, run_min_cadence_hz: float | None = None
) -> tuple:
    """Mode of every step of ``steps`` from a step-window model (no window-to-step lookup).

    ``window.by = "steps"``: each step of the PDR's step table is one window (its
    samples from the previous step's peak to its own peak, as in training,
    :func:`gaitml.features.step_windows.spans_from_steps`), classified on its own
    samples and corrected by the adjacent-window rule over the steps (paper 003 sec.
    3.4). A step too short to classify (under 3 samples) takes the mode of the nearest
    classified step. ``window.by = "strides"``: the model's zero-velocity detector cuts
    the strides, and each step takes the mode of the stride nearest its time (a stride
    holds two steps).

    Parameters
    ----------
    model : TrainedModel with ``window.by`` steps or strides.
    recording : Recording
    steps : DataFrame, a step detector's table (``peak``, ``t_peak_s``) at the recording's rate.
    run_min_cadence_hz : the run-cadence rule of :func:`gaitml.models.predict_step_windows` (None: its default, 0: off).

    Returns
    -------
    (modes, note, in_domain) : ndarray of str (one per step), a sentence for the PDR
        notes, and the out-of-domain flag of every step (object array of True/False, or
        None when the model has no domain record). With ``with_reasons`` a fourth item: the
        ``out_of_domain_reason`` of every step (object array of str, empty in domain or
        unchecked), taken from its window as its flag is.
    """
    from gaitml.features.step_windows import spans_from_steps
    from gaitml.models import predict_step_windows

    n = len(steps)
    if n == 0:
        out = (np.zeros(0, dtype=str), "no steps: nothing to classify", np.zeros(0, dtype=object))
        return (*out, np.zeros(0, dtype=object)) if with_reasons else out
    by = model.window_by
    t_step = steps["t_peak_s"].to_numpy(float) if "t_peak_s" in steps else steps["peak"].to_numpy(float) / recording.sampling_rate_hz
    if by == "steps":
        fs = model.sampling_rate_hz
        scale = fs / recording.sampling_rate_hz
        n_model = int(round(recording.n_samples * scale))
        at_model = pd.DataFrame(
            {"peak": np.clip(np.round(steps["peak"].to_numpy(float) * scale), 0, n_model - 1).astype(np.int64), "t_peak_s": t_step}
        )
        spans = spans_from_steps(at_model, n_model, fs)
        table = predict_step_windows(model, recording, correction=True, spans=spans, run_min_cadence_hz=run_min_cadence_hz)
        modes = np.full(n, "", dtype=object)
        modes[table["step"].to_numpy(dtype=np.int64)] = table["mode"].to_numpy().astype(str)
        missing = np.flatnonzero(modes == "")
        if len(missing):
            if len(table) == 0:
                raise InputError(
                    "every step is shorter than 3 samples at the model's rate; no step can be classified: use --modes true or forward."
                )
            modes[missing] = modes_from_windows(table, t_step[missing])
        in_domain = _per_step(table, "in_domain", n, missing, t_step)
        note = f"modes per step from the step-window model ({n} steps classified on their own samples, no window lookup)"
        if with_reasons:
            return modes.astype(str), note, in_domain, _reasons(_per_step(table, "out_of_domain_reason", n, missing, t_step))
        return modes.astype(str), note, in_domain
    table = predict_step_windows(model, recording, correction=True, run_min_cadence_hz=run_min_cadence_hz)
    if len(table) == 0:
        raise InputError(
            f"the model's zero-velocity detector {model.window_detector!r} found no strides; use --modes true or forward, or a step-window model."
        )
    note = (
        f"modes per step from the stride-window model ({len(table)} strides of {model.window_detector}; each step takes its stride's mode)"
    )
    out = (modes_from_windows(table, t_step), note, window_values_at_steps(table, t_step, "in_domain"))
    if with_reasons:
        return (*out, _reasons(window_values_at_steps(table, t_step, "out_of_domain_reason")))
    return out


def _per_step(table: pd.DataFrame, column: str, n: int, missing: np.ndarray, t_step: np.ndarray) -> np.ndarray:
    """``column`` of a per-step prediction table for each of ``n`` steps; the ``missing`` steps (too short to
    classify) take the value of the nearest classified step."""
    out = np.full(n, None, dtype=object)
    out[table["step"].to_numpy(dtype=np.int64)] = table[column].to_numpy(dtype=object)
    if len(missing):
        out[missing] = window_values_at_steps(table, t_step[missing], column)
    return out


def _reasons(values) -> np.ndarray:
    """``out_of_domain_reason`` values as str (empty for none)."""
    return np.array([str(v or "") for v in values], dtype=object)
