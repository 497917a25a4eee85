"""Step counting from acceleration-magnitude zero-velocity intervals (paper 004).

Chen & Yang, "Step Counting Algorithm Based on Zero Velocity Update", Geomatics
and Information Science of Wuhan University 42(6), 2017 (``papers/004``), sec. 2.
For a foot-mounted sensor every zero-velocity (foot-flat) interval that survives
the pseudo-zero rejection is one step of that foot.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
import pandas as pd

from gaitml._base import POSITIVE
from gaitml.errors import InputError
from gaitml.recording import Recording
from gaitml.steps._base import BaseStepDetector
from gaitml.steps._table import make_step_table
from gaitml.zupt.magnitude import DEFAULT_T_MAX_MS2, DEFAULT_T_MIN_MS2, MIN_RUN_FRACTION_OF_FS, MagnitudeZuptDetector

__all__ = ["RATE_FLOOR_HZ", "ZuptMagnitudeStepDetector", "steps_from_zupts"]


def steps_from_zupts(
    zupts: pd.DataFrame, sampling_rate_hz: float, *, n_samples: int | None = None, count_leading: bool = False
) -> pd.DataFrame:
    """One step per zero-velocity interval (paper 004 sec. 2.2 step 3).

    Parameters
    ----------
    zupts : DataFrame with ``start``, ``end`` (exclusive) sample columns.
    sampling_rate_hz : float
    n_samples : int, optional
        Length of the recording (unused except for validation).
    count_leading : bool
        Count an interval that begins at sample 0 (default False: the foot was
        already on the ground when the recording started, no landing was observed,
        so it is not a step).

    Returns
    -------
    DataFrame
        The DESIGN step table: ``start``/``end`` = the interval (foot-flat),
        ``peak`` = its middle sample, ``period_s`` = time from the previous
        step's start (the first step gets the next step's period, or its own
        duration when it is the only one), ``duration_s`` = foot-flat duration.
        ``attrs['event'] = 't_start_s'``: a step is dated at the foot landing.
    """
    start = np.asarray(zupts["start"], dtype=np.int64)
    end = np.asarray(zupts["end"], dtype=np.int64)
    if n_samples is not None and len(end) and end.max() > n_samples:
        raise InputError(f"zero-velocity interval ends at {int(end.max())} beyond the recording ({n_samples} samples).")
    if not count_leading and len(start) and start[0] == 0:
        start, end = start[1:], end[1:]
    fs = float(sampling_rate_hz)
    peak = (start + end - 1) // 2
    if len(start) >= 2:
        period = np.diff(start) / fs
        period = np.concatenate(([period[0]], period))
    else:
        period = (end - start) / fs
    return make_step_table(start, peak, end, fs, event="t_start_s", period_s=period, duration_s=(end - start) / fs)


#: lowest recording rate (Hz) zupt-magnitude's count holds at: paper 004 records its foot-mounted sensor at 50 Hz
#: (sec. 3); the floor rule of :mod:`gaitml.steps._rate` on the tyrex phones gives the same (no foot-mounted
#: recording was taken down; the figures: experiments/reports/tyrex-steps.md, 'rate floors')
RATE_FLOOR_HZ = 50.0


class ZuptMagnitudeStepDetector(BaseStepDetector):
    """The ``zupt-magnitude`` step detector: paper 004's step counter.

    Parameters
    ----------
    t_min_ms2, t_max_ms2 : float, default 9.0 / 11.0
        |a| band of paper 004 eq. (3) (default 9-11 m/s^2, gravity included; see
        :mod:`gaitml.zupt.magnitude` for why, the paper prints no values).
    min_run_fraction : float
        Pseudo-zero rejection: runs shorter than this fraction of the sampling
        frequency are dropped (paper: 0.10).
    count_leading : bool
        Count an interval that starts at the first sample (default False).

    Attributes
    ----------
    steps_ : DataFrame
        Step table (``gaitml.steps.make_step_table``), event ``t_start_s``.
    zupts_ : DataFrame
        The zero-velocity intervals the steps come from.

    Notes
    -----
    Meant for a foot-mounted sensor: each foot-flat interval of that foot is one
    of its steps (one stride of the gait cycle). A recording that starts or ends
    standing still has a long interval at its ends; the leading one is not a
    landing and is not counted, the trailing one is the last landing and is.

    References
    ----------
    Paper 004 (Chen & Yang, 2017), sec. 2.2, Fig. 6.
    """

    name = "zupt-magnitude"
    rate_floor_hz = RATE_FLOOR_HZ
    _parameter_constraints: ClassVar[dict[str, list]] = {
        "min_run_fraction": [POSITIVE],
    }

    def __init__(
        self,
        *,
        t_min_ms2: float = DEFAULT_T_MIN_MS2,
        t_max_ms2: float = DEFAULT_T_MAX_MS2,
        min_run_fraction: float = MIN_RUN_FRACTION_OF_FS,
        count_leading: bool = False,
    ):
        self.t_min_ms2 = t_min_ms2
        self.t_max_ms2 = t_max_ms2
        self.min_run_fraction = min_run_fraction
        self.count_leading = count_leading

    def detect(self, recording: Recording) -> ZuptMagnitudeStepDetector:
        """Detect steps; sets ``steps_`` and ``zupts_`` and returns ``self``."""
        params = self._validate_params()
        if not isinstance(recording, Recording):
            raise InputError(f"detect needs a gaitml Recording, got {type(recording).__name__}.")
        count_leading = params.pop("count_leading")
        det = MagnitudeZuptDetector(**params).detect(recording)
        self.zupts_ = det.zupts_
        self.per_sample_zupts_ = det.per_sample_zupts_
        self.steps_ = steps_from_zupts(det.zupts_, recording.sampling_rate_hz, n_samples=recording.n_samples, count_leading=count_leading)
        return self
