"""The rate check of a step table: was the recording made below the lowest rate its detector's count holds at?

Every step detector declares a **rate floor** (``rate_floor_hz``, a module-level constant of its module): the
lowest sampling rate at which its count was measured to hold. The floors come from one rule, fixed before the
figures were read (``experiments/reports/tyrex-steps.md``, "rate floors"; ``python -m
experiments.scripts.tyrex_steps_rates --floors``): every tyrex recording (3 people x 3 phones, walking and running,
motion-capture step counts) taken down to 50, 30, 25, 20, 15 and 10 Hz; the floor is the lowest of those rates at
which, and at every one above which, every scored motion's mean count accuracy is within 0.05 of its figure at the
phones' own rate (about 100 and 200 Hz). 10 Hz, the lowest rate measured, is a floor too: below it nothing is known.
Where a floor chosen on two people let the third lose more than that (checked leave-one-person-out), the detector
takes the highest floor any fold gives (``adaptive``, ``adfsm``). The Oxford walks (3 people, 6 carrying positions,
foot switches) are a second check.

A recording made below :data:`RATE_TOLERANCE` times the floor is **flagged, not refused**: the steps are counted
as always, and the step table's ``attrs['rate_check']`` (:func:`rate_check`) says so; a reader's
``meta['rate_changes']`` stretches recorded below it flag the steps in them (:func:`rate_flags`). The rate read
is the one the recording was made at (:func:`gaitml.recording.recorded_rate_hz`, the rate a model's rate check
reads): a recording resampled up from a slow phone is still flagged. ``gaitml steps``, ``pdr``, ``label`` and
``segment`` print one warning line (:func:`rate_warning`) and carry the check in their JSON and tables.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.recording.timestamps import RATE_TOLERANCE  # a recording is below a floor under this fraction of it (as a model's rate check)

__all__ = ["RATE_TOLERANCE", "add_rate_reasons", "rate_check", "rate_flags", "rate_reason", "rate_record", "rate_warning"]

#: the detector named in the fix of the warning line: ``adaptive``, the default, built for any carrying position
#: (floor 15 Hz since the leave-one-person-out check; not the lowest floor: ``ifsm``'s is 10 Hz)
FALLBACK_DETECTOR = "adaptive"


def rate_reason(detector: str, floor_hz: float | None, recorded_hz: float | None) -> str | None:
    """``"rate: recorded at 10 Hz, below the 50 Hz down to which single-peak's step count holds"`` when
    ``recorded_hz`` is below :data:`RATE_TOLERANCE` x ``floor_hz``, ``""`` when it is not, None when not checked
    (no floor or no rate)."""
    if floor_hz is None or recorded_hz is None:
        return None
    hz, floor = float(recorded_hz), float(floor_hz)
    if hz < RATE_TOLERANCE * floor:
        return f"rate: recorded at {hz:.3g} Hz, below the {floor:.3g} Hz down to which {detector}'s step count holds"
    return ""


def rate_check(detector: str, floor_hz: float | None, recorded_hz: float | None, rate_changes=None) -> dict | None:
    """What a step table's ``attrs['rate_check']`` says (JSON-ready), None when not checked.

    Parameters
    ----------
    detector : str
        The detector's registered name.
    floor_hz : float or None
        Its rate floor (``rate_floor_hz``).
    recorded_hz : float or None
        The rate the recording was made at (:func:`gaitml.recording.recorded_rate_hz`).
    rate_changes : list, optional
        The reader's ``meta['rate_changes']`` (``[[t_start_s, t_end_s, rate_hz], ...]``, s from the first sample).

    Returns
    -------
    dict or None
        ``detector``, ``recorded_hz``, ``floor_hz``, ``tolerance``, ``below`` (the whole recording),
        ``reason`` (:func:`rate_reason`), ``stretches_below`` (the stretches recorded below the floor, each
        ``[t_start_s, t_end_s, rate_hz]``; empty when the whole recording is below or none is).
    """
    reason = rate_reason(detector, floor_hz, recorded_hz)
    if reason is None:
        return None
    stretches = []
    if not reason:
        for a, b, hz in rate_changes or []:
            if rate_reason(detector, floor_hz, float(hz)):
                stretches.append([float(a), float(b), float(hz)])
    return {
        "detector": str(detector),
        "recorded_hz": float(recorded_hz),
        "floor_hz": float(floor_hz),
        "tolerance": RATE_TOLERANCE,
        "below": bool(reason),
        "reason": reason,
        "stretches_below": stretches,
    }


def rate_flags(steps: pd.DataFrame, check: dict | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Per step of ``steps``: flagged (bool) and its reason (``""`` when not flagged), from ``check``
    (default ``steps.attrs['rate_check']``): every step when the whole recording is below the floor, else the steps
    whose time (the column ``attrs['event']`` names) lies in a stretch recorded below it."""
    check = steps.attrs.get("rate_check") if check is None else check
    n = len(steps)
    flags = np.zeros(n, dtype=bool)
    reasons = np.full(n, "", dtype=object)
    if not check or not n:
        return flags, reasons
    if check["below"]:
        return np.ones(n, dtype=bool), np.full(n, check["reason"], dtype=object)
    event = steps.attrs.get("event", "t_peak_s")
    t = steps[event if event in steps.columns else "t_peak_s"].to_numpy(dtype=float)
    for a, b, hz in check.get("stretches_below", []):
        hit = (t >= a) & (t < b)
        flags |= hit
        reasons[hit] = rate_reason(check["detector"], check["floor_hz"], hz)
    return flags, reasons


def add_rate_reasons(
    table: pd.DataFrame, steps: pd.DataFrame | None = None, check: dict | None = None, *, leading_rows: int = 0
) -> np.ndarray:
    """Add a ``rate_reason`` column to ``table`` (in place) when :func:`rate_flags` of ``steps`` and ``check`` flags a
    step; return the flags (bool, one per step).

    ``table`` holds one row per step of ``steps`` (None: ``table`` is the step table itself) after ``leading_rows`` rows
    that are no step (a trajectory's start row), whose reason is None; a step that was not flagged gets ``""``. Without
    a flagged step ``table`` gets no column: the tables of ``gaitml steps``, ``segment``, ``label`` and ``pdr`` carry it
    only then.
    """
    steps = table if steps is None else steps
    flagged, why = rate_flags(steps, check)
    if len(table) != leading_rows + len(flagged):
        raise ValueError(f"a table of {len(table)} rows for {len(flagged)} steps after {leading_rows} leading rows")
    if flagged.any():
        table["rate_reason"] = np.concatenate([np.full(leading_rows, None, dtype=object), why]).astype(object)
    return flagged


def rate_record(steps: pd.DataFrame) -> dict | None:
    """A step table's rate check (``attrs['rate_check']``) as the commands' JSON carries it: its keys plus
    ``n_steps`` and ``n_steps_below`` (the steps :func:`rate_flags` flags); None when not checked."""
    check = steps.attrs.get("rate_check")
    if check is None:
        return None
    flags, _ = rate_flags(steps, check)
    return {
        **check,
        "stretches_below": [list(s) for s in check["stretches_below"]],
        "n_steps": int(len(steps)),
        "n_steps_below": int(flags.sum()),
    }


def rate_warning(check: dict | None, n_flagged: int | None = None, n_steps: int | None = None) -> str | None:
    """The one warning line (without the ``gaitml: warning:`` prefix) of a rate check that flagged, else None.

    ``n_flagged`` / ``n_steps``: how many steps lie in stretches recorded below the floor (a recording whose
    rate changes; default the record's ``n_steps_below`` / ``n_steps``, :func:`rate_record`); the line then names them.
    """
    if not check:
        return None
    n_flagged = check.get("n_steps_below") if n_flagged is None else n_flagged
    n_steps = check.get("n_steps") if n_steps is None else n_steps
    stretches = check.get("stretches_below") or []
    if not check["below"] and not stretches:
        return None
    from gaitml.steps._registry import DETECTORS

    det, floor = check["detector"], check["floor_hz"]
    if check["below"]:
        hz = check["recorded_hz"]
        head = f"the recording was made at {hz:.3g} Hz, below the {floor:.3g} Hz down to which {det}'s step count holds"
    else:
        hz = min(s[2] for s in stretches)
        what = f"{n_flagged} of its {n_steps} steps lie" if n_flagged is not None and n_steps is not None else "steps lie"
        head = (
            f"{what} in {len(stretches)} stretch(es) recorded at down to {hz:.3g} Hz, below the {floor:.3g} Hz down to "
            f"which {det}'s step count holds"
        )
    fallback = float(DETECTORS[FALLBACK_DETECTOR].rate_floor_hz)
    fix = f"record at {floor:g} Hz or more"
    if det != FALLBACK_DETECTOR and hz >= RATE_TOLERANCE * fallback:
        fix = f"use --detector {FALLBACK_DETECTOR} for a carried phone (its count holds down to {fallback:g} Hz), or {fix}"
    return f"{head} (docs/steps-and-zupt.md: 'Sampling rates'): the count may be far off; {fix}"
