"""Cross-check of a fixed-threshold step count against the adaptive detector.

Paper 003's ``single-peak`` detector (sec. 2.2) keeps a peak of ``|acc|`` only when it
rises 2 m/s^2 above g. Calm walking with a hand-held phone stays below that: the Oxford
``InHand`` walks of the calmest user have an ``|acc|`` standard deviation of 1.1 m/s^2,
and on the simulator a walker with hand gain 0.27 keeps about half of its steps (route
seed 4 of ``experiments/scripts/pdr_report.py``). The count is then silently short, and so
is a PDR trajectory built on it. :func:`undercount_warning` runs the ``adaptive``
detector (:mod:`gaitml.steps.adaptive`: thresholds relative to the signal's own
periodicity) on the same recording and says so when the fixed-threshold count is well
below it; ``gaitml steps`` and ``gaitml pdr`` print it as one warning line and put it in
their JSON under ``warnings``.
"""

from __future__ import annotations

__all__ = ["FIXED_THRESHOLD_DETECTORS", "UNDERCOUNT_RATIO", "MIN_ADAPTIVE_STEPS", "undercount_warning"]

#: Detectors with a fixed absolute peak height that calm walking can stay below.
FIXED_THRESHOLD_DETECTORS = ("single-peak",)
#: Warn when the fixed-threshold count is below this fraction of the adaptive count. On the
#: real walks of ``../shared/data`` the two detectors agree within a few percent where
#: single-peak is right (IFSM 284 / 319 both); the calm simulated walkers that single-peak
#: fails on lose 40-50 % of their steps. 0.85 lies between.
UNDERCOUNT_RATIO = 0.85
#: ... and only when the adaptive detector found at least this many steps (a short clip or
#: standing still says nothing).
MIN_ADAPTIVE_STEPS = 10


def undercount_warning(recording, n_steps: int, detector: str) -> str | None:
    """One warning line when ``detector`` (fixed threshold) found far fewer steps than ``adaptive``.

    Parameters
    ----------
    recording : Recording
        The recording the steps were detected on.
    n_steps : int
        How many steps ``detector`` found.
    detector : str
        The detector's registered name; only :data:`FIXED_THRESHOLD_DETECTORS` are checked.

    Returns
    -------
    str or None
        The message (without the ``gaitml: warning:`` prefix), or None when the counts agree.
    """
    if detector not in FIXED_THRESHOLD_DETECTORS:
        return None
    from gaitml.steps._registry import get_detector

    n_adaptive = len(get_detector("adaptive").detect(recording).steps_)
    if n_adaptive < MIN_ADAPTIVE_STEPS or n_steps >= UNDERCOUNT_RATIO * n_adaptive:
        return None
    return (
        f"{detector} found {n_steps} steps where the adaptive detector finds {n_adaptive}: the walking may be too calm "
        f"for its fixed peak height (paper 003: 2 m/s^2 above g); use --detector adaptive"
    )
