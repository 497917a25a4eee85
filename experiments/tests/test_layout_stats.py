"""experiments.scripts.layout_stats counts what it says on a small tree built here."""

from __future__ import annotations

from experiments.scripts.layout_stats import LONG_FUNCTION_LINES, LONG_MODULE_LINES, layout_stats, markdown


def test_the_counts_of_a_small_tree(tmp_path):
    pkg = tmp_path / "gaitml" / "steps"
    pkg.mkdir(parents=True)
    (tmp_path / "gaitml" / "__init__.py").write_text("x = 1\n")
    body = "\n".join(["        y = 0"] * LONG_FUNCTION_LINES)  # def line + body: one line over the limit
    (pkg / "long.py").write_text(f"class A:\n    def f(self):\n{body}\n" + "\n" * LONG_MODULE_LINES)
    (pkg / "short.py").write_text("def g():\n    return 1\n")
    (tmp_path / "README.md").write_text("# t\n\nline\n")
    s = layout_stats(tmp_path)
    assert s["readme_lines"] == 3 and s["gaitml_modules"] == 3
    assert s["long_functions"] == [("gaitml/steps/long.py:A.f", LONG_FUNCTION_LINES + 1)]
    assert [m for m, _ in s["long_modules"]] == ["gaitml/steps/long.py"]
    assert s["gaitml_folders"]["gaitml/(top-level modules)"] == 1 and s["gaitml_folders"]["gaitml/steps"] == s["top_folders"]["gaitml"] - 1
    assert "| functions over 80 lines | 1 |" in markdown({"t": s})
