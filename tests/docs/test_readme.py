"""Every `gaitml ...` command in the README and the docs/ pages works as written (exit 0).

The commands run in a scratch folder laid out like a checkout: `data`, `models` and
`experiments` link to the repository's, and `../shared` to the shared real data, so
relative paths resolve as they do for a user in the repository root. A user runs them
top to bottom (a later command may read what an earlier one wrote), so they run once, in
that order, and each test checks one command's outcome: the tests pass in any order.
"""

from __future__ import annotations

import contextlib
import io
import os
import re
import shlex
from pathlib import Path

import pytest

from gaitml.cli import main
from tests.conftest import ROOT, SHARED_DATA

README = ROOT / "README.md"
#: The README and the task pages it links to (docs/*.md): their commands are checked alike.
DOCS = [README, *sorted((ROOT / "docs").glob("*.md"))]


def docs_text() -> str:
    return "\n".join(p.read_text() for p in DOCS)


#: README commands that run a long experiment: exercised by the slow test below.
SLOW = ("evaluate experiments/paper-svm.toml", "evaluate experiments/window-sweep.toml", "train experiments/demo.toml", "bench")


def readme_commands() -> list[str]:
    text = docs_text()
    cmds = []
    for block in re.findall(r"```bash\n(.*?)```", text, flags=re.S):
        for line in block.splitlines():
            line = line.split("#", 1)[0].strip()
            if line.startswith("gaitml "):
                cmds.append(line[len("gaitml ") :])
    return cmds


#: The README's fast commands, in README order.
FAST = [c for c in readme_commands() if not c.startswith(SLOW)]


@pytest.fixture(scope="module")
def sandbox(tmp_path_factory):
    root = tmp_path_factory.mktemp("readme")
    work = root / "work"
    work.mkdir()
    for name in ("data", "models", "experiments"):
        (work / name).symlink_to(ROOT / name)
    if SHARED_DATA.exists():
        (root / "shared").mkdir()
        (root / "shared" / "data").symlink_to(SHARED_DATA)
    return work


def _run(cmd: str, sandbox: Path) -> tuple[int | None, str]:
    """(exit code, stderr) of ``gaitml CMD`` run in ``sandbox``; None for a command that needs absent shared data."""
    if "../shared/data" in cmd and not SHARED_DATA.exists():
        return None, "shared real data not found"
    # the shipped default models are trained on real recordings in ../shared/data (their configs read it)
    if cmd.startswith(("train experiments/demo.toml", "train experiments/demo-acc.toml")) and not SHARED_DATA.exists():
        return None, "shared real data not found (the default models' configs read ../shared/data/tyrex-attitude)"
    here = os.getcwd()
    err = io.StringIO()
    try:
        os.chdir(sandbox)
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
            code = main(shlex.split(cmd))
    finally:
        os.chdir(here)
    return code, err.getvalue()


@pytest.fixture(scope="module")
def fast_outcomes(sandbox) -> dict[str, tuple[int | None, str]]:
    """Every fast README command, run once in README order: command -> (exit code, stderr)."""
    return {cmd: _run(cmd, sandbox) for cmd in FAST}


def _check(cmd: str, outcome: tuple[int | None, str]) -> None:
    code, err = outcome
    if code is None:
        pytest.skip(err)
    assert code == 0, f"gaitml {cmd}: exit {code}: {err.strip()[-300:]}"


def test_the_readme_is_short_and_links_every_docs_page():
    text = README.read_text()
    assert len(text.splitlines()) <= 120
    assert len(DOCS) >= 8 and all(f"docs/{p.name}" in text for p in DOCS[1:])


def test_readme_has_commands():
    cmds = readme_commands()
    assert len(cmds) >= 15
    sub = {c.split()[0] for c in cmds}
    assert sub >= {"info", "simulate", "steps", "zupt", "features", "evaluate", "train", "predict", "pdr", "bench"}


@pytest.mark.parametrize("cmd", FAST)
def test_readme_command(cmd, fast_outcomes):
    _check(cmd, fast_outcomes[cmd])


@pytest.mark.slow
@pytest.mark.parametrize("cmd", [c for c in readme_commands() if c.startswith(SLOW)])
def test_readme_slow_command(cmd, sandbox):
    _check(cmd, _run(cmd, sandbox))
