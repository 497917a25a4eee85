"""Reader for the IFSM paper's flat-held phone walks (xlsx, paper 000 data).

Each sheet has no header and four numeric columns: ax, ay, az (m/s^2, gravity
included) and the magnitude; no time column, sample k is at k / 50 s (Xiaomi 6,
50 Hz; see ``../shared/data/ifsm-flat-phone/README.md``). The published true
step counts are attached as ``reference['n_steps_true']`` for the two known files.
"""

from __future__ import annotations

import os
import zipfile
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError
from gaitml.io._common import require_file
from gaitml.recording import Recording

__all__ = ["read_ifsm_xlsx", "IFSM_RATE_HZ", "IFSM_TRUE_STEPS"]

#: Sampling rate of the IFSM recordings (paper 000 sec. 3: 50 Hz).
IFSM_RATE_HZ = 50.0
#: True step counts published with the data (paper 000 Table 2).
IFSM_TRUE_STEPS = {"acceleration_flat_holding_1": 284, "acceleration_flat_holding_2": 319}


def read_ifsm_xlsx(path: str | os.PathLike, *, sampling_rate_hz: float = IFSM_RATE_HZ) -> Recording:
    """Read an IFSM xlsx file (columns ax, ay, az, |a|; no header) at 50 Hz."""
    p = require_file(path)
    try:
        df = pd.read_excel(p, header=None)
    except (zipfile.BadZipFile, ValueError, KeyError, OSError) as exc:
        raise InputError(f"cannot read {p.name} as an IFSM xlsx ({exc}); the file may be truncated.") from exc
    if df.shape[1] < 3:
        raise InputError(f"{p.name} has {df.shape[1]} columns; an IFSM sheet has ax, ay, az[, |a|].")
    vals = df.iloc[:, :3].apply(pd.to_numeric, errors="coerce").to_numpy(dtype=float)
    bad = ~np.isfinite(vals).all(axis=1)
    if bad.any():
        raise InputError(
            f"{p.name}: {int(bad.sum())} rows with missing or non-numeric values (first at row {int(np.flatnonzero(bad)[0]) + 1}); fix the sheet."
        )
    ref = {}
    if p.stem in IFSM_TRUE_STEPS:
        ref["n_steps_true"] = IFSM_TRUE_STEPS[p.stem]
    meta = {
        "source": str(p),
        "format": "ifsm-xlsx",
        "id": p.stem,
        "subject": p.stem,
        "session": p.stem,
        "device": "Xiaomi 6",
        "position": "flat-hand",
    }
    return Recording(acc=vals, sampling_rate_hz=sampling_rate_hz, meta=meta, reference=ref)


def is_xlsx(path: Path) -> bool:
    """Whether the file is a zip container with an Excel workbook inside."""
    try:
        with zipfile.ZipFile(path) as z:
            return any(n.startswith("xl/") for n in z.namelist())
    except (zipfile.BadZipFile, OSError):
        return False
