"""Labelling front end: turn a person's time intervals into per-sample and per-step labels.

A researcher records with a phone app and notes when each motion mode started
and ended, in a CSV ``start_s,end_s,label`` or as an Audacity label track
(tab-separated ``start end label`` per line, exported with *File > Export >
Export Labels*). Hand-written boundaries are off by a few tenths of a second;
:class:`IntervalLabeller` moves a boundary onto a detected step (or stride)
boundary within ``max_snap_s`` when the steps show the mode change there (rule
``'change'``, default: the first step whose character departs from the old mode,
:mod:`gaitml.labels._evidence`; without clean evidence the boundary stays as
written, status ``ambiguous``) or to the nearest one (rule ``'nearest'``), so that
every step carries one label, and labels every sample (samples outside all
intervals get an explicit ``unlabelled`` label, nothing is dropped).

Boundaries
----------
``snap='steps'``: a step detector (default ``single-peak``; any of
:data:`gaitml.steps.DETECTORS`) finds the steps. With ``boundary='peak'``
(default) a boundary between two steps is the step event, the acceleration peak
at the foot's impact (heel strike, DESIGN sec. 2): the sample of the peak ends
one step and the next sample begins the following one, so step ``k`` spans the
samples after peak ``k - 1`` up to and including peak ``k`` (the convention of
the simulator, whose labels change right after a step's event). Every detector
reports the peak (``t_peak_s``); ``boundary='edges'`` uses the detector's own
step start/end samples instead (its segmentation around the peak, e.g. zero
crossings or troughs).

``snap='strides'``: for foot-mounted sensors, a zero-velocity detector (default
``pseudo-std``; any of :data:`gaitml.zupt.DETECTORS`) finds the stance phases
and :func:`gaitml.zupt.segment_strides` cuts strides from mid-stance to
mid-stance; the stride starts are the boundaries.

``snap='none'``: boundaries stay where they were written (the per-step table
still uses the step detector).

A boundary with no candidate within ``max_snap_s`` stays where it was and is
reported; a boundary at the very start or end of the recording is not moved.
Two boundaries that would snap onto the same sample (an interval shorter than
a step) both stay and are reported.

The agreement of snapped labels with the truth on simulated walks, per seed and per
mode change, is measured by ``python -m experiments.scripts.label_snap``
(:func:`evaluate_snapping`; figures in ``experiments/reports/label-snap.md``).
"""

from gaitml.labels._evaluation import SNAP_DETECTORS, evaluate_snapping, perturb_intervals, sample_agreement
from gaitml.labels._intervals import check_intervals, intervals_from_labels, read_intervals
from gaitml.labels._labeller import BOUNDARY_KINDS, SNAP_MODES, SNAP_RULES, UNLABELLED, IntervalLabeller, label_recording
from gaitml.labels._plot import plot_label_report

__all__ = [
    "IntervalLabeller",
    "label_recording",
    "read_intervals",
    "check_intervals",
    "intervals_from_labels",
    "perturb_intervals",
    "sample_agreement",
    "evaluate_snapping",
    "SNAP_DETECTORS",
    "plot_label_report",
    "SNAP_MODES",
    "SNAP_RULES",
    "BOUNDARY_KINDS",
    "UNLABELLED",
]
