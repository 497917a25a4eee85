"""The size and shape of a checkout: folders, lines per folder, long modules and long functions.

Run ``python -m experiments.scripts.layout_stats [ROOT ...]`` (default: this checkout) to print,
per checkout, the README's length, the Python lines per top-level folder and per folder of
``gaitml/``, the modules of ``gaitml/`` over :data:`LONG_MODULE_LINES` lines and the functions
(and methods) of ``gaitml/`` over :data:`LONG_FUNCTION_LINES` lines, as markdown. Several roots
give one column each (``experiments/reports/layout.md`` compares main with the layout branch).

Lines are physical lines of ``*.py`` files (docstrings and comments included); a function's
length runs from its ``def`` (decorators excluded) to its last line.
"""

from __future__ import annotations

import argparse
import ast
import sys
from collections import Counter
from pathlib import Path

__all__ = ["LONG_FUNCTION_LINES", "LONG_MODULE_LINES", "layout_stats", "main", "markdown"]

#: A module of ``gaitml/`` longer than this many lines counts as long.
LONG_MODULE_LINES = 500
#: A function or method of ``gaitml/`` longer than this many lines counts as long.
LONG_FUNCTION_LINES = 80
#: Top-level folders counted (Python files below them).
TOP_FOLDERS = ("gaitml", "tests", "experiments", "benchmarks")


def _py_files(folder: Path) -> list[Path]:
    return sorted(p for p in folder.rglob("*.py") if "__pycache__" not in p.parts and ".venv" not in p.parts)


def _lines(path: Path) -> int:
    return len(path.read_text(encoding="utf-8").splitlines())


def long_functions(path: Path, limit: int = LONG_FUNCTION_LINES) -> list[tuple[str, int]]:
    """``(qualified name, lines)`` of the functions and methods of ``path`` longer than ``limit`` lines."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    out: list[tuple[str, int]] = []

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, ast.FunctionDef | ast.AsyncFunctionDef):
                n = child.end_lineno - child.lineno + 1
                if n > limit:
                    out.append((prefix + child.name, n))
                visit(child, prefix + child.name + ".")
            elif isinstance(child, ast.ClassDef):
                visit(child, prefix + child.name + ".")

    visit(tree, "")
    return out


def layout_stats(root: Path) -> dict:
    """The figures of one checkout ``root`` (see the module docstring)."""
    root = Path(root)
    pkg = root / "gaitml"
    top = {name: sum(_lines(p) for p in _py_files(root / name)) for name in TOP_FOLDERS if (root / name).is_dir()}
    per_folder: Counter = Counter()
    modules = _py_files(pkg)
    for p in modules:
        rel = p.relative_to(pkg)
        per_folder["gaitml/" + (rel.parts[0] if len(rel.parts) > 1 else "(top-level modules)")] += _lines(p)
    long_modules = sorted(((str(p.relative_to(root)), _lines(p)) for p in modules if _lines(p) > LONG_MODULE_LINES), key=lambda x: -x[1])
    long_funcs = sorted(
        ((f"{p.relative_to(root)}:{name}", n) for p in modules for name, n in long_functions(p)),
        key=lambda x: -x[1],
    )
    docs = root / "docs"
    return {
        "readme_lines": _lines(root / "README.md") if (root / "README.md").exists() else 0,
        "docs_pages": len(list(docs.glob("*.md"))) if docs.is_dir() else 0,
        "top_folders": top,
        "gaitml_folders": dict(sorted(per_folder.items())),
        "gaitml_modules": len(modules),
        "long_modules": long_modules,
        "long_functions": long_funcs,
    }


def markdown(stats: dict[str, dict]) -> str:
    """One column per checkout: the summary rows, the lines per folder, then the long modules and functions."""
    names = list(stats)
    head = "| | " + " | ".join(names) + " |\n|---|" + "---|" * len(names)
    rows = [head]

    def row(label, values):
        rows.append(f"| {label} | " + " | ".join(str(v) for v in values) + " |")

    row("README lines", [s["readme_lines"] for s in stats.values()])
    row("docs/ pages", [s["docs_pages"] for s in stats.values()])
    row("gaitml modules", [s["gaitml_modules"] for s in stats.values()])
    row(f"modules over {LONG_MODULE_LINES} lines", [len(s["long_modules"]) for s in stats.values()])
    row(f"functions over {LONG_FUNCTION_LINES} lines", [len(s["long_functions"]) for s in stats.values()])
    for folder in TOP_FOLDERS:
        row(f"{folder}/ lines", [s["top_folders"].get(folder, 0) for s in stats.values()])
    folders = sorted({f for s in stats.values() for f in s["gaitml_folders"]})
    for f in folders:
        row(f"{f} lines", [s["gaitml_folders"].get(f, 0) for s in stats.values()])
    out = ["\n".join(rows)]
    for name, s in stats.items():
        out.append(
            f"\n{name}: modules over {LONG_MODULE_LINES} lines: " + (", ".join(f"{m} ({n})" for m, n in s["long_modules"]) or "none")
        )
        out.append(
            f"{name}: functions over {LONG_FUNCTION_LINES} lines: " + (", ".join(f"{m} ({n})" for m, n in s["long_functions"]) or "none")
        )
    return "\n".join(out) + "\n"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Folders, lines per folder, long modules and functions of one or more checkouts.")
    ap.add_argument("roots", nargs="*", metavar="ROOT", help="checkout folders (default: this one)")
    args = ap.parse_args(argv)
    roots = [Path(r) for r in args.roots] or [Path(__file__).resolve().parents[2]]
    stats = {str(r): layout_stats(r) for r in roots}
    sys.stdout.write(markdown(stats))
    return 0


if __name__ == "__main__":
    sys.exit(main())
