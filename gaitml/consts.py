"""Units, column names and vocabularies shared by every gaitml module."""

from __future__ import annotations

#: Standard gravity in m/s^2 (paper 000 Table 1 uses A_T = 9.81).
GRAVITY_MS2 = 9.80665

#: The five motion modes of paper 003 (sec. 3): order used in reports.
MOTION_MODES = ("walk", "run", "side_left", "side_right", "backward")

#: Column names of the gaitml-csv v1 format (DESIGN sec. 3).
TIME_COL = "t"
ACC_COLS = ("acc_x", "acc_y", "acc_z")
GYR_COLS = ("gyr_x", "gyr_y", "gyr_z")
LABEL_COL = "label"

#: The step detector of ``gaitml pdr``, ``steps``, ``label`` and ``segment --by steps`` (and of
#: :func:`gaitml.pdr.run_pdr`, :func:`gaitml.segment.segment`, the labeller) when none is named:
#: the one that served real walkers best held out (``experiments/reports/tyrex-pdr.md``).
#: Paper 003's own detector is ``single-peak``, one option away.
DEFAULT_STEP_DETECTOR = "adaptive"

#: ``gaitml pdr --short-runs`` / :func:`gaitml.pdr.run_pdr`'s ``short_run_windows`` when not given: the short-run
#: rule's length in model windows (:func:`gaitml.pdr.step_modes.forward_short_runs`; 0: the rule off). Kept here, not
#: in :mod:`gaitml.pdr.step_modes`, so that building the command-line parser imports no algorithm; the choice and its
#: figures: :data:`gaitml.pdr.step_modes.SHORT_RUN_DEFAULT`.
SHORT_RUN_DEFAULT = 0.0

#: Columns of a step-event table (DESIGN sec. 2).
STEP_COLUMNS = ("start", "peak", "end", "t_start_s", "t_peak_s", "t_end_s", "period_s")

#: Columns of a zero-velocity interval table.
ZUPT_COLUMNS = ("start", "end", "t_start_s", "t_end_s")

DEG2RAD = 3.141592653589793 / 180.0

#: Largest |value| any accelerometer in a phone or wearable IMU can report, m/s^2
#: (500 g). Phone accelerometers have full-scale ranges of +-2..+-16 g (Bosch
#: BMI270, ST LSM6DSO datasheets), the widest wearable parts +-32 g (ST LSM6DSO32)
#: and +-320 g on a dedicated high-g channel (ST LSM6DSV320X), shock sensors for
#: impact studies +-200 g (ADI ADXL375); the human body outside crashes and
#: head impacts stays far below 100 g. A larger value cannot have been measured:
#: it is a corrupt row or a wrong unit. Used by :class:`gaitml.recording.Recording`.
ACC_LIMIT_MS2 = 500.0 * GRAVITY_MS2

#: Largest |value| any gyroscope of a phone or wearable can report, rad/s
#: (20,000 deg/s = 349 rad/s). Phone gyroscopes have full-scale ranges of
#: +-125..+-2000 deg/s (Bosch BMI270, ST LSM6DSO/LSM6DSO32 datasheets), the widest
#: phone/wearable IMUs +-4000 deg/s (ST LSM6DSV, LSM6DSV32X, LSM6DSV320X datasheets);
#: the limit is 5x that, and more than twice the fastest human segment rotation
#: (shoulder internal rotation in a baseball pitch, ~7000-9000 deg/s). A larger
#: value cannot have been measured: it is a corrupt row or a wrong unit.
GYR_LIMIT_RADS = 20_000.0 * DEG2RAD

#: The widest full-scale range of a phone or wearable IMU gyroscope, rad/s
#: (+-4000 deg/s, ST LSM6DSV family): a rad/s column whose 99th percentile is
#: above this cannot come from such a sensor (it is deg/s).
GYR_FULL_SCALE_MAX_RADS = 4000.0 * DEG2RAD
