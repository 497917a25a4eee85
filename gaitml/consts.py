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

#: Columns of a step-event table (DESIGN sec. 2).
STEP_COLUMNS = ("start", "peak", "end", "t_start_s", "t_peak_s", "t_end_s", "period_s")

#: Columns of a zero-velocity interval table.
ZUPT_COLUMNS = ("start", "end", "t_start_s", "t_end_s")

DEG2RAD = 3.141592653589793 / 180.0
