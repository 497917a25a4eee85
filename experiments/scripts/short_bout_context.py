"""The opt-in short-bout rule of the gait check (``confirm_bout_steps=10``) on real walks and simulated non-gait.

``adaptive`` runs once with its gait check off on every recording (raw steps cached under ``--cache``); then
:func:`gaitml.steps._gait_evidence.gait_check` of those steps with the rule off (the default) and on
(``confirm_bout_steps=10``). Run it against two code states (``PYTHONPATH``) to compare them; the cache of raw
steps is shared (``adaptive`` with the check off is the same in both).

- tyrex (every readable recording, steps inside the motion-capture span, as ``tyrex_steps`` counts them): per
  person and motion group (walking: Texting, Phoning, FrontPocket, BackPocket, Swinging; AR; running), the
  motion-capture count and ``adaptive``'s count with the rule off and on;
- simulated gestures and desk handling, selection seeds 0-39 and held-out seeds 100-119 (120 s each): steps per
  minute, mean / worst recording.

Nothing is fitted here (the rule's settings are those of experiments/reports/nongait.md).

    PYTHONPATH=$PWD python experiments/scripts/short_bout_context.py --data /work/shared/data --cache /tmp/chunkfix
"""

from __future__ import annotations

import argparse
import pickle
import sys
import warnings
from pathlib import Path

import numpy as np
import pandas as pd

GROUPS = {
    "Texting": "walking",
    "Phoning": "walking",
    "FrontPocket": "walking",
    "BackPocket": "walking",
    "Swinging": "walking",
    "AR": "AR",
    "RunningPocket": "running",
    "RunningHand": "running",
}


def _raw(rec):
    from gaitml.steps import get_detector

    return get_detector("adaptive", gait_check=False).detect(rec).steps_


def tyrex_raw(data: str, cache: Path) -> list[dict]:
    p = cache / "tyrex_raw.pkl"
    if p.exists():
        return pickle.loads(p.read_bytes())
    from experiments.scripts.tyrex_steps import tyrex_walks

    out = []
    for walk in tyrex_walks(data):
        segs = []
        for r in walk["recs"]:
            segs.append(
                {"steps": _raw(r), "gyr": r.gyr, "acc": r.acc, "fs": r.sampling_rate_hz, "t0": float(r.meta.get("t0_original_s", 0.0))}
            )
        out.append({"name": walk["name"], "motion": walk["motion"], "person": walk["person"], "ref": walk["ref"], "segs": segs})
        print(f"tyrex {walk['name']}", file=sys.stderr, flush=True)
    p.write_bytes(pickle.dumps(out))
    return out


def nongait_raw(kind: str, seeds, cache: Path) -> list[dict]:
    from gaitml.simulate.nongait import simulate_nongait

    p = cache / f"{kind}_{seeds[0]}_{seeds[-1]}.pkl"
    if p.exists():
        return pickle.loads(p.read_bytes())
    out = []
    for s in seeds:
        rec = simulate_nongait(kind, duration_s=120.0, seed=s)
        out.append({"steps": _raw(rec), "gyr": rec.gyr, "acc": rec.acc, "fs": rec.sampling_rate_hz, "minutes": rec.duration_s / 60.0})
    p.write_bytes(pickle.dumps(out))
    return out


def _checked(seg: dict, confirm: int) -> pd.DataFrame:
    from gaitml.steps._gait_evidence import gait_check

    return gait_check(seg["steps"], seg["gyr"], seg["fs"], acc=seg["acc"], confirm_bout_steps=confirm)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--data", default="/work/shared/data")
    ap.add_argument("--cache", default="/tmp/chunkfix")
    a = ap.parse_args()
    cache = Path(a.cache)
    cache.mkdir(parents=True, exist_ok=True)
    warnings.simplefilter("ignore")
    import gaitml

    print(f"gaitml from {gaitml.__file__}")
    rows = []
    for w in tyrex_raw(a.data, cache):
        n = {0: 0, 10: 0}
        for seg in w["segs"]:
            for c in n:
                st = _checked(seg, c)
                t = seg["t0"] + st[st.attrs.get("event", "t_peak_s")].to_numpy()
                n[c] += int(np.sum((t >= w["ref"]["t_first_s"]) & (t <= w["ref"]["t_last_s"])))
        rows.append(
            {"person": w["person"], "group": GROUPS.get(w["motion"], w["motion"]), "mocap": w["ref"]["n_steps"], "off": n[0], "on": n[10]}
        )
    df = pd.DataFrame(rows)
    g = df.groupby(["group", "person"])[["mocap", "off", "on"]].sum().reset_index()
    g["lost_to_rule"] = g["off"] - g["on"]
    print("\n## tyrex: steps inside the motion-capture span (adaptive; rule off = default, on = confirm_bout_steps=10)\n")
    print("| group | person | motion capture | rule off | rule on | lost to the rule | count ratio off | count ratio on |")
    print("|---|---|---|---|---|---|---|---|")
    for r in g.itertuples(index=False):
        print(
            f"| {r.group} | {r.person} | {r.mocap} | {r.off} | {r.on} | {r.lost_to_rule} | {r.off / r.mocap:.3f} | {r.on / r.mocap:.3f} |"
        )
    print("\n## simulated non-gait: adaptive steps per minute, mean / worst recording\n")
    print("| kind | seeds | rule off | rule on |")
    print("|---|---|---|---|")
    for kind in ("gestures", "desk"):
        for name, seeds in (("selection 0-39", list(range(40))), ("held out 100-119", list(range(100, 120)))):
            recs = nongait_raw(kind, seeds, cache)
            res = {}
            for c in (0, 10):
                r = np.array([len(_checked(x, c)) / x["minutes"] for x in recs])
                res[c] = f"{r.mean():.3f} / {r.max():.1f}"
            print(f"| {kind} | {name} | {res[0]} | {res[10]} |", flush=True)


if __name__ == "__main__":
    main()
