"""Step detector throughput: samples per second on a 1-hour recording.

The recording is a real Oxford hand-held walk (100 Hz) tiled to one hour, or a
synthetic walk when the shared data is absent. Each detector's ``detect`` is
timed end to end (magnitude, filtering, resampling, the state machine, the step
table). Where a plain reference exists it is timed in the same run on the same
input: a naive per-sample Python loop of single-peak, and the per-sample loop
versions of the FSMs (``ifsm_steps_loop``, ``adfsm_steps_loop`` in
``tests/steps/reference_fsm.py``, the
self-learning FSM without jumping); ``ratio = reference_seconds / seconds``.
For ``adaptive`` the reference is the detector as it was before issue 13
(``tests/steps/reference_adaptive.py``): the ratio compares the reworked
detector with the one it replaced, not with a plain loop.
"""

from __future__ import annotations

import os
import platform
import time
from pathlib import Path

import numpy as np

from gaitml.recording import Recording
from gaitml.signal import lowpass, magnitude, moving_average

__all__ = ["run", "naive_single_peak", "bench_recording"]

_ORIGIN = "Pixel_Jamie_Hard_InHand_1"


def bench_recording(duration_s: float) -> tuple[Recording, str]:
    """A walking recording of ``duration_s`` seconds (tiled real data when available)."""
    root = Path(os.environ.get("GAITML_SHARED_DATA", Path(__file__).resolve().parents[2] / "shared" / "data"))
    folder = root / "oxford-step-counter" / "optimisation" / "data" / _ORIGIN
    if folder.is_dir():
        from gaitml.io import read_recording

        base = read_recording(folder)
        src = f"Oxford {_ORIGIN} (100 Hz) tiled"
        acc, fs = base.acc, base.sampling_rate_hz
    else:
        fs = 100.0
        t = np.arange(int(60 * fs)) / fs
        rng = np.random.default_rng(0)
        acc = np.column_stack([rng.normal(0, 0.3, len(t)), rng.normal(0, 0.3, len(t)), 9.81 + 3 * np.sin(2 * np.pi * 1.8 * t)])
        src = "synthetic 1.8 Hz walk (100 Hz) tiled"
    n = int(duration_s * fs)
    reps = int(np.ceil(n / len(acc)))
    return Recording.from_arrays(np.tile(acc, (reps, 1))[:n], fs), src


def naive_single_peak(acc: np.ndarray, fs: float) -> list[tuple[int, int, int]]:
    """Single-peak (paper 003 sec. 2.2) as a plain per-sample Python loop: the speed reference.

    Returns ``(left zero, peak, right zero)`` per step; same rules as
    :func:`gaitml.steps.single_peak.single_peak_steps` (centred 3-sample moving
    average, peaks > 2 m/s^2 at least 0.3 s apart with the higher one kept,
    zero-point search 0.24 s back / 0.5 s forward).
    """
    n = len(acc)
    m = [(acc[i, 0] ** 2 + acc[i, 1] ** 2 + acc[i, 2] ** 2) ** 0.5 - 9.8 for i in range(n)]
    w = max(1, round(0.06 * fs))
    back, fwd = w // 2, w - 1 - w // 2
    a = []
    for i in range(n):
        lo, hi = max(0, i - back), min(n, i + fwd + 1)
        s = 0.0
        for j in range(lo, hi):
            s += m[j]
        a.append(s / (hi - lo))
    dist = max(1, round(0.3 * fs))
    peaks: list[int] = []
    for i in range(1, n - 1):
        if a[i] > 2.0 and a[i] > a[i - 1] and a[i] >= a[i + 1]:
            if peaks and i - peaks[-1] < dist:
                if a[i] > a[peaks[-1]]:
                    peaks[-1] = i
            else:
                peaks.append(i)
    lmax, rmax = round(0.24 * fs), round(0.5 * fs)
    out = []
    for p in peaks:
        left = max(p - lmax, 0)
        for j in range(p, max(p - lmax, 0), -1):
            if (a[j] >= 0) != (a[j - 1] >= 0):
                left = j
                break
        right, seen = min(p + rmax, n), 0
        for j in range(p + 1, min(p + rmax, n - 1) + 1):
            if (a[j] >= 0) != (a[j - 1] >= 0):
                seen += 1
                if seen == 2:
                    right = j
                    break
        out.append((left, p, right))
    return out


def _references(rec: Recording) -> dict:
    from gaitml.steps._common import resample_signal
    from gaitml.steps.fsm_selflearn import SelfLearningFSMStepDetector, learn_thresholds, selflearn_fsm_run
    from gaitml.steps.ifsm import IFSM_READINGS
    from tests.steps.reference_fsm import adfsm_steps_loop, ifsm_steps_loop

    fs = rec.sampling_rate_hz

    def ifsm_ref(reading):
        def f():
            A = moving_average(resample_signal(magnitude(rec.acc), fs, 50.0), 5)
            ce, inc, end = IFSM_READINGS[reading]
            ifsm_steps_loop(A, count_entry=ce, inclusive=inc, end_condition=end)

        return f

    def adfsm_ref():
        adfsm_steps_loop(moving_average(resample_signal(magnitude(rec.acc), fs, 50.0), 5))

    def selflearn_ref():
        d = SelfLearningFSMStepDetector()
        a = lowpass(magnitude(rec.acc), d.lowpass_hz, fs)
        kw = dict(max_step_samples=int(round(d.max_step_s * fs)), end_timeout_samples=int(round(d.end_timeout_s * fs)))
        th, _ = learn_thresholds(a, (d.thr_ms2, d.thr_peak_ms2, d.thr_trough_ms2, d.thr_neg_ms2), **kw)
        selflearn_fsm_run(a, th, jump=False, **kw)

    def autocorr_ref():
        from gaitml.steps.autocorr import AutocorrStepDetector

        d = AutocorrStepDetector()
        x = moving_average(magnitude(rec.acc), max(1, int(round(d.smoothing_s * fs))))
        L = int(round(d.window_s * fs))
        lo, hi = max(2, int(round(d.min_period_s * fs))), int(round(d.max_period_s * fs))
        for i in range(len(x) // L):  # one window at a time, direct autocorrelation
            w = x[i * L : (i + 1) * L] - x[i * L : (i + 1) * L].mean()
            r = np.correlate(w, w, "full")[L - 1 :]
            r = r / r[0] if r[0] > 0 else r
            seg = r[lo - 1 : hi + 2]
            _ = [k for k in range(1, len(seg) - 1) if seg[k] > seg[k - 1] and seg[k] >= seg[k + 1]]

    def adaptive_ref():
        # the adaptive detector as it was before issue 13 (tests/steps/reference_adaptive.py), same input
        from tests.steps.reference_adaptive import adaptive_step_peaks

        adaptive_step_peaks(magnitude(rec.acc), fs)

    def zupt_magnitude_ref():
        from gaitml.steps.zupt_magnitude import ZuptMagnitudeStepDetector, steps_from_zupts
        from gaitml.zupt import intervals_table
        from tests.reference.zupt import reference_magnitude

        d = ZuptMagnitudeStepDetector()
        mask = reference_magnitude(rec.acc, fs, d.t_min_ms2, d.t_max_ms2, d.min_run_fraction)
        steps_from_zupts(intervals_table(mask, fs), fs, n_samples=rec.n_samples)

    return {
        "single-peak": ("naive per-sample Python loop of single-peak", lambda: naive_single_peak(rec.acc, fs)),
        "autocorr": ("per-window np.correlate loop of the autocorrelation", autocorr_ref),
        "adaptive": ("the pre-issue-13 adaptive core (tests/steps/reference_adaptive.py): ratio > 1 = the rework is faster", adaptive_ref),
        "zupt-magnitude": ("per-sample state-machine loop of paper 004's interval test", zupt_magnitude_ref),
        "ifsm": ("per-sample loop ifsm_steps_loop", ifsm_ref("reproduce")),
        "ifsm-literal": ("per-sample loop ifsm_steps_loop", ifsm_ref("literal")),
        "adfsm": ("per-sample loop adfsm_steps_loop", adfsm_ref),
        "fsm-selflearn": ("per-sample loop (no jumping)", selflearn_ref),
    }


def _best_of(f, repeats: int) -> tuple[float, float]:
    """Best wall-clock and best CPU (process) time of ``repeats`` runs: on a shared machine the CPU time shows the cost without the wait."""
    best, best_cpu = np.inf, np.inf
    for _ in range(repeats):
        t, c = time.perf_counter(), time.process_time()
        f()
        best = min(best, time.perf_counter() - t)
        best_cpu = min(best_cpu, time.process_time() - c)
    return best, best_cpu


def run(quick: bool = False) -> list[dict]:
    """Time every step detector on a 1-hour recording (5 minutes with ``quick``)."""
    from gaitml.steps import detector_names, get_detector

    duration = 300.0 if quick else 3600.0
    rec, src = bench_recording(duration)
    refs = _references(rec)
    machine = f"{platform.machine()}, {os.cpu_count()} CPUs, Python {platform.python_version()}"
    rows = []
    for name in detector_names():
        try:
            det = get_detector(name)
        except Exception:  # e.g. zupt-magnitude missing in this checkout
            continue
        secs, cpu = _best_of(lambda det=det: det.detect(rec), 1 if quick else 5)
        n_steps = len(det.steps_)
        row = {
            "area": "steps",
            "name": name,
            "n_items": rec.n_samples,
            "unit": "samples",
            "seconds": secs,
            "throughput_per_s": rec.n_samples / secs,
            "cpu_seconds": cpu,
            "note": f"{src}, {duration / 60:g} min at {rec.sampling_rate_hz:g} Hz, {n_steps} steps; CPU-time throughput "
            f"{rec.n_samples / max(cpu, 1e-9) / 1e6:.2f} M samples/s; {machine}, load average {os.getloadavg()[0]:.1f}",
        }
        if name in refs:
            what, f = refs[name]
            rsecs, _ = _best_of(f, 1)
            row.update(reference_seconds=rsecs, ratio=rsecs / secs)
            row["note"] += f"; reference: {what}"
        rows.append(row)
    # adaptive with a gyroscope (its stride-versus-step check): the same recording with a swing rate added (the
    # bench walk has no gyroscope: a 0.9 Hz swing with noise); reference = the accelerometer alone on that input
    t = np.arange(rec.n_samples) / rec.sampling_rate_hz
    rng = np.random.default_rng(0)
    gyr = np.column_stack([1.5 * np.sin(2 * np.pi * 0.9 * t), 0.2 * np.sin(2 * np.pi * 1.8 * t), np.zeros_like(t)])
    rec_g = Recording.from_arrays(rec.acc, rec.sampling_rate_hz, gyr=gyr + rng.normal(0, 0.01, gyr.shape))
    det = get_detector("adaptive")
    secs, cpu = _best_of(lambda: det.detect(rec_g), 1 if quick else 5)
    rsecs, _ = _best_of(lambda: get_detector("adaptive", use_gyroscope=False, gait_check=False).detect(rec_g), 1 if quick else 5)
    rows.append(
        {
            "area": "steps",
            "name": "adaptive (gyroscope)",
            "n_items": rec.n_samples,
            "unit": "samples",
            "seconds": secs,
            "throughput_per_s": rec.n_samples / secs,
            "cpu_seconds": cpu,
            "reference_seconds": rsecs,
            "ratio": rsecs / secs,
            "note": f"{src} with a synthetic 0.9 Hz swing rate as gyroscope, {len(det.steps_)} steps; CPU-time throughput "
            f"{rec.n_samples / max(cpu, 1e-9) / 1e6:.2f} M samples/s; reference: adaptive with use_gyroscope=False, gait_check=False on the "
            f"same input (ratio < 1 = the cost of the check); {machine}, load average {os.getloadavg()[0]:.1f}",
        }
    )
    # the opt-in stages on the same input; reference = adaptive at its defaults (the stage off), timed above
    default_secs = secs
    for name, params in (
        ("adaptive (gyroscope, swing stage on)", {"gyro_swing_min_periodicity": 0.3}),  # the swing where |acc| is weak (stage 2c)
        ("adaptive (gyroscope, octave stage on)", {"octave_swing_min_correlation": 0.5, "max_short_bout_interval_cv": 0.2}),  # 5a
    ):
        det = get_detector("adaptive", **params)
        secs, cpu = _best_of(lambda det=det: det.detect(rec_g), 1 if quick else 5)
        setting = ", ".join(f"{k}={v:g}" for k, v in params.items())
        rows.append(
            {
                "area": "steps",
                "name": name,
                "n_items": rec.n_samples,
                "unit": "samples",
                "seconds": secs,
                "throughput_per_s": rec.n_samples / secs,
                "cpu_seconds": cpu,
                "reference_seconds": default_secs,
                "ratio": default_secs / secs,
                "note": f"{src} with the same synthetic swing, {setting}, {len(det.steps_)} steps; reference: adaptive at its defaults "
                f"(the stage off) on the same input, the row above (ratio < 1 = the cost of the stage); {machine}, load average "
                f"{os.getloadavg()[0]:.1f}",
            }
        )
    return rows


if __name__ == "__main__":  # pragma: no cover
    for r in run(quick=bool(os.environ.get("QUICK"))):
        print(
            f"{r['name']:15s} {r['throughput_per_s'] / 1e6:7.2f} M samples/s wall ({r['seconds']:.3f} s), "
            f"{r['n_items'] / r['cpu_seconds'] / 1e6:7.2f} M samples/s CPU, ratio {r.get('ratio', float('nan')):.1f}"
        )
