"""The package's layering: no module of gaitml/ imports from a higher layer.

The layers (lowest first; a module may import its own layer and lower ones):

====  =========================================================
L0    consts, errors, the package root (version, errors), _base
L1    recording
L2    signal, io, parallel
L3    simulate, zupt
L4    steps (the zupt-magnitude step detector builds on zupt)
L5    features, postprocess, labels (snapping interval labels to detected steps), segment (steps/strides/zupt as one segment table)
L6    models
L7    pdr
L8    evaluation
L9    pipeline (config runner), demo, chunked_run, info
L10   commands, cli, __main__
====  =========================================================

Every ``import`` and ``from ... import`` is checked, at module level and inside
functions, absolute and relative. Lab, report and benchmark code is not in the
package at all: no module of gaitml/ imports ``benchmarks``, ``experiments`` (the
repository folder) or ``tests``.
"""

from __future__ import annotations

import ast
import functools
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "gaitml"

LAYERS: dict[str, int] = {
    **dict.fromkeys(("consts", "errors", "__init__", "_base"), 0),
    "recording": 1,
    **dict.fromkeys(("signal", "io", "parallel"), 2),
    **dict.fromkeys(("simulate", "zupt"), 3),
    "steps": 4,
    **dict.fromkeys(("features", "postprocess", "labels", "segment"), 5),
    "models": 6,
    "pdr": 7,
    "evaluation": 8,
    **dict.fromkeys(("pipeline", "demo", "chunked_run", "info"), 9),
    **dict.fromkeys(("commands", "cli", "__main__"), 10),
}
#: Top-level folders of the repository that the package must not import.
OUTSIDE = ("benchmarks", "experiments", "tests")


def _modules(package: Path = PACKAGE) -> list[Path]:
    return sorted(package.rglob("*.py"))


def _unit(path: Path, package: Path = PACKAGE) -> str:
    """The layer unit of a file: its folder below gaitml/, or its own name for a top-level module."""
    return path.relative_to(package).with_suffix("").parts[0]


def _package_of(path: Path, package: Path) -> list[str]:
    """Dotted package of a file, e.g. ['gaitml', 'steps'] for gaitml/steps/ifsm.py."""
    return list(path.relative_to(package.parent).with_suffix("").parts[:-1])


def imports(path: Path, package: Path = PACKAGE) -> list[tuple[int, str]]:
    """Every imported module of ``path`` as (line, absolute dotted name), relative imports resolved."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                pkg = _package_of(path, package)
                base = pkg[: len(pkg) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            out.append((node.lineno, mod))
            # `from gaitml import steps` / `from . import x`: the names may be modules themselves
            out += [(node.lineno, f"{mod}.{a.name}") for a in node.names if f"{mod}.{a.name}".count(".") == 1 and mod == "gaitml"]
    return out


def _target_unit(mod: str) -> str | None:
    parts = mod.split(".")
    if parts[0] != "gaitml":
        return None
    return parts[1] if len(parts) > 1 else "__init__"


@functools.cache
def violations(package: Path = PACKAGE) -> tuple[tuple[str, str], ...]:
    """``(unit, "file:line: ...")`` for every import from a higher layer or from outside the package."""
    bad = []
    for path in _modules(package):
        src = _unit(path, package)
        rel = path.relative_to(package.parent)
        if src not in LAYERS:
            bad.append((src, f"{rel}: {src} has no layer (lab code belongs outside the package)"))
            continue
        for line, mod in imports(path, package):
            if mod.split(".")[0] in OUTSIDE:
                bad.append((src, f"{rel}:{line}: imports {mod}, which is not part of the package"))
                continue
            dst = _target_unit(mod)
            if dst is None or dst == src or dst not in LAYERS:
                continue
            if LAYERS[dst] > LAYERS[src]:
                bad.append((src, f"{rel}:{line}: {src} (L{LAYERS[src]}) imports {mod} ({dst}, L{LAYERS[dst]})"))
    return tuple(bad)


def test_every_unit_has_a_layer():
    units = {_unit(p) for p in _modules()}
    assert units <= set(LAYERS), f"add {sorted(units - set(LAYERS))} to the layers (tests/test_layers.py and LAYERS)"


def test_imports_are_found_at_every_level(tmp_path):
    """The parser sees function-level and relative imports (a check that can fail)."""
    pkg = tmp_path / "gaitml" / "zupt"
    pkg.mkdir(parents=True)
    f = pkg / "x.py"
    f.write_text(
        "import numpy\nfrom gaitml.errors import InputError\n\ndef g():\n    from ..steps import ifsm\n    import gaitml.pdr.hde\n"
    )
    assert [m for _, m in imports(f, pkg.parent)] == ["numpy", "gaitml.errors", "gaitml.steps", "gaitml.pdr.hde"]
    assert [u for u, _ in violations(pkg.parent)] == ["zupt", "zupt"]  # steps (L4) and pdr (L7) from zupt (L3)


@pytest.mark.parametrize("unit", sorted({_unit(p) for p in _modules()}))
def test_no_import_from_a_higher_layer(unit):
    bad = [msg for u, msg in violations() if u == unit]
    assert not bad, "imports against the layering:\n" + "\n".join(bad)


if __name__ == "__main__":  # pragma: no cover - `python tests/test_layers.py [PACKAGE_DIR]` lists the violations
    for _, msg in violations(Path(sys.argv[1]).resolve() if len(sys.argv) > 1 else PACKAGE):
        print(msg)
