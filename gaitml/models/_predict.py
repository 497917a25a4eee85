"""Per-window motion modes of a recording with a saved model."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.recording.timestamps import recorded_rate_hz  # the rate check's reading of a recording's rate (shared with the step detectors)

__all__ = [
    "predict_recording",
    "model_inputs",
    "model_view",
    "domain_columns",
    "windows_with_changed_samples",
    "still_windows",
    "side_direction_unsure",
    "still_unsure",
    "stride_rhythm",
    "STILL_UNSURE_DEFAULT",
    "STILL_UNSURE_PAD_S",
    "window_step_cadence",
    "best_other_modes",
    "run_cadence_rule",
    "still_statistic",
    "describe_still_gate",
    "STILL",
    "STILL_RULE",
    "STILL_RULES",
    "STILL_STD_LP_MS2",
    "STILL_LOWPASS_HZ",
    "STILL_LOWPASS_ORDER",
    "STILL_STD_MS2",
    "STILL_RANGE_MS2",
    "STILL_THRESHOLDS_MS2",
    "STILL_STEP_VETO_MIN_STEPS",
    "STILL_STEP_VETO_DEFAULT",
    "STILL_STEP_SWING_PERIODICITY",
    "still_step_veto_threshold",
    "window_step_counts",
    "veto_counts",
    "recording_steps",
    "veto_steps",
    "steps_found_once",
    "veto_reads_own_steps",
    "veto_can_change_step_modes",
    "SIDE_MODES",
    "FACE_UP_MAX_DEG",
    "RUN_MODE",
    "RUN_MIN_CADENCE_HZ",
    "RUN_CADENCE_REACH_S",
    "RUN_STRIDE_CADENCE_HZ",
    "RUN_CADENCE_DEFAULT_HZ",
    "run_cadence_threshold",
    "DOMAIN_REASON",
    "foot_placement",
    "rate_reason",
    "window_placement_reason",
]

#: The mode reported for a window with no gait in it (a phone lying still, a person standing).
STILL = "still"
#: The statistics the still gate can read from a window's |acc| (see :func:`still_statistic`).
STILL_RULES = ("std_lp", "std", "range")
#: The default still gate: the standard deviation of |acc| after a :data:`STILL_LOWPASS_HZ` low-pass
#: (:data:`STILL_STD_LP_MS2`), which reads about the same at every input rate from 20 Hz up.
STILL_RULE = "std_lp"
#: Rule ``"std_lp"``: the cut-off (Hz) of the low-pass applied to a window's acceleration before its
#: |acc| standard deviation is taken. A recording made at 20 Hz reaches the model's rate through
#: :func:`gaitml.models.resample_recording`, whose anti-alias filter cuts at 0.45 x 20 = 9 Hz, while a
#: recording made at 50 Hz keeps its content up to 25 Hz: the same calm walk then has a smaller |acc|
#: spread at 20 Hz. Cutting every input at the same 9 Hz removes that difference. It keeps the gait:
#: the acceleration of walking and running repeats at the step frequency (1.5-3.5 steps/s, paper 003
#: sec. 2.2) and carries its power in that frequency and its first harmonics (Antonsson and Mann 1985,
#: "The frequency content of gait", *J. Biomech.* 18(1): 39-47, measure the frequency content of the
#: walking of 12 subjects), while what lies above 9 Hz in a carried phone is mostly the short transient
#: of a foot strike, a tap or a knock, which the standard deviation should not count as stepping.
STILL_LOWPASS_HZ = 9.0
#: Order of the :data:`STILL_LOWPASS_HZ` Butterworth low-pass (run forwards and backwards over the
#: window's own samples, zero phase), the same filter as :func:`gaitml.models.resample_recording`'s
#: anti-alias filter.
STILL_LOWPASS_ORDER = 4
#: Rule ``"std_lp"``: a window whose |acc|, after the :data:`STILL_LOWPASS_HZ` low-pass, has a standard
#: deviation below this (m/s^2) holds no walking: the physics of rule ``"std"`` (:data:`STILL_STD_MS2`),
#: read the same way at every input rate. The value is the one at which the standing windows of real
#: hand-held and pocket phones are read still as often as with the ``"range"`` rule, chosen on
#: recordings of real walkers (experiments/reports/still-gate.md).
STILL_STD_LP_MS2 = 0.38
#: Rule ``"std"`` (the default gate before ``"std_lp"``; unfiltered, so a recording made at a lower
#: rate reads lower): a window whose |acc| has a standard deviation below this (m/s^2) holds no
#: walking. A walker's steps make the acceleration magnitude oscillate at the step rate for the
#: whole window (the vertical bounce of paper 003 sec. 2.2: a peak above gravity and a valley
#: below it at every step), so its standard deviation measures the sustained stepping energy;
#: a standing walker's hand tremor and the single jolt of a tap, a shuffle or a phone put down
#: move few samples and leave it small. (A sinusoidal bounce of amplitude A has a standard
#: deviation of A / sqrt(2) and a max - min of 2 A: 0.41 m/s^2 is the standard deviation of a
#: bounce swinging 1.16 m/s^2, about half of :data:`STILL_RANGE_MS2`.) The value is the one at
#: which the standing windows of real hand-held and pocket phones are read still as often as
#: with the ``"range"`` rule, chosen on recordings of real walkers (experiments/reports/still-gate.md).
STILL_STD_MS2 = 0.41
#: Rule ``"range"`` (the gate before the ``"std"`` rule): a window whose |acc| swings by less than
#: this (m/s^2) from its lowest to its highest sample holds no step: paper 003 sec. 2.2 counts a
#: step only at a peak rising sigma1 = 2 m/s^2 above gravity
#: (:data:`gaitml.steps.single_peak.PEAK_THRESHOLD_MS2`), so a window whose whole swing is smaller
#: cannot hold one. Two extreme samples set it, so one jolt of a standing hand lifts it over the gate.
STILL_RANGE_MS2 = 2.0
#: The threshold (m/s^2) of each rule of the still gate.
STILL_THRESHOLDS_MS2 = {"std_lp": STILL_STD_LP_MS2, "std": STILL_STD_MS2, "range": STILL_RANGE_MS2}
#: The still gate's step veto: a window the |acc| statistic reads still in which the veto's step finder
#: (:func:`veto_steps`: ``adaptive`` with its gait check and, on a recording with a gyroscope, its swing stage at
#: :data:`STILL_STEP_SWING_PERIODICITY`, run once over the recording at the model's rate; without a gyroscope the
#: steps the run-cadence rule reads) finds at least this many steps with their peak inside the window is not still:
#: it keeps the model's mode (the phone at the ear of a calm walker varies |acc| as little as a standing hand, but
#: its steps repeat). Two, because a walk at 1.33 steps/s or faster (``adaptive``'s slowest step is 0.75 steps/s,
#: :data:`gaitml.steps.adaptive.MIN_STEP_HZ`) puts at least two steps into every 1.5 s window, while one step
#: inside, or steps just outside, is what the last step of a walk that has just stopped leaves; the detector keeps
#: only bouts of at least :data:`gaitml.steps.adaptive.MIN_BOUT_STEPS` steps that pass its gait check, so a jolt of a
#: standing hand gives none. Fixed by that reasoning before it was measured (experiments/reports/still-gate.md,
#: "The step veto": each tyrex person left out, by a rule fixed before the measurement).
STILL_STEP_VETO_MIN_STEPS = 2
#: The step veto predict applies when the caller gives none (``still_step_veto=None``): :data:`STILL_STEP_VETO_MIN_STEPS`,
#: the veto on; None turns it off in every path by default (:func:`still_step_veto_threshold`).
STILL_STEP_VETO_DEFAULT: int | None = STILL_STEP_VETO_MIN_STEPS
#: The step finder of the still gate's veto (:func:`veto_steps`; the run-cadence rule keeps ``adaptive``'s defaults,
#: :func:`recording_steps`) runs ``adaptive`` with its opt-in swing stage 2c at this value
#: (``gyro_swing_min_periodicity``; :func:`gaitml.steps.adaptive.gyro_swing_cadence`) on a recording with a gyroscope:
#: where |acc| repeats too weakly for ``adaptive``'s periodicity floor (a calm walker with the phone at the ear: the
#: centre of mass bounces less the slower the walk, Orendurff et al. 2004) the phone's regular stride-periodic turning
#: sets the step period (the body that carries it turns once per stride and reverses between steps, Perry & Burnfield
#: 2010 ch. 10). 0.3 is the stage's documented value (|acc|'s own floor, chosen leave-one-person-out on tyrex for the
#: step counts, experiments/reports/tyrex-steps.md). It is not ``gaitml steps``' default (it adds steps to simulated
#: gestures and desk handling there); for the veto it was adopted by a rule fixed before it was scored (each tyrex
#: person left out, native and 20 Hz: no motion's silently wrong windows rise, Phoning's fall, standing read as a mode,
#: the table, desk and gesture still shares within 0.02; experiments/reports/still-gate.md, "The step veto's
#: evidence"). 0 runs ``adaptive`` at its defaults. Without a gyroscope the stage cannot run and is not asked for: the
#: veto and the run-cadence rule then read the same steps, found once.
STILL_STEP_SWING_PERIODICITY = 0.3
#: Mark a window the still gate reports :data:`STILL` (after the step veto) *unsure* (``still_unsure``) where the
#: phone turns with a stride rhythm around it (:func:`stride_rhythm`): the gate reads no gait in |acc|, the gyroscope
#: reads the body walking, and the table says so instead of deciding. The window keeps the mode ``still`` (``mode_raw``
#: keeps the model's answer) and claims neither; a standing window it marks is not read as a mode. Only the windows the
#: gate reports still are looked at, only with a gyroscope. The rhythm alone decides too often to be a veto (as one it
#: read many standing windows as a mode: experiments/reports/still-gate.md, vetoswing); as a mark it was adopted by a
#: rule fixed before it was scored (each tyrex person left out, native rate and 20 Hz: Phoning's silently wrong share
#: <= 0.05, no motion's silently wrong count rising, no motion's right share falling by more than 0.01, standing
#: windows marked <= 0.15 and none more read as a mode; same report, "Say unsure where the still gate and the gait
#: evidence disagree").
#: False turns the mark off (the column is then all False).
STILL_UNSURE_DEFAULT = True
#: :func:`stride_rhythm` band-passes, for each window it reads, the 5 s of angular rate around the window and this
#: many seconds more on each side (inside the recording), so that the zero-phase filter's start-up at the ends of the
#: piece settles before the 5 s it reads (the band's lowest edge, 0.3 Hz, rings for about one period, 3.3 s). Each
#: window reads only samples within 7.5 s of its centre, or, where its 5 s are moved inside the recording, within 10 s
#: of the recording's first or last sample: a chunk with a margin wider than 7.5 s gives the whole-file answer.
STILL_UNSURE_PAD_S = 5.0
#: The side-step modes, whose name carries a direction (left / right of the walker).
SIDE_MODES = ("side_left", "side_right")
#: A side step's direction is read from the phone's own lateral axis (the phone-frame features
#: of paper 003 sec. 3.2). It is tied to the walker's left and right only while the screen faces
#: up towards a walker who holds the phone in front (the top pointing forward, x to the right):
#: the window's gravity within this angle of the phone's +z axis. A phone held upright (in a
#: trouser pocket, the swinging hand, at the ear) may face in or out and sit on either leg,
#: which flips its lateral axis against the body, so its left / right is unsure there.
FACE_UP_MAX_DEG = 60.0
#: The mode the run-cadence rule checks (:func:`run_cadence_rule`).
RUN_MODE = "run"
#: A window read :data:`RUN_MODE` whose local step cadence (steps/s) is below this is answered with the
#: model's best mode other than run (:func:`run_cadence_rule`). 140 steps/min is the cadence at which
#: adults change from walking to running: Hansen et al. 2017 ("The role of stride frequency for
#: walk-to-run transition in humans", *Sci. Rep.*, doi:10.1038/s41598-017-01972-1) measure the transition
#: at 70.6 +- 3.2 strides/min (141 steps/min, at about 7.6 km/h), and on treadmill bouts of rising speed
#: ("Cadence (steps/min) as an indicator of the walk-to-run transition", *Hum. Mov. Sci.* 90: 103117, 2023)
#: a cadence of 140 steps/min told walking from running in 91 % of bouts against 55 % for the transition
#: speed (2.1 m/s); their own data give 135-140 steps/min. Above the transition the running step frequency
#: stays in a narrow band while the speed grows: Cavanagh and Kram 1989 (*Med. Sci. Sports Exerc.* 21:
#: 467-479) find stride frequency up only 4 % from 3.15 to 4.12 m/s (stride length up 28 %). So a run does
#: not come at a walking cadence, while a fast walk can shake a phone as hard as a slow run.
RUN_MIN_CADENCE_HZ = 140.0 / 60.0
#: The run-cadence threshold (steps/s) that predict uses when the caller gives none (``run_min_cadence_hz=None``
#: in :func:`predict_recording`, :func:`gaitml.models.predict_step_windows`, :func:`gaitml.chunked_run.long_predict`
#: and the PDR built on them): :data:`RUN_MIN_CADENCE_HZ`, the rule on; None turns it off in every path
#: unless a caller asks for it.
RUN_CADENCE_DEFAULT_HZ: float | None = RUN_MIN_CADENCE_HZ
#: A window cadence below this (steps/s) is no evidence of walking for the run-cadence rule: twice it is
#: still a running step frequency (up to :data:`gaitml.steps.adaptive.MAX_STEP_HZ`, 3.5 steps/s, the
#: fastest step the detector looks for), so it may be the stride of a run whose steps came in pairs (a
#: phone in a pocket sees one leg, and the detector's stride-versus-step decision can miss). Half of
#: :data:`gaitml.steps.adaptive.MAX_STEP_HZ`.
RUN_STRIDE_CADENCE_HZ = 3.5 / 2
#: The steps whose peak lies within this many seconds before the window's start or after its end
#: count toward its local cadence (:func:`window_step_cadence`): a window falling between two steps
#: of a slow walk still finds them.
RUN_CADENCE_REACH_S = 0.5
#: The ``out_of_domain_reason`` of a window the model's own domain check flags (:mod:`gaitml.models.domain`);
#: a window the foot-placement rule flags gets :data:`gaitml.models._placement.FOOT_REASON`.
DOMAIN_REASON = "unlike the training data"


def still_statistic(recording: Recording, windows: pd.DataFrame, rule: str = STILL_RULE, recorded: Recording | None = None) -> np.ndarray:
    """The still gate's statistic of each window (``start``, ``end`` samples of ``recording``), m/s^2.

    ``rule`` ``"std_lp"``: the window's three acceleration axes low-passed at :data:`STILL_LOWPASS_HZ`
    (:data:`STILL_LOWPASS_ORDER`-th order Butterworth, zero phase, over the window's own samples;
    no filter when the recording's Nyquist frequency is not above the cut-off), then the standard
    deviation of |acc| (sqrt(acc_x^2 + acc_y^2 + acc_z^2); population form, divided by the number of
    samples); ``"std"``: the standard deviation of the unfiltered |acc|; ``"range"``: its max - min.
    An empty window gives 0. Only the window's own samples are read, so a recording cut into chunks
    gives every window the same value.

    ``recorded``: the recording as it was made, when ``recording`` is it resampled (to a model's rate,
    :func:`gaitml.models.resample_recording`). Rule ``"std_lp"`` then reads each window's span of time
    in ``recorded``'s own samples (the window's start time, and its length in samples scaled to
    ``recorded``'s rate), so that the up-sampling's interpolation, which smooths |acc| further, does
    not lower the statistic of a recording made at a lower rate. The other rules read ``recording``.
    """
    if rule not in STILL_RULES:
        raise InputError(f"unknown still rule {rule!r}; choose one of {', '.join(STILL_RULES)}.")
    n = len(windows)
    out = np.zeros(n)
    if n == 0:
        return out
    if rule == "std_lp" and recorded is not None and recorded is not recording:
        windows = _windows_as_recorded(recording, windows, recorded)
        recording = recorded
    acc = np.asarray(recording.acc, dtype=float)
    mag = np.sqrt(np.sum(np.square(acc), axis=1))
    start = windows["start"].to_numpy(dtype=np.int64)
    end = np.minimum(windows["end"].to_numpy(dtype=np.int64), len(mag))
    lengths = end - start
    if rule == "std_lp":
        sos = _still_lowpass(recording.sampling_rate_hz)
        if lengths.size and (lengths == lengths[0]).all() and lengths[0] > 0:
            sub = np.lib.stride_tricks.sliding_window_view(acc, int(lengths[0]), axis=0)[start]  # (n, 3, length)
            return _lowpassed_magnitude(sub, sos).std(axis=1)
        for i, (a, b) in enumerate(zip(start, end, strict=True)):
            if b > a:
                out[i] = float(_lowpassed_magnitude(acc[a:b].T[None], sos).std())
        return out
    if (lengths == lengths[0]).all() and lengths[0] > 0:
        sub = np.lib.stride_tricks.sliding_window_view(mag, int(lengths[0]))[start]
        return sub.std(axis=1) if rule == "std" else sub.max(axis=1) - sub.min(axis=1)
    for i, (a, b) in enumerate(zip(start, end, strict=True)):
        if b > a:
            out[i] = float(np.std(mag[a:b])) if rule == "std" else float(np.ptp(mag[a:b]))
    return out


def _windows_as_recorded(recording: Recording, windows: pd.DataFrame, recorded: Recording) -> pd.DataFrame:
    """``windows`` (samples of ``recording``) as the same spans of time in samples of ``recorded``."""
    start = windows["start"].to_numpy(dtype=np.int64)
    end = windows["end"].to_numpy(dtype=np.int64)
    scale = recorded.sampling_rate_hz / recording.sampling_rate_hz
    t = np.asarray(recording.t_s, dtype=float)
    t_start = t[np.clip(start, 0, max(len(t) - 1, 0))] if len(t) else np.zeros(len(start))
    t_rec = np.asarray(recorded.t_s, dtype=float)
    a = np.searchsorted(t_rec, t_start - 0.5 / recorded.sampling_rate_hz)
    b = a + np.rint((end - start) * scale).astype(np.int64)
    return pd.DataFrame({"start": a, "end": np.minimum(b, len(t_rec))})


def _still_lowpass(sampling_rate_hz: float):
    """The ``"std_lp"`` rule's low-pass as second-order sections, or None when the rate's Nyquist frequency is not above the cut-off."""
    import scipy.signal

    if sampling_rate_hz / 2.0 <= STILL_LOWPASS_HZ:
        return None
    return scipy.signal.butter(STILL_LOWPASS_ORDER, STILL_LOWPASS_HZ, btype="lowpass", fs=sampling_rate_hz, output="sos")


def _lowpassed_magnitude(sub: np.ndarray, sos) -> np.ndarray:
    """|acc| of windows ``sub`` (shape (n, 3, length)) after the low-pass ``sos`` along each window (None: unfiltered)."""
    import scipy.signal

    if sos is not None:
        length = sub.shape[-1]
        pad = min(3 * (2 * len(sos) + 1), length - 1)
        if length > 1:
            sub = scipy.signal.sosfiltfilt(sos, sub, axis=-1, padtype="odd", padlen=pad)
    return np.sqrt(np.sum(np.square(sub), axis=1))


def still_windows(
    recording: Recording,
    windows: pd.DataFrame,
    rule: str = STILL_RULE,
    threshold_ms2: float | None = None,
    recorded: Recording | None = None,
) -> np.ndarray:
    """Whether each window (``start``, ``end`` samples of ``recording``) holds no gait.

    True where :func:`still_statistic` of ``rule`` is below ``threshold_ms2`` (None: the rule's
    default, :data:`STILL_STD_LP_MS2` for ``"std_lp"``, :data:`STILL_STD_MS2` for ``"std"``,
    :data:`STILL_RANGE_MS2` for ``"range"``).
    ``recorded``: the recording as it was made, when ``recording`` is it resampled (see :func:`still_statistic`).
    """
    return still_statistic(recording, windows, rule, recorded) < _still_threshold(rule, threshold_ms2)


def _still_threshold(rule: str, threshold_ms2) -> float:
    """The gate's threshold (m/s^2): the rule's default for None, else a finite number >= 0 (0 turns the gate off)."""
    if rule not in STILL_RULES:
        raise InputError(f"unknown still rule {rule!r}; choose one of {', '.join(STILL_RULES)}.")
    if threshold_ms2 is None:
        return STILL_THRESHOLDS_MS2[rule]
    try:
        thr = float(threshold_ms2)
    except (TypeError, ValueError):
        thr = float("nan")
    if not np.isfinite(thr) or thr < 0:
        raise InputError(f"still gate threshold {threshold_ms2!r} m/s^2 is not a finite number >= 0; give one (0 turns the gate off).")
    return thr


def describe_still_gate(rule: str = STILL_RULE, threshold_ms2: float | None = None, step_veto: int | None = None) -> str:
    """The still gate in words, for messages: e.g. ``"the standard deviation of |acc| is under 0.41 m/s^2"``, and with
    the step veto (``step_veto``: None the default, :func:`still_step_veto_threshold`) ``"... and fewer than 2 steps are
    detected in it"``."""
    thr = _still_threshold(rule, threshold_ms2)
    what = {
        "std_lp": f"the standard deviation of |acc| (low-passed at {STILL_LOWPASS_HZ:g} Hz) is",
        "std": "the standard deviation of |acc| is",
        "range": "|acc| swings by",
    }[rule]
    veto = still_step_veto_threshold(step_veto)
    return f"{what} under {thr:g} m/s^2" + ("" if veto is None else f" and fewer than {veto} steps are detected in it")


def still_step_veto_threshold(min_steps: int | None = None) -> int | None:
    """The step veto in force (:data:`STILL_STEP_VETO_MIN_STEPS`): the number of detected steps inside a window that keeps
    it from being still, or None when the veto is off.

    None: :data:`STILL_STEP_VETO_DEFAULT`; 0: off; else a whole number of steps >= 1; an InputError names the fix.
    """
    if min_steps is None:
        return STILL_STEP_VETO_DEFAULT
    if isinstance(min_steps, bool):
        min_steps = float("nan")
    try:
        n = float(min_steps)
    except (TypeError, ValueError):
        n = float("nan")
    if not np.isfinite(n) or n < 0 or n != int(n):
        raise InputError(
            f"still-gate step veto {min_steps!r} is not a whole number of steps >= 0; give e.g. {STILL_STEP_VETO_MIN_STEPS} (0 turns the veto off)."
        )
    return int(n) or None


def window_step_counts(windows: pd.DataFrame, steps: pd.DataFrame | None) -> np.ndarray:
    """The number of ``steps`` (a :func:`recording_steps` table of the same recording; None: no steps) whose ``peak`` lies
    inside each window ``[start, end)`` (samples), as int."""
    n = len(windows)
    if steps is None or steps.empty or n == 0:
        return np.zeros(n, dtype=np.int64)
    peak = np.sort(steps["peak"].to_numpy(np.int64))
    return np.searchsorted(peak, windows["end"].to_numpy(np.int64), side="left") - np.searchsorted(
        peak, windows["start"].to_numpy(np.int64), side="left"
    )


def veto_counts(counts, read_still) -> np.ndarray:
    """The ``window_steps`` column: each window's count of the veto's steps (``counts``, :func:`window_step_counts`)
    where the gate's statistic reads it still (``read_still``: the windows the veto decides on), NaN elsewhere."""
    return np.where(np.asarray(read_still, dtype=bool), np.asarray(counts, dtype=float), np.nan)


def _windows_for(recording: Recording, length_s: float, overlap: float) -> pd.DataFrame:
    """All complete windows of the recording (labels not needed, none dropped)."""
    from gaitml.features import make_windows

    w = make_windows(recording, length_s, overlap, min_label_fraction=0.0).reset_index(drop=True)
    return w


def model_view(model, recording: Recording) -> tuple[Recording, dict | None]:
    """``recording`` as ``model`` reads it, and what that changed.

    A model with an accelerometer range (``acc_range_ms2`` in model.json,
    :mod:`gaitml.features._range`) reads every phone through the narrowest range in its
    training data: each acceleration axis clipped to +-``acc_range_ms2``. The view feeds the
    classifier's inputs and the domain check (fitted on the training windows read the same
    way); the fixed physics rules (foot placement, still gate, side direction) read
    ``recording`` itself.

    Returns
    -------
    (Recording, dict or None)
        The view (``recording`` itself without a range) and
        :func:`gaitml.features.acc_range_tally` of ``recording`` (None without a range).
    """
    from gaitml.features import acc_range_tally, clip_acc

    r = getattr(model, "acc_range_ms2", None)
    if r is None:
        return recording, None
    tally = acc_range_tally(recording.acc, r)
    if tally["n_samples_clipped"] == 0:
        return recording, tally
    return recording.replace(acc=clip_acc(recording.acc, r), check_units=False), tally


def model_inputs(model, recording: Recording, windows: pd.DataFrame) -> np.ndarray:
    """The model's input for ``windows`` of ``recording`` (features in saved order, or raw).

    ``recording`` is read as it is: pass :func:`model_view` of it for a model with an accelerometer range.
    """
    from gaitml.models._dataset import raw_windows

    if model.input_kind == "raw":
        length = int(round(model.length_s * model.sampling_rate_hz))
        return raw_windows(recording, windows["start"].to_numpy(), length, model.raw_channels, getattr(model, "frame", "phone"))
    from gaitml.features import extract_features

    feats = extract_features(recording, windows, subset=model.feature_set, frame=getattr(model, "frame", "phone"))
    names = model.feature_names
    missing = [n for n in names if n not in feats.columns]
    if missing:
        raise InputError(f"the feature table lacks {missing[:3]} that the model needs; the feature set changed, retrain the model.")
    return feats[names].to_numpy(dtype=float)


def domain_columns(model, recording: Recording, windows: pd.DataFrame, X: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The out-of-domain check of every window (:mod:`gaitml.models.domain`).

    Parameters
    ----------
    model : TrainedModel
    recording : Recording at the model's rate.
    windows : DataFrame with ``start``, ``end``.
    X : the model's feature matrix of these windows of ``recording``, reused when the domain is on the
        model's own features (feature models; a record with its own accelerometer range recomputes only the
        windows holding a sample it clips, :func:`windows_with_changed_samples`); computed otherwise.

    Returns
    -------
    dict
        ``in_domain`` (object array of True/False, or None for every window when the
        model has no domain record), ``domain_distance`` and ``gravity_angle_deg``
        (float, NaN when not available).
    """
    dom = getattr(model, "domain", None)
    if dom is None or len(windows) == 0:
        return unchecked_domain_columns(dom, len(windows))
    from gaitml.models.domain import feature_gravity, window_gravity

    seen = recording
    recording, clipped = domain_view(dom, recording)  # a record with its own accelerometer range reads the recording through it

    starts = windows["start"].to_numpy(np.int64)
    length = int(round(model.length_s * model.sampling_rate_hz))
    same = (
        X is not None
        and model.input_kind == "features"
        and dom.feature_set == model.feature_set
        and dom.frame == getattr(model, "frame", "phone")
    )
    if not same or clipped:
        from gaitml.features import features_from_arrays

        gyr = recording.gyr if "gyro" in dom.feature_set else None
        if not same:
            X = features_from_arrays(recording.acc, gyr, recording.sampling_rate_hz, starts, length, dom.feature_set, dom.frame)
        else:  # the model's rows read the unclipped recording: only the windows holding a clipped sample read other features
            rows = windows_with_changed_samples(seen.acc, recording.acc, starts, length)
            X = np.array(X, dtype=float)
            if rows.any():
                X[rows] = features_from_arrays(
                    recording.acc, gyr, recording.sampling_rate_hz, starts[rows], length, dom.feature_set, dom.frame
                )
    gravity = None
    if dom.gravity_check:  # phone frame: the features hold the window means of the acceleration (else one pass over the recording)
        gravity = feature_gravity(X, dom.feature_names) if dom.frame == "phone" else None
        if gravity is None:
            gravity = window_gravity(recording.acc, starts, length)
    return checked_domain_columns(dom, X, gravity, recording_dynamics(dom, recording, starts, starts + length))


def windows_with_changed_samples(acc, acc_seen, starts, length: int) -> np.ndarray:
    """Whether each window ``[start, start + length)`` holds a sample whose acceleration differs between ``acc`` and
    ``acc_seen`` (both (n, 3): a recording and its :func:`domain_view`; a NaN sample counts as differing).

    A window's features read its own samples only (:mod:`gaitml.features._catalogue`), so every other window has the
    same features in both: :func:`domain_columns` computes the domain record's features of these windows alone and
    takes the classifier's rows for the rest, instead of a second pass over every window.
    """
    a, b = np.asarray(acc, dtype=float), np.asarray(acc_seen, dtype=float)
    starts = np.asarray(starts, dtype=np.int64)
    if a is b:
        return np.zeros(len(starts), dtype=bool)
    changed = np.concatenate([[0], np.cumsum((a != b).any(axis=1))])
    return changed[np.minimum(starts + int(length), len(a))] > changed[starts]


def domain_view(dom, recording: Recording) -> tuple[Recording, bool]:
    """``recording`` as the domain record ``dom`` reads it, and whether that clipped any sample.

    A record with its own accelerometer range (``dom.acc_range_ms2``, ``[train]
    domain_acc_range_ms2``) was fitted on the training recordings clipped per axis to
    +-that range (:func:`gaitml.features.clip_acc`) and reads every recording the same
    way, while the classifier reads it as it comes; without one, ``recording`` itself.
    """
    from gaitml.features import acc_range_tally, clip_acc

    r = getattr(dom, "acc_range_ms2", None)
    if r is None or acc_range_tally(recording.acc, r)["n_samples_clipped"] == 0:
        return recording, False
    return recording.replace(acc=clip_acc(recording.acc, r), check_units=False), True


def recording_dynamics(dom, recording: Recording, starts, ends) -> np.ndarray | None:
    """:func:`gaitml.models.domain.orientation_dynamics` of the windows the check reads, or None when it reads none.

    ``starts``, ``ends``: all windows of the recording, in time order; the descriptors are
    computed for the windows :meth:`~gaitml.models.domain.DomainModel.dynamics_rows` names
    only (every ``dynamics["every"]``-th: what :meth:`~gaitml.models.domain.DomainModel.check` reads).
    """
    if getattr(dom, "dynamics", None) is None or recording.gyr is None:
        return None
    from gaitml.models.domain import orientation_dynamics

    rows = dom.dynamics_rows(len(starts))
    return orientation_dynamics(recording.acc, recording.gyr, np.asarray(starts)[rows], np.asarray(ends)[rows], recording.sampling_rate_hz)


def unchecked_domain_columns(dom, n: int) -> dict[str, np.ndarray]:
    """The domain columns of ``n`` windows that are not checked: flags None without a domain record, else empty."""
    flags = np.full(n, None, dtype=object) if dom is None else np.zeros(n, dtype=object)
    return {"in_domain": flags, "domain_distance": np.full(n, np.nan), "gravity_angle_deg": np.full(n, np.nan)}


def checked_domain_columns(dom, X: np.ndarray, gravity: np.ndarray | None, dynamics: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """The domain columns from :meth:`gaitml.models.domain.DomainModel.check` of features ``X``, window ``gravity`` and ``dynamics``.

    ``dynamics`` rows are windows of one recording in time order (:func:`recording_dynamics`: the ones the check reads).
    """
    res = dom.check(X, gravity, dynamics)
    out = {
        "in_domain": res["in_domain"].astype(object),
        "domain_distance": res["distance"],
        "gravity_angle_deg": np.degrees(res["gravity_angle_rad"]),
    }
    if getattr(dom, "dynamics", None) is not None:  # the running median the decision used (why a window is flagged)
        out["dynamics_distance"] = res["dynamics_distance"]
    return out


def predict_recording(
    model,
    recording: Recording,
    correction: bool = True,
    *,
    still_rule: str = STILL_RULE,
    still_threshold_ms2: float | None = None,
    run_min_cadence_hz: float | None = None,
    still_step_veto: int | None = None,
    veto_for_step_modes: bool = False,
    found_steps: dict | None = None,
    mark_still_unsure: bool = True,
) -> pd.DataFrame:
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
    still_rule, still_threshold_ms2 : the still gate (:func:`still_windows`): ``"std_lp"`` (the
        default, :data:`STILL_STD_LP_MS2`), ``"std"`` (the gate before it, unfiltered, :data:`STILL_STD_MS2`)
        or ``"range"`` (the earliest gate, :data:`STILL_RANGE_MS2`),
        and its threshold (None: the rule's default).
    still_step_veto : the still gate's step veto (:data:`STILL_STEP_VETO_MIN_STEPS`): a window the gate reads still in
        which the veto's step finder (:func:`veto_steps`) finds at least this many steps is not still; None:
        :data:`STILL_STEP_VETO_DEFAULT` (:func:`still_step_veto_threshold`); 0 turns it off.
    veto_for_step_modes : the table is read only for the modes steps take (``gaitml pdr``): the veto's step finder runs
        only when it can change them (:func:`veto_can_change_step_modes`; see :func:`finish_predictions`).
    run_min_cadence_hz : the run-cadence rule (:func:`run_cadence_rule`): a window read ``run`` whose
        local step cadence is below this (steps/s; :data:`RUN_MIN_CADENCE_HZ` is the walk-to-run
        transition cadence) gets the model's best other mode; None: :data:`RUN_CADENCE_DEFAULT_HZ`
        (:func:`run_cadence_threshold`); 0 turns it off.
    found_steps : a dict that shares the step detector's runs with the caller (:func:`steps_found_once`): the steps the
        veto and the run-cadence rule find on the recording at the model's rate are kept in it, and steps already there
        are read instead of found again (:func:`gaitml.chunked_run.long_predict`'s later pass over a chunk). None: each
        finder's steps are found once within the call.
    mark_still_unsure : add the ``still_unsure`` column (:func:`still_unsure`); False (or ``veto_for_step_modes``): the
        table has no such column and the stride rhythm is not computed (a caller that never reads ``still``).

    Returns
    -------
    DataFrame
        One row per window: ``start``, ``end`` (samples at the model's rate),
        ``t_start_s``, ``t_end_s``, ``mode_raw`` (model output), ``mode`` (after
        the correction, or equal to ``mode_raw``; ``"still"`` for a window with no
        gait in it, :func:`still_windows`, unless the step veto keeps it; the model's best other mode for a window
        read ``run`` at a walking cadence, :func:`run_cadence_rule`), ``still``, ``still_vetoed`` (the gate's
        statistic read the window still and the veto kept its mode), ``still_unsure`` (a window reported ``still`` in which
        the phone turns with a stride rhythm: the gate and the gyroscope disagree, :func:`still_unsure`), ``window_steps`` (in each window the gate's statistic
        reads still, the count of the veto's steps, :func:`veto_steps`, that the veto decided on; NaN in every other
        window, and in every window when the veto is off: :func:`veto_counts`), ``run_at_walking_cadence`` (the rule
        moved the window), ``step_cadence_hz`` (the windows' local step cadence when some window is
        read run, else NaN), ``in_domain`` (True/False from
        the model's domain record, :mod:`gaitml.models.domain`, and the foot-placement
        rule, :func:`foot_placement`; None when the model has no record),
        ``out_of_domain_reason`` (why a window is out of domain; empty in domain; None, as
        ``in_domain``, when the model has no record: nothing was checked),
        ``domain_distance``, ``gravity_angle_deg`` (NaN when not checked), plus ``label`` and ``label_fraction`` when the recording has
        labels. ``attrs`` holds ``sampling_rate_hz``, ``resampled_from_hz`` (or
        None), ``correction``, ``has_domain`` and ``acc_range`` (None for a model without an
        accelerometer range, else :func:`gaitml.features.acc_range_tally` of the recording at the
        model's rate: the range and how many samples it clipped; :func:`model_view`).

    Raises
    ------
    InputError
        The recording is shorter than one window, or lacks a gyroscope the
        feature set needs.
    """
    from gaitml.models._dataset import resample_recording

    rec = resample_recording(recording, model.sampling_rate_hz)
    length = int(round(model.length_s * model.sampling_rate_hz))
    rec.require_samples(length, f"one {model.length_s} s window of the model")
    if "gyro" in model.feature_set:
        rec.require_gyr(
            f"the model's feature set {model.feature_set!r}",
            "the accelerometer-only model models/demo-acc (feature set 'all52')",
        )
    w = _windows_for(rec, model.length_s, model.overlap)
    seen, tally = model_view(model, rec)  # the classifier and the domain record read the accelerometer through the model's range
    X = model_inputs(model, seen, w)
    out = w[["start", "end", "t_start_s", "t_end_s"]].copy()
    out["mode_raw"], out["mode"] = predicted_modes(model, X, correction)
    # ---- out-of-domain check (gaitml.models.domain)
    domain = domain_columns(model, seen, w, X if model.input_kind == "features" else None)
    return finish_predictions(
        out,
        w,
        domain,
        model,
        recording,
        rec,
        correction,
        still_rule=still_rule,
        still_threshold_ms2=still_threshold_ms2,
        still_step_veto=still_step_veto,
        veto_for_step_modes=veto_for_step_modes,
        found_steps=found_steps,
        mark_still_unsure=mark_still_unsure,
        X=X,
        run_min_cadence_hz=run_min_cadence_hz,
        has_domain=getattr(model, "domain", None) is not None,
        acc_range=tally,
    )


def predicted_modes(model, X: np.ndarray, correction: bool) -> tuple[np.ndarray, np.ndarray]:
    """The model's mode of every row of ``X`` as str, raw and (with ``correction``) after the adjacent-window correction."""
    from gaitml.postprocess import adjacent_window_correction

    pred = np.asarray(model.estimator.predict(X)).astype(str)
    return pred, (np.asarray(adjacent_window_correction(pred)).astype(str) if correction else pred)


def side_direction_unsure(recording: Recording, windows: pd.DataFrame, modes, max_deg: float = FACE_UP_MAX_DEG) -> np.ndarray:
    """Whether each window is a side step whose direction is unsure (see :data:`FACE_UP_MAX_DEG`).

    True where ``modes`` is ``side_left`` or ``side_right`` and the window's gravity direction
    (the unit mean of its acceleration) is more than ``max_deg`` from the phone's +z axis.
    """
    modes = np.asarray(modes).astype(str)
    n = len(windows)
    out = np.zeros(n, dtype=bool)
    side = np.isin(modes, SIDE_MODES)
    if n == 0 or not side.any():
        return out
    acc = np.asarray(recording.acc, dtype=float)
    start = windows["start"].to_numpy(dtype=np.int64)
    end = np.minimum(windows["end"].to_numpy(dtype=np.int64), len(acc))
    cum = np.vstack([np.zeros((1, 3)), np.cumsum(acc, axis=0)])
    total = cum[end] - cum[start]
    norm = np.linalg.norm(total, axis=1)
    cos_z = np.divide(total[:, 2], norm, out=np.zeros(n), where=norm > 0)
    return side & (cos_z < np.cos(np.radians(float(max_deg))))


def stride_rhythm(recording: Recording, windows: pd.DataFrame, pad_s: float = STILL_UNSURE_PAD_S) -> np.ndarray:
    """Per window (``start``, ``end`` samples of ``recording``): does the phone turn with a stride rhythm around it?

    The body that carries the phone (trunk, head, the arm that holds it to the ear) rotates once per stride and
    reverses between the left and the right step (Perry & Burnfield, *Gait Analysis*, 2nd ed. 2010, ch. 10; the
    physics of :mod:`gaitml.steps.adaptive`'s stages 2b and 2c); a standing body's sway has no stride period and
    reverses at no half-stride. The test uses ``adaptive``'s own constants (none fitted here): over the
    :data:`~gaitml.steps.adaptive.WINDOW_S` (5 s) centred on the window (moved inside the recording at its ends), the
    angular rate, mean removed and band-passed to :data:`~gaitml.steps.adaptive.GYRO_BAND_HZ` (order 2, zero phase,
    over the 5 s and ``pad_s`` more on each side), taken at the rate ``adaptive`` decimates to
    (:func:`~gaitml.steps.adaptive.cadence_decimation`) and projected on its principal axis, has an RMS of at least
    :data:`~gaitml.steps.adaptive.GYRO_MIN_RMS_RADS`; its stride period P (:func:`~gaitml.steps.adaptive.swing_stride`:
    the shortest autocorrelation peak near the strongest over two steps of the human range) correlates at least
    :data:`~gaitml.steps.adaptive.MIN_PERIODICITY`, P / 2 is a step of the human range
    (:data:`~gaitml.steps.adaptive.MIN_STEP_HZ`-:data:`~gaitml.steps.adaptive.MAX_STEP_HZ`), and the rate is in
    anti-phase at P / 2 (correlation at most -:data:`~gaitml.steps.adaptive.GYRO_SWING_HALF_CORRELATION`).

    All False without a gyroscope and for a recording shorter than 5 s. Windows are read in batches (bounded memory).
    A ``pad_s`` that is not a finite number >= 0 is refused (:class:`~gaitml.errors.InputError`).
    """
    from gaitml.signal import bandpass
    from gaitml.steps import adaptive as ad

    try:
        pad_ok = math.isfinite(float(pad_s)) and float(pad_s) >= 0.0
    except (TypeError, ValueError):
        pad_ok = False
    if not pad_ok:
        raise InputError(
            f"stride_rhythm: pad_s={pad_s!r} is not a finite number of seconds >= 0; give e.g. {STILL_UNSURE_PAD_S:g} (the default)."
        )
    n = len(windows)
    out = np.zeros(n, dtype=bool)
    if recording.gyr is None or n == 0:
        return out
    fs = float(recording.sampling_rate_hz)
    g = np.asarray(recording.gyr, dtype=float)
    q = ad.cadence_decimation(fs)
    L = int(round(ad.WINDOW_S * fs / q))  # decimated samples of the 5 s
    span = L * q  # the 5 s in samples
    if len(g) < span:
        return out
    pad = int(round(float(pad_s) * fs))
    hi_hz = min(ad.GYRO_BAND_HZ[1], 0.45 * fs)
    # the 5 s, [a, a + span), centred on the window (half a sample early where the centre falls between samples): in
    # integers, so that a part of the recording (a chunk) starting at any sample reads the same samples (round-half-even
    # of a half-integer centre depends on where the part starts)
    se = windows["start"].to_numpy(np.int64) + windows["end"].to_numpy(np.int64)
    a = np.clip((se - span) // 2, 0, len(g) - span)
    lo = np.maximum(a - pad, 0)
    hi = np.minimum(a + span + pad, len(g))
    proj = np.zeros((n, L))
    # pieces of one length are filtered together (all but the ones clipped at the recording's ends), in batches
    for length in np.unique(hi - lo):
        idx = np.flatnonzero(hi - lo == length)
        for b in range(0, len(idx), 256):
            sel = idx[b : b + 256]
            seg = g[lo[sel][None, :] + np.arange(length)[:, None]]  # (length, k, 3)
            seg = bandpass(seg - seg.mean(axis=0, keepdims=True), ad.GYRO_BAND_HZ[0], hi_hz, fs, order=2)
            take = (a[sel] - lo[sel])[None, :] + np.arange(0, span, q)[:, None]  # (L, k): the 5 s, decimated
            five = np.take_along_axis(seg, take[:, :, None], axis=0).transpose(1, 0, 2)  # (k, L, 3)
            five = five - five.mean(axis=1, keepdims=True)
            axis = np.linalg.eigh(np.einsum("klc,kld->kcd", five, five))[1][:, :, -1]
            proj[sel] = np.einsum("klc,kc->kl", five, axis)
    rms = np.sqrt(np.mean(proj**2, axis=1))
    return ad.swing_rhythm(proj, rms, fs / q)[0]


def still_unsure(recording: Recording, windows: pd.DataFrame, still) -> np.ndarray:
    """The ``still_unsure`` column (:data:`STILL_UNSURE_DEFAULT`): windows reported ``still`` (``still``: bool per window,
    after the step veto) in which the phone turns with a stride rhythm (:func:`stride_rhythm`); all False when the mark
    is off or without a gyroscope. Only the still windows are read."""
    still = np.asarray(still, dtype=bool)
    out = np.zeros(len(still), dtype=bool)
    if not STILL_UNSURE_DEFAULT or recording.gyr is None or not still.any():
        return out
    idx = np.flatnonzero(still)
    out[idx] = stride_rhythm(recording, windows.iloc[idx])
    return out


def recording_steps(recording: Recording, swing_periodicity: float = 0.0) -> pd.DataFrame:
    """The steps of the default detector (:class:`gaitml.steps.adaptive.AdaptiveStepDetector` at its defaults, gait
    check on; with ``swing_periodicity`` > 0 and a gyroscope, its swing stage 2c at that value) over the whole of
    ``recording``: its ``steps_`` table (``peak`` in samples, ``cadence_hz``, ...), empty for a recording too short for
    the detector. The run-cadence rule (:func:`window_step_cadence`) reads these at the defaults, the still gate's step
    veto :func:`veto_steps`; each found once per recording (one run when they are the same, :func:`veto_reads_own_steps`;
    :func:`steps_found_once`)."""
    from gaitml.steps import get_detector

    swing = float(swing_periodicity)
    kw = {"gyro_swing_min_periodicity": swing} if swing > 0 and recording.has_gyr else {}
    try:
        return get_detector("adaptive", **kw).detect(recording).steps_
    except InputError:  # shorter than the detector's cadence window: no steps
        return pd.DataFrame({"start": [], "peak": [], "end": [], "cadence_hz": []}).astype(
            {"start": np.int64, "peak": np.int64, "end": np.int64, "cadence_hz": float}
        )


def veto_reads_own_steps(recording: Recording) -> bool:
    """Whether the still gate's step veto reads other steps than the run-cadence rule on ``recording``: the swing stage
    (:data:`STILL_STEP_SWING_PERIODICITY`) is on and the recording has a gyroscope for it."""
    return float(STILL_STEP_SWING_PERIODICITY) > 0 and recording.has_gyr


def veto_steps(recording: Recording) -> pd.DataFrame:
    """The steps the still gate's step veto reads (:data:`STILL_STEP_VETO_MIN_STEPS`): :func:`recording_steps` with the
    swing stage at :data:`STILL_STEP_SWING_PERIODICITY`."""
    return recording_steps(recording, STILL_STEP_SWING_PERIODICITY)


def steps_found_once(found: dict, recording: Recording, *, veto: bool) -> pd.DataFrame:
    """The still gate's veto's steps (``veto``: :func:`veto_steps`) or the run-cadence rule's (:func:`recording_steps` at
    ``adaptive``'s defaults) of ``recording``, each found once: read from ``found`` (a dict the caller keeps while it
    reads one recording) when the same steps of the same recording object are already there, else found and kept there.

    Without a gyroscope for the veto's swing stage (:func:`veto_reads_own_steps` False) the two are the same steps, kept
    under one key: the run-cadence rule reads the veto's and the other way round. :func:`predict_recording` (its
    ``found_steps``) and :func:`gaitml.chunked_run.long_predict` (a resampled file's chunk, whose veto counts come after
    its prediction) share one such dict.
    """
    key = "veto" if veto and veto_reads_own_steps(recording) else "defaults"
    hit = found.get(key)
    if hit is not None and hit[0] is recording:
        return hit[1]
    steps = veto_steps(recording) if veto else recording_steps(recording)
    found[key] = (recording, steps)
    return steps


def veto_can_change_step_modes(still, modes, modes_raw) -> bool:
    """Whether the still gate's step veto can change what a reader of the table's modes per step takes
    (:func:`gaitml.pdr.step_modes.modes_from_windows` and the PDR's side-step check,
    :func:`gaitml.pdr.pipeline.run_pdr`).

    ``still``: the windows the gate's statistic reads still (before the veto); ``modes``: every window's mode after the
    adjacent-window correction, before the gate; ``modes_raw``: the model's answers. A step whose window stays still
    takes the model's raw answer, and the window is never marked ``side_direction_unsure`` (its mode is ``still``); a
    vetoed window keeps its corrected mode, which the run-cadence rule then reads (it moves only a window read
    :data:`RUN_MODE`) and the side-direction check (only a side step, :data:`SIDE_MODES`). So the veto changes
    nothing such a reader takes unless some still-read window's corrected mode differs from its raw answer, or that
    answer is run or a side step: then True.
    """
    still = np.asarray(still, dtype=bool)
    modes = np.asarray(modes).astype(str)[still]
    raw = np.asarray(modes_raw).astype(str)[still]
    return bool(((modes != raw) | (raw == RUN_MODE) | np.isin(raw, SIDE_MODES)).any())


def window_step_cadence(
    recording: Recording,
    windows: pd.DataFrame,
    reach_s: float = RUN_CADENCE_REACH_S,
    steps: pd.DataFrame | None = None,
    *,
    reduce=np.max,
) -> np.ndarray:
    """The local step cadence (steps/s) of each window (``start``, ``end`` samples of ``recording``).

    The steps are :class:`gaitml.steps.adaptive.AdaptiveStepDetector`'s at its defaults, found once
    over the whole recording (its cadence comes from 5 s autocorrelation windows and decides between a
    step and a stride with the half-period and gyroscope checks); a window's cadence is the highest
    ``cadence_hz`` of the steps whose peak lies in the window or within ``reach_s`` seconds of it, so
    a window reads as walking only when every step near it does (a window at the start of a run,
    whose first steps' 5 s cadence windows still hold the walk before it, keeps the run's cadence
    of its later steps). NaN for a window with no step there, and for every window of a recording
    too short for the detector. ``steps``: the recording's :func:`recording_steps` when already found (None: found here).
    ``reduce``: how the cadences of a window's steps combine (the highest, the rule's; e.g. ``np.min`` for the lowest).
    """
    n = len(windows)
    out = np.full(n, np.nan)
    if n == 0:
        return out
    if steps is None:
        steps = recording_steps(recording)
    if steps.empty:
        return out
    order = np.argsort(steps["peak"].to_numpy(np.int64), kind="stable")
    peak = steps["peak"].to_numpy(np.int64)[order]
    cad = steps["cadence_hz"].to_numpy(float)[order]
    reach = int(round(float(reach_s) * recording.sampling_rate_hz))
    lo = np.searchsorted(peak, windows["start"].to_numpy(np.int64) - reach, side="left")
    hi = np.searchsorted(peak, windows["end"].to_numpy(np.int64) + reach, side="left")
    for i in np.flatnonzero(hi > lo):
        out[i] = float(reduce(cad[lo[i] : hi[i]]))
    return out


def best_other_modes(model, X, exclude: str = RUN_MODE) -> np.ndarray:
    """The model's best mode other than ``exclude`` for every row of ``X`` (str).

    Read from the estimator's class scores: ``decision_function`` (the linear OVO SVM: the one-vs-one
    votes plus the squashed confidence sums whose argmax is its answer, :mod:`gaitml.models._svm`), else
    ``predict_proba``; the class ``exclude`` is left out of the argmax. A model without ``exclude`` among
    its classes gives its own answer.
    """
    est = model.estimator
    classes = np.asarray(est.classes_).astype(str)
    if len(classes) < 2:
        return np.full(len(X), classes[0] if len(classes) else "", dtype=object).astype(str)
    if hasattr(est, "decision_function"):
        scores = np.asarray(est.decision_function(X), dtype=float)
        if scores.ndim == 1:  # two classes: positive means classes_[1]
            scores = np.column_stack([-scores, scores])
    else:
        scores = np.asarray(est.predict_proba(X), dtype=float)
    scores = scores.copy()
    scores[:, classes == str(exclude)] = -np.inf
    return classes[np.argmax(scores, axis=1)]


def run_cadence_rule(
    modes,
    modes_raw,
    cadence_hz,
    other_modes,
    min_cadence_hz: float | None = RUN_MIN_CADENCE_HZ,
    stride_cadence_hz: float = RUN_STRIDE_CADENCE_HZ,
):
    """The run-cadence rule: a window answered :data:`RUN_MODE` at a walking cadence gets another mode.

    A window whose mode (after the correction) is ``run`` and whose local step cadence
    (:func:`window_step_cadence`) is below ``min_cadence_hz`` (:data:`RUN_MIN_CADENCE_HZ`: people run
    above the walk-to-run transition cadence, not below it) and at least ``stride_cadence_hz``
    (:data:`RUN_STRIDE_CADENCE_HZ`: a lower cadence may be a run's stride) is answered with the model's
    best mode other than run: its raw answer when that is not run (the correction made it run), else
    ``other_modes`` (:func:`best_other_modes`). A window without a cadence (NaN: no step found near it)
    keeps its mode. ``min_cadence_hz`` None or 0 turns the rule off.

    Returns
    -------
    (ndarray of str, ndarray of bool)
        The modes and which windows the rule moved.
    """
    modes = np.asarray(modes).astype(str)
    moved = np.zeros(len(modes), dtype=bool)
    if not min_cadence_hz or len(modes) == 0:
        return modes, moved
    cad = np.asarray(cadence_hz, dtype=float)
    with np.errstate(invalid="ignore"):
        moved = (modes == RUN_MODE) & (cad < float(min_cadence_hz)) & (cad >= float(stride_cadence_hz))
    if not moved.any():
        return modes, moved
    raw = np.asarray(modes_raw).astype(str)
    other = np.asarray(other_modes).astype(object)
    out = modes.astype(object)
    out[moved] = np.where(raw[moved] != RUN_MODE, raw[moved].astype(object), other[moved])
    return out.astype(str), moved


def run_cadence_threshold(min_cadence_hz: float | None = None) -> float | None:
    """The run-cadence rule's threshold in force (steps/s), or None when the rule is off.

    None: :data:`RUN_CADENCE_DEFAULT_HZ`; 0: off; else steps/s above :data:`RUN_STRIDE_CADENCE_HZ` (below it
    the rule could move nothing) and at most :data:`gaitml.steps.adaptive.MAX_STEP_HZ` (a number beyond it is
    most likely steps/min); an InputError names the fix.
    """
    if min_cadence_hz is None:
        min_cadence_hz = RUN_CADENCE_DEFAULT_HZ
        if min_cadence_hz is None:
            return None
    try:
        thr = float(min_cadence_hz)
    except (TypeError, ValueError):
        thr = float("nan")
    if not np.isfinite(thr) or thr < 0:
        raise InputError(f"run cadence threshold {min_cadence_hz!r} steps/s is not a finite number >= 0; give one (0 turns the rule off).")
    if thr == 0:
        return None
    from gaitml.steps.adaptive import MAX_STEP_HZ

    if not RUN_STRIDE_CADENCE_HZ < thr <= MAX_STEP_HZ:
        raise InputError(
            f"run cadence threshold {min_cadence_hz!r} is not in steps/s between {RUN_STRIDE_CADENCE_HZ:g} and {MAX_STEP_HZ:g}; "
            f"give steps/s, e.g. {RUN_MIN_CADENCE_HZ:.3g} (= {60 * RUN_MIN_CADENCE_HZ:.0f} steps/min), or 0 to turn the rule off."
        )
    return thr


def foot_rule_applies(model) -> bool:
    """Whether the foot-placement rule is checked for ``model``: it has a domain record and no training position on a foot (a name starting ``foot``)."""
    dom = getattr(model, "domain", None)
    return dom is not None and not any(str(p).lower().startswith("foot") for p in dom.positions)


def foot_placement(model, recording: Recording, windows: pd.DataFrame) -> np.ndarray | None:
    """Which windows rest between fast swings as a foot-mounted sensor does (:func:`gaitml.models._placement.foot_like_windows`), or None when not checked.

    Checked for a model with a domain record none of whose training positions is on a foot
    (a position name starting ``foot``); read with the recording's gyroscope when it has one,
    else with the accelerometer-only rule.
    """
    if not foot_rule_applies(model):
        return None
    from gaitml.models._placement import foot_like_windows

    return foot_like_windows(recording.acc, recording.gyr, recording.sampling_rate_hz, windows)["foot_like"]


def window_placement_reason(model, acc, gyr=None, sampling_rate_hz: float | None = None) -> str | None:
    """The foot-placement rule of one window (a stream's window): its ``out_of_domain_reason`` from the rule.

    ``acc`` (and ``gyr``, None without a gyroscope) are the window's own samples, shape (length, 3) in
    m/s^2 and rad/s, at the model's rate: the samples a streaming loop (e.g. over
    :class:`gaitml.features.StreamingFeatureExtractor`) classifies. The rule reads a window's own
    samples only (:mod:`gaitml.models._placement`), so calling this on every window of a stream gives
    the windows :func:`predict_recording` flags on the whole recording.
    ``sampling_rate_hz`` (None: the model's) is the samples' rate; a rate other than the model's is
    refused (the rule's durations count samples at the model's rate: resample first).

    Raises
    ------
    InputError
        Arrays not of shape (length, 3), non-finite samples, a window shorter than the rule can
        flag (:func:`gaitml.models._placement.min_window_samples`), or a rate other than the model's.

    Returns
    -------
    str or None
        :data:`gaitml.models._placement.FOOT_REASON` when the window rests between fast swings (a foot-mounted sensor, or a gesturing hand)
        (the window is then out of domain, whatever the domain record says), ``""`` when it does not,
        None when the rule is not checked for this model (as :func:`foot_placement`: no domain record,
        or a foot position in training).
    """
    from gaitml.errors import InputError
    from gaitml.models._placement import FOOT_REASON, foot_like_windows, min_window_samples

    fs = float(model.sampling_rate_hz)
    if sampling_rate_hz is not None:
        try:
            rate = float(sampling_rate_hz)
        except (TypeError, ValueError):
            rate = float("nan")
        if not np.isfinite(rate) or abs(rate - fs) > 1e-6 * fs:
            raise InputError(
                f"the window's samples are at {sampling_rate_hz!r} Hz, the model's rate is {fs:g} Hz; resample the stream to {fs:g} Hz first."
            )
    if not foot_rule_applies(model):
        return None
    a = np.asarray(acc, dtype=float)
    g = None if gyr is None else np.asarray(gyr, dtype=float)
    if a.ndim != 2 or a.shape[1] != 3 or (g is not None and g.shape != a.shape):
        shapes = f"acc {a.shape}" + ("" if g is None else f", gyr {g.shape}")
        raise InputError(f"one window's samples must be (length, 3) arrays of the same length, got {shapes}; pass acc[s:s+length].")
    need = min_window_samples(fs)
    if len(a) < need:
        raise InputError(
            f"one window of {len(a)} samples is too short for the foot-placement rule (at least {need} at {fs:g} Hz); pass a whole window acc[s:s+length]."
        )
    if not np.isfinite(a).all() or (g is not None and not np.isfinite(g).all()):
        which = "acc" if not np.isfinite(a).all() else "gyr"
        raise InputError(f"the window's {which} samples hold NaN or infinite values; fill or drop the gap before calling the rule.")
    win = pd.DataFrame({"start": [0], "end": [len(a)]})
    return FOOT_REASON if bool(foot_like_windows(a, g, fs, win)["foot_like"][0]) else ""


def rate_reason(model, recorded_hz: float | None) -> str | None:
    """The rate check of a recording made at ``recorded_hz`` (Hz): the ``out_of_domain_reason`` of every one of its windows.

    A model whose domain record holds the lowest sampling rate it was trained at (``min_rate_hz``,
    :class:`gaitml.models.domain.DomainModel`) answers a recording made below
    :data:`gaitml.models.domain.RATE_TOLERANCE` times that rate with a reason like ``"rate: recorded at
    12 Hz, below the 20 Hz the model was trained at"``: every window is out of domain, whatever its
    features. ``""``: the rate is within the domain. None: not checked (no domain record, or a record
    written before the rate was kept). A streaming loop, which resamples its samples to the model's
    rate before :class:`gaitml.features.StreamingFeatureExtractor`, calls it once with the rate its
    phone records at (:meth:`~gaitml.features.StreamingFeatureExtractor.for_model` with
    ``recorded_hz`` keeps it as ``rate_reason_``).
    """
    from gaitml.models.domain import domain_rate_reason

    return domain_rate_reason(getattr(model, "domain", None), recorded_hz)


def rate_check(model, recorded_hz: float | None) -> dict | None:
    """What a prediction table's ``attrs['rate_check']`` says: ``recorded_hz``, ``trained_min_hz``, ``tolerance``, ``below``; None when not checked."""
    from gaitml.models.domain import RATE_TOLERANCE

    reason = rate_reason(model, recorded_hz)
    if reason is None:
        return None
    return {
        "recorded_hz": float(recorded_hz),
        "trained_min_hz": float(model.domain.min_rate_hz),
        "tolerance": RATE_TOLERANCE,
        "below": bool(reason),
    }


def apply_rate_check(out: pd.DataFrame, model, recorded_hz: float | None, rate_changes=None) -> pd.DataFrame:
    """Mark every window of ``out`` out of domain with :func:`rate_reason` when the recording was made below the model's rates; ``attrs['rate_check']``.

    ``rate_changes``: the reader's ``meta['rate_changes']`` (``[[t_start_s, t_end_s, rate_hz], ...]``, s
    from the recording's first sample): the windows that overlap a stretch recorded below the model's
    rates are out of domain with that stretch's reason, whatever the file's own rate.
    """
    reason = rate_reason(model, recorded_hz)
    if reason and len(out):
        out["in_domain"] = np.full(len(out), False, dtype=object)
        out["out_of_domain_reason"] = np.full(len(out), reason, dtype=object)
    elif reason == "" and len(out) and rate_changes and {"t_start_s", "t_end_s"} <= set(out.columns):
        # a checked rate ("") means a domain record, so the domain columns are there
        t0, t1 = out["t_start_s"].to_numpy(float), out["t_end_s"].to_numpy(float)
        flags = out["in_domain"].to_numpy(dtype=object).copy()
        reasons = out["out_of_domain_reason"].to_numpy(dtype=object).copy()
        for a, b, hz in rate_changes:
            why = rate_reason(model, float(hz))
            hit = (t1 > float(a)) & (t0 < float(b))
            if why and hit.any():
                flags[hit], reasons[hit] = False, why
        out["in_domain"], out["out_of_domain_reason"] = flags, reasons
    out.attrs["rate_check"] = rate_check(model, recorded_hz)
    return out


def finish_predictions(
    out: pd.DataFrame,
    windows: pd.DataFrame,
    domain: dict,
    model,
    recording: Recording,
    rec: Recording,
    correction: bool,
    *,
    still_rule: str = STILL_RULE,
    still_threshold_ms2: float | None = None,
    X: np.ndarray | None = None,
    run_min_cadence_hz: float | None = None,
    still_step_veto: int | None = None,
    veto_for_step_modes: bool = False,
    found_steps: dict | None = None,
    mark_still_unsure: bool = True,
    **attrs,
) -> pd.DataFrame:
    """The common end of a prediction table: the out-of-domain columns, the still gate, the windows' labels, the ``attrs``.

    A window that rests between fast swings as a foot-mounted sensor does (:func:`foot_placement`) is out of domain
    (``in_domain`` False); ``out_of_domain_reason`` says why a window is out of domain
    (:data:`gaitml.models._placement.FOOT_REASON` or :data:`DOMAIN_REASON`; empty in domain; None where ``in_domain``
    is None, a model without a domain record, whose windows are not checked).

    A window with no gait in it (:func:`still_windows` with ``still_rule``, ``still_threshold_ms2``) gets the mode :data:`STILL`
    and ``still = True``; ``mode_raw`` keeps the model's answer; unless the step veto (``still_step_veto``,
    :func:`still_step_veto_threshold`) finds at least that many of the veto's steps inside it
    (:func:`veto_steps` of ``rec``: ``adaptive`` with its swing stage where there is a gyroscope, found once, only when
    some window reads still; shared with the run-cadence rule when they are the same steps, :func:`veto_reads_own_steps`):
    then it keeps its mode, ``still_vetoed = True``. A window left ``still`` in which the phone turns with a stride
    rhythm (:func:`still_unsure`, :data:`STILL_UNSURE_DEFAULT`) is marked ``still_unsure = True``: it keeps the mode
    ``still``, and the table says the evidence disagrees there. ``window_steps`` holds, in each window the statistic reads still,
    the count of the veto's steps the veto decided on (:func:`veto_counts`), NaN in every other window and whenever the
    veto is off (a whole file and its chunks give the same column). A window then answered ``run`` whose
    local step cadence is below ``run_min_cadence_hz`` (:func:`run_cadence_threshold`; 0: off) gets
    the model's best other mode (:func:`run_cadence_rule`, the best mode read from ``X``, the model's
    inputs of ``windows``; None: the rule is not applied; ``run_min_cadence_hz`` None:
    :data:`RUN_CADENCE_DEFAULT_HZ`) and ``run_at_walking_cadence = True``;
    ``step_cadence_hz`` holds every window's local cadence (:func:`window_step_cadence`) when some
    window of the recording is read run (raw or corrected), NaN otherwise. (A cadence under
    :data:`RUN_STRIDE_CADENCE_HZ` may be a run's stride and moves nothing.) ``side_direction_unsure``
    marks side steps read from an upright phone (:func:`side_direction_unsure`).

    ``rec`` is ``recording`` at the model's rate (``recording`` itself when no resampling was needed).
    A recording made below the lowest rate the model was trained at (:func:`rate_reason` of ``recording``'s
    own rate) has every window out of domain with that reason.

    ``attrs`` gets ``sampling_rate_hz`` (the model's), ``resampled_from_hz`` (``recording``'s rate,
    or None), ``correction``, ``still_gate`` (``statistic``, ``threshold_ms2``, ``step_veto_min_steps``: None when the
    veto is off), ``run_cadence``
    (``min_cadence_hz``: None when the rule is off), ``rate_check`` (:func:`rate_check`) and then the
    caller's own ``attrs``.

    ``veto_for_step_modes``: the caller reads the table only for the modes its steps take (``gaitml pdr``): the veto's
    step finder then runs only when the veto can change them (:func:`veto_can_change_step_modes`); when it does not
    run, ``still``, ``still_vetoed`` and ``window_steps`` are those of the veto off, and every mode a step takes is the
    same as with it. Such a table, or one with ``mark_still_unsure`` False, has no ``still_unsure`` column (the mark
    qualifies the ``still`` reading, which no step takes).
    """
    for c, v in domain.items():
        out[c] = v
    # a rest between fast swings (a fixed physics rule): a foot-mounted sensor at every stride, or a gesturing hand; no carried phone
    from gaitml.models._placement import FOOT_REASON

    flags = out["in_domain"].to_numpy(dtype=object).copy()
    flagged = np.array([v is False or v is np.False_ for v in flags], dtype=bool)
    reason = np.where(flagged, DOMAIN_REASON, "").astype(object)
    reason[np.array([v is None for v in flags], dtype=bool)] = None  # not checked: unknown, as in_domain
    foot = foot_placement(model, rec, windows)
    if foot is not None and foot.any():
        flags[foot] = False
        reason[foot] = FOOT_REASON
        out["in_domain"] = flags
    out["out_of_domain_reason"] = reason
    # a recording made below the lowest rate the model was trained at: every window, whatever its features
    apply_rate_check(out, model, recorded_rate_hz(recording.sampling_rate_hz, recording.meta), recording.meta.get("rate_changes"))
    # a window with no gait is no motion mode: `still` (the model's answer stays in mode_raw)
    still = still_windows(rec, windows, still_rule, still_threshold_ms2, recorded=recording)
    # ... unless the veto's step finder finds steps in it (a calm walker): the steps are found once, and only when needed
    veto_n = still_step_veto_threshold(still_step_veto)
    found = (
        {} if found_steps is None else found_steps
    )  # each detector setting runs once (the veto's and the rule's are one without a gyroscope)
    n_steps, vetoed = np.full(len(out), np.nan), np.zeros(len(out), dtype=bool)
    needed = still.any() and (not veto_for_step_modes or veto_can_change_step_modes(still, out["mode"], out["mode_raw"]))
    if veto_n is not None and needed:
        vsteps = steps_found_once(found, rec, veto=True)
        counts = window_step_counts(windows, vsteps)
        n_steps = veto_counts(counts, still)  # the counts the veto decided on
        vetoed = still & (counts >= veto_n)
        still = still & ~vetoed
    out["still"] = still
    out["still_vetoed"] = vetoed
    # a still window in which the phone turns with a stride rhythm: the evidence disagrees, the table says so (not for a
    # table read only for the modes steps take: a step in a still window takes the model's raw answer, never 'still')
    if mark_still_unsure and not veto_for_step_modes:
        out["still_unsure"] = still_unsure(rec, windows, still)
    out["mode"] = np.where(still, STILL, out["mode"].to_numpy(dtype=object)).astype(str)
    # a window read run at a walking cadence: the model's best other mode (the model's answer stays in mode_raw)
    run_thr = run_cadence_threshold(run_min_cadence_hz)
    modes = out["mode"].to_numpy().astype(str)
    raw = out["mode_raw"].to_numpy().astype(str)
    cadence = np.full(len(out), np.nan)
    moved = np.zeros(len(out), dtype=bool)
    if run_thr is not None and X is not None and ((modes == RUN_MODE) | (raw == RUN_MODE)).any():
        cadence = window_step_cadence(rec, windows, steps=steps_found_once(found, rec, veto=False))
        with np.errstate(invalid="ignore"):
            slow = (modes == RUN_MODE) & (raw == RUN_MODE) & (cadence < run_thr) & (cadence >= RUN_STRIDE_CADENCE_HZ)
        other = raw.astype(object)
        if slow.any():
            other[slow] = best_other_modes(model, np.asarray(X)[slow])
        modes, moved = run_cadence_rule(modes, raw, cadence, other, run_thr)
        out["mode"] = modes
    out["step_cadence_hz"] = cadence
    out["window_steps"] = n_steps
    out["run_at_walking_cadence"] = moved
    # a side step read from an upright phone: its left / right is not tied to the walker's
    out["side_direction_unsure"] = side_direction_unsure(rec, windows, out["mode"].to_numpy())
    for c in ("label", "label_fraction"):
        if c in windows.columns:
            out[c] = windows[c].to_numpy()
    out.attrs.update(
        sampling_rate_hz=model.sampling_rate_hz,
        resampled_from_hz=None if rec is recording else recording.sampling_rate_hz,
        correction=bool(correction),
        still_gate={
            "statistic": still_rule,
            "threshold_ms2": _still_threshold(still_rule, still_threshold_ms2),
            "step_veto_min_steps": veto_n,
        },
        run_cadence={"min_cadence_hz": run_thr},
        **attrs,
    )
    return out
