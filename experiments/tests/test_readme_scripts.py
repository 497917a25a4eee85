"""Every `python -m MODULE` the README and docs/ pages document (lab scripts and benchmarks) is a module with a command line."""

from __future__ import annotations

import re

import pytest

from experiments.tests.conftest import ROOT

DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def readme_python_modules() -> list[str]:
    """Every `python -m MODULE` the README and the docs/ pages document."""
    return sorted(set(re.findall(r"python -m ([\w.]+)", "\n".join(p.read_text() for p in DOCS))))


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
