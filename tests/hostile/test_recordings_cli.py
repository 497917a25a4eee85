"""Every recording command against the hostile corpus, as a user runs it.

For each input class of :data:`tests.hostile.corpus.RECORDING_CASES` and each of
``info, steps, zupt, features, predict, pdr``: the command-line contract holds
(exit 0 or 2, one stderr line naming the problem and a fix, one JSON object with
--json, nothing left behind after a failure) and the outcome is the one the class
declares. Accepted variants of the base walk must give the base walk's answer.
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from tests.hostile.corpus import OK, RECORDING_CASES, RECORDING_COMMANDS, Case
from tests.hostile.runner import check_contract, command_argv, run_cli, run_subprocess

CASES = {c.name: c for c in RECORDING_CASES}


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """Each case's input file, generated once per module into a temporary folder."""
    made = {}

    def get(case: Case):
        if case.name not in made:
            d = tmp_path_factory.mktemp(case.name)
            made[case.name] = case.make(d)
        return made[case.name]

    return get


@pytest.fixture(scope="module")
def base_answers(inputs, tmp_path_factory):
    """The base walk's answer to every command (JSON and output table)."""
    base = CASES["base"]
    answers = {}
    for command in RECORDING_COMMANDS:
        out = tmp_path_factory.mktemp(f"base-{command}")
        argv = command_argv(command, inputs(base), out)
        code, stdout, stderr = run_cli(argv)
        js = check_contract(argv, code, stdout, stderr, OK, out)
        answers[command] = (js, _table(argv))
    return answers


def _table(argv):
    if "--out" not in argv:
        return None
    out = argv[argv.index("--out") + 1]
    return pd.read_csv(f"{out}/manifest.csv") if argv[0] == "split" else pd.read_csv(out)


def _same_answer(case: Case, command: str, js, table, base) -> None:
    bjs, btab = base[command]
    tol = case.steps_tolerance
    if command == "info":
        for key in ("n_samples", "sampling_rate_hz", "channels", "labels"):
            assert js[key] == bjs[key], f"{case.name}: info {key} = {js[key]!r}, base {bjs[key]!r}"
    elif command in ("steps", "pdr"):
        assert abs(js["n_steps"] - bjs["n_steps"]) <= tol, f"{case.name}: {js['n_steps']} steps, base {bjs['n_steps']}"
        if tol == 0 and command == "pdr":
            np.testing.assert_allclose(js["end_xy_m"], bjs["end_xy_m"], atol=1e-6)
    elif command == "zupt":
        assert js["n_intervals"] == bjs["n_intervals"] and js["zero_velocity_fraction"] == pytest.approx(bjs["zero_velocity_fraction"])
    elif command == "predict":
        assert len(table) == len(btab) and (table.iloc[:, -1] == btab.iloc[:, -1]).mean() >= 0.95
    elif command == "split":  # the same samples, in as many segments as the base (one)
        assert js["n_segments"] == bjs["n_segments"] and table["n_samples"].sum() == btab["n_samples"].sum()
    elif command == "features":
        assert table.shape == btab.shape
        np.testing.assert_allclose(table.select_dtypes("number").to_numpy(), btab.select_dtypes("number").to_numpy(), rtol=1e-6, atol=1e-6)


PAIRS = [(c.name, cmd) for c in RECORDING_CASES for cmd in RECORDING_COMMANDS]


@pytest.mark.parametrize(("case_name", "command"), PAIRS, ids=[f"{c}-{m}" for c, m in PAIRS])
def test_command_on_hostile_input(case_name, command, inputs, base_answers, tmp_path):
    case = CASES[case_name]
    path = inputs(case)
    out = tmp_path / "out"
    out.mkdir()
    argv = command_argv(command, path, out, case.args)
    code, stdout, stderr = run_cli(argv)
    expect = case.outcome(command)
    js = check_contract(argv, code, stdout, stderr, expect, out)
    if code != 0:
        return
    table = _table(argv)
    if case.same_as_base:
        _same_answer(case, command, js, table, base_answers)
    if case.check is not None:
        case.check(command, js, table)


def test_the_corpus_covers_the_issue_classes():
    """Issue 17 lists these input classes; each is in the corpus (the names say which)."""
    names = set(CASES)
    wanted = {
        "empty-file", "header-only", "binary", "gzip-garbage", "bom", "crlf", "semicolon", "semicolon-decimal-comma",
        "unicode-labels-and-header", "nan", "inf", "duplicate-timestamps", "decreasing-timestamps", "t-in-ms", "t-in-ns",
        "one-sample", "two-samples", "three-samples", "constant", "small-gap", "gap-1e7s", "acc-in-g", "gyr-in-deg-s",
        "gyro-only", "rate-1hz", "rate-20khz", "line-100k-chars", "gyr-1e308", "jog-pocket-rad-s",
    }  # fmt: skip
    assert wanted <= names, sorted(wanted - names)
    assert sum(c.expect == OK or OK in c.per_command.values() for c in RECORDING_CASES) >= 10
    assert sum(c.expect != OK for c in RECORDING_CASES) >= 30


@pytest.mark.parametrize("case_name", ["base", "gap-1e7s", "gyr-1e308", "jog-pocket-rad-s"])
def test_real_entry_point(case_name, inputs, tmp_path):
    """A few cases through ``python -m gaitml.cli`` in a child process (the real entry point)."""
    case = CASES[case_name]
    command = "pdr"
    argv = command_argv(command, inputs(case), tmp_path, case.args)
    code, stdout, stderr = run_subprocess(argv)
    js = check_contract(argv, code, stdout, stderr, case.outcome(command), tmp_path)
    if js is not None:
        assert js["n_steps"] > 0
        json.dumps(js)
