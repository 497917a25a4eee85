"""Put an accelerometer and a gyroscope logged on separate clocks onto one time base.

Phone apps log each sensor "as fast as possible" with its own timestamps
(phyphox tables, Sensor Logger files); the two streams start and stop at
slightly different times and their sample times never coincide. gaitml merges
them in one documented way that keeps every accelerometer sample:

1. the merged recording spans the accelerometer (every step detector, and the
   time base a person labels against, is the accelerometer's); t = 0 stays at
   its first sample;
2. each gyroscope axis is linearly interpolated onto the accelerometer's times
   where the gyroscope runs; where it does not (it started late or stopped
   early), it is filled by holding its first or last sample (the stated rule,
   :data:`FILL_RULE`), and those spans are reported in
   ``meta['clock_merge']['gyr_filled_s']``;
3. gyroscope samples outside the accelerometer's span have no accelerometer to
   go with and are counted in ``dropped_gyr_samples``;
4. when more than :data:`WARN_SAMPLES` samples are filled or dropped, the merge
   returns one warning line (``info['warning']``), which the readers put in
   ``meta['warnings']`` and every command prints.

:meth:`gaitml.recording.Recording.from_timestamps` then makes the result
uniform (and reports that resampling separately). Linear interpolation of a
2 Hz gait component sampled at >= 100 Hz errs by < 1e-3 of its amplitude (see
``from_timestamps``).

Two streams that overlap for less than half of the shorter one are refused as
unsynchronised clocks (for example one table in seconds and the other in
milliseconds, or tables from two different recordings).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from gaitml.errors import InputError

__all__ = ["override_units", "merge_clocks", "MIN_OVERLAP_FRACTION", "WARN_SAMPLES", "FILL_RULE", "check_times"]

#: Refuse two streams whose overlap is shorter than this fraction of the shorter stream.
MIN_OVERLAP_FRACTION = 0.5
#: A merge that fills or drops more than this many samples of either stream is warned about
#: (sensors switched on a few milliseconds apart are ordinary and stay silent).
WARN_SAMPLES = 5
#: How the second stream is filled where it did not run (see the module docstring).
FILL_RULE = "hold the nearest sample"


def check_times(t: np.ndarray, what: str) -> None:
    """One-line InputError unless ``t`` is finite and strictly increasing with >= 2 samples."""
    if len(t) < 2:
        raise InputError(f"{what} has {len(t)} samples; record for longer with this sensor switched on.")
    if not np.isfinite(t).all():
        i = int(np.flatnonzero(~np.isfinite(t))[0])
        raise InputError(f"{what} has a missing or non-numeric time at row {i + 1}; export the recording again.")
    dt = np.diff(t)
    if (dt <= 0).any():
        i = int(np.flatnonzero(dt <= 0)[0]) + 1
        kind = "repeats" if dt[i - 1] == 0 else "goes back"
        raise InputError(
            f"{what}: time {kind} at row {i + 1} ({t[i - 1]:.9g} -> {t[i]:.9g} s); sort the rows by time or remove duplicated rows."
        )


def merge_clocks(
    t_acc: np.ndarray,
    acc: np.ndarray,
    t_gyr: np.ndarray,
    gyr: np.ndarray,
    *,
    what: str = "the recording",
    names: tuple[str, str] = ("accelerometer", "gyroscope"),
) -> tuple[np.ndarray, np.ndarray, np.ndarray, dict[str, Any]]:
    """Interpolate the gyroscope onto every accelerometer time (see the module docstring).

    Parameters
    ----------
    t_acc, t_gyr : ndarray, shape (n,), (m,)
        Sample times in s on the *same* clock, strictly increasing.
    acc, gyr : ndarray, shape (n, 3), (m, 3)
        Accelerometer (any unit) and gyroscope (any unit) samples.
    what : str
        Names the export in error messages.
    names : (str, str)
        What the two streams are, for the messages (e.g. the gravity sensor).

    Returns
    -------
    t, acc, gyr : ndarrays
        The accelerometer's times and samples (all of them), and the gyroscope
        interpolated at those times (held at its edge sample outside its span).
    info : dict
        For ``meta['clock_merge']``: ``method``, ``overlap_s`` (start, end on the
        input clock), ``acc_rate_hz``, ``gyr_rate_hz`` (median rates),
        ``dropped_acc_samples`` (always 0), ``dropped_gyr_samples`` (outside the
        accelerometer's span), ``filled_gyr_samples`` and ``gyr_filled_s``
        (``[[start, end], ...]`` in s from the first accelerometer sample) and
        ``warning`` (one line, or None).

    Raises
    ------
    InputError
        No overlap, or an overlap shorter than :data:`MIN_OVERLAP_FRACTION` of
        the shorter stream (unsynchronised clocks); too few samples; times not
        increasing.
    """
    first, second = names
    t_acc = np.asarray(t_acc, dtype=float)
    t_gyr = np.asarray(t_gyr, dtype=float)
    acc = np.asarray(acc, dtype=float)
    gyr = np.asarray(gyr, dtype=float)
    check_times(t_acc, f"the {first} table of {what}")
    check_times(t_gyr, f"the {second} table of {what}")
    a0, a1, g0, g1 = float(t_acc[0]), float(t_acc[-1]), float(t_gyr[0]), float(t_gyr[-1])
    lo, hi = max(a0, g0), min(a1, g1)
    if hi <= lo:
        raise InputError(
            f"the {first} ({a0:.3f} to {a1:.3f} s) and {second} ({g0:.3f} to {g1:.3f} s) clocks of {what} do not overlap; "
            f"export both sensors from the same recording, or remove the {second} table to read the {first} alone."
        )
    shorter = min(a1 - a0, g1 - g0)
    if hi - lo < MIN_OVERLAP_FRACTION * shorter:
        raise InputError(
            f"the {first} ({a0:.3f} to {a1:.3f} s) and {second} ({g0:.3f} to {g1:.3f} s) of {what} overlap for only "
            f"{hi - lo:.3f} s of {shorter:.3f} s: unsynchronised clocks (other time units or another recording?); "
            "export both sensors from the same recording with the same time unit."
        )
    # np.interp holds the edge samples outside [g0, g1]: the stated fill rule
    gyr_on_acc = np.column_stack([np.interp(t_acc, t_gyr, gyr[:, j]) for j in range(gyr.shape[1])])
    before, after = t_acc < g0, t_acc > g1
    filled = [[round(float(t_acc[m][0] - a0), 6), round(float(t_acc[m][-1] - a0), 6)] for m in (before, after) if m.any()]
    n_filled = int(before.sum() + after.sum())
    n_dropped = int(((t_gyr < a0) | (t_gyr > a1)).sum())
    warning = None
    if n_filled > WARN_SAMPLES or n_dropped > WARN_SAMPLES:
        parts = []
        if n_filled > WARN_SAMPLES:
            spans = " and ".join(f"{a:.3g}-{b:.3g} s" for a, b in filled)
            parts.append(
                f"the {second} did not run for {n_filled} of the {first}'s {len(t_acc)} samples ({spans}), "
                f"filled there by the rule '{FILL_RULE}' (not measured)"
            )
        if n_dropped > WARN_SAMPLES:
            parts.append(f"{n_dropped} {second} samples outside the {first}'s span ({a0:.3f} to {a1:.3f} s) were dropped")
        warning = f"{what}: {'; '.join(parts)}; every {first} sample is kept (t = 0 at its first sample)" + (
            f"; trim the recording to {lo - a0:.3f}-{hi - a0:.3f} s if the {second} matters there." if n_filled > WARN_SAMPLES else "."
        )
    info = {
        "method": f"{second} linearly interpolated onto every {first} time; outside its span: {FILL_RULE}",
        "overlap_s": [round(lo, 6), round(hi, 6)],
        "acc_rate_hz": round(1.0 / float(np.median(np.diff(t_acc))), 3),
        "gyr_rate_hz": round(1.0 / float(np.median(np.diff(t_gyr))), 3),
        "dropped_acc_samples": 0,
        "dropped_gyr_samples": n_dropped,
        "filled_gyr_samples": n_filled,
        "gyr_filled_s": filled,
        "warning": warning,
    }
    return t_acc, acc, gyr_on_acc, info


def override_units(meta: dict, acc_unit: str, gyr_unit: str, acc_given: str | None, gyr_given: str | None) -> tuple[str, str]:
    """The units to convert from: the export's own (``acc_unit``, ``gyr_unit``) unless the user named others.

    A phone app's header can state m/s^2 over values in g (an app setting, a re-export);
    ``--acc-unit`` / ``--gyr-unit`` then say what the values are, and ``meta['unit_override']``
    records both.
    """
    notes = []
    if acc_given is not None and acc_given != acc_unit:
        notes.append(f"acc in {acc_given} as given (the export says {acc_unit})")
        acc_unit = acc_given
    if gyr_given is not None and gyr_given != gyr_unit:
        notes.append(f"gyr in {gyr_given} as given (the export says {gyr_unit})")
        gyr_unit = gyr_given
    if notes:
        meta["unit_override"] = notes
    return acc_unit, gyr_unit
