"""SIGTERM and SIGHUP end a chunked `features --out` cleanly, as SIGINT does: no temporary file is left."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from tests.conftest import ROOT

#: Runs the CLI with the chunked path switched on for any input longer than 1000 samples. SIGINT gets Python's own
#: handler, as at a terminal: a child of a non-interactive background job inherits SIGINT ignored.
_RUN = (
    "import signal, sys; signal.signal(signal.SIGINT, signal.default_int_handler); "
    "import gaitml.io.chunked as c; c.LARGE_INPUT_SAMPLES = 1000; from gaitml.cli import main; sys.exit(main(sys.argv[1:]))"
)


@pytest.fixture(scope="module")
def hour_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("sig") / "hour.csv"
    fs, n = 100.0, 360_000
    t = np.arange(n) / fs
    rng = np.random.default_rng(0)
    acc = np.column_stack([np.sin(2 * np.pi * 2 * t), np.cos(2 * np.pi * 2 * t), 9.81 + 2 * np.sin(2 * np.pi * 2 * t)])
    acc += 0.05 * rng.standard_normal(acc.shape)
    np.savetxt(path, np.column_stack([t, acc]), delimiter=",", fmt="%.4f", header="t,acc_x,acc_y,acc_z", comments="")
    return path


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGHUP", "SIGINT"])
def test_killed_features_leaves_no_file(tmp_path, hour_file, sig):
    out = tmp_path / "out" / "features.csv"
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen(
        [sys.executable, "-c", _RUN, "features", str(hour_file), "--out", str(out)], env=env, stderr=subprocess.PIPE, text=True
    )
    deadline = time.monotonic() + 120
    # wait until the temporary output exists and holds some rows: the kill lands mid-write
    while time.monotonic() < deadline and proc.poll() is None:
        tmps = list(out.parent.glob(".features.csv.*")) if out.parent.exists() else []
        if tmps and tmps[0].stat().st_size > 0:
            break
        time.sleep(0.05)
    assert proc.poll() is None, "the run ended before it could be killed; make the input longer"
    proc.send_signal(getattr(signal, sig))
    _, err = proc.communicate(timeout=60)
    assert proc.returncode != 0
    assert "Traceback" not in err
    assert sorted(p.name for p in out.parent.iterdir()) == []
