"""Phone-app exports as containers: a folder or a zip archive of CSV tables.

The phone-app readers (:mod:`gaitml.io.phyphox`, :mod:`gaitml.io.sensor_logger`)
see an export as a mapping from a table's file name to its bytes, whether the
user unpacked the export into a folder or passes the zip the app wrote. Only the
CSV tables are listed; sub-folders (phyphox ``meta/``) are listed with their
path relative to the export root, so ``meta/device.csv`` is not mistaken for a
sensor table.
"""

from __future__ import annotations

import io
import zipfile
from pathlib import Path, PurePosixPath

import pandas as pd

from gaitml.errors import InputError

__all__ = ["ExportContainer", "open_export", "read_table", "sniff_csv"]

#: Largest member of a zip export read into memory (a 1 h, 500 Hz, 3-axis table is ~200 MB).
_MAX_MEMBER_BYTES = 2_000_000_000


class ExportContainer:
    """The CSV tables of an app export (folder or zip), by relative POSIX path."""

    def __init__(self, path: Path):
        self.path = path
        self._zip: zipfile.ZipFile | None = None
        self.members: dict[str, object] = {}
        if path.is_dir():
            for f in sorted(path.rglob("*")):
                if f.is_file() and f.suffix.lower() == ".csv" and not any(part.startswith(".") for part in f.relative_to(path).parts):
                    self.members[f.relative_to(path).as_posix()] = f
        elif zipfile.is_zipfile(path):
            try:
                self._zip = zipfile.ZipFile(path)
                names = self._zip.namelist()
            except (zipfile.BadZipFile, OSError) as exc:
                raise InputError(f"cannot open {path.name} as a zip archive ({exc}); export the recording again.") from exc
            csvs = [n for n in names if n.lower().endswith(".csv") and not n.startswith("__MACOSX/")]
            root = _common_root(csvs)
            for n in sorted(csvs):
                self.members[n[len(root) :]] = n
        else:
            self.members[path.name] = path

    def close(self) -> None:
        """Close the zip archive, if any."""
        if self._zip is not None:
            self._zip.close()

    def __enter__(self) -> ExportContainer:
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def top_level(self) -> dict[str, str]:
        """Top-level tables: lower-case file name -> member key (sub-folders like ``meta/`` excluded)."""
        return {k.lower(): k for k in self.members if "/" not in k}

    def read_bytes(self, key: str) -> bytes:
        """The raw bytes of one table."""
        src = self.members[key]
        try:
            if self._zip is not None:
                info = self._zip.getinfo(str(src))
                if info.file_size > _MAX_MEMBER_BYTES:
                    raise InputError(
                        f"{key} in {self.path.name} is {info.file_size / 1e9:.1f} GB; unpack the export and split the recording."
                    )
                return self._zip.read(str(src))
            return Path(str(src)).read_bytes()
        except (zipfile.BadZipFile, OSError, EOFError) as exc:
            raise InputError(
                f"cannot read {key} from {self.path.name} ({exc}); the export is truncated or corrupt, export it again."
            ) from exc

    def head(self, key: str, n_bytes: int = 2048) -> str:
        """The first bytes of a table as text (for content detection)."""
        src = self.members[key]
        try:
            if self._zip is not None:
                with self._zip.open(str(src)) as fh:
                    data = fh.read(n_bytes)
            else:
                with open(str(src), "rb") as fh:
                    data = fh.read(n_bytes)
        except (zipfile.BadZipFile, OSError, EOFError):
            return ""
        return data.decode("utf-8-sig", errors="replace")


def _common_root(names: list[str]) -> str:
    """The folder every name lies in (a zip of an exported folder), with trailing '/', or ''."""
    if not names:
        return ""
    parts = [PurePosixPath(n).parts for n in names]
    if any(len(p) < 2 for p in parts):
        return ""
    first = parts[0][0]
    return f"{first}/" if all(p[0] == first for p in parts) else ""


def open_export(path: Path) -> ExportContainer:
    """Open a folder, a zip archive or a single CSV file as an export container."""
    return ExportContainer(path)


def sniff_csv(header_line: str) -> tuple[str, str]:
    """``(separator, decimal)`` of a CSV from its header line.

    phyphox offers comma, tab and semicolon separators (the semicolon one with
    decimal commas); Sensor Logger writes commas.
    """
    if "\t" in header_line:
        return "\t", "."
    if ";" in header_line and header_line.count(";") >= header_line.count(","):
        return ";", ","
    return ",", "."


def read_table(container: ExportContainer, key: str) -> pd.DataFrame:
    """Read one CSV table of an export (separator sniffed), with a one-line error if it is empty or unparsable."""
    data = container.read_bytes(key)
    where = f"{key} in {container.path.name}" if container.path.name != key else key
    text_head = data[:2048].decode("utf-8-sig", errors="replace")
    if not text_head.strip():
        raise InputError(f"{where} is empty; record again with this sensor switched on, or export the recording again.")
    sep, dec = sniff_csv(text_head.splitlines()[0])
    try:
        df = pd.read_csv(io.BytesIO(data), sep=sep, decimal=dec, encoding="utf-8-sig")
    except pd.errors.EmptyDataError as exc:
        raise InputError(f"{where} is empty; record again with this sensor switched on, or export the recording again.") from exc
    except (pd.errors.ParserError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot parse {where} as CSV ({str(exc).splitlines()[0]}); export the recording again as CSV.") from exc
    df.columns = [str(c).strip().strip('"') for c in df.columns]
    if len(df) == 0:
        raise InputError(f"{where} has a header but no samples; record again with this sensor switched on.")
    return df
