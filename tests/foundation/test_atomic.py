"""Atomic writes: a failure leaves nothing behind; success gives normal file modes."""

from __future__ import annotations

import os
import stat
import subprocess
import sys
import textwrap

import pandas as pd
import pytest

from gaitml.io import atomic_dir, atomic_path, write_csv, write_json


def test_success_has_umask_mode(tmp_path):
    p = write_json(tmp_path / "a.json", {"x": 1})
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(p.stat().st_mode) == 0o666 & ~mask


def test_exception_leaves_no_file(tmp_path):
    with pytest.raises(RuntimeError):
        with atomic_path(tmp_path / "out.csv") as tmp:
            tmp.write_text("half")
            raise RuntimeError("boom")
    assert list(tmp_path.iterdir()) == []


def test_existing_file_kept_on_failure(tmp_path):
    write_csv(tmp_path / "t.csv", pd.DataFrame({"a": [1]}))
    with pytest.raises(ValueError):
        with atomic_path(tmp_path / "t.csv") as tmp:
            tmp.write_text("a\n2\n")
            raise ValueError
    assert (tmp_path / "t.csv").read_text() == "a\n1\n"


def test_dir_replaced_only_when_complete(tmp_path):
    with atomic_dir(tmp_path / "model") as d:
        (d / "model.json").write_text("{}")
    with pytest.raises(KeyError):
        with atomic_dir(tmp_path / "model") as d:
            (d / "model.json").write_text('{"new": 1}')
            raise KeyError
    assert (tmp_path / "model" / "model.json").read_text() == "{}"
    assert [p.name for p in tmp_path.iterdir()] == ["model"]


def test_killed_process_leaves_no_partial_output(tmp_path):
    """SIGKILL in the middle of a write: the target never appears, only a hidden temp file."""
    script = textwrap.dedent(
        f"""
        import os, signal
        from gaitml.io import atomic_path
        with atomic_path({str(tmp_path / "table.csv")!r}) as tmp:
            with open(tmp, "w") as fh:
                fh.write("a,b\\n1,2\\n")
                fh.flush()
                os.kill(os.getpid(), signal.SIGKILL)
        """
    )
    res = subprocess.run([sys.executable, "-c", script])
    assert res.returncode == -9
    assert not (tmp_path / "table.csv").exists()
    assert all(p.name.startswith(".table.csv.") for p in tmp_path.iterdir())


def test_atomic_dir_never_deletes_foreign_folders_or_files(tmp_path):
    from gaitml.errors import InputError

    foreign = tmp_path / "mine"
    foreign.mkdir()
    (foreign / "important.txt").write_text("x")
    with pytest.raises(InputError, match="folder of other files"):
        with atomic_dir(foreign) as d:
            (d / "model.json").write_text("{}")
    assert (foreign / "important.txt").read_text() == "x"
    f = tmp_path / "f.csv"
    f.write_text("data")
    with pytest.raises(InputError, match="existing file"):
        with atomic_dir(f):
            pass
    assert f.read_text() == "data"
    # an artifact folder of ours is replaced
    art = tmp_path / "model"
    with atomic_dir(art) as d:
        (d / "model.json").write_text("{}")
    with atomic_dir(art) as d:
        (d / "model.json").write_text('{"v": 2}')
    assert (art / "model.json").read_text() == '{"v": 2}'


def test_write_errors_are_input_errors(tmp_path):
    from gaitml.errors import InputError

    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="part of its folder path is a file"):
        write_json(tmp_path / "file" / "a.json", {})
    with pytest.raises(InputError, match="it is a folder"):
        write_json(tmp_path, {})


def test_devices_are_written_not_replaced_and_disk_full_is_an_input_error(tmp_path, monkeypatch):
    import errno

    from gaitml.errors import InputError

    write_json("/dev/null", {"a": 1})  # as root, a replace would turn /dev/null into a regular file
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    with pytest.raises(InputError, match="No space left on device; free some disk space"):
        write_json("/dev/full", {"a": 1})
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)

    def full(self, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    import pathlib

    monkeypatch.setattr(pathlib.Path, "write_text", full)
    with pytest.raises(InputError, match="No space left on device"):
        write_json(tmp_path / "a.json", {"a": 1})
    assert list(tmp_path.iterdir()) == []  # no temporary file left
    with pytest.raises(InputError, match="No space left on device"), atomic_dir(tmp_path / "run") as d:
        (d / "x.txt").write_text("x")
    assert list(tmp_path.iterdir()) == []
