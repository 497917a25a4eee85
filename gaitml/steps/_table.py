"""The step-event table every step detector returns (DESIGN sec. 2)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from gaitml.consts import STEP_COLUMNS

__all__ = ["make_step_table", "empty_step_table", "gait_check_record"]


def make_step_table(
    start: np.ndarray,
    peak: np.ndarray,
    end: np.ndarray,
    sampling_rate_hz: float,
    *,
    event: str,
    period_s: np.ndarray | None = None,
    **extra: np.ndarray,
) -> pd.DataFrame:
    """Build a step table: one row per step, sample indices and times.

    Parameters
    ----------
    start, peak, end : int arrays
        Sample indices; ``end`` is exclusive (the step covers ``[start, end)``).
    sampling_rate_hz : float
    event : {'t_end_s', 't_peak_s'}
        Which time stands for the step when matching to ground truth (FSM
        detectors: step completion ``t_end_s``; peak detectors: ``t_peak_s``).
        Stored in ``table.attrs['event']``.
    period_s : float array, optional
        Step period; default ``(end - start) / sampling_rate_hz``.
    **extra : detector-specific columns.
    """
    start = np.asarray(start, dtype=np.int64)
    peak = np.asarray(peak, dtype=np.int64)
    end = np.asarray(end, dtype=np.int64)
    fs = float(sampling_rate_hz)
    if period_s is None:
        period_s = (end - start) / fs
    table = pd.DataFrame(
        {
            "start": start,
            "peak": peak,
            "end": end,
            "t_start_s": start / fs,
            "t_peak_s": peak / fs,
            "t_end_s": end / fs,
            "period_s": np.asarray(period_s, dtype=float),
            **{k: np.asarray(v) for k, v in extra.items()},
        }
    )
    if event not in ("t_end_s", "t_peak_s", "t_start_s"):
        raise ValueError(f"event must be 't_end_s', 't_peak_s' or 't_start_s', got {event!r}")
    table.attrs["event"] = event
    table.attrs["sampling_rate_hz"] = fs
    return table


def empty_step_table(sampling_rate_hz: float, *, event: str) -> pd.DataFrame:
    """A step table with no rows (and the right columns)."""
    z = np.zeros(0, dtype=np.int64)
    return make_step_table(z, z, z, sampling_rate_hz, event=event)


assert STEP_COLUMNS[:3] == ("start", "peak", "end")


def gait_check_record(account: dict | None) -> dict | None:
    """A step table's gait-evidence account (``steps.attrs['gait_check']``, from
    :func:`gaitml.steps._gait_evidence.gait_check`) as a JSON-ready dict, or None when no test ran."""
    if account is None:
        return None
    out = {k: v.item() if isinstance(v, np.generic) else v for k, v in account.items() if k != "rejected_t_s"}
    out["rejected_t_s"] = [float(v) for v in account.get("rejected_t_s", [])]
    return out
