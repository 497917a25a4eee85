"""Helpers shared by the readers."""

from __future__ import annotations

import gzip
import zlib
from pathlib import Path

from gaitml.errors import InputError


def require_file(path: str | Path) -> Path:
    """Return ``path`` as a Path, raising a one-line InputError if it is missing or empty."""
    p = Path(path)
    if not p.exists():
        raise InputError(f"no such file or folder: {p}; check the path.")
    if p.is_file() and p.stat().st_size == 0:
        raise InputError(f"the file is empty: {p}; record or export the data again.")
    return p


def head_bytes(path: Path, n: int = 4096) -> bytes:
    """The first ``n`` bytes of a file, decompressed when it is gzip."""
    with open(path, "rb") as fh:
        magic = fh.read(2)
    try:
        if magic == b"\x1f\x8b":
            with gzip.open(path, "rb") as fh:
                return fh.read(n)
        with open(path, "rb") as fh:
            return fh.read(n)
    except (OSError, EOFError, zlib.error) as exc:
        raise InputError(f"cannot read {path}: {exc}; the file may be truncated or corrupt.") from exc


def head_lines(path: Path, n: int = 3) -> list[str]:
    """The first ``n`` text lines of a (possibly gzipped) file."""
    text = head_bytes(path).decode("utf-8", errors="replace").removeprefix("\ufeff")
    return text.splitlines()[:n]
