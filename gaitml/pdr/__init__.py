"""Pedestrian dead reckoning (paper 003 sec. 4, paper 002 sec. 3; DESIGN sec. 4).

- :mod:`~gaitml.pdr.step_length`: linear and Weinberg step length models per mode.
- :mod:`~gaitml.pdr.attitude`: quaternion gyro integration, heading of the phone's forward axis.
- :mod:`~gaitml.pdr.heading`: the heading-source base (``estimate(recording, steps)``) and the raw gyro heading.
- :mod:`~gaitml.pdr.hde`: buffered heuristic drift elimination.
- :mod:`~gaitml.pdr.dwpca`: dynamic-window PCA step direction.
- :mod:`~gaitml.pdr.update`: multi-state and forward-only position updates.
- :mod:`~gaitml.pdr.step_modes`: per-step modes from window predictions, mode-boundary refinement.
- :mod:`~gaitml.pdr.pipeline`: :func:`run_pdr`, recording -> trajectory.
- :mod:`~gaitml.pdr.calibrate`: per-subject step length / DW-PCA calibration (from true steps, a truth
  trajectory such as motion capture, or a known distance).
- :mod:`~gaitml.pdr.plot`; the simulated-route report is ``python -m experiments.scripts.pdr_report`` (source checkout).
"""

from gaitml.pdr.attitude import AttitudeEstimator, compass_heading, initial_attitude, integrate_gyro, step_headings, wrap_angle
from gaitml.pdr.dwpca import DwPcaHdeHeading, DwPcaHeading, dwpca_check_and_average, pca_step_directions
from gaitml.pdr.hde import HeuristicDriftElimination, direction_structure, estimate_drift_rate, hde_correct, hde_heading
from gaitml.pdr.heading import BaseHeadingSource, GyroHeading
from gaitml.pdr.pipeline import HEADING_SOURCES, MODE_SOURCES, PdrResult, modes_from_labels, run_pdr
from gaitml.pdr.step_length import StepLengthModel, linear_step_length, step_length_features, weinberg_step_length
from gaitml.pdr.step_modes import MODE_ASSIGNMENTS, modes_from_windows, pair_margin, refine_mode_boundaries
from gaitml.pdr.update import MODE_OFFSET_RAD, dead_reckon, forward_update, mode_offsets_rad, multi_state_update

__all__ = [
    "HEADING_SOURCES",
    "MODE_ASSIGNMENTS",
    "MODE_OFFSET_RAD",
    "MODE_SOURCES",
    "AttitudeEstimator",
    "BaseHeadingSource",
    "Calibration",
    "DwPcaHdeHeading",
    "DwPcaHeading",
    "GyroHeading",
    "HeuristicDriftElimination",
    "PdrResult",
    "StepLengthModel",
    "calibrate_from_reference",
    "calibrate_from_truth",
    "calibrate_walk_distance",
    "compass_heading",
    "dead_reckon",
    "direction_structure",
    "dwpca_check_and_average",
    "estimate_drift_rate",
    "forward_update",
    "hde_correct",
    "hde_heading",
    "initial_attitude",
    "integrate_gyro",
    "linear_step_length",
    "mode_offsets_rad",
    "modes_from_labels",
    "modes_from_windows",
    "multi_state_update",
    "pair_margin",
    "pca_step_directions",
    "refine_mode_boundaries",
    "run_pdr",
    "step_headings",
    "step_length_features",
    "weinberg_step_length",
    "wrap_angle",
]


#: Names served from :mod:`gaitml.pdr.calibrate` on first use: importing the package does not import that module, so
#: ``python -m gaitml.pdr.calibrate`` runs it as ``__main__`` without runpy's double-import warning.
_CALIBRATE_NAMES = ("Calibration", "calibrate_from_reference", "calibrate_from_truth", "calibrate_walk_distance")


def __getattr__(name: str):
    if name in _CALIBRATE_NAMES:
        from gaitml.pdr import calibrate

        return getattr(calibrate, name)
    raise AttributeError(f"module 'gaitml.pdr' has no attribute {name!r}")
