"""Every `gaitml ...` command in the README and the docs/ pages works as written (exit 0).

The commands run in a scratch folder laid out like a checkout: `data`, `models` and
`experiments` link to the repository's, and `../shared` to the shared real data, so
relative paths resolve as they do for a user in the repository root.
"""

from __future__ import annotations

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


def _run(cmd: str, sandbox: Path, monkeypatch, capsys):
    if "../shared/data" in cmd and not SHARED_DATA.exists():
        pytest.skip("shared real data not found")
    monkeypatch.chdir(sandbox)
    code = main(shlex.split(cmd))
    out, err = capsys.readouterr()
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


@pytest.mark.parametrize("cmd", [c for c in readme_commands() if not c.startswith(SLOW)])
def test_readme_command(cmd, sandbox, monkeypatch, capsys):
    _run(cmd, sandbox, monkeypatch, capsys)


@pytest.mark.slow
@pytest.mark.parametrize("cmd", [c for c in readme_commands() if c.startswith(SLOW)])
def test_readme_slow_command(cmd, sandbox, monkeypatch, capsys):
    _run(cmd, sandbox, monkeypatch, capsys)


def readme_python_modules() -> list[str]:
    """Every `python -m MODULE` the README documents."""
    return sorted(set(re.findall(r"python -m ([\w.]+)", docs_text())))


def test_readme_documents_the_lab_scripts():
    mods = readme_python_modules()
    assert {"benchmarks", "benchmarks.longinput", "experiments.scripts.pdr_report", "experiments.scripts.zupt_report"} <= set(mods)
    assert not [m for m in mods if m.startswith(("gaitml.bench", "gaitml.simulate.realism", "gaitml.zupt.report", "gaitml.pdr.report"))]


@pytest.mark.parametrize("module", readme_python_modules())
def test_readme_python_module_exists(module, monkeypatch):
    """Each documented `python -m` target is a module with a command line (run from the repository root)."""
    import importlib
    import importlib.util

    monkeypatch.syspath_prepend(str(ROOT))
    spec = importlib.util.find_spec(module)
    assert spec is not None, f"python -m {module}: no such module"
    if spec.submodule_search_locations:  # a package: `python -m` runs its __main__
        assert importlib.util.find_spec(f"{module}.__main__") is not None, f"python -m {module}: the package has no __main__"
    assert callable(getattr(importlib.import_module(module), "main", None)), f"python -m {module}: no main()"
