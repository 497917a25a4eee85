"""gaitml-csv v1: the package's own recording format (DESIGN sec. 3).

One CSV per recording with a header row: ``t`` (s, increasing, may be
irregular), ``acc_x, acc_y, acc_z`` (m/s^2, gravity included), optional
``gyr_x, gyr_y, gyr_z`` (rad/s) and optional ``label``. Other columns are not
read; their names are listed in ``meta['ignored_columns']``.

Sidecar files written by the simulator are read as ground truth when they sit
beside the recording: ``<stem>.steps.csv`` (true steps; ``reference['steps_t_s']``
and ``reference['steps']``) and ``<stem>.trajectory.csv``
(``reference['trajectory']``).

A data set is a folder of such files plus an optional ``manifest.csv`` with
columns ``file, subject, session`` and any free columns, which become each
recording's ``meta``. Without a manifest, subject and session are the file stem.
"""

from __future__ import annotations

import dataclasses
import gzip
import os
import re
import zlib
from pathlib import Path

import numpy as np
import pandas as pd

from gaitml.consts import ACC_COLS, GYR_COLS, LABEL_COL, TIME_COL
from gaitml.errors import InputError
from gaitml.io._atomic import write_csv
from gaitml.io._common import require_file
from gaitml.recording import Recording

__all__ = [
    "read_gaitml_csv",
    "write_gaitml_csv",
    "read_gaitml_folder",
    "write_manifest",
    "SIDECAR_SUFFIXES",
    "is_gaitml_header",
]

#: Files with these endings beside a recording are ground truth, not recordings.
SIDECAR_SUFFIXES = (".steps.csv", ".trajectory.csv", ".windows.csv", ".pred.csv", ".step-labels.csv")
REQUIRED = (TIME_COL, *ACC_COLS)


def is_gaitml_header(columns: list[str]) -> bool:
    """Whether a header row has the gaitml-csv required columns."""
    cols = [c.strip().strip('"') for c in columns]
    return all(c in cols for c in REQUIRED)


#: Field separators accepted for a gaitml-csv: ',' (the format), and ';' / tab as
#: spreadsheet programs write them in locales with a decimal comma.
SEPARATORS = (",", ";", "\t")


def sniff_dialect(lines: list[str]) -> tuple[str, str] | None:
    """``(separator, decimal)`` of a gaitml-csv from its first lines, or None if the header is not one.

    The separator is the first of :data:`SEPARATORS` that splits the header into
    the required columns; with ';' or tab a ',' in the first data line means a
    decimal comma.
    """
    if not lines:
        return None
    for sep in SEPARATORS:
        if is_gaitml_header(lines[0].split(sep)):
            decimal = "," if sep != "," and len(lines) > 1 and "," in lines[1] else "."
            return sep, decimal
    return None


def looks_like_gaitml(lines: list[str]) -> bool:
    """Whether a header is an attempt at a gaitml-csv: it has a ``t`` column and an acc or gyr column."""
    if not lines:
        return False
    for sep in SEPARATORS:
        cols = [c.strip().strip('"') for c in lines[0].split(sep)]
        if TIME_COL in cols and any(c in cols for c in (*ACC_COLS, *GYR_COLS)):
            return True
    return False


def _short(name: object, n: int = 40) -> str:
    text = str(name)
    return text if len(text) <= n else text[: n - 3] + "..."


def read_gaitml_csv(
    path: str | os.PathLike,
    *,
    sampling_rate_hz: float | None = None,
    acc_unit: str = "m/s^2",
    gyr_unit: str = "rad/s",
    meta: dict | None = None,
    segments: bool = False,
) -> Recording | list[Recording]:
    """Read one gaitml-csv file into a :class:`Recording`.

    With ``segments=True`` the file is cut at every gap too long to bridge and a
    list of recordings is returned (see :meth:`Recording.segments_from_timestamps`);
    by default such a gap is refused.

    Uniform timestamps are kept; irregular ones are resampled by linear
    interpolation (see :meth:`Recording.from_timestamps`) to ``sampling_rate_hz``
    or, if not given, to the median rate, and the resampling is reported in
    ``meta``.
    """
    p = require_file(path)
    df = _read_table(p)
    cols = check_columns(p, list(df.columns), n_rows=len(df))
    block = parse_block(p, df, cols, first_line=2)
    block.raise_nan(p)
    m = {"source": str(p), "format": "gaitml-csv", "id": p.stem, "subject": p.stem, "session": p.stem}
    if cols.ignored:
        m["ignored_columns"] = cols.ignored
    m.update(meta or {})
    reference = _read_sidecars(p)
    check_sidecar_times(p, reference, block.t)
    build = Recording.segments_from_timestamps if segments else Recording.from_timestamps
    t, acc, gyr, labels = block.t, block.acc, block.gyr, block.labels
    if len(t) > 1 and (np.diff(t) > 0).all():  # sample-and-hold columns (gaitml.io._hold); bad times are refused below
        from gaitml.io.columns_csv import dehold_rows

        t, acc, gyr, labels = dehold_rows(t, acc, gyr, labels, m, p.name)
    return build(
        t,
        acc,
        gyr=gyr,
        labels=labels,
        sampling_rate_hz=sampling_rate_hz,
        meta=m,
        reference=reference,
        acc_unit=acc_unit,
        gyr_unit=gyr_unit,
    )


@dataclasses.dataclass(frozen=True)
class Columns:
    """The columns of a gaitml-csv: whether it has a gyroscope and labels, and the columns not read."""

    has_gyr: bool
    has_labels: bool
    ignored: list[str]


def check_columns(p: Path, columns: list[str], *, n_rows: int | None = None) -> Columns:
    """Refuse a header without the required columns, with part of the gyroscope, or a file without rows."""
    missing = [c for c in REQUIRED if c not in columns]
    if missing:
        found = [_short(c) for c in columns[:8]]
        raise InputError(
            f"{_short(p.name)} is not a gaitml-csv: missing columns {missing} (found {found}); "
            f"expected {', '.join(REQUIRED)} [, {', '.join(GYR_COLS)}] [, {LABEL_COL}]."
        )
    if n_rows == 0:
        raise InputError(f"{p.name} has a header but no samples; record or export the data again.")
    has_gyr = [c for c in GYR_COLS if c in columns]
    if has_gyr and len(has_gyr) != 3:
        raise InputError(f"{p.name} has only {has_gyr} of the gyro columns; give all of {', '.join(GYR_COLS)} or none.")
    num_cols = [*REQUIRED, *has_gyr]
    return Columns(bool(has_gyr), LABEL_COL in columns, [c for c in columns if c not in (*num_cols, LABEL_COL)])


@dataclasses.dataclass
class Block:
    """Rows of a gaitml-csv as arrays (``t``, ``acc``, ``gyr``, ``labels``) and its rows with NaN/inf values."""

    t: np.ndarray
    acc: np.ndarray
    gyr: np.ndarray | None
    labels: np.ndarray | None
    nan_first_line: int | None = None
    nan_count: int = 0

    def raise_nan(self, p: Path) -> None:
        """Refuse the rows with NaN/inf values (the count and the first line)."""
        if self.nan_count:
            raise InputError(
                f"{p.name}: {self.nan_count} rows with NaN/inf values (first at line {self.nan_first_line}); "
                "remove or interpolate them before loading."
            )


#: Characters a label may not hold (control characters: a NUL byte, escape codes...).
_CONTROL = re.compile(r"[\x00-\x08\x0b-\x1f\x7f]")


def parse_block(p: Path, df: pd.DataFrame, cols: Columns, *, first_line: int) -> Block:
    """Check and convert rows of a gaitml-csv (the whole file, or one block of a long one).

    ``first_line`` is the file line of the block's first row, for the messages.
    Numeric columns must be numbers (a decimal comma or a date in ``t`` is named
    with its fix); labels are kept as the strings written (``"01"`` stays
    ``"01"``, ``"NA"`` and ``"None"`` are labels), and an empty label or one with
    a control character is refused. Rows with NaN/inf are counted in the block
    (:meth:`Block.raise_nan` refuses them) so that a long file read in blocks is
    refused with the same count as when read whole.
    """
    num_cols = [*REQUIRED, *(GYR_COLS if cols.has_gyr else ())]
    for c in num_cols:
        if not pd.api.types.is_numeric_dtype(df[c]):
            bad = pd.to_numeric(df[c], errors="coerce").isna() & df[c].notna()
            row = int(np.flatnonzero(bad.to_numpy())[0]) if bad.any() else 0
            value = _short(df[c].iloc[row], 30)
            if re.fullmatch(r"\s*[-+]?\d+,\d+\s*", str(df[c].iloc[row])):
                raise InputError(
                    f"{p.name}: column {c!r} has the decimal comma {value!r} at line {row + first_line}; "
                    "write decimals with '.', or separate the fields with ';' (then decimal commas are read)."
                )
            if c == TIME_COL:
                raise InputError(
                    f"{p.name}: the time column 't' holds {value!r} at line {row + first_line}, not a number of seconds; "
                    "write t as seconds (e.g. 0.02), not a date or clock time."
                )
            raise InputError(
                f"{p.name}: column {c!r} has a non-numeric value at line {row + first_line} ({value!r}); fix or remove that row."
            )
    vals = df[num_cols].to_numpy(dtype=float)
    nan_rows = df[num_cols].isna().any(axis=1).to_numpy() | ~np.isfinite(vals).all(axis=1)
    labels = None
    if cols.has_labels:
        raw = df[LABEL_COL]
        lab = raw.fillna("").astype(str).to_numpy(dtype=object)
        empty = np.array([not str(v).strip() for v in lab], dtype=bool)
        if empty.any():
            first = int(np.flatnonzero(empty)[0])
            raise InputError(f"{p.name}: empty label at line {first + first_line}; label every sample or drop the label column.")
        ctrl = np.array([bool(_CONTROL.search(v)) for v in lab], dtype=bool)
        if ctrl.any():
            first = int(np.flatnonzero(ctrl)[0])
            raise InputError(
                f"{p.name}: the label at line {first + first_line} holds a control character ({lab[first]!r}); "
                "write labels as plain text (no NUL bytes or escape codes)."
            )
        labels = lab.astype(str)
    nan_first = int(np.flatnonzero(nan_rows)[0]) + first_line if nan_rows.any() else None
    return Block(
        t=vals[:, 0],
        acc=vals[:, 1:4],
        gyr=vals[:, 4:7] if cols.has_gyr else None,
        labels=labels,
        nan_first_line=nan_first,
        nan_count=int(nan_rows.sum()),
    )


def csv_options(p: Path) -> dict:
    """The ``pandas.read_csv`` options of a gaitml-csv: dialect sniffed, labels read as the strings written.

    Only empty fields and pandas' NA words (``nan``, ``NaN``, ``NA``...) in the
    numeric columns are missing values; the label column is text as written.
    """
    from pandas._libs.parsers import STR_NA_VALUES

    from gaitml.io._common import head_lines

    sep, decimal = sniff_dialect(head_lines(p, 2)) or (",", ".")
    na = sorted(STR_NA_VALUES)
    return {
        "sep": sep,
        "decimal": decimal,
        "skipinitialspace": True,
        "index_col": False,
        "encoding": "utf-8-sig",
        "dtype": {LABEL_COL: str},
        "keep_default_na": False,
        "na_values": {c: na for c in (*REQUIRED, *GYR_COLS)},
    }


def _read_table(p: Path, *, chunksize: int | None = None):
    """Read a gaitml-csv into a DataFrame (or an iterator of blocks of ``chunksize`` rows):
    dialect sniffed, ragged rows and duplicate columns refused."""
    reader = _guard_reading(p, lambda: pd.read_csv(p, chunksize=chunksize, **csv_options(p)))
    if chunksize is None:
        return _clean_columns(p, reader)
    return _blocks(p, reader)


def _blocks(p: Path, reader):
    try:
        it = iter(reader)
        while True:
            df = _guard_reading(p, lambda: next(it, None))
            if df is None:
                return
            yield _clean_columns(p, df)
    finally:
        reader.close()


def _guard_reading(p: Path, read):
    """Run ``read()`` turning pandas' parsing errors into one-line InputErrors."""
    import warnings

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", pd.errors.ParserWarning)
            return read()
    except pd.errors.EmptyDataError as exc:
        raise InputError(f"the file is empty: {p}; record or export the data again.") from exc
    except pd.errors.ParserWarning as exc:
        raise InputError(
            f"{p.name}: some rows have more fields than the header; if numbers use a decimal comma, separate fields with ';' "
            "(or write decimals with '.'), and quote text that contains the separator."
        ) from exc
    except (pd.errors.ParserError, UnicodeDecodeError, ValueError) as exc:
        raise InputError(
            f"cannot parse {p.name} as CSV ({_short(str(exc).splitlines()[0], 120)}); check the file is a gaitml-csv."
        ) from exc
    except (EOFError, zlib.error, gzip.BadGzipFile, OSError) as exc:
        raise InputError(f"cannot read {p.name}: {_short(exc, 120)}; the compressed file is truncated or corrupt.") from exc


def _clean_columns(p: Path, df: pd.DataFrame) -> pd.DataFrame:
    names = [str(c).strip() for c in df.columns]
    dup = sorted({c for c in names if names.count(c) > 1})
    dup += sorted({c.rsplit(".", 1)[0] for c in names if "." in c and c.rsplit(".", 1)[0] in names and c.rsplit(".", 1)[1].isdigit()})
    dup = [c for c in dup if c in (*REQUIRED, *GYR_COLS, LABEL_COL)]
    if dup:
        raise InputError(f"{p.name} has the column {dup[0]!r} more than once; keep one column per name.")
    df.columns = names
    return df


def _stem(path: Path) -> str:
    name = path.name
    for ext in (".csv.gz", ".csv"):
        if name.endswith(ext):
            return name[: -len(ext)]
    return path.stem


def _read_sidecars(p: Path) -> dict:
    ref: dict = {}
    stem = _stem(p)
    steps = p.with_name(f"{stem}.steps.csv")
    if steps.exists():
        tab = pd.read_csv(steps)
        if "t_s" not in tab.columns:
            raise InputError(f"{steps.name} has no 't_s' column; a steps sidecar needs t_s (s) per true step.")
        ref["steps"] = tab
        ref["steps_t_s"] = tab["t_s"].to_numpy(dtype=float)
    traj = p.with_name(f"{stem}.trajectory.csv")
    if traj.exists():
        ref["trajectory"] = pd.read_csv(traj)
    return ref


#: Sidecar event times may lie this far (s) outside the recording's timestamps (an event at its very edge).
SIDECAR_SLACK_S = 1.0


def check_sidecar_times(p: Path, reference: dict, t: np.ndarray) -> None:
    """Refuse sidecar event times (``<stem>.steps.csv``'s ``t_s``) outside the recording's time span.

    They are on the recording's clock in seconds; times beyond the recording
    are another unit or another clock, and scoring against them would give
    F1 = 0 without a word. When the times divided by 1000 fall inside, the
    message names milliseconds.
    """
    v = np.asarray(reference.get("steps_t_s", []), dtype=float)
    if not len(v) or not len(t):
        return
    lo, hi = float(t[0]) - SIDECAR_SLACK_S, float(t[-1]) + SIDECAR_SLACK_S
    if np.isfinite(v).all() and v.min() >= lo and v.max() <= hi:
        return
    name = f"{_stem(p)}.steps.csv"
    span = f"the recording runs from t = {t[0]:.6g} to {t[-1]:.6g} s"
    if np.isfinite(v).all() and (v / 1000).min() >= lo and (v / 1000).max() <= hi:
        raise InputError(
            f"{name}: t_s runs from {v.min():.6g} to {v.max():.6g} but {span}: the step times look like milliseconds; "
            "write t_s in seconds (divide by 1000)."
        )
    raise InputError(
        f"{name}: t_s runs from {np.nanmin(v):.6g} to {np.nanmax(v):.6g} but {span}; write the true step times in seconds "
        "on the recording's clock (the same t as the recording), or remove the sidecar."
    )


def write_gaitml_csv(recording: Recording, path: str | os.PathLike) -> Path:
    """Write a recording as gaitml-csv v1, atomically.

    Times are ``k / sampling_rate_hz`` from 0; values are written with full
    (round-trip) precision, so reading the file back gives the same arrays.
    """
    cols: dict[str, np.ndarray] = {TIME_COL: recording.t_s}
    for j, c in enumerate(ACC_COLS):
        cols[c] = recording.acc[:, j]
    if recording.gyr is not None:
        for j, c in enumerate(GYR_COLS):
            cols[c] = recording.gyr[:, j]
    if recording.labels is not None:
        cols[LABEL_COL] = recording.labels
    return write_csv(path, pd.DataFrame(cols))


def write_manifest(rows: list[dict], folder: str | os.PathLike) -> Path:
    """Write ``manifest.csv`` (``file, subject, session`` first, then free columns)."""
    df = pd.DataFrame(rows)
    for c in ("file", "subject", "session"):
        if c not in df.columns:
            raise InputError(f"manifest rows need a {c!r} entry.")
    first = ["file", "subject", "session"]
    df = df[first + [c for c in df.columns if c not in first]]
    return write_csv(Path(folder) / "manifest.csv", df)


def list_gaitml_files(folder: Path) -> list[Path]:
    """The recording files of a folder (CSV files that are not sidecars or the manifest)."""
    out = []
    for f in sorted(folder.iterdir()):
        if not f.is_file() or f.name == "manifest.csv" or f.name.startswith("."):
            continue
        if not (f.name.endswith(".csv") or f.name.endswith(".csv.gz")):
            continue
        if any(f.name.endswith(s) for s in SIDECAR_SUFFIXES):
            continue
        out.append(f)
    return out


def read_gaitml_folder(folder: str | os.PathLike, **kwargs) -> list[Recording]:
    """Read a gaitml-csv data set folder (with or without ``manifest.csv``)."""
    d = require_file(folder)
    if not d.is_dir():
        raise InputError(f"{d} is not a folder; pass the data set folder.")
    manifest = d / "manifest.csv"
    recs = []
    if manifest.exists():
        man = pd.read_csv(manifest, skipinitialspace=True)
        for c in ("file", "subject", "session"):
            if c not in man.columns:
                raise InputError(f"{manifest} has no {c!r} column; a manifest needs file, subject, session.")
        for row in man.to_dict("records"):
            f = d / str(row["file"])
            if not f.exists():
                raise InputError(f"{manifest.name} names a missing file: {row['file']}; add the file or remove its row.")
            meta = {k: (v.item() if hasattr(v, "item") else v) for k, v in row.items() if k != "file"}
            meta["subject"] = str(meta["subject"])
            meta["session"] = str(meta["session"])
            recs.append(read_gaitml_csv(f, meta=meta, **kwargs))
    else:
        files = list_gaitml_files(d)
        if not files:
            raise InputError(f"{d} holds no gaitml-csv recordings; add <name>.csv files with t, acc_x, acc_y, acc_z.")
        recs = [read_gaitml_csv(f, **kwargs) for f in files]
    return recs
