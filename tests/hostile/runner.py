"""Run a gaitml command as a user would and check the command-line contract.

``run_cli`` calls :func:`gaitml.cli.main` in process with stdout/stderr captured;
``run_subprocess`` runs ``python -m gaitml.cli`` for real. ``check_contract``
asserts: exit 0 or 2 only; on 2 exactly one stderr line ``gaitml: error: ...``
naming the problem (the case's expected pattern) and a fix (text after ';');
with ``--json`` exactly one JSON object on stdout; no output file or temporary
file left after a failure; the output file present after a success.
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

from tests.hostile.corpus import DEMO_MODEL, OK, ROOT

#: Commands that print one JSON object with --json, and their output file name.
OUT_NAMES = {
    "steps": "steps.csv",
    "zupt": "zupt.csv",
    "features": "features.csv",
    "predict": "pred.csv",
    "pdr": "traj.csv",
    "segment": "segments.csv",
    "split": "segments",  # a folder: one gaitml-csv per segment and manifest.csv
}


def command_argv(command: str, input_path: Path, out_dir: Path, args: tuple[str, ...] = (), model: Path = DEMO_MODEL) -> list[str]:
    """The argv of ``command`` on ``input_path`` with its output into ``out_dir``."""
    argv = [command]
    if command == "predict":
        argv.append(str(model))
    argv.append(str(input_path))
    if command != "features":
        argv.append("--json")
    if command in OUT_NAMES:
        argv += ["--out", str(out_dir / OUT_NAMES[command])]
    return argv + list(args)


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    """``gaitml.cli.main(argv)`` in process; returns (exit status, stdout, stderr)."""
    from gaitml.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err), warnings.catch_warnings():
        warnings.simplefilter("default")  # a warning printed by a command counts as output, as for a user
        warnings.showwarning = lambda message, category, filename, lineno, file=None, line=None: err.write(
            f"{category.__name__}: {message}\n"
        )
        code = main(argv)
    return code, out.getvalue(), err.getvalue()


def run_subprocess(argv: list[str], *, preexec_fn=None, timeout: float = 300) -> tuple[int, str, str]:
    """``python -m gaitml.cli argv`` in a child process with this checkout first on the path."""
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    proc = subprocess.run(
        [sys.executable, "-m", "gaitml.cli", *argv],
        capture_output=True,
        text=True,
        env=env,
        cwd=ROOT,
        timeout=timeout,
        preexec_fn=preexec_fn,
    )
    return proc.returncode, proc.stdout, proc.stderr


def files_in(folder: Path) -> list[str]:
    """Every file and folder below ``folder`` (hidden temporaries included)."""
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*")) if folder.exists() else []


def check_contract(
    argv: list[str], code: int, stdout: str, stderr: str, expect: str, out_dir: Path, *, before: list[str] | None = None
) -> dict | None:
    """Assert the command-line contract; returns the parsed JSON object of a success (or None)."""
    where = f"gaitml {' '.join(a[:60] for a in argv)}"
    assert code in (0, 2), f"{where}: exit {code} (only 0 or 2 allowed); stderr: {stderr[-800:]}"
    wants_json = "--json" in argv
    if code == 2:
        lines = stderr.strip("\n").split("\n")
        assert len(lines) == 1, f"{where}: {len(lines)} stderr lines on exit 2 (one expected): {stderr[:800]}"
        line = lines[0]
        assert line.startswith("gaitml: error: "), f"{where}: {line[:300]}"
        assert len(line) < 600, f"{where}: the message is {len(line)} characters long"
        assert expect != OK, f"{where}: refused an input that must be accepted: {line}"
        assert re.search(expect, line, re.IGNORECASE), f"{where}: message does not name the problem /{expect}/: {line}"
        problem, _, fix = line.partition("; ")
        assert fix.strip(), f"{where}: the message names no fix after ';': {line}"
        assert stdout == "", f"{where}: stdout on failure: {stdout[:300]}"
        left = [f for f in files_in(out_dir) if f not in (before or [])]
        assert not left, f"{where}: files left behind after the failure: {left}"
        return None
    assert expect == OK, f"{where}: accepted an input that must be refused (/{expect}/); stdout: {stdout[:300]}"
    js = None
    if wants_json:
        lines = [ln for ln in stdout.split("\n") if ln.strip()]
        assert len(lines) == 1, f"{where}: {len(lines)} stdout lines with --json (one JSON object expected)"
        js = json.loads(lines[0])
        assert isinstance(js, dict), f"{where}: stdout JSON is a {type(js).__name__}, not an object"
    if "--out" in argv:
        target = Path(argv[argv.index("--out") + 1])
        assert target.exists(), f"{where}: exit 0 but no output at {target}"
        hidden = [f for f in files_in(target.parent) if Path(f).name.startswith(".")]
        assert not hidden, f"{where}: temporary files left: {hidden}"
    assert "Traceback" not in stderr, f"{where}: {stderr[-800:]}"
    return js
