"""Atomic writes: a failed or killed run never leaves a half-written file or folder.

Everything is written to a temporary sibling first and moved into place with
``os.replace`` (atomic on POSIX within one file system).
"""

from __future__ import annotations

import contextlib
import errno
import json
import os
import shutil
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from gaitml.errors import InputError

__all__ = ["atomic_path", "atomic_dir", "write_text", "write_json", "write_csv"]

#: A folder holding one of these files is a gaitml artifact that ``atomic_dir`` may replace.
ARTIFACT_MARKERS = ("model.json", "metrics.json")


def _prepare_parent(target: Path) -> None:
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
    except (FileExistsError, NotADirectoryError) as exc:
        raise InputError(f"cannot write {target}: a part of its folder path is a file; choose another output path.") from exc
    except PermissionError as exc:
        raise InputError(f"cannot create the folder {target.parent}: permission denied; choose a writable output path.") from exc


def _write_error(target: Path, exc: OSError) -> InputError:
    why = exc.strerror or type(exc).__name__
    if exc.errno in (errno.ENOSPC, errno.EDQUOT):
        return InputError(f"cannot write {target}: {why}; free some disk space or write to another disk.")
    return InputError(f"cannot write {target}: {why}; choose a writable output path (a file path, not a folder).")


#: errno values of a failed write that are the user's to fix (disk full, read-only...).
_WRITE_ERRNOS = {errno.ENOSPC, errno.EDQUOT, errno.EROFS, errno.EFBIG, errno.EACCES, errno.EPERM, errno.EIO}


@contextlib.contextmanager
def _fixable_write_errors(target: Path) -> Iterator[None]:
    """Turn a write error the user can fix (:data:`_WRITE_ERRNOS`) inside the block into an InputError naming ``target``."""
    try:
        yield
    except OSError as exc:
        if exc.errno in _WRITE_ERRNOS:
            raise _write_error(target, exc) from exc
        raise


def _is_special(target: Path) -> bool:
    """Whether ``target`` exists and is a device, pipe or socket (``/dev/null``, ``/dev/stdout``)."""
    try:
        mode = os.stat(target).st_mode
    except OSError:
        return False
    return not (stat.S_ISREG(mode) or stat.S_ISDIR(mode))


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike, *, suffix: str | None = None) -> Iterator[Path]:
    """Yield a temporary path beside ``path``; on success move it onto ``path``.

    On any exception the temporary file is removed and ``path`` is untouched.
    A write error the user can fix (disk full, read-only file system) becomes an
    InputError. An existing device or pipe (``/dev/null``, ``/dev/stdout``) is
    written directly, never replaced by a regular file.
    """
    target = Path(path)
    if _is_special(target):
        with _fixable_write_errors(target):
            yield target
        return
    _prepare_parent(target)
    if target.is_dir():
        raise InputError(f"cannot write {target}: it is a folder; give a file path.")
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=suffix or ".tmp", dir=target.parent)
    except OSError as exc:
        raise _write_error(target, exc) from exc
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        with _fixable_write_errors(target):
            yield tmp_path
        if tmp_path.exists():
            os.chmod(tmp_path, 0o666 & ~_umask())  # mkstemp creates 0600; give the usual mode
        try:
            os.replace(tmp_path, target)
        except OSError as exc:
            raise _write_error(target, exc) from exc
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            tmp_path.unlink()
        raise


@contextlib.contextmanager
def atomic_dir(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary folder beside ``path``; on success it replaces ``path``.

    An existing folder at ``path`` is replaced only once the new one is complete,
    and only if it is empty or a gaitml artifact (holds one of
    :data:`ARTIFACT_MARKERS`): a folder of other files, or a file, is never
    deleted (InputError before any work is written).
    """
    target = Path(path)
    _prepare_parent(target)
    check_replaceable_dir(target)
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".tmp", dir=target.parent))
    except OSError as exc:
        raise _write_error(target, exc) from exc
    try:
        with _fixable_write_errors(target):
            yield tmp
        os.chmod(tmp, 0o777 & ~_umask())  # mkdtemp creates 0700
        if target.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{target.name}.", suffix=".old", dir=target.parent))
            os.replace(target, old / "x")
            os.replace(tmp, target)
            shutil.rmtree(old, ignore_errors=True)
        else:
            os.replace(tmp, target)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise


def check_replaceable_dir(target: str | os.PathLike) -> None:
    """Raise InputError unless ``target`` is absent, an empty folder or a gaitml artifact folder."""
    t = Path(target)
    if not t.exists():
        return
    if not t.is_dir():
        raise InputError(f"{t} is an existing file; give a new folder path for the output.")
    entries = [p for p in t.iterdir() if not p.name.startswith(".")]
    if entries and not any((t / m).exists() for m in ARTIFACT_MARKERS):
        raise InputError(f"{t} is a folder of other files ({len(entries)} entries) and would be replaced; give a new or empty folder.")


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_text(path: str | os.PathLike, text: str) -> Path:
    """Write ``text`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_text(text, encoding="utf-8")
    return Path(path)


def write_json(path: str | os.PathLike, obj: Any) -> Path:
    """Write ``obj`` as indented JSON to ``path`` atomically."""
    return write_text(path, json.dumps(obj, indent=2, default=_json_default) + "\n")


def write_csv(path: str | os.PathLike, frame: Any, **kwargs: Any) -> Path:
    """Write a DataFrame to CSV atomically (``index=False`` unless given)."""
    kwargs.setdefault("index", False)
    with atomic_path(path) as tmp:
        frame.to_csv(tmp, **kwargs)
    return Path(path)


def _json_default(o: Any) -> Any:
    import numpy as np

    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    if isinstance(o, np.bool_):
        return bool(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"not JSON serialisable: {type(o).__name__}")
