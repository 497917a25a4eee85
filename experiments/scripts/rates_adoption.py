"""The adoption rule of ``data.augment.rates``, applied to two ``tyrex_modes --out`` files (without and with the rates).

``python -m experiments.scripts.rates_adoption BASE.md RATES.md [--rate 20]`` from the repository root, where
both files come from ``python -m experiments.scripts.tyrex_modes --config experiments/demo.toml --recipes a
--baseline "" --no-positions --score-rates 50,20 --rates "" | 20 --out FILE``.

The rule (fixed before the runs): adopt the rates when, held out (each tyrex person left out in turn), the
figures at ``--rate`` improve (pooled right up and pooled silently wrong down, against what the model without
rate copies answers there from its features alone: the state before the rate check existed) and no figure at
the native rate (a tyrex motion's right share, a held-out simulator row's right share) falls by more than its
fold spread (max - min of the baseline's figure over the left-out people).
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

__all__ = ["read_tables", "main"]


def read_tables(path: Path) -> dict[str, list[dict]]:
    """Every markdown table of a ``tyrex_modes --out`` file, keyed by the last heading or text line before it
    (a title met again gets ``" #2"``, ``" #3"``, ... in file order)."""
    out: dict[str, list[dict]] = {}
    title, cols, rows = "", None, []
    for line in [*path.read_text().splitlines(), ""]:
        if line.startswith("|"):
            cells = [c.strip() for c in line.strip("|").split("|")]
            if cols is None:
                cols = cells
            elif not set(line) <= set("|-"):
                rows.append(dict(zip(cols, cells, strict=True)))
            continue
        if cols is not None:
            key, k = title, 1
            while key in out:
                k += 1
                key = f"{title} #{k}"
            out[key] = rows
            cols, rows = None, []
        if line.strip():
            title = line.strip("# ").strip()
    return out


def _find(tables: dict, *must: str, avoid: str | None = None) -> list[dict]:
    keys = [k for k in tables if all(m in k for m in must) and (avoid is None or avoid not in k)]
    if not keys:
        raise SystemExit(f"no table with {must} (avoiding {avoid!r}); tables: {list(tables)}")
    return tables[keys[0]]


def _spread(s: str) -> float:
    lo, hi = (float(v) for v in re.findall(r"\d+\.\d+", s)[:2])
    return hi - lo


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("base", type=Path)
    ap.add_argument("rates", type=Path)
    ap.add_argument("--rate", type=float, default=20.0)
    a = ap.parse_args(argv)
    b, r = read_tables(a.base), read_tables(a.rates)
    fails, lines = [], []
    # native tyrex motions
    bt = {row["motion"]: row for row in _find(b, "each tyrex person left out in turn", avoid="recorded at")}
    rt = {row["motion"]: row for row in _find(r, "each tyrex person left out in turn", avoid="recorded at")}
    lines.append("| native (as recorded) | right without | right with | fold spread without | verdict |")
    lines.append("|---|---|---|---|---|")
    for m, row in bt.items():
        drop = float(row["right"]) - float(rt[m]["right"])
        sp = _spread(row["right per left-out"])
        bad = drop > sp + 1e-9
        fails += [f"tyrex {m}"] if bad else []
        lines.append(f"| tyrex {m} | {row['right']} | {rt[m]['right']} | {sp:.2f} | {'FALLS' if bad else 'ok'} |")
    bs = _find(b, "held-out simulator (seed")
    rs = _find(r, "held-out simulator (seed")
    for row, row2 in zip(bs, rs, strict=True):
        drop = float(row["right"]) - float(row2["right"])
        sp = _spread(row["right over folds"])
        bad = drop > sp + 1e-9
        what = f"simulator {row['position']} {row['mode']}"
        fails += [what] if bad else []
        lines.append(f"| {what} | {row['right']} | {row2['right']} | {sp:.2f} | {'FALLS' if bad else 'ok'} |")
    at = f"recorded at {a.rate:g} Hz"
    base_low = _find(b, "without the rate check", f"at {a.rate:g} Hz")
    rates_low = _find(r, at, "left-out people")
    bl = {row["motion"]: row for row in base_low}
    rl = {row["motion"]: row for row in rates_low}
    lines += ["", f"| at {a.rate:g} Hz | right / silently wrong without (features alone) | with | verdict |", "|---|---|---|---|"]
    for m, row in bl.items():
        better = float(rl[m]["right"]) >= float(row["right"]) and float(rl[m]["silently wrong"]) <= float(row["silently wrong"])
        lines.append(
            f"| tyrex {m} | {row['right']} / {row['silently wrong']} | {rl[m]['right']} / {rl[m]['silently wrong']} | {'not worse' if better else 'worse'} |"
        )
    improve = float(rl["all"]["right"]) > float(bl["all"]["right"]) and float(rl["all"]["silently wrong"]) < float(
        bl["all"]["silently wrong"]
    )
    print("\n".join(lines))
    print(f"\npooled at {a.rate:g} Hz improves: {improve}; native figures that fall by more than their fold spread: {fails or 'none'}")
    print(f"adopt: {improve and not fails}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
