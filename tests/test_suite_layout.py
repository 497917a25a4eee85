"""The layout of the test suite: the library's tests never import the lab, the lab's tests import no private lab name.

The library's tests (``tests/``) check the installed package; the lab's study scripts
(``experiments/scripts/``) are tested by the lab's own tests (``experiments/tests/``), which
may import the library and the lab's public functions. Every import, at module level and
inside functions, is read with :mod:`ast`.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """(line, module, imported names) of every absolute import of ``path``."""
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), filename=str(path))):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name, []) for a in node.names]
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            out.append((node.lineno, node.module, [a.name for a in node.names]))
    return out


def lab_imports(folder: Path) -> list[str]:
    """``file:line: module`` for every import of the lab (``experiments``) below ``folder``."""
    return [
        f"{p.relative_to(folder.parent)}:{line}: {mod}"
        for p in sorted(folder.rglob("*.py"))
        for line, mod, _ in _imports(p)
        if mod.split(".")[0] == "experiments"
    ]


def private_lab_imports(folder: Path) -> list[str]:
    """``file:line: module.name`` for every ``from experiments... import _name`` below ``folder``."""
    return [
        f"{p.relative_to(folder.parent)}:{line}: {mod}.{name}"
        for p in sorted(folder.rglob("*.py"))
        for line, mod, names in _imports(p)
        if mod.startswith("experiments.")
        for name in names
        if name.startswith("_") and not name.startswith("__")
    ]


def test_the_checks_find_what_they_look_for(tmp_path):
    (tmp_path / "t.py").write_text("def f():\n    from experiments.scripts.x import _y, z\nimport experiments.scripts.w\nimport numpy\n")
    assert sorted(m.split(": ")[1] for m in lab_imports(tmp_path)) == ["experiments.scripts.w", "experiments.scripts.x"]
    assert [m.split(": ")[1] for m in private_lab_imports(tmp_path)] == ["experiments.scripts.x._y"]


def test_the_library_tests_never_import_the_lab():
    bad = lab_imports(ROOT / "tests")
    assert not bad, "tests/ imports the lab (move the test to experiments/tests/):\n" + "\n".join(bad)


@pytest.mark.parametrize("folder", ["tests", "experiments/tests"])
def test_no_test_imports_a_private_lab_name(folder):
    bad = private_lab_imports(ROOT / folder)
    assert not bad, "private lab names imported (make them public functions of the lab module):\n" + "\n".join(bad)
