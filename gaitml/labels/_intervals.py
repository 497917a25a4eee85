"""Reading and checking hand-written time intervals (CSV ``start_s,end_s,label`` or an Audacity label track)."""

from __future__ import annotations

import io
import os
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.errors import InputError

__all__ = ["check_intervals", "intervals_from_labels", "read_intervals"]

#: Tolerance (s) of the interval comparisons.
_EPS = 1e-9


def read_intervals(path: str | os.PathLike) -> pd.DataFrame:
    """Read an intervals file: CSV ``start_s,end_s,label`` or an Audacity label track.

    An Audacity label track has one label per line, ``start<TAB>end<TAB>label``
    in seconds; lines beginning with ``\\`` (Audacity's frequency range of a
    spectral selection) are skipped. A CSV needs a header with ``start_s``,
    ``end_s`` and ``label``.

    Returns
    -------
    DataFrame
        ``start_s``, ``end_s``, ``label`` and ``line`` (the line in the file),
        in file order. Not yet checked against a recording: see
        :func:`check_intervals`.

    Raises
    ------
    InputError
        Empty file, missing columns, non-numeric times, empty labels, point
        labels (start == end) or reversed intervals, each naming the line.
    """
    p = Path(path)
    if not p.exists():
        raise InputError(f"no such intervals file: {p}; check the path.")
    text = p.read_text(encoding="utf-8-sig", errors="replace")
    lines = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip()]
    if not lines:
        raise InputError(f"the intervals file {p.name} is empty; write one 'start_s,end_s,label' row per interval.")
    first = lines[0][1].split("\t")
    if len(first) >= 2 and _is_number(first[0]) and _is_number(first[1]):
        rows = []
        for n, ln in lines:
            if ln.startswith("\\"):
                continue
            parts = ln.split("\t")
            if len(parts) < 2 or not (_is_number(parts[0]) and _is_number(parts[1])):
                raise InputError(f"{p.name} line {n} is not an Audacity label (start<TAB>end<TAB>label): {ln[:60]!r}; fix that line.")
            rows.append((float(parts[0]), float(parts[1]), parts[2].strip() if len(parts) > 2 else "", n))
        df = pd.DataFrame(rows, columns=["start_s", "end_s", "label", "line"])
        kind = "Audacity label track"
    else:
        try:
            df = pd.read_csv(io.StringIO(text), skipinitialspace=True, dtype={"label": str}, keep_default_na=False)
        except (pd.errors.ParserError, pd.errors.EmptyDataError) as exc:
            raise InputError(f"cannot parse {p.name} as CSV ({str(exc).splitlines()[0]}); write 'start_s,end_s,label' rows.") from exc
        df.columns = [str(c).strip().lower() for c in df.columns]
        missing = [c for c in ("start_s", "end_s", "label") if c not in df.columns]
        if missing:
            raise InputError(
                f"{p.name} lacks the columns {missing} (found {list(df.columns)[:6]}); write a header 'start_s,end_s,label' "
                "or export an Audacity label track."
            )
        if len(df) == 0:
            raise InputError(f"the intervals file {p.name} has a header but no intervals; add 'start_s,end_s,label' rows.")
        data_lines = [n for n, _ in lines[1:]]
        df = df[["start_s", "end_s", "label"]].copy()
        df["line"] = data_lines[: len(df)]
        for c in ("start_s", "end_s"):
            num = pd.to_numeric(df[c], errors="coerce")
            if num.isna().any():
                i = int(np.flatnonzero(num.isna().to_numpy())[0])
                raise InputError(f"{p.name} line {df['line'].iloc[i]}: {c} {df[c].iloc[i]!r} is not a number of seconds; fix that row.")
            df[c] = num.astype(float)
        df["label"] = df["label"].astype(str).str.strip()
        kind = "CSV"
    for row in df.itertuples():
        if not np.isfinite(row.start_s) or not np.isfinite(row.end_s):
            raise InputError(f"{p.name} line {row.line}: the times must be finite numbers of seconds; fix that row.")
        if not row.label:
            raise InputError(f"{p.name} line {row.line}: the interval {row.start_s:g}-{row.end_s:g} s has no label; name it or delete it.")
        if row.end_s == row.start_s:
            raise InputError(
                f"{p.name} line {row.line}: {row.label!r} is a point label at {row.start_s:g} s, not an interval; "
                "mark a region (in Audacity drag across the time range before adding the label), or give end_s > start_s."
            )
        if row.end_s < row.start_s:
            raise InputError(
                f"{p.name} line {row.line}: {row.label!r} ends ({row.end_s:g} s) before it starts ({row.start_s:g} s); swap or fix the times."
            )
    df.attrs["source"] = str(p)
    df.attrs["kind"] = kind
    return df.reset_index(drop=True)


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


def check_intervals(intervals: pd.DataFrame, duration_s: float, sampling_rate_hz: float) -> pd.DataFrame:
    """Sort intervals by start and refuse overlaps and times outside the recording.

    An interval may end up to one sample period after the last sample (the
    recording's ``duration_s``); touching intervals (one ends where the next
    starts) are fine.

    Returns
    -------
    DataFrame
        The intervals sorted by ``start_s``.
    """
    need = {"start_s", "end_s", "label"}
    if not need <= set(intervals.columns):
        raise InputError(f"intervals need the columns start_s, end_s, label; got {list(intervals.columns)}.")
    df = intervals.copy()
    if "line" not in df.columns:
        df["line"] = np.arange(len(df)) + 1
    if len(df) == 0:
        raise InputError("no intervals given; write at least one 'start_s,end_s,label' row.")
    if (df["end_s"] <= df["start_s"]).any():
        row = df[df["end_s"] <= df["start_s"]].iloc[0]
        raise InputError(
            f"interval {row['label']!r} (line {row['line']}) has end_s {row['end_s']:g} <= start_s {row['start_s']:g}; give end_s > start_s."
        )
    df = df.sort_values("start_s", kind="stable").reset_index(drop=True)
    tol = 1.0 / sampling_rate_hz
    early = df[df["start_s"] < -_EPS]
    if len(early):
        row = early.iloc[0]
        raise InputError(
            f"interval {row['label']!r} (line {row['line']}) starts at {row['start_s']:g} s, before the recording (0 s); start it at 0 or later."
        )
    late = df[df["end_s"] > duration_s + tol + _EPS]
    if len(late):
        row = late.iloc[0]
        raise InputError(
            f"interval {row['label']!r} (line {row['line']}) ends at {row['end_s']:g} s, after the recording ends ({duration_s:.3f} s); "
            "end it within the recording (times are seconds from the first sample)."
        )
    ends = df["end_s"].to_numpy()
    starts = df["start_s"].to_numpy()
    bad = np.flatnonzero(starts[1:] < ends[:-1] - _EPS)
    if len(bad):
        a, b = df.iloc[bad[0]], df.iloc[bad[0] + 1]
        raise InputError(
            f"intervals overlap: {a['label']!r} {a['start_s']:g}-{a['end_s']:g} s (line {a['line']}) and {b['label']!r} "
            f"{b['start_s']:g}-{b['end_s']:g} s (line {b['line']}); let each interval end at or before the next one starts."
        )
    return df


def intervals_from_labels(labels: np.ndarray, sampling_rate_hz: float) -> pd.DataFrame:
    """The runs of equal labels as intervals ``start_s, end_s, label`` (half-open, s from the first sample)."""
    lab = np.asarray(labels).astype(str)
    if len(lab) == 0:
        return pd.DataFrame(columns=["start_s", "end_s", "label"])
    change = np.flatnonzero(lab[1:] != lab[:-1]) + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [len(lab)]])
    return pd.DataFrame({"start_s": starts / sampling_rate_hz, "end_s": ends / sampling_rate_hz, "label": lab[starts]})
