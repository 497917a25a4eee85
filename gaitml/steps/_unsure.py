"""Confident or unsure: does a recording's step table show gait at all?

A step detector finds steps wherever the acceleration is periodic enough; a
phone handled at a desk or in a gesturing hand gives a few such "steps". The
``adaptive`` detector gives every step a ``confidence`` in [0, 1] (the
periodicity of the signal at the step, times the regularity of its timing,
halved for a stride inferred from the cadence range alone, scaled down in
bouts of fewer than ten steps; see :mod:`gaitml.steps.adaptive`). That
per-step number ranks steps, but a threshold on it does not tell real steps
from non-gait ones: a walker's steps with the phone in a back trouser pocket,
or texting while stopping and turning, can have confidences as low as a
handled phone's, so a threshold that spares real steps keeps the non-gait
ones and one that removes the non-gait ones calls much real walking unsure.

What separates them is **how long the steps keep going**. Walking comes in
bouts of regular steps; a pedometer confirms a walk only after about ten
regular steps (Bassett et al., Med. Sci. Sports Exerc. 28, 1996, on the
10-step delay of spring-levered pedometers; the same number is
``adaptive``'s ``SHORT_BOUT_STEPS``). Handling and gesturing give short
runs of "steps" between pauses. A walker also stops, turns and starts again,
and the steps around a stop form short bouts of their own; they belong to the
walk they interrupt. So:

- a **bout** is a run of steps in which no interval exceeds
  ``BOUT_GAP_RATIO`` (2) local step periods (the step table's ``period_s``;
  as ``adaptive`` splits its bouts);
- a bout of at least ``CONFIDENT_BOUT_STEPS`` (10) steps is **confirmed
  gait**;
- a step is **confident** when a step of a confirmed bout lies within
  ``CONFIDENT_WINDOW_S`` (60 s) of it (its own bout counts), **unsure**
  otherwise. Nothing is dropped: the count stays, and the summary says how
  many steps are not known to be gait. ``window_s=inf`` judges the whole
  table at once (one confirmed bout anywhere makes every step confident).

The window is a setting chosen on real walks (the steps of a slow walker who
stops at walls while texting or phoning, with a motion-capture reference);
the longer it is, the more of a non-gait stretch next to a walk is called
confident.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.steps.adaptive import BOUT_GAP_RATIO, SHORT_BOUT_STEPS

__all__ = ["CONFIDENT_BOUT_STEPS", "CONFIDENT_WINDOW_S", "confident_steps", "gait_confidence", "table_bouts"]

#: a bout of at least this many regular steps is confirmed gait (the ten-step confirmation of pedometers, Bassett et
#: al. 1996; adaptive's SHORT_BOUT_STEPS)
CONFIDENT_BOUT_STEPS = SHORT_BOUT_STEPS
#: a step is confident when a step of a bout of CONFIDENT_BOUT_STEPS lies within this many seconds of it: the
#: pauses, turns and restarts of a walk stay part of it (chosen on the real tyrex walks of all three people: with one
#: person left out the choice is not stable, see the lab's step-confidence report)
CONFIDENT_WINDOW_S = 60.0


def _times(steps: pd.DataFrame) -> np.ndarray:
    """The step times: the column named by ``attrs['event']`` (default ``t_peak_s``)."""
    return steps[steps.attrs.get("event", "t_peak_s")].to_numpy(dtype=float)


def table_bouts(steps: pd.DataFrame) -> np.ndarray:
    """Bout index (0, 1, ... in time order) of each step of a step table (rows in any order).

    An interval between consecutive step times longer than ``BOUT_GAP_RATIO``
    times the larger ``period_s`` of its two steps ends a bout.
    """
    t = _times(steps)
    if len(t) == 0:
        return np.zeros(0, dtype=np.int64)
    order = np.argsort(t, kind="stable")
    period = steps["period_s"].to_numpy(dtype=float)[order]
    gap = np.diff(t[order]) > BOUT_GAP_RATIO * np.maximum(period[:-1], period[1:])
    bout = np.empty(len(t), dtype=np.int64)
    bout[order] = np.concatenate([[0], np.cumsum(gap)])
    return bout


def confident_steps(
    steps: pd.DataFrame, *, min_bout_steps: int = CONFIDENT_BOUT_STEPS, window_s: float = CONFIDENT_WINDOW_S
) -> tuple[np.ndarray, np.ndarray]:
    """Per step: confident (bool) and the size of its bout (module docstring)."""
    if min_bout_steps < 1:
        raise ValueError(f"`min_bout_steps` must be at least 1, got {min_bout_steps}.")
    if not window_s >= 0:
        raise ValueError(f"`window_s` must be >= 0 seconds (inf: the whole table), got {window_s}.")
    bout = table_bouts(steps)
    if len(bout) == 0:
        return np.zeros(0, dtype=bool), np.zeros(0, dtype=np.int64)
    size = np.bincount(bout)[bout]
    t = _times(steps)
    order = np.argsort(t, kind="stable")
    tc = np.sort(t[size >= min_bout_steps])
    if len(tc) == 0:
        return np.zeros(len(t), dtype=bool), size
    # distance from each step to the nearest step of a confirmed bout
    j = np.searchsorted(tc, t[order])
    left = tc[np.clip(j - 1, 0, len(tc) - 1)]
    right = tc[np.clip(j, 0, len(tc) - 1)]
    d = np.empty(len(t))
    d[order] = np.minimum(np.abs(t[order] - left), np.abs(right - t[order]))
    return d <= window_s, size


def gait_confidence(steps: pd.DataFrame, *, min_bout_steps: int = CONFIDENT_BOUT_STEPS, window_s: float = CONFIDENT_WINDOW_S) -> dict:
    """How many of the table's steps are confident gait, how many unsure (module docstring).

    Returns
    -------
    dict
        ``n_confident``, ``n_unsure``, ``confident_gait`` (bool: any step
        confident), ``min_bout_steps``, ``window_s``, ``longest_bout_steps``,
        ``n_bouts``, ``rule`` (one line). The per-step verdict is
        :func:`confident_steps`.
    """
    ok, size = confident_steps(steps, min_bout_steps=min_bout_steps, window_s=window_s)
    bout = table_bouts(steps)
    n_conf = int(ok.sum())
    return {
        "confident_gait": bool(n_conf > 0),
        "n_confident": n_conf,
        "n_unsure": int(len(ok) - n_conf),
        "min_bout_steps": int(min_bout_steps),
        "window_s": float(window_s),
        "longest_bout_steps": int(size.max()) if len(size) else 0,
        "n_bouts": int(bout.max() + 1) if len(bout) else 0,
        "rule": f"a step is confident when a bout of >= {min_bout_steps} regular steps (no interval over "
        f"{BOUT_GAP_RATIO:g} step periods) lies within {window_s:g} s of it, else unsure",
    }
