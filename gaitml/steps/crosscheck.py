"""Cross-check of a fixed-threshold step count against the adaptive detector.

Paper 003's ``single-peak`` detector (sec. 2.2) keeps a peak of ``|acc|`` only when it
rises 2 m/s^2 above g. That fixed height fails both ways:

- **undercount**: calm walking with a hand-held phone stays below it (calm real
  hand-held walks and calm simulated walkers, low :attr:`~gaitml.simulate.Subject.hand_gain`);
- **overcount**: a phone bouncing in a front pocket during vigorous walking crosses it
  more than once per step.

The count is then silently wrong, and so is a PDR trajectory built on it.
:func:`count_warning` runs the ``adaptive`` detector (:mod:`gaitml.steps.adaptive`:
thresholds relative to the signal's own periodicity) on the same recording and says so
when the fixed-threshold count is well below or well above it (:func:`compare_counts`
decides from the two counts alone, which is what a chunked run of a long input uses);
``gaitml steps`` and ``gaitml pdr`` print it as one warning line and put it in their JSON
under ``warnings``. The two ratios and how they score on the real walks of
``../shared/data``, in sample and leave-one-user-out: ``experiments/reports/steps-crosscheck.md``
(``python -m experiments.scripts.crosscheck_report``).
"""

from __future__ import annotations

__all__ = [
    "CROSSCHECK_DETECTOR",
    "FIXED_THRESHOLD_DETECTORS",
    "MIN_ADAPTIVE_STEPS",
    "OVERCOUNT_RATIO",
    "UNDERCOUNT_RATIO",
    "compare_counts",
    "count_warning",
]

#: Detectors with a fixed absolute peak height that calm walking can stay below and a
#: bouncing phone can cross more than once per step.
FIXED_THRESHOLD_DETECTORS = ("single-peak",)
#: The detector whose count the fixed-threshold one is compared with.
CROSSCHECK_DETECTOR = "adaptive"
#: Warn when the fixed-threshold count is below this fraction of the adaptive count: between
#: the near-agreement of the two detectors where single-peak is right and the share of steps
#: it loses on calm walkers (figures: ``experiments/reports/steps-crosscheck.md``).
UNDERCOUNT_RATIO = 0.85
#: Warn when the fixed-threshold count is above this multiple of the adaptive count. Chosen
#: on the real walks of ``../shared/data`` by ``python -m experiments.scripts.crosscheck_report``:
#: the middle of the ratios (grid 1.01-1.17, step 0.01; at most 1 / :data:`UNDERCOUNT_RATIO`,
#: the mirror of the undercount side) with the fewest false and missed warnings. The choice in
#: sample and leave-one-user-out: ``experiments/reports/steps-crosscheck.md``.
OVERCOUNT_RATIO = 1.11
#: ... and only when the adaptive detector found at least this many steps (a short clip or
#: standing still says nothing).
MIN_ADAPTIVE_STEPS = 10


def compare_counts(
    n_steps: int,
    n_adaptive: int,
    detector: str,
    *,
    undercount_ratio: float = UNDERCOUNT_RATIO,
    overcount_ratio: float = OVERCOUNT_RATIO,
) -> str | None:
    """The warning for a ``detector`` count against the adaptive count of the same recording.

    Parameters
    ----------
    n_steps : int
        How many steps ``detector`` found.
    n_adaptive : int
        How many steps :data:`CROSSCHECK_DETECTOR` found on the same samples.
    detector : str
        The detector's registered name; only :data:`FIXED_THRESHOLD_DETECTORS` are checked.
    undercount_ratio, overcount_ratio : float
        Warn below ``undercount_ratio * n_adaptive`` and above ``overcount_ratio * n_adaptive``
        (dimensionless; defaults :data:`UNDERCOUNT_RATIO` and :data:`OVERCOUNT_RATIO`).

    Returns
    -------
    str or None
        One line (without the ``gaitml: warning:`` prefix), or None when the counts agree,
        the detector is not a fixed-threshold one or ``n_adaptive < MIN_ADAPTIVE_STEPS``.
    """
    if detector not in FIXED_THRESHOLD_DETECTORS or n_adaptive < MIN_ADAPTIVE_STEPS:
        return None
    if n_steps < undercount_ratio * n_adaptive:
        return (
            f"{detector} found {n_steps} steps where the adaptive detector finds {n_adaptive}: the walking may be too calm "
            f"for its fixed peak height (paper 003: 2 m/s^2 above g); use --detector adaptive"
        )
    if n_steps > overcount_ratio * n_adaptive:
        return (
            f"{detector} found {n_steps} steps where the adaptive detector finds {n_adaptive}: a phone bouncing in a pocket "
            f"or bag may cross its fixed peak height (paper 003: 2 m/s^2 above g) more than once per step; use --detector adaptive"
        )
    return None


def count_warning(recording, n_steps: int, detector: str) -> str | None:
    """One warning line when ``detector`` (fixed threshold) found far fewer or far more steps than ``adaptive``.

    Parameters
    ----------
    recording : Recording
        The recording the steps were detected on.
    n_steps : int
        How many steps ``detector`` found.
    detector : str
        The detector's registered name; only :data:`FIXED_THRESHOLD_DETECTORS` are checked
        (the adaptive detector is not run for the others).

    Returns
    -------
    str or None
        The message of :func:`compare_counts`, or None when the counts agree.
    """
    if detector not in FIXED_THRESHOLD_DETECTORS:
        return None
    from gaitml.steps._registry import get_detector

    n_adaptive = len(get_detector(CROSSCHECK_DETECTOR).detect(recording).steps_)
    return compare_counts(n_steps, n_adaptive, detector)
