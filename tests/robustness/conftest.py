"""Print how many hypothesis examples each entry point saw (see tests/robustness/_hyp.py)."""

from __future__ import annotations

import json
import os

from tests.robustness._hyp import COUNTS, PROFILE


def pytest_terminal_summary(terminalreporter):
    if not COUNTS:
        return
    entries = sorted({e for e, _ in COUNTS})
    terminalreporter.section(f"hypothesis examples per entry point (profile {PROFILE})")
    for e in entries:
        parts = {o: n for (e2, o), n in sorted(COUNTS.items()) if e2 == e}
        detail = ", ".join(f"{n} {o}" for o, n in parts.items())
        terminalreporter.write_line(f"{e:32s} {sum(parts.values()):7d} examples ({detail})")
    path = os.environ.get("GAITML_HYPOTHESIS_COUNTS")
    if path:
        with open(path, "w", encoding="utf-8") as fh:
            json.dump({"profile": PROFILE, "counts": {f"{e}:{o}": n for (e, o), n in sorted(COUNTS.items())}}, fh, indent=2)
