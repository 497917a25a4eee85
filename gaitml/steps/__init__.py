"""Step detectors (one algorithm per module) and the step table."""

from gaitml.steps._table import empty_step_table, make_step_table

__all__ = ["empty_step_table", "make_step_table"]
